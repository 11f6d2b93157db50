"""What a study reads back from its run folders: every passage's signature and each run's
own quantities, and their distributions (numpy/pandas; no histories, no Taichi).

One passage is one sample of a chaotic bounce, so a finding is a distribution over
passages (:func:`taichi_bearing.checks.passages.passage_statistics`). Independent passages come
from runs of one case whose first roller starts at slightly different angles
(:func:`spread_angles`); the run's checks have already put each passage's signature in
``summary.json`` ``events``.

:data:`QUANTITIES` are what the convergence study compares: the preload's
(static, one value per run, from ``preload.json``), each passage's (dynamic, from the
events) and the spall size estimated from the run's acceleration (dynamic, one per run).
The zone-edge share is the smallest force of a loaded roller (one carrying more than
:data:`taichi_bearing.checks.LOADED_SHARE` of Q_max, the checks' own definition) over
Q_max: the roller whose force is the small difference of two ring displacements.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from taichi_bearing.checks.common import LOADED_SHARE
from taichi_bearing.checks.passages import PASSAGE_QUANTITIES, passage_statistics
from taichi_bearing.checks.quantities import QUANTITIES
from taichi_bearing.output.layout import PRELOAD_FILE
from taichi_bearing.output.run_folder import passage_events, read_json, read_summary

__all__ = [
    "ANGLE_KEY",
    "collect",
    "group_statistics",
    "run_passages",
    "run_values",
    "spread_angles",
    "zone_edge_share",
]

ANGLE_KEY = "run.first_roller_angle_deg"


RUN_COLUMNS = ("hertz_half_width_m", "hertz_peak_pressure_Pa", "zone_edge_roller",
               "contact_patch_nodes", "defect_size_note")  # fmt: skip
# event entries that are times or set-up rather than the passage's signature
EVENT_FIRST = ("roller", "entry_time_s", "first_impact_time_s", "exit_time_s", "force_before_N")


def spread_angles(centre_deg: float, spread_deg: float, n: int) -> list[float]:
    """``n`` starting angles spread evenly over ``centre +- spread / 2`` (deg, both ends
    included); ``[centre]`` for one run. Rounded to 1e-9 deg (a folder name and a case
    value that read back the same).

    Raises
    ------
    ValueError
        ``n < 1`` or a negative or non-finite spread.
    """
    if n < 1:
        raise ValueError(f"needs at least one run, got {n}")
    if not (math.isfinite(spread_deg) and spread_deg >= 0):
        raise ValueError(f"spread must be a number >= 0, got {spread_deg}")
    if n == 1:
        return [float(centre_deg)]
    a = np.linspace(centre_deg - 0.5 * spread_deg, centre_deg + 0.5 * spread_deg, n)
    return [round(float(v), 9) for v in a]


def zone_edge_share(forces: Sequence[float], loaded: float = LOADED_SHARE) -> tuple[float, int]:
    """The smallest force of a roller carrying more than ``loaded`` of Q_max, over Q_max,
    and that roller's index; (NaN, -1) when no roller carries force."""
    f = np.asarray(forces, dtype=float)
    if f.size == 0 or not np.nanmax(f) > 0:
        return math.nan, -1
    q_max = float(np.nanmax(f))
    idx = np.flatnonzero(f > loaded * q_max)
    j = int(idx[np.argmin(f[idx])])
    return float(f[j] / q_max), j


def _num(value) -> float:
    try:
        return math.nan if value is None else float(value)
    except (TypeError, ValueError):
        return math.nan


def run_values(run_dir: str | os.PathLike) -> dict[str, float | str]:
    """A run's own quantities: the preload's (``preload.json``: Q_max, the zone-edge share
    and roller, the contact patch beside Hertz's) and the spall size estimate
    (``summary.json``, with its check's note: why there is none); NaN for what the folder
    lacks."""
    run_dir = Path(run_dir)
    path = run_dir / PRELOAD_FILE
    preload = read_json(path) if path.is_file() else {}
    forces = preload.get("outer_force_N") or []
    share, roller = zone_edge_share(forces) if forces else (math.nan, -1)
    patch = preload.get("contact_patch") or {}
    summary = read_summary(run_dir) or {}
    return {
        "q_max_N": float(max(forces)) if forces else math.nan,
        "zone_edge_share": share,
        "zone_edge_roller": roller,
        "contact_half_width_m": _num(patch.get("half_width_m")),
        "contact_peak_pressure_Pa": _num(patch.get("peak_pressure_Pa")),
        "hertz_half_width_m": _num(patch.get("hertz_half_width_m")),
        "hertz_peak_pressure_Pa": _num(patch.get("hertz_peak_pressure_Pa")),
        "contact_patch_nodes": _num(patch.get("nodes")),
        "defect_size_estimate_m": _num(summary.get("defect_size_estimate_m")),
        "defect_size_note": str(
            ((summary.get("checks") or {}).get("defect_size") or {}).get("note") or ""
        ),
    }


def run_passages(run_dir: str | os.PathLike) -> list[dict]:
    """The passages of a run (``summary.json`` events with a roller), each with its
    signature as the run's checks wrote it; scalar entries only."""
    summary = read_summary(run_dir) or {}
    out = []
    for e in passage_events(summary):
        if e.get("roller") is None:
            continue
        out.append({k: v for k, v in e.items() if not isinstance(v, (list, dict))})
    return out


def collect(results: Iterable, labels: Mapping[str, str]) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Every passage and every run of a study's finished cells.

    Parameters
    ----------
    results : iterable of taichi_bearing.studies.sweep.CellResult
    labels : mapping
        Varied key -> its column (:func:`taichi_bearing.studies.sweep.column_labels`).

    Returns
    -------
    passages : DataFrame
        One row per passage: ``run``, the varied columns, ``roller``, the event times and
        every quantity of its signature (:data:`~taichi_bearing.checks.passages.PASSAGE_QUANTITIES`
        first).
    runs : DataFrame
        One row per cell: ``run``, the varied columns, ``status``, ``n_passages`` and the
        run's own quantities (:func:`run_values`; NaN for a cell that did not finish).
    """
    passages, runs = [], []
    for r in results:
        cell = {"run": r.name, **{labels[k]: v for k, v in r.values.items()}}
        found = run_passages(r.out_dir) if r.status == "finished" else []
        values = run_values(r.out_dir) if r.status == "finished" else {}
        runs.append({**cell, "status": r.status, "n_passages": len(found), **values})
        passages += [{**cell, **p} for p in found]
    first = [*runs[0]] if runs else ["run"]
    known = [c for c in first if c not in ("status", "n_passages")]
    cell_cols = [c for c in known if c not in (*[q.name for q in QUANTITIES], *RUN_COLUMNS)]
    columns = [*cell_cols, *EVENT_FIRST, *PASSAGE_QUANTITIES]
    extra = sorted({k for p in passages for k in p} - set(columns))
    return pd.DataFrame(passages, columns=[*columns, *extra]), pd.DataFrame(runs)


def group_statistics(
    passages: pd.DataFrame, runs: pd.DataFrame, by: str | None = None
) -> dict[object, dict[str, dict[str, float | int]]]:
    """Median, quartiles and count of every :data:`QUANTITIES` entry (and of its
    reference), over the passages or the finished runs of each value of column ``by``
    (one group, key None, without it).

    Returns
    -------
    dict
        group value -> quantity name -> ``{median, q25, q75, n}``.
    """
    finished = runs[runs["status"] == "finished"] if len(runs) else runs
    groups = [None] if by is None else list(dict.fromkeys(runs[by])) if len(runs) else []
    out = {}
    per_run = [q.name for q in QUANTITIES if q.per == "run"]
    per_run += [q.reference for q in QUANTITIES if q.reference]
    per_passage = [q.name for q in QUANTITIES if q.per == "passage"]
    for g in groups:
        p = passages if g is None else passages[passages[by] == g]
        r = finished if g is None else finished[finished[by] == g]
        stats = passage_statistics(r.to_dict("records"), [c for c in per_run if c in r])
        stats.update(passage_statistics(p.to_dict("records"), per_passage))
        for name in (*per_run, *per_passage):
            stats.setdefault(name, {"median": math.nan, "q25": math.nan, "q75": math.nan, "n": 0})
        out[g] = stats
    return out
