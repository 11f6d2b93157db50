"""The quantities a sweep compares across its cells, read back from one run folder.

Everything comes from the run's files (``summary.json``, histories): the squared-envelope
spectrum level of the analysed sensor acceleration at BPFO, and the contact forces of each
roller that passed the spall (``summary["events"]``) on the outer and inner raceway: their
peak and the maximum of their Hilbert envelope about the force before the spall, and the
re-stressing impulse (largest force on the roller, either raceway, in the re-stressing
burst after it meets the exit edge: the window of
:data:`taichi_bearing.checks.passages.EXIT_BURST_S`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence

import numpy as np

from diagnostics import envelope
from taichi_bearing.checks.passages import EXIT_BURST_S
from taichi_bearing.output.layout import RACES, TIME_COLUMN, roller_force_column
from taichi_bearing.output.run_folder import load_run, sensor_acceleration
from taichi_bearing.studies.sweep import CellResult, column_labels

__all__ = ["METRICS", "cell_metrics", "envelope_level_at", "summary_rows"]

# Passage window: from this long before entry to this long after re-stressing (s); the
# re-stressing window starts at the first impact on the exit edge and lasts this long or
# EXIT_BURST_S, whichever is longer.
WINDOW_S = 3e-4

# name -> (label, unit) of every per-cell quantity, in the order of sweep_summary.csv
METRICS: dict[str, tuple[str, str]] = {
    "env_bpfo": ("squared-envelope spectrum at BPFO", "(m/s^2)^2"),
    "accel_peak": ("peak |acceleration - median|", "m/s^2"),
    "outer_peak_N": ("outer-raceway force peak, rollers through the spall", "N"),
    "outer_env_max_N": ("outer-raceway force envelope maximum", "N"),
    "inner_peak_N": ("inner-raceway force peak, rollers through the spall", "N"),
    "inner_env_max_N": ("inner-raceway force envelope maximum", "N"),
    "restress_peak_N": ("re-stressing burst peak (either raceway, after the exit edge)", "N"),
    "static_outer_N": ("outer force of the roller before the spall", "N"),
    "max_outer_fn_N": ("largest outer-raceway force, all rollers, whole record", "N"),
    "max_inner_fn_N": ("largest inner-raceway force, all rollers, whole record", "N"),
}


def envelope_level_at(x, fs: float, f0: float) -> float:
    r"""Amplitude of the squared envelope's component at ``f0`` (Hz).

    The squared Hilbert envelope, mean removed, projected on :math:`e^{-2 \pi i f_0 t}`:
    :math:`2 \bigl|\sum_k e_k e^{-2 \pi i f_0 k / f_s}\bigr| / n`. When the record holds a
    whole number of ``f0`` periods this is the :func:`diagnostics.envelope_spectrum` bin at
    ``f0``; otherwise it is that spectrum zero-padded and read at ``f0`` exactly (records
    shorter than :math:`1/f_0` do not resolve the line: the level then measures the envelope's
    slow fluctuation).
    """
    env = envelope(x, fs) ** 2
    env = env - env.mean()
    k = np.arange(env.size)
    return float(2.0 * abs(np.sum(env * np.exp(-2j * math.pi * f0 * k / fs))) / env.size)


def _window(t: np.ndarray, lo: float, hi: float) -> np.ndarray:
    return (t >= lo) & (t <= hi)


def _passage_forces(hist, event: dict) -> dict[str, float]:
    """Peak and envelope maximum of one passing roller's raceway forces."""
    t = hist[TIME_COLUMN].to_numpy(dtype=float)
    fs = 1.0 / float(np.median(np.diff(t)))
    j = int(event["roller"])
    entry, leave = float(event["entry_time_s"]), float(event["exit_time_s"])
    win = _window(t, entry - WINDOW_S, leave + WINDOW_S)
    before = t < entry - WINDOW_S
    out: dict[str, float] = {}
    for race in RACES:
        fn = hist[roller_force_column(j, race, "fn")].to_numpy(dtype=float)
        ref = float(np.median(fn[before])) if before.any() else float(np.median(fn))
        # envelope over the whole record (no edge effect inside the window), about the
        # force the roller carried before the spall
        env = envelope(fn - ref, fs)
        out[f"{race}_peak_N"] = float(fn[win].max()) if win.any() else math.nan
        out[f"{race}_env_max_N"] = float(env[win].max()) if win.any() else math.nan
    both = np.maximum(
        hist[roller_force_column(j, "outer", "fn")].to_numpy(dtype=float),
        hist[roller_force_column(j, "inner", "fn")].to_numpy(dtype=float),
    )
    hit = float(event.get("first_impact_time_s", leave))
    rs = _window(t, hit, hit + max(WINDOW_S, EXIT_BURST_S))
    out["restress_peak_N"] = float(both[rs].max()) if rs.any() else math.nan
    out["static_outer_N"] = float(event.get("force_before_N", math.nan))
    return out


def cell_metrics(run_dir: str | os.PathLike) -> dict[str, float]:
    """The :data:`METRICS` of one finished run folder, plus ``bpfo_hz``, ``periods``
    (record length in BPFO periods) and ``n_passages``; NaN where a run has no passage.

    Raises
    ------
    FileNotFoundError, ValueError
        When the folder is not a readable run (see
        :func:`taichi_bearing.output.run_folder.load_run`).
    """
    run = load_run(run_dir)
    hist = run.histories
    x, _ = sensor_acceleration(run)
    t = hist[TIME_COLUMN].to_numpy(dtype=float)
    m: dict[str, float] = dict.fromkeys(METRICS, math.nan)
    m["bpfo_hz"] = run.bpfo_hz
    m["periods"] = float((t[-1] - t[0] + 1.0 / run.fs) * run.bpfo_hz)
    # the last whole number of BPFO periods (no leakage; the start-up left out); a
    # record shorter than one period does not resolve BPFO: NaN
    whole = int(m["periods"])
    if whole >= 1:
        n = int(round(whole * run.fs / run.bpfo_hz))
        m["env_bpfo"] = envelope_level_at(x[-n:], run.fs, run.bpfo_hz)
    m["accel_peak"] = float(np.max(np.abs(x - np.median(x))))
    outer = [c for c in hist.columns if c.endswith("_outer_fn")]
    inner = [c for c in hist.columns if c.endswith("_inner_fn")]
    m["max_outer_fn_N"] = float(hist[outer].to_numpy().max()) if outer else math.nan
    m["max_inner_fn_N"] = float(hist[inner].to_numpy().max()) if inner else math.nan
    events = [e for e in run.events if e["roller"] is not None]
    m["n_passages"] = len(events)
    per = [_passage_forces(hist, e) for e in events]
    for key in ("outer_peak_N", "outer_env_max_N", "inner_peak_N", "inner_env_max_N",
                "restress_peak_N"):  # fmt: skip
        vals = [p[key] for p in per if math.isfinite(p[key])]
        m[key] = max(vals) if vals else math.nan
    statics = [p["static_outer_N"] for p in per if math.isfinite(p["static_outer_N"])]
    m["static_outer_N"] = float(np.mean(statics)) if statics else math.nan
    return m


def summary_rows(results: Sequence[CellResult]) -> list[dict]:
    """One row per cell: a column per varied key
    (:func:`taichi_bearing.studies.sweep.column_labels`), status, run folder, error and
    the metrics (NaN for a cell that did not finish or whose folder cannot be read)."""
    labels = column_labels(results[0].values) if results else {}
    rows = []
    for r in results:
        row: dict = {labels[k]: v for k, v in r.values.items()}
        row.update(status=r.status, run_dir=os.path.basename(r.out_dir), ran=bool(r.ran),
                   error=r.error)  # fmt: skip
        values: dict[str, float] = dict.fromkeys(
            ("bpfo_hz", "periods", "n_passages", *METRICS), math.nan
        )
        if r.status == "finished":
            try:
                values.update(cell_metrics(r.out_dir))
            except (OSError, ValueError, KeyError) as exc:
                row["error"] = f"metrics: {type(exc).__name__}: {exc}"
        row.update(values)
        rows.append(row)
    return rows
