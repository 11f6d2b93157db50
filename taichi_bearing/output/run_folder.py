"""Reading a run folder: the one loader every reader uses (:func:`load_run`), the JSON and
case files, and the signals the checks and figures take from the histories. What each
file holds is :mod:`taichi_bearing.output.layout`; a run that did not finish is read as
far as it got."""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd
import yaml

from taichi_bearing.output.histories import read_histories
from taichi_bearing.output.layout import (
    CASE_FILE,
    HISTORIES_FILE,
    HISTORIES_PARTS_DIR,
    MESH_INFO_FILE,
    PRELOAD_FILE,
    REFERENCE_KEY,
    ROLLING_RATES_KEY,
    STATUS_FINISHED,
    SUMMARY_FILE,
    TIME_COLUMN,
    sensor_column,
)

__all__ = [
    "AccelerationSignal",
    "RunData",
    "acceleration_signal",
    "load_run",
    "missing_for_checks",
    "passage_events",
    "read_json",
    "read_case_dict",
    "read_summary",
    "sensor_acceleration",
]


def read_json(path: str | os.PathLike) -> dict:
    """A JSON object from a run folder.

    Raises
    ------
    FileNotFoundError
        If the file is missing.
    ValueError
        If it is not valid JSON or not an object.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: no such file") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: not valid JSON ({exc})") from None
    if not isinstance(data, dict):
        raise ValueError(f"{path}: expected a JSON object")
    return data


def _read_optional_json(path: Path) -> dict | None:
    return read_json(path) if path.is_file() else None


def read_summary(run_dir: str | os.PathLike) -> dict | None:
    """``summary.json`` of a run folder, None when there is none."""
    return _read_optional_json(Path(run_dir) / SUMMARY_FILE)


def read_case_dict(run_dir: str | os.PathLike) -> dict:
    """``case.yaml`` of a run folder as plain YAML data (empty when absent)."""
    path = Path(run_dir) / CASE_FILE
    if not path.is_file():
        return {}
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, yaml.YAMLError) as exc:
        raise ValueError(f"{path}: not readable YAML ({exc})") from None
    return data if isinstance(data, dict) else {}


@dataclass
class RunData:
    r"""What a run folder holds, as plain data.

    Attributes
    ----------
    run_dir : Path
    summary : dict
        ``summary.json`` (empty when the run was killed before writing one).
    case : dict
        ``case.yaml`` as written by the run (empty when absent).
    histories : pandas.DataFrame
        The histories on disk: the merged file and/or the chunk parts.
    fs : float
        Sampling rate of the histories, Hz:
        :math:`(\mathrm{rows} - 1) / (\mathrm{last\ time} - \mathrm{first\ time})`.
    t0 : float
        Time of the first history row, s.
    mesh_info : dict or None
        ``mesh_info.json``.
    preload : dict or None
        ``preload.json``.
    merged : bool
        Whether ``histories.parquet`` exists (False: only parts of a run killed hard).
    notes : list of str
        What the reader noticed (an irregular time step).
    """

    run_dir: Path
    summary: dict
    case: dict
    histories: pd.DataFrame
    fs: float
    t0: float
    mesh_info: dict | None = None
    preload: dict | None = None
    merged: bool = True
    notes: list[str] = field(default_factory=list)

    @property
    def status(self) -> str | None:
        """``summary["status"]``; None without a summary."""
        return self.summary.get("status")

    @property
    def partial(self) -> bool:
        """The run did not finish: its status is not ``finished`` (or it has no summary)."""
        return self.status != STATUS_FINISHED

    @property
    def t_end(self) -> float:
        """Time of the last history row, s."""
        return float(self.histories[TIME_COLUMN].iloc[-1])

    @property
    def case_name(self) -> str:
        return str(self.summary.get("case_name") or self.case.get("name") or self.run_dir.name)

    @property
    def bpfo_hz(self) -> float:
        return float(self.summary["bpfo_hz"])

    @property
    def shaft_hz(self) -> float:
        return float(self.summary["shaft_hz"])

    @property
    def sensor_names(self) -> list[str]:
        names = self.summary.get("sensor_names")
        if names:
            return list(names)
        suffix = "_ay"
        return [c[: -len(suffix)] for c in self.histories.columns if c.endswith(suffix)]

    @property
    def rollers(self) -> int:
        n = self.summary.get("n_rollers")
        if n is not None:
            return int(n)
        return sum(1 for c in self.histories.columns if c.endswith("_outer_fn"))

    @property
    def events(self) -> list[dict]:
        """The spall passages of the summary (:func:`passage_events`)."""
        return passage_events(self.summary)


def load_run(run_dir: str | os.PathLike) -> RunData:
    """Read a run folder, finished or not.

    Parameters
    ----------
    run_dir : str or path-like

    Returns
    -------
    RunData

    Raises
    ------
    FileNotFoundError
        If the folder holds neither ``summary.json`` nor ``case.yaml`` (not a run folder),
        or no histories (neither ``histories.parquet`` nor parts).
    ValueError
        If a file cannot be read, or the histories hold fewer than 2 rows.
    """
    run_dir = Path(run_dir)
    if not run_dir.is_dir():
        raise FileNotFoundError(f"{run_dir}: not a folder")
    summary = read_summary(run_dir)
    if summary is None and not (run_dir / CASE_FILE).is_file():
        raise FileNotFoundError(
            f"{run_dir}: not a run folder (neither {SUMMARY_FILE} nor {CASE_FILE})"
        )
    case = read_case_dict(run_dir)
    try:
        hist = read_histories(run_dir)
    except FileNotFoundError:
        raise FileNotFoundError(
            f"{run_dir}: no histories recorded (no {HISTORIES_FILE}, no {HISTORIES_PARTS_DIR}/)"
        ) from None
    t = hist[TIME_COLUMN].to_numpy(dtype=float)
    if t.size < 2:
        raise ValueError(f"{run_dir}: histories hold {t.size} rows; need at least 2")
    fs = (t.size - 1) / (t[-1] - t[0])
    notes = []
    if np.max(np.abs(np.diff(t) * fs - 1.0)) > 0.01:
        notes.append("history time step varies by more than 1 %; spectra assume the mean step")
    return RunData(
        run_dir,
        summary or {},
        case,
        hist,
        float(fs),
        float(t[0]),
        _read_optional_json(run_dir / MESH_INFO_FILE),
        _read_optional_json(run_dir / PRELOAD_FILE),
        (run_dir / HISTORIES_FILE).is_file(),
        notes,
    )


def missing_for_checks(run: RunData) -> list[str]:
    """What the checks need and the folder lacks (empty: the checks can run).

    Run folders made before the checks became pure post-processing lack ``mesh_info.json``
    and the ``preload.json`` entries written after the preload.
    """
    missing = [name for name in (CASE_FILE,) if not (run.run_dir / name).is_file()]
    if run.mesh_info is None:
        missing.append(MESH_INFO_FILE)
    if run.preload is None:
        missing.append(PRELOAD_FILE)
    else:
        missing += [
            f"{PRELOAD_FILE}:{key}"
            for key in (REFERENCE_KEY, ROLLING_RATES_KEY)
            if key not in run.preload
        ]
    return missing


class AccelerationSignal(NamedTuple):
    """A sensor acceleration of a run (m/s^2): the values, what they are, and the history
    column they are (None for a combination of columns, e.g. radial)."""

    x: np.ndarray
    label: str
    column: str | None


def acceleration_signal(run: RunData, sensor: str | None = None) -> AccelerationSignal:
    """Acceleration of a sensor, m/s^2.

    Without ``sensor``: the column the run analysed (``summary["analysed_signal"]``) when
    given. A history column name (e.g. ``adapter_top_ax``) is taken as it is. A sensor
    name: its radial acceleration, radial being the direction of its position in
    ``case.yaml`` (outward from the bearing centre); without a position, its vertical
    component ``ay``.

    Raises
    ------
    ValueError
        If the histories hold no sensor, or not the one asked for.
    """
    names = run.sensor_names
    if not names:
        raise ValueError(f"{run.run_dir}: no sensor acceleration columns in the histories")
    column = run.summary.get("analysed_signal") if sensor is None else sensor
    if column in run.histories and column != TIME_COLUMN:
        # The signal the run's own checks analysed (e.g. "adapter_top_ay"), or a column.
        return AccelerationSignal(
            run.histories[column].to_numpy(dtype=float), f"{column} (m/s^2)", column
        )
    sensor = sensor or names[0]
    ay_col = sensor_column(sensor, "ay")
    if ay_col not in run.histories:
        raise ValueError(f"{run.run_dir}: no sensor {sensor!r}; sensors: {', '.join(names)}")
    ax = run.histories[sensor_column(sensor, "ax")].to_numpy(dtype=float)
    ay = run.histories[ay_col].to_numpy(dtype=float)
    pos = (run.case.get("sensors") or {}).get(sensor) or {}
    x, y = pos.get("x_mm"), pos.get("y_mm")
    if x is not None and y is not None and math.hypot(x, y) > 0:
        r = math.hypot(x, y)
        return AccelerationSignal((x * ax + y * ay) / r, f"{sensor} radial acceleration", None)
    return AccelerationSignal(ay, f"{sensor} vertical acceleration (ay)", ay_col)


def sensor_acceleration(run: RunData, sensor: str | None = None) -> tuple[np.ndarray, str]:
    """Acceleration of a sensor (m/s^2) and a label saying which
    (:func:`acceleration_signal`)."""
    signal = acceleration_signal(run, sensor)
    return signal.x, signal.label


def passage_events(summary: Mapping) -> list[dict]:
    """Spall passages ``{roller, entry_time_s, exit_time_s}`` (with the run's other event
    entries, e.g. ``first_impact_time_s``, ``exit_impulses``), from ``events`` or, failing
    that, from ``entry_times_s`` / ``restress_times_s`` paired in order (roller unknown).
    Missing times are NaN."""
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
