"""The run folder: the name of every file a run writes, the history columns, the summary
keys, and the one loader every reader uses (:func:`load_run`).

``python -m taichi_bearing run CASE.yaml --out DIR`` writes (design.md section 7):

========================  ==================================================================
name (constant)           content
========================  ==================================================================
``case.yaml``             :data:`CASE_FILE`: the case as run, every key resolved.
``mesh_statistics.json``  :data:`MESH_STATISTICS_FILE`: sizes, quality, critical step.
``mesh_info.json``        :data:`MESH_INFO_FILE`: the mesh's ``info``: polygon edge counts of
                          the rolling surfaces, spall geometry and corner nodes, roller
                          centres, cage (what the checks need from the mesh).
``preload.json``          :data:`PRELOAD_FILE`: end of the preload: steps, KE ratio, each
                          roller's force on both raceways, plate drop, wall time; the
                          flexible-ring reference forces (:data:`REFERENCE_KEY`, solved
                          on the run's mesh right after the preload) and the ideal rolling
                          rates the transient starts from (:data:`ROLLING_RATES_KEY`).
``summary.json``          :data:`SUMMARY_FILE`: written with status ``running`` before the
                          transient, ``finished`` (checks included), ``interrupted``
                          (Ctrl-C) or ``stopped`` (the solver stopped) at its end.
``histories.parquet``     :data:`HISTORIES_FILE`: one row per sample, columns below.
``histories.parts/``      :data:`HISTORIES_PARTS_DIR`: the rows in chunks while the run goes
                          on; what is left of a run killed hard (``kill -9``).
``histories.csv``         :data:`HISTORIES_CSV_FILE`, with ``output.csv: true``.
``frames/frames.pvd``     :data:`FRAMES_DIR`, :data:`PVD_FILE`: VTU frames and their series.
``checkpoints/``          :data:`CHECKPOINTS_DIR`: restart files (``--resume``).
``figures/``              :data:`FIGURES_DIR`: PNG figures and :data:`FIGURES_INDEX_FILE`
                          (their captions and numbers, for the report).
``report.md``, ``.html``  :data:`REPORT_MD_FILE`, :data:`REPORT_HTML_FILE`.
``compare/``              :data:`COMPARE_DIR`: ``python -m taichi_bearing compare`` output.
``animation.gif``         :data:`ANIMATION_FILES`: ``python -m taichi_bearing animate`` (or
                          ``.mp4``).
========================  ==================================================================

History columns (SI units): ``time_s``; per sensor ``<sensor>_ux|uy|vx|vy|ax|ay``; per
roller ``roller<j>_<race>_fx|fy|fn|ft`` (race ``outer`` or ``inner``, ``j`` from 0) and
``roller<j>_angle_rad|spin_rad_s|radius_m``; ``cage_angle_rad``, ``cage_speed_rad_s``;
``energy_<kind>`` and ``energy_balance_error``.

Summary keys: :data:`REQUIRED_SUMMARY_KEYS` in every finished run; besides them
``case_name``, ``status`` (:data:`STATUSES`), ``stop_reason``, ``sensor_names``,
``analysed_signal``, ``n_rollers``, ``shaft_hz``, ``ftf_hz``, ``events`` (one entry per
spall passage: ``roller``, ``entry_time_s``, ``exit_time_s``, ...), ``checks`` (each
``{value, limit, passed, note}``), ``missing_keys``, and ``partial`` when ``post`` checked
a run that did not finish. :class:`RunData` reads the ones readers need.

A run that did not finish (Ctrl-C, a solver stop, ``kill -9``) is still a run folder:
:func:`load_run` reads whatever histories are on disk (merged file and/or parts) and says
so (:attr:`RunData.partial`).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd
import yaml

__all__ = [
    "ANIMATION_FILES",
    "AccelerationSignal",
    "BALANCE_COLUMN",
    "CAGE_COLUMNS",
    "CASE_FILE",
    "CHECKPOINTS_DIR",
    "COMPARE_DIR",
    "ENERGY_KINDS",
    "FIGURES_DIR",
    "FIGURES_INDEX_FILE",
    "FRAMES_DIR",
    "HISTORIES_CSV_FILE",
    "HISTORIES_FILE",
    "HISTORIES_PARTS_DIR",
    "MESH_INFO_FILE",
    "MESH_STATISTICS_FILE",
    "PRELOAD_FILE",
    "PVD_FILE",
    "RACES",
    "REFERENCE_KEY",
    "REPORT_HTML_FILE",
    "REPORT_MD_FILE",
    "REQUIRED_SUMMARY_KEYS",
    "ROLLER_FORCE_COMPONENTS",
    "ROLLER_MOTION_QUANTITIES",
    "ROLLING_RATES_KEY",
    "SENSOR_QUANTITIES",
    "STATUSES",
    "SUMMARY_FILE",
    "TIME_COLUMN",
    "RunData",
    "acceleration_signal",
    "energy_columns",
    "history_columns",
    "load_run",
    "missing_for_checks",
    "passage_events",
    "read_json",
    "read_case_dict",
    "read_summary",
    "roller_force_column",
    "roller_force_columns",
    "roller_motion_column",
    "rolling_rates_entry",
    "sensor_acceleration",
    "sensor_column",
    "sensor_columns",
]

# --------------------------------------------------------------------------- files

CASE_FILE = "case.yaml"
MESH_STATISTICS_FILE = "mesh_statistics.json"
MESH_INFO_FILE = "mesh_info.json"
PRELOAD_FILE = "preload.json"
SUMMARY_FILE = "summary.json"
HISTORIES_FILE = "histories.parquet"
HISTORIES_PARTS_DIR = "histories.parts"
HISTORIES_CSV_FILE = "histories.csv"
FRAMES_DIR = "frames"
PVD_FILE = "frames.pvd"
CHECKPOINTS_DIR = "checkpoints"
FIGURES_DIR = "figures"
FIGURES_INDEX_FILE = "figures.json"
REPORT_MD_FILE = "report.md"
REPORT_HTML_FILE = "report.html"
COMPARE_DIR = "compare"
ANIMATION_FILES = {"gif": "animation.gif", "mp4": "animation.mp4"}  # by format

# preload.json entries written after the preload for the checks
REFERENCE_KEY = "reference_roller_forces_N"
ROLLING_RATES_KEY = "rolling_rates_rad_s"

# --------------------------------------------------------------------------- summary

STATUS_RUNNING = "running"
STATUS_FINISHED = "finished"
STATUS_INTERRUPTED = "interrupted"
STATUS_STOPPED = "stopped"
STATUSES = (STATUS_RUNNING, STATUS_FINISHED, STATUS_INTERRUPTED, STATUS_STOPPED)

REQUIRED_SUMMARY_KEYS = (
    "n_elements",
    "n_nodes",
    "dt_s",
    "n_steps",
    "wall_time_s",
    "element_steps_per_s",
    "energy_balance_error",
    "static_roller_forces_N",
    "analytical_roller_forces_N",
    "cage_speed_rel_error",
    "bpfo_hz",
    "restress_times_s",
    "entry_times_s",
    "noise_frequencies_predicted_hz",
    "noise_frequencies_measured_hz",
    "defect_size_estimate_m",
    "defect_size_true_m",
)

# --------------------------------------------------------------------------- columns

TIME_COLUMN = "time_s"
SENSOR_QUANTITIES = ("ux", "uy", "vx", "vy", "ax", "ay")
RACES = ("outer", "inner")
ROLLER_FORCE_COMPONENTS = ("fx", "fy", "fn", "ft")
ROLLER_MOTION_QUANTITIES = ("angle_rad", "spin_rad_s", "radius_m")
CAGE_COLUMNS = ("cage_angle_rad", "cage_speed_rad_s")
ENERGY_KINDS = ("kinetic", "internal", "hourglass", "contact", "damping", "external_work")
BALANCE_COLUMN = "energy_balance_error"


def sensor_column(sensor: str, quantity: str) -> str:
    """``<sensor>_<quantity>``, quantity one of :data:`SENSOR_QUANTITIES`."""
    return f"{sensor}_{quantity}"


def roller_force_column(j: int, race: str, component: str) -> str:
    """``roller<j>_<race>_<component>``: race ``outer``/``inner``, component ``fx, fy, fn, ft``."""
    return f"roller{j}_{race}_{component}"


def roller_motion_column(j: int, quantity: str) -> str:
    """``roller<j>_<quantity>``, quantity one of :data:`ROLLER_MOTION_QUANTITIES`."""
    return f"roller{j}_{quantity}"


def sensor_columns(names: Iterable[str]) -> list[str]:
    """Columns of the sensor records: ``<sensor>_ux, _uy, _vx, _vy, _ax, _ay`` per sensor.

    Parameters
    ----------
    names : iterable of str
        Sensor names, in the order their values are appended.

    Returns
    -------
    list of str
    """
    return [sensor_column(name, q) for name in names for q in SENSOR_QUANTITIES]


def roller_force_columns(n_rollers: int, races: Sequence[str] = RACES) -> list[str]:
    """Columns of the per-roller contact forces: ``roller<j>_<race>_fx|fy|fn|ft``.

    Ordered roller by roller (j from 0), then race (``outer``, ``inner``), then component
    (``fx, fy, fn, ft``).
    """
    if int(n_rollers) != n_rollers or n_rollers < 0:
        raise ValueError(f"n_rollers must be a non-negative integer, got {n_rollers!r}")
    return [
        roller_force_column(j, race, c)
        for j in range(int(n_rollers))
        for race in races
        for c in ROLLER_FORCE_COMPONENTS
    ]


def energy_columns(kinds: Iterable[str] = ENERGY_KINDS) -> list[str]:
    """Columns of the energies: ``energy_<kind>`` (default kinds: :data:`ENERGY_KINDS`)."""
    return [f"energy_{k}" for k in kinds]


def history_columns(
    sensor_names: Iterable[str] = (),
    n_rollers: int = 0,
    energy_kinds: Iterable[str] = ENERGY_KINDS,
) -> list[str]:
    """All columns of a run in the standard order: time, sensors, roller forces, energies."""
    return [
        TIME_COLUMN,
        *sensor_columns(sensor_names),
        *roller_force_columns(n_rollers),
        *energy_columns(energy_kinds),
    ]


def rolling_rates_entry(rates) -> dict[str, float]:
    """The :data:`ROLLING_RATES_KEY` entry of ``preload.json`` from the set-up's rolling
    rates (attributes ``shaft``, ``cage``, ``roller``, ``roller_relative``, rad/s)."""
    return {
        "shaft": float(rates.shaft),
        "cage": float(rates.cage),
        "roller": float(rates.roller),
        "roller_relative": float(rates.roller_relative),
    }


# --------------------------------------------------------------------------- reading


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
    """What a run folder holds, as plain data.

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
        Sampling rate of the histories, Hz: ``(rows - 1) / (last time - first time)``.
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
    from taichi_bearing.output.histories import read_histories

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
