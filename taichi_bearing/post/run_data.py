"""What the post-processing reads from a run folder (see notes/rundir.md), as plain data.

One loader for the figures and the report, so both see the same signal, the same events
and the same sampling rate.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from taichi_bearing.output.histories import read_histories

__all__ = ["RunData", "load_run", "passage_events", "sensor_acceleration"]


@dataclass
class RunData:
    """A run folder's summary, case (raw YAML) and histories.

    Attributes
    ----------
    run_dir : Path
    summary : dict
        ``summary.json``.
    case : dict
        ``case.yaml`` as written by the run (empty when absent).
    histories : pandas.DataFrame
        ``histories.parquet`` (finished or partial).
    fs : float
        Sampling rate of the histories, Hz (from the mean time step).
    t0 : float
        Time of the first history row, s.
    """

    run_dir: Path
    summary: dict
    case: dict
    histories: pd.DataFrame
    fs: float
    t0: float
    notes: list[str] = field(default_factory=list)

    @property
    def bpfo_hz(self) -> float:
        return float(self.summary["bpfo_hz"])

    @property
    def sensor_names(self) -> list[str]:
        names = self.summary.get("sensor_names")
        if names:
            return list(names)
        cols = [c[: -len("_ay")] for c in self.histories.columns if c.endswith("_ay")]
        return cols

    @property
    def rollers(self) -> int:
        n = self.summary.get("n_rollers")
        if n is not None:
            return int(n)
        return sum(1 for c in self.histories.columns if c.endswith("_outer_fn"))


def load_run(run_dir: str | os.PathLike) -> RunData:
    """Read a run folder.

    Raises
    ------
    FileNotFoundError
        If ``summary.json`` or the histories are missing.
    ValueError
        If the histories hold fewer than 2 rows or an irregular time step.
    """
    run_dir = Path(run_dir)
    summary_path = run_dir / "summary.json"
    if not summary_path.is_file():
        raise FileNotFoundError(f"{run_dir}: no summary.json (is this a run folder?)")
    summary = json.loads(summary_path.read_text())
    case_path = run_dir / "case.yaml"
    case = yaml.safe_load(case_path.read_text()) if case_path.is_file() else {}
    hist = read_histories(run_dir)
    t = hist["time_s"].to_numpy(dtype=float)
    if t.size < 2:
        raise ValueError(f"{run_dir}: histories hold {t.size} rows; need at least 2")
    step = np.diff(t)
    mean_step = (t[-1] - t[0]) / (t.size - 1)
    notes = []
    if np.max(np.abs(step - mean_step)) > 0.01 * mean_step:
        notes.append("history time step varies by more than 1 %; spectra assume the mean step")
    return RunData(run_dir, summary, case or {}, hist, 1.0 / mean_step, float(t[0]), notes)


def sensor_acceleration(run: RunData, sensor: str | None = None) -> tuple[np.ndarray, str]:
    """Acceleration of a sensor (m/s^2) and a label saying which.

    Without ``sensor``: the column the run analysed (``summary["analysed_signal"]``) when
    given. Otherwise the radial acceleration of the sensor, radial being the direction of
    its position in ``case.yaml`` (outward from the bearing centre); without a position the
    vertical component ``ay`` is used.
    """
    names = run.sensor_names
    if not names:
        raise ValueError(f"{run.run_dir}: no sensor acceleration columns in the histories")
    analysed = run.summary.get("analysed_signal")
    if sensor is None and analysed in run.histories:
        # The signal the run's own checks analysed (e.g. "adapter_top_ay").
        return run.histories[analysed].to_numpy(dtype=float), f"{analysed} (m/s^2)"
    sensor = sensor or names[0]
    if f"{sensor}_ay" not in run.histories:
        raise ValueError(f"{run.run_dir}: no sensor {sensor!r}; sensors: {', '.join(names)}")
    ax = run.histories[f"{sensor}_ax"].to_numpy(dtype=float)
    ay = run.histories[f"{sensor}_ay"].to_numpy(dtype=float)
    pos = (run.case.get("sensors") or {}).get(sensor) or {}
    x, y = pos.get("x_mm"), pos.get("y_mm")
    if x is not None and y is not None and math.hypot(x, y) > 0:
        r = math.hypot(x, y)
        return (x * ax + y * ay) / r, f"{sensor} radial acceleration"
    return ay, f"{sensor} vertical acceleration (ay)"


def passage_events(summary: dict) -> list[dict]:
    """Spall passages ``{roller, entry_time_s, exit_time_s}`` (with the run's other event
    entries, e.g. ``first_impact_time_s``, ``exit_impulses``), from ``events`` or, failing
    that, from ``entry_times_s`` / ``restress_times_s`` paired in order (roller unknown)."""
    events = summary.get("events")
    if events:
        return [
            {
                **e,
                "roller": e.get("roller"),
                "entry_time_s": _num(e.get("entry_time_s")),
                "exit_time_s": _num(e.get("exit_time_s")),
            }
            for e in events
        ]
    entries = [_num(v) for v in summary.get("entry_times_s") or []]
    exits = [_num(v) for v in summary.get("restress_times_s") or []]
    n = max(len(entries), len(exits))
    entries += [math.nan] * (n - len(entries))
    exits += [math.nan] * (n - len(exits))
    return [
        {"roller": None, "entry_time_s": a, "exit_time_s": b}
        for a, b in zip(entries, exits, strict=True)
    ]


def _num(value) -> float:
    return math.nan if value is None else float(value)
