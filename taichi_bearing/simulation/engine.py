r"""The transient run's driver: sample by sample, advance the model (the time loop is
:func:`taichi_bearing.solver.stepping.advance`) and record averaged sensor histories,
energies, frames, checkpoints; stop safely on NaN, inverted elements or energy errors;
resume; show progress.

The output interval :math:`T_s = 1 / \mathrm{sample\_rate}` is an exact whole number
:math:`S` of steps (the step is lowered to fit). Sample :math:`k` is the mean of the sensor
values at the :math:`S` steps :math:`t_n` in :math:`((k-1) T_s, k T_s]` (a boxcar
anti-alias filter, group delay :math:`T_s / 2`), labelled with time :math:`k T_s`; the
energies are those at :math:`k T_s`. The sums are taken in a
Taichi kernel each step and read once per sample.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from taichi_bearing.errors import InputError, SimulationError
from taichi_bearing.output.checkpoint import latest_checkpoint, load_checkpoint, save_checkpoint
from taichi_bearing.output.histories import HistoryWriter
from taichi_bearing.output.layout import (
    BALANCE_COLUMN,
    CHECKPOINTS_DIR,
    ENERGY_KINDS,
    history_columns,
)
from taichi_bearing.output.progress import LOG_INTERVAL_S, RunProgress
from taichi_bearing.output.recorder import Recorder
from taichi_bearing.output.vtk import FrameWriter
from taichi_bearing.solver.model import Model

__all__ = ["Recorder", "RunConfig", "RunResult", "run_members", "run_transient", "steps_per_sample"]


def _stateful(model: Model, recorders: Sequence[Recorder]) -> dict[str, object]:
    items = {f"contributor{k}": c for k, c in enumerate(model.contributors)}
    items.update({f"recorder{k}": r for k, r in enumerate(recorders)})
    return items


def _save_states(arrays: dict, objects: dict[str, object]) -> None:
    for prefix, obj in objects.items():
        for name, a in obj.state_arrays().items():
            arrays[f"{prefix}.{name}"] = a


def _load_states(arrays, objects: dict[str, object]) -> None:
    for prefix, obj in objects.items():
        mine = {k[len(prefix) + 1 :]: arrays[k] for k in arrays if k.startswith(prefix + ".")}
        if mine:
            obj.load_state_arrays(mine)


@dataclass
class RunConfig:
    """What a transient run records and how often (times in s, rates in Hz).

    Attributes
    ----------
    duration : float
        Simulated time.
    sample_rate : float
        Output sample rate of the histories.
    frame_interval : float, optional
        Time between VTU frames (rounded to whole samples); None: no frames.
    checkpoint_interval : float, optional
        Time between checkpoints (rounded to whole samples); None: none.
    energy_tol : float
        Stop when |energy balance error| exceeds this (relative to the largest energy).
    energy_floor : float
        Energies below this (J) do not count as a scale for the balance error.
    chunk_rows : int
        History rows per flushed chunk.
    csv : bool
        Also write ``histories.csv``.
    progress : bool, optional
        True: the progress bar; False: no progress at all; None (default): the bar on a
        terminal, else a line every ``progress_interval`` s.
    progress_interval : float, optional
        Wall seconds between progress lines when the output is not a terminal (a log);
        None: no lines.
    keep_checkpoints : int
        How many checkpoints to keep.
    """

    duration: float
    sample_rate: float
    frame_interval: float | None = None
    checkpoint_interval: float | None = None
    energy_tol: float = 0.05
    energy_floor: float = 1e-12
    chunk_rows: int = 4096
    csv: bool = False
    progress: bool | None = None
    progress_interval: float | None = LOG_INTERVAL_S
    keep_checkpoints: int = 3


@dataclass
class RunResult:
    """Histories recorded by this call (a resumed run: only the rows after the resume)."""

    columns: list[str]
    rows: np.ndarray
    dt: float
    steps: int
    wall_s: float
    frames: list = field(default_factory=list)
    error: SimulationError | None = None  # why an ensemble's member stopped

    def column(self, name: str) -> np.ndarray:
        return self.rows[:, self.columns.index(name)]


def steps_per_sample(dt_stable: float, sample_rate: float, multiple: int = 1) -> tuple[int, float]:
    """Whole steps per output interval, a multiple of ``multiple`` (multi-rate stepping's
    cycle, :attr:`Model.cycle_steps`), and the step that fits it exactly."""
    if not sample_rate > 0:
        raise InputError(f"run.sample_rate: must be positive, got {sample_rate!r}")
    interval = 1.0 / sample_rate
    s = max(1, math.ceil(interval / dt_stable / multiple * (1 - 1e-12))) * multiple
    return s, interval / s


def _every(interval: float | None, sample_rate: float) -> int | None:
    """An interval in whole samples (at least one), or None."""
    if interval is None:
        return None
    return max(1, round(interval * sample_rate))


def _diagnose(model: Model, step: int, t: float, what: str, cause: str) -> SimulationError:
    """A SimulationError naming the step, time, worst node and element."""
    x = model.positions()
    v = model.velocities()
    bad_nodes = np.flatnonzero(~np.all(np.isfinite(x) & np.isfinite(v), axis=1))
    if bad_nodes.size:
        node_txt = f"node {int(bad_nodes[0])} is not finite"
    else:
        k = int(np.argmax(np.linalg.norm(v, axis=1)))
        node_txt = f"fastest node {k} ({np.linalg.norm(v[k]):.3g} m/s)"
    bad = model.bad_element_index()
    if bad is not None:
        elem_txt = f"element {bad} inverted (det F <= 0)"
    else:
        dens = model.e_int.to_numpy()[: model.n_elements] / (model.area_np * model.thickness)
        dens = np.where(np.isfinite(dens), dens, np.inf)
        k = int(np.argmax(dens))
        elem_txt = f"element {k} has the largest strain energy density ({dens[k]:.3g} J/m^3)"
    return SimulationError(
        f"step {step}, t = {t * 1e3:.6g} ms: {what}; {node_txt}; {elem_txt}; likely cause: {cause}"
    )


def run_transient(
    model: Model,
    config: RunConfig,
    out_dir: str | os.PathLike | None = None,
    resume: bool = False,
    fingerprint: str = "",
    recorders: Sequence[Recorder] = (),
) -> RunResult:
    """Run the model from its current state for ``config.duration`` s.

    Parameters
    ----------
    model : Model
        Fresh (time 0, e.g. after :func:`~taichi_bearing.solver.relaxation.relax` and
        :meth:`Model.set_initial_velocities`); on resume its state is replaced by the
        checkpoint's.
    config : RunConfig
    out_dir : path-like, optional
        Run folder: ``histories.parquet`` (chunked as it goes), ``frames/``,
        ``checkpoints/``. None: nothing is written (histories only in the result).
    resume : bool
        Continue from the last checkpoint in ``out_dir/checkpoints``.
    fingerprint : str
        Hash of the case and mesh (:func:`taichi_bearing.output.checkpoint.fingerprint`);
        a checkpoint with another one is refused on resume.
    recorders : sequence of Recorder
        Extra columns, placed after the sensor columns. Their state, and the state of the
        model's contributors (their ``state_arrays``), goes into every checkpoint.

    Returns
    -------
    RunResult

    Raises
    ------
    SimulationError
        NaN/inf, energy balance error beyond ``config.energy_tol`` or an inverted element;
        the message names step, time, node and element. Histories and frames recorded
        until then stay on disk (histories up to the last full sample).
    """
    if model.ensemble_size != 1:
        raise ValueError("run_transient steps one model; an ensemble's is run_members")
    (result,) = run_members(model, config, [out_dir], [recorders], resume, fingerprint)
    if result.error is not None:
        raise result.error
    return result


@dataclass
class _Member:
    """One member's share of a transient: its sensors, recorders, folder and balance."""

    k: int
    sensors: slice
    recorders: Sequence[Recorder]
    out: Path | None
    writer: HistoryWriter | None = None
    rows: list = field(default_factory=list)
    e0: float = 0.0
    error: SimulationError | None = None
    view: object = None  # an ensemble member's MemberModel
    held: bool = False  # not run (it stopped before the transient)

    @property
    def live(self) -> bool:
        return self.error is None and not self.held


def run_members(
    model: Model,
    config: RunConfig,
    out_dirs: Sequence[str | os.PathLike | None],
    recorders: Sequence[Sequence[Recorder]],
    resume: bool = False,
    fingerprint: str = "",
    sample=None,
    active: Sequence[bool] | None = None,
) -> list[RunResult]:
    """:func:`run_transient` of every member of an ensemble (one model: one member).

    Each member writes its own folder (``out_dirs[k]``) with its own recorders and energy
    balance: the rows its case run alone writes. A member that stops (NaN, an inverted
    element, the balance) is held still and its error kept in its result
    (``RunResult.error``); the others go on. Frames and checkpoints (and ``resume``) are
    for one model only. ``sample`` (an
    :class:`~taichi_bearing.simulation.members.EnsembleSample`) is refreshed before the
    members' recorders read each sample.
    """
    if not config.duration > 0:
        raise InputError(f"run.duration: must be positive, got {config.duration!r}")
    nm = model.ensemble_size
    if len(out_dirs) != nm or len(recorders) != nm:
        raise ValueError(f"run_members: one folder and one recorder list per member ({nm})")
    single = nm == 1
    out = Path(out_dirs[0]) if single and out_dirs[0] is not None else None
    ckpt_dir = out / CHECKPOINTS_DIR if out is not None else None
    s_steps, dt = steps_per_sample(model.dt_stable, config.sample_rate, model.cycle_steps)
    n_samples = max(1, round(config.duration * config.sample_rate))
    frame_every = _every(config.frame_interval, config.sample_rate) if out else None
    ckpt_every = _every(config.checkpoint_interval, config.sample_rate) if out else None
    ns = model.n_sensor // nm
    names = model.sensor_names[:ns]
    if "member_info" in model.mesh.info:  # a stacked mesh: a member's own sensor names
        names = [n.split(":", 1)[-1] for n in names]
    base = history_columns(names, 0, ENERGY_KINDS)
    n_head = 1 + 6 * ns
    extra = [c for r in recorders[0] for c in r.columns]
    columns = base[:n_head] + extra + base[n_head:] + [BALANCE_COLUMN]
    members = [
        _Member(
            k,
            slice(k * ns, (k + 1) * ns),
            recorders[k],
            Path(out_dirs[k]) if out_dirs[k] is not None else None,
        )  # fmt: skip
        for k in range(nm)
    ]
    if not single:
        from taichi_bearing.simulation.members import MemberModel

        for m, on in zip(members, active if active is not None else [True] * nm, strict=True):
            m.view = MemberModel(sample, m.k)
            m.held = not on
            m.out = m.out if on else None
        model.set_members_active([m.live for m in members])
    stateful = _stateful(model, recorders[0]) if single else {}

    def refresh() -> None:
        if sample is not None:
            sample.refresh()

    k0 = 0
    resume_time = None
    if resume:
        if not single:
            raise InputError("--resume: an ensemble is not resumed; run it again")
        if ckpt_dir is None:
            raise InputError("--resume needs an output folder")
        path = latest_checkpoint(ckpt_dir)
        if path is None:
            raise InputError(f"--resume: no checkpoint in {ckpt_dir}")
        _, resume_time, arrays, meta = load_checkpoint(path, fingerprint or None)
        model.load_state_arrays(arrays)
        _load_states(arrays, stateful)
        members[0].e0 = float(arrays["initial_energy"])
        k0 = int(meta["sample"])
        if int(meta["steps_per_sample"]) != s_steps:
            raise InputError(f"{path}: checkpoint was written with another sample rate")
    else:
        model.set_dt(dt)
        model.restart_accounting()
        model.reset_bad_elements()
        model.advance(1, record_last=True)  # t = 0 -> dt (a half step for v)
        model.take_sensor_means(1)  # t = 0 belongs to no output interval
        refresh()
        for m in members:
            for r in m.recorders if not m.held else ():
                r.sample(_view(model, m))  # likewise for the recorders' sums
        for m, en in zip(members, model.member_energies(), strict=True):
            m.e0 = en["kinetic"] + en["internal"] + en["hourglass"]

    for m in members:
        if m.out is not None:
            m.writer = HistoryWriter(m.out, columns, config.chunk_rows, config.csv, resume_time)
    frames = FrameWriter(out, model.mesh, resume_time) if frame_every else None
    wall0 = time.perf_counter()
    step = lambda: model.step_count - 1  # noqa: E731 - index of the last step taken
    try:
        with RunProgress(
            n_samples / config.sample_rate,
            "transient",
            enabled=config.progress,
            log_every_s=config.progress_interval,
            start_time=k0 * s_steps * dt,
            start_step=k0 * s_steps,
        ) as bar:
            for k in range(k0 + 1, n_samples + 1):
                model.advance(s_steps, record_last=True)
                t = step() * model.dt
                means = model.take_sensor_means(s_steps)
                refresh()
                energies = model.member_energies()
                contact = _contact_energies(model)
                live = [m for m in members if m.live]
                for m in live:
                    _member_sample(model, m, config, t, means, energies, contact, step)
                if single and members[0].error is not None:
                    break
                if not single and any(m.error is not None for m in live):
                    model.set_members_active([m.live for m in members])
                    if not any(m.live for m in members):
                        break
                if frames is not None and k % frame_every == 0:
                    frames.write(
                        t, model.displacements(), model.velocities(), model.von_mises_stress()
                    )
                if ckpt_every is not None and k % ckpt_every == 0 and k < n_samples:
                    members[0].writer.flush()
                    arrays = model.state_arrays()
                    arrays["initial_energy"] = np.float64(members[0].e0)
                    _save_states(arrays, stateful)
                    save_checkpoint(
                        ckpt_dir,
                        model.step_count,
                        t,
                        arrays,
                        {"fingerprint": fingerprint, "sample": k, "steps_per_sample": s_steps},
                        keep=config.keep_checkpoints,
                    )
                bar.update(model.step_count, t)
    finally:
        for m in members:
            if m.writer is not None:
                m.writer.close()
        if not single:
            model.set_members_active([True] * nm)
    wall = time.perf_counter() - wall0
    return [
        RunResult(
            columns,
            np.array(m.rows).reshape(-1, len(columns)),
            model.dt,
            model.step_count,
            wall,
            frames.frames if frames is not None else [],
            m.error,
        )
        for m in members
    ]


def _view(model: Model, m: _Member):
    """What member ``m``'s recorders read: the model itself, or the member's view."""
    return model if m.view is None else m.view


def _contact_energies(model: Model) -> list[float]:
    """Each member's sum of the contributors' ``energy()`` (stored penalty energy, the
    cage's motion). Informational: the work of contributor forces is already in
    ``external_work`` (it is part of the non-elastic nodal force), so it is not added to
    the balance again."""
    per = [c.member_energies() for c in model.contributors]
    return [float(sum(e[k] for e in per)) for k in range(model.ensemble_size)]


def _member_sample(model, m: _Member, config: RunConfig, t: float, means, energies,
                   contact, step) -> None:  # fmt: skip
    """Member ``m``'s row of this sample, written; an error kept in ``m.error``."""
    extra_values = [np.asarray(r.sample(_view(model, m)), dtype=float) for r in m.recorders]
    en = dict(energies[m.k])
    en["contact"] = contact[m.k]
    mech = en["kinetic"] + en["internal"] + en["hourglass"]
    resid = mech + en["damping"] - en["external_work"] - m.e0
    scale = max(mech, abs(en["external_work"]), m.e0, en["damping"])
    balance = resid / scale if scale > config.energy_floor else 0.0
    row = np.concatenate(
        [
            [t],
            means[m.sensors].ravel(),
            *extra_values,
            [en[kind] if kind in en else 0.0 for kind in ENERGY_KINDS],
            [balance],
        ]
    )
    if not np.all(np.isfinite(row)):
        m.error = _diagnose(
            model,
            step(),
            t,
            "a value is NaN or infinite",
            "unstable step (dt too large for a stiffness) or a load too large",
        )
        return
    if model.bad_element_index(m.k) is not None:
        m.error = _diagnose(
            model,
            step(),
            t,
            "an element turned inside out",
            "large deformation (load too large, penalty too stiff, mesh too coarse)",
        )
        return
    m.rows.append(row)
    if m.writer is not None:
        m.writer.append(row)
    if abs(balance) > config.energy_tol:
        m.error = _diagnose(
            model,
            step(),
            t,
            f"energy balance error {balance:.3g} exceeds {config.energy_tol:g}",
            "instability (time step, penalty stiffness) or a constraint adding energy",
        )
