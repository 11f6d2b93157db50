"""The run folder's layout: the name of every file a run writes, the history columns and
the summary keys. Writers take the names from here; readers load a folder with
:func:`taichi_bearing.output.run_folder.load_run`.

``python -m taichi_bearing run CASE.yaml --out DIR`` writes:

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
                          (Ctrl-C) or ``stopped`` (the solver stopped) at its end;
                          ``failed`` when a study's cell died without saying why
                          (``kill -9``, out of memory, a lost worker): the study
                          writes it, with ``stop_reason``.
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
a run that did not finish. :class:`~taichi_bearing.output.run_folder.RunData` reads the
ones readers need.

A run that did not finish (Ctrl-C, a solver stop, ``kill -9``) is still a run folder:
:func:`~taichi_bearing.output.run_folder.load_run` reads whatever histories are on disk
(merged file and/or parts) and says so
(:attr:`~taichi_bearing.output.run_folder.RunData.partial`).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

__all__ = [
    "ANIMATION_FILES",
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
    "energy_columns",
    "history_columns",
    "roller_force_column",
    "roller_force_columns",
    "roller_motion_column",
    "rolling_rates_entry",
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
# a study's cell whose process died without a word (the study that ran it says so)
STATUS_FAILED = "failed"
STATUSES = (STATUS_RUNNING, STATUS_FINISHED, STATUS_INTERRUPTED, STATUS_STOPPED, STATUS_FAILED)

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
