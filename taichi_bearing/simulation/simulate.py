"""The bearing simulated: mesh -> preload -> spin -> transient, written to its run folder.

:func:`simulate` takes each stage's plain data to the next: the case, the mesh
(:mod:`taichi_bearing.mesh`), the set-up (:mod:`taichi_bearing.simulation.starter`), the
Taichi model (:mod:`taichi_bearing.solver`) and its transient, sample by sample
(:mod:`taichi_bearing.simulation.engine`). The run folder's files are those of
:mod:`taichi_bearing.output.layout`: ``case.yaml``, ``mesh_statistics.json``,
``mesh_info.json``, ``preload.json`` (with the flexible-ring reference), ``summary.json``
(status ``running`` until the checks), ``histories.parquet``, ``frames/``,
``checkpoints/``. The checks, figures and report follow in
:func:`taichi_bearing.pipeline.run_case`.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from bearing_io.files import to_jsonable, write_json
from taichi_bearing.analytic.contact_pressure import raceway_patch
from taichi_bearing.case import Case, case_to_dict
from taichi_bearing.errors import InputError, SimulationError
from taichi_bearing.mesh import build_bearing_mesh, mesh_statistics, spec_from_case
from taichi_bearing.mesh.quality import resolution_warning
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.output.checkpoint import fingerprint, latest_checkpoint
from taichi_bearing.output.layout import (
    CASE_FILE,
    CHECKPOINTS_DIR,
    MESH_INFO_FILE,
    MESH_STATISTICS_FILE,
    PRELOAD_FILE,
    REFERENCE_KEY,
    ROLLING_RATES_KEY,
    STATUS_INTERRUPTED,
    STATUS_RUNNING,
    STATUS_STOPPED,
    rolling_rates_entry,
)
from taichi_bearing.output.progress import LOG_INTERVAL_S, RelaxProgress
from taichi_bearing.output.run_folder import read_json
from taichi_bearing.output.summary import write_partial_summary
from taichi_bearing.simulation.recorders import (
    CageRecorder,
    ContactForceRecorder,
    RollerMotionRecorder,
)
from taichi_bearing.simulation.starter import Setup, align_rollers, build_setup, rolling_rates

__all__ = [
    "BearingModel",
    "Simulated",
    "build_model",
    "check_entries",
    "fitted_step",
    "mass_scaling_entry",
    "open_run_folder",
    "preload",
    "preload_entries",
    "simulate",
    "stage_mesh",
    "transient_entries",
]


@dataclass
class BearingModel:
    """The live model of a bearing case: Taichi model, contact, cage and recorders."""

    case: Case
    mesh: Mesh
    setup: Setup
    model: object  # taichi_bearing.solver.Model
    contact: object | None
    cage: object | None
    recorders: list = field(default_factory=list)


def stage_mesh(case: Case) -> tuple[Mesh, dict]:
    """Mesh the case (rollers aligned, :func:`~taichi_bearing.simulation.starter.align_rollers`);
    return the mesh and its statistics as a plain dict."""
    mesh = align_rollers(build_bearing_mesh(spec_from_case(case)), case.bearing.n_rollers)
    m = case.material
    stats = mesh_statistics(mesh, m.youngs_modulus, m.poissons_ratio, m.density)
    return mesh, to_jsonable(dataclasses.asdict(stats))


def mass_scaling_entry(added_mass, part_mass, part_names, n_elements: int) -> dict:
    """What selective mass scaling did: elements scaled, mass added per part (kg, and as a
    fraction of the part's mass)."""
    added = {
        part_names[p]: (float(m), float(m / part_mass[p]))
        for p, m in enumerate(added_mass)
        if m > 0
    }
    return {
        "n_elements": n_elements,
        "added_mass_kg": {k: v[0] for k, v in added.items()},
        "added_mass_fraction": {k: v[1] for k, v in added.items()},
    }


def _mass_scaling(model, mesh: Mesh) -> dict:
    return mass_scaling_entry(model.added_mass, model.part_mass, mesh.part_names,
                              model.n_mass_scaled)  # fmt: skip


def _mass_scaling_text(model, mesh: Mesh) -> str:
    info = _mass_scaling(model, mesh)
    if not info["n_elements"]:
        return "no mass scaling"
    frac = info["added_mass_fraction"]
    return (
        f"mass scaling: {info['n_elements']} elements in {len(frac)} parts, at most "
        f"+{max(frac.values()):.2g} of a part's mass"
    )


def build_model(case: Case, mesh: Mesh, arch: str = "cpu", threads: int | None = None):
    """Start Taichi and build the model, contact, cage and recorders of a case."""
    from taichi_bearing.solver import Model, PenaltyContact, RigidCage, init_taichi

    init_taichi(arch, threads)
    setup = build_setup(case, mesh)
    model = Model(
        mesh,
        setup.material,
        thickness=setup.thickness,
        constraints=setup.constraints,
        loads=setup.loads,
        initial_velocities=setup.initial_velocities,
        damping=setup.damping,
        max_added_mass=case.run.max_added_mass,
        time_step=case.run.time_step,
        multirate_levels=case.run.multirate_levels,
    )
    contact = PenaltyContact(model, setup.contact_pairs, setup.contact_params)
    model.add_contributor(contact)
    cage = None
    if case.cage.model == "rigid":
        cage = RigidCage.from_mesh(
            model,
            setup.contact_params,
            case.cage.mass,
            case.cage.pocket_clearance,
            start_speed=setup.rates.cage,
        )
        model.add_contributor(cage)
    rollers = RollerMotionRecorder.of_model(model, mesh, setup.n_rollers)
    recorders = [
        ContactForceRecorder(contact, setup.pair_table),
        rollers,
        CageRecorder(cage, rollers),
    ]
    return BearingModel(case, mesh, setup, model, contact, cage, recorders)


def preload(bm: BearingModel, progress: Callable[[int, float], None] | None = None) -> dict:
    """Dynamic relaxation under the load with nothing turning; the static contact forces.

    ``progress`` (e.g. :meth:`~taichi_bearing.output.progress.RelaxProgress.update`) is
    called with the steps taken and the KE ratio as the relaxation goes.

    Returns
    -------
    dict
        ``steps``, ``ke_ratio``, ``converged``, ``outer_force_N`` and ``inner_force_N``
        (normal force of each roller on each raceway at the end), ``plate_drop_m``,
        ``contact_patch`` (the most loaded roller's outer contact: half-width and peak
        pressure from the nodal forces beside Hertz's,
        :func:`taichi_bearing.analytic.contact_pressure.raceway_patch`).
    """
    from taichi_bearing.solver import relax

    case, model = bm.case, bm.model
    res = relax(model, case.preload.ke_ratio_tol, case.preload.max_steps, progress=progress,
                scale_masses=case.preload.mass_scaling)  # fmt: skip
    forces = np.asarray(bm.contact.current_resultants())[bm.setup.pair_table]
    return preload_entries(case, bm.mesh, res, forces, model.positions(), bm.contact.nodal_forces())


def preload_entries(case: Case, mesh: Mesh, res, forces: np.ndarray, positions: np.ndarray,
                    nodal_forces: np.ndarray) -> dict:  # fmt: skip
    """:func:`preload`'s result from the relaxation's (``res``), the pairs' resultants
    ``forces`` (roller, race, 4), and the nodes' positions and contact forces.

    Raises
    ------
    SimulationError
        If the relaxation did not converge.
    """
    if not res.converged:
        raise SimulationError(
            f"preload did not converge in {res.steps} steps (KE ratio {res.ke_ratio:.3g} > "
            f"{case.preload.ke_ratio_tol:g}); raise preload.max_steps or check the load"
        )
    top = mesh.node_sets["adapter_top"]
    drop = float(-np.mean((positions - np.asarray(mesh.nodes, dtype=float))[top, 1]))
    # the most loaded roller's outer contact as the mesh resolves it, beside Hertz
    j = int(np.argmax(forces[:, 0, 2]))
    cx, cy = np.asarray(mesh.info["roller_centres"], dtype=float)[j]
    patch = raceway_patch(
        positions,
        nodal_forces,
        np.asarray(mesh.surfaces["outer_raceway"]),
        math.atan2(cy, cx),
        case.bearing,
        case.material,
    )
    entries = {
        "steps": res.steps,
        "ke_ratio": res.ke_ratio,
        "converged": res.converged,
        "outer_force_N": forces[:, 0, 2].tolist(),
        "inner_force_N": forces[:, 1, 2].tolist(),
        "outer_fx_N": forces[:, 0, 0].tolist(),
        "outer_fy_N": forces[:, 0, 1].tolist(),
        "plate_drop_m": drop,
        "contact_patch": {"roller": j, "race": "outer", **patch},
    }
    if case.preload.mass_scaling:
        entries["mass_scaling"] = {"nodes": res.scaled_nodes, "dt_s": res.dt}
    return entries


def _scaling_note(pre: dict) -> str:
    """What the preload's mass scaling did, for the preload's line (nothing without it)."""
    ms = pre.get("mass_scaling")
    if not ms:
        return ""
    return f"; {ms['nodes']} contact nodes heavier, relaxed at dt {ms['dt_s']:.3g} s"


def fitted_step(model, case: Case) -> float:
    """The run's time step: the stable one lowered to fit a whole number of steps in the
    output interval (:func:`~taichi_bearing.simulation.engine.steps_per_sample`)."""
    from taichi_bearing.simulation.engine import steps_per_sample

    return steps_per_sample(model.dt_stable, case.run.sample_rate, model.cycle_steps)[1]


def open_run_folder(case: Case, out: Path, mesh: Mesh, stats: dict) -> None:
    """Create a run folder with the case, the mesh statistics and the mesh info."""
    out.mkdir(parents=True, exist_ok=True)
    _write_case(case, out)
    write_json(out / MESH_STATISTICS_FILE, stats)
    write_json(out / MESH_INFO_FILE, mesh.info)


def transient_entries(model) -> dict:
    """The summary's entries on how the model stepped: the step, its estimate, the
    multi-rate classes, the steps in each stepping mode."""
    return {
        "dt_s": model.dt,
        "time_step": {
            "method": model.time_step,
            "critical_step_s": model.critical_step,
            "damping_step_factor": model.damping_step_factor,
            "element_step_s": float(model.element_dt.min()),
        },
        **({"multirate": model.step_classes.summary()} if model.step_classes else {}),
        # preload and transient steps by stepping mode: "serial" where other processes
        # kept the cores busy (see solver.stepping.choose_mode)
        "steps_by_mode": dict(model.steps_by_mode),
    }


# Keys that do not change the state a checkpoint holds: a run may be resumed with other
# values (e.g. a longer duration extends a finished run from its last checkpoint).
_RESUMABLE_RUN_KEYS = (
    "arch",
    "threads",
    "duration_ms",
    "frame_interval_ms",
    "checkpoint_interval_ms",
    "max_steps",
)


def _fingerprint(case: Case, mesh: Mesh) -> str:
    d = case_to_dict(case)
    d.pop("output", None)
    d["run"] = {k: v for k, v in d["run"].items() if k not in _RESUMABLE_RUN_KEYS}
    return fingerprint(d, mesh.nodes, mesh.elements)


def _write_case(case: Case, out: Path) -> None:
    from bearing_io.files import atomic_path

    path = out / CASE_FILE
    with atomic_path(path) as tmp:
        Path(tmp).write_text(yaml.safe_dump(case_to_dict(case), sort_keys=False))


def check_entries(case: Case, mesh: Mesh) -> dict:
    """The ``preload.json`` entries the checks read besides the preload's own result: the
    flexible-ring reference forces, solved on this mesh (one sparse factorisation of the
    rings' stiffness), and the ideal rolling rates the transient starts from."""
    from taichi_bearing.simulation.static_reference import reference_roller_forces

    return {
        REFERENCE_KEY: reference_roller_forces(case, mesh).tolist(),
        ROLLING_RATES_KEY: rolling_rates_entry(rolling_rates(case)),
    }


@dataclass(frozen=True)
class Simulated:
    """What :func:`simulate` leaves for the checks: the summary so far (status still
    ``running``), the mesh's ``info`` and ``preload.json``'s entries."""

    summary: dict
    mesh_info: dict
    preload: dict


def simulate(
    case: Case,
    out_dir: str | Path | None = None,
    *,
    resume: bool = False,
    arch: str | None = None,
    threads: int | None = None,
    quiet: bool = False,
    progress_interval: float | None = LOG_INTERVAL_S,
    log=print,
) -> Simulated:
    """Mesh, preload and step a case, writing its run folder up to the histories.

    The run's checks, figures and report follow in
    :func:`taichi_bearing.pipeline.run_case`, which is what the command line runs.

    Parameters
    ----------
    case : Case
    out_dir : path, optional
        Run folder (default ``case.out_dir``).
    resume : bool
        Continue from the last checkpoint in ``out_dir/checkpoints`` (no preload).
    arch, threads : optional
        Override ``run.arch`` / ``run.threads``.
    quiet : bool
        No progress bar and no stage lines.
    progress_interval : float, optional
        Wall seconds between progress lines of the preload and the transient when stderr
        is not a terminal (a log); None: none.
    log : callable
        Where stage lines go.

    Returns
    -------
    Simulated
        The summary so far (written to ``summary.json`` with status ``running``), the mesh
        info and the preload's entries.

    Raises
    ------
    SimulationError
        The run stopped (instability, preload not converged); files so far are kept.
    KeyboardInterrupt
        After the histories up to that point and a partial summary have been written.
    """
    from taichi_bearing.simulation.engine import RunConfig, run_transient

    say = (lambda *a: None) if quiet else log
    out = Path(out_dir) if out_dir is not None else case.out_dir
    arch = arch or case.run.arch
    threads = case.run.threads if threads is None else threads
    times: dict[str, float] = {}
    summary: dict = {"case_name": case.name, "stage_times_s": times, "status": STATUS_RUNNING}

    t0 = time.perf_counter()
    mesh, stats = stage_mesh(case)
    open_run_folder(case, out, mesh, stats)
    times["mesh"] = time.perf_counter() - t0
    say(f"mesh: {mesh.n_elements} elements, {mesh.n_nodes} nodes ({times['mesh']:.1f} s)")
    note = resolution_warning(stats, 0.5 * case.run.sample_rate, "run.sample_rate_Hz / 2")
    if note:
        log(f"warning: {note}")

    say(f"model: starting Taichi ({arch}), assembling, finding the stable time step ...")
    t0 = time.perf_counter()
    bm = build_model(case, mesh, arch, threads)
    model = bm.model
    times["model"] = time.perf_counter() - t0
    say(
        f"model: dt {model.dt_stable:.3g} s ({model.time_step} estimate), damping step "
        f"factor {model.damping_step_factor:.3f}, {_mass_scaling_text(model, mesh)}"
    )

    # The preload steps at the transient's step (fitted to the sample interval): an
    # ensemble's members, whose stable steps differ in the last bits, then share it.
    model.set_dt(fitted_step(model, case))
    if resume:
        pre_path = out / PRELOAD_FILE
        if latest_checkpoint(out / CHECKPOINTS_DIR) is None or not pre_path.is_file():
            raise InputError(f"--resume: no checkpoint or {PRELOAD_FILE} in {out}")
        pre = read_json(pre_path)
        times["preload"] = float(pre.get("wall_s", 0.0))
        if REFERENCE_KEY not in pre or ROLLING_RATES_KEY not in pre:
            # a folder from before the preload recorded them: solve them on this mesh
            pre.update(check_entries(case, mesh))
            write_json(pre_path, pre)
    else:
        t0 = time.perf_counter()
        with RelaxProgress(
            case.preload.ke_ratio_tol,
            case.preload.max_steps,
            enabled=False if quiet else None,
            log_every_s=progress_interval,
        ) as bar:
            pre = preload(bm, bar.update)
        pre["wall_s"] = times["preload"] = time.perf_counter() - t0
        say(
            f"preload: {pre['steps']} steps, KE ratio {pre['ke_ratio']:.2g}, "
            f"max roller force {max(pre['outer_force_N']):.4g} N ({times['preload']:.1f} s)"
            + _scaling_note(pre)
        )
        t0 = time.perf_counter()
        pre.update(check_entries(case, mesh))
        times["reference"] = time.perf_counter() - t0
        write_json(out / PRELOAD_FILE, pre)
        say(
            f"flexible-ring reference: max roller force {max(pre[REFERENCE_KEY]):.4g} N "
            f"({times['reference']:.1f} s)"
        )
        # t = 0: ideal rolling from the preloaded positions (the cage at its kinematic
        # speed, the contact's dissipation counted from here)
        model.set_initial_velocities()

    config = RunConfig(
        duration=case.run.duration,
        sample_rate=case.run.sample_rate,
        frame_interval=case.run.frame_interval if case.output.frames else None,
        checkpoint_interval=case.run.checkpoint_interval,
        csv=case.output.csv,
        progress=False if quiet else None,
        progress_interval=progress_interval,
    )
    size = {"n_elements": mesh.n_elements, "n_nodes": mesh.n_nodes}
    inputs = {"mesh_statistics": stats, "preload": pre, "setup_notes": bm.setup.notes}
    # status "running" until the end: what a run killed hard (kill -9) leaves as summary
    # (the time step is set by the transient, to fit the sample interval)
    write_partial_summary(out, {**summary, **size, **inputs})
    t0 = time.perf_counter()
    interrupted = None
    try:
        result = run_transient(
            model, config, out, resume=resume, fingerprint=_fingerprint(case, mesh),
            recorders=bm.recorders,
        )  # fmt: skip
    except (KeyboardInterrupt, SimulationError) as exc:
        interrupted = exc
        result = None
    times["transient"] = time.perf_counter() - t0
    summary.update(
        {
            **size,
            **transient_entries(model),
            "mass_scaling": _mass_scaling(model, mesh),
            "n_steps": int(model.step_count),
            "wall_time_s": times["transient"],
            "element_steps_per_s": (
                mesh.n_elements * _steps_this_call(result, model, case, resume)
                / max(times["transient"], 1e-9)
            ),
            **inputs,
        }
    )  # fmt: skip
    if interrupted is not None:
        summary["status"] = (
            STATUS_INTERRUPTED if isinstance(interrupted, KeyboardInterrupt) else STATUS_STOPPED
        )
        summary["stop_reason"] = str(interrupted) or type(interrupted).__name__
        write_partial_summary(out, summary)
        raise interrupted
    say(
        f"transient: {result.steps} steps in {times['transient']:.1f} s "
        f"({summary['element_steps_per_s']:.3g} element-steps/s)"
    )
    if "multirate" in summary:
        info = summary["multirate"]
        shares = ", ".join(f"{100 * x:.0f} %" for x in info["element_share"])
        say(
            f"multi-rate stepping: elements per class (1, 2, ... {2 ** info['levels']} steps) "
            f"{shares}: {info['element_work']:.3f} of the single-rate element work"
        )
    return Simulated(summary, mesh.info, pre)


def _steps_this_call(result, model, case: Case, resume: bool) -> int:
    """Steps taken by this call (a resumed run: only those after the checkpoint)."""
    if result is None:
        return int(model.step_count)
    per_sample = round(1.0 / (case.run.sample_rate * result.dt))
    return len(result.rows) * per_sample + (0 if resume else 1)
