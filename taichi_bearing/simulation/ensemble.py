"""An ensemble: several bearing cases that share one mesh topology and one time step,
stepped as one model.

Each member is a case of its own (the rollers at another start angle, another load or
speed); the model holds their meshes one after another
(:func:`~taichi_bearing.mesh.stack.stack_meshes`) and every member keeps its own
constraints, loads, contact pairs and cage
(:class:`~taichi_bearing.solver.model.Model` with ``members``). Stepped by the same
kernels, each member's arithmetic is that of its case run alone, so its histories are the
same, bit for bit.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bearing_io.files import write_json
from taichi_bearing.case import Case, case_to_dict
from taichi_bearing.errors import InputError, SimulationError
from taichi_bearing.mesh.stack import member_name, stack_meshes
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.output.layout import PRELOAD_FILE, STATUS_RUNNING, STATUS_STOPPED
from taichi_bearing.output.progress import LOG_INTERVAL_S, RelaxProgress
from taichi_bearing.output.summary import write_partial_summary
from taichi_bearing.simulation.recorders import (
    CageRecorder,
    ContactForceRecorder,
    RollerMotionRecorder,
)
from taichi_bearing.simulation.roller_readout import RollerReadout
from taichi_bearing.simulation.simulate import (
    Simulated,
    check_entries,
    fitted_step,
    mass_scaling_entry,
    open_run_folder,
    preload_entries,
    stage_mesh,
    transient_entries,
)
from taichi_bearing.simulation.starter import Setup, build_setup, roller_kinematics_matrix
from taichi_bearing.solver.contact_setup import ContactPair
from taichi_bearing.solver.loads import RigidVelocity

__all__ = [
    "MEMBER_KEYS",
    "EnsembleModel",
    "build_ensemble_model",
    "check_members",
    "member_signature",
    "simulate_ensemble",
]

# The keys an ensemble's members may differ in: neither the mesh's topology nor the
# stable step depends on them, and the kernels read them as data (loads, speeds, start
# positions), not as compiled constants.
MEMBER_KEYS = (
    "run.first_roller_angle_deg",
    "operating.load_kN",
    "operating.speed_rpm",
    "output.dir",
    "name",
)


@dataclass
class EnsembleModel:
    """The live model of an ensemble: its members' cases, meshes and set-ups (member
    numbering), the stacked mesh, and the one Taichi model with its contact and cage."""

    cases: list[Case]
    meshes: list[Mesh]
    setups: list[Setup]
    mesh: Mesh
    model: object  # taichi_bearing.solver.Model
    contact: object
    cage: object | None
    pair_tables: list[np.ndarray] = field(default_factory=list)

    @property
    def size(self) -> int:
        return len(self.cases)


def _flat(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flat(v, key + "."))
        else:
            out[key] = v
    return out


def member_signature(case: Case) -> tuple:
    """What a case must share with the other members of its ensemble: every key of the
    case but :data:`MEMBER_KEYS`, as a sorted tuple of (key, value). Two cases can be
    members of one model exactly when their signatures are equal."""
    flat = _flat(case_to_dict(case))
    return tuple(sorted((k, repr(v)) for k, v in flat.items() if k not in MEMBER_KEYS))


def check_members(cases: Sequence[Case]) -> None:
    """Refuse members that cannot share one model: keys other than :data:`MEMBER_KEYS`
    that differ from the first member's.

    Raises
    ------
    InputError
        Naming the first key that differs and the members.
    """
    if not cases:
        raise InputError("an ensemble needs at least one member")
    first = _flat(case_to_dict(cases[0]))
    for k, case in enumerate(cases[1:], 1):
        other = _flat(case_to_dict(case))
        for key in sorted(set(first) | set(other)):
            if key in MEMBER_KEYS or first.get(key) == other.get(key):
                continue
            raise InputError(
                f"{key}: ensemble members 0 and {k} differ ({first.get(key)!r} and "
                f"{other.get(key)!r}); members may differ only in {', '.join(MEMBER_KEYS)}"
            )


def _member_setup(setup: Setup, k: int, nn: int) -> Setup:
    """Member ``k``'s set-up in the stacked mesh: its nodes moved on by ``k nn``, its
    parts and surfaces renamed (:func:`member_name`)."""

    def moved(c):
        return dataclasses.replace(c, nodes=np.asarray(c.nodes) + k * nn)

    velocities = [
        dataclasses.replace(v, part=member_name(v.part, k))
        if isinstance(v, RigidVelocity) and isinstance(v.part, str)
        else v
        for v in setup.initial_velocities
    ]
    pairs = [
        ContactPair(
            member_name(p.name, k),
            member_name(p.slave_surface, k),
            member_name(p.master_surface, k),
            p.two_pass,
        )
        for p in setup.contact_pairs
    ]
    return dataclasses.replace(
        setup,
        constraints=[moved(c) for c in setup.constraints],
        loads=[moved(f) for f in setup.loads],
        initial_velocities=velocities,
        contact_pairs=pairs,
    )


def build_ensemble_model(
    cases: Sequence[Case], meshes: Sequence[Mesh], arch: str = "cpu", threads: int | None = None
) -> EnsembleModel:
    """Start Taichi and build the one model of an ensemble's members.

    Parameters
    ----------
    cases : sequence of Case
        The members (:func:`check_members`).
    meshes : sequence of Mesh
        Each member's mesh (:func:`~taichi_bearing.simulation.simulate.stage_mesh`).
    arch, threads : optional
        Taichi backend and CPU threads.

    Returns
    -------
    EnsembleModel
    """
    from taichi_bearing.solver import Model, PenaltyContact, RigidCage, init_taichi

    check_members(cases)
    init_taichi(arch, threads)
    nn = meshes[0].n_nodes
    mesh = stack_meshes(meshes)
    setups = [build_setup(c, m) for c, m in zip(cases, meshes, strict=True)]
    moved = [_member_setup(s, k, nn) for k, s in enumerate(setups)]
    first, case = setups[0], cases[0]
    model = Model(
        mesh,
        first.material,
        thickness=first.thickness,
        constraints=[c for s in moved for c in s.constraints],
        loads=[f for s in moved for f in s.loads],
        initial_velocities=[v for s in moved for v in s.initial_velocities],
        damping=first.damping,
        max_added_mass=case.run.max_added_mass,
        time_step=case.run.time_step,
        multirate_levels=case.run.multirate_levels,
        members=len(cases),
    )
    pairs = [p for s in moved for p in s.contact_pairs]
    contact = PenaltyContact(model, pairs, first.contact_params)
    model.add_contributor(contact)
    n_pairs = len(first.contact_pairs)
    tables = [s.pair_table + k * n_pairs for k, s in enumerate(setups)]
    cage = None
    if case.cage.model == "rigid":
        cage = RigidCage.from_mesh(
            model,
            first.contact_params,
            case.cage.mass,
            case.cage.pocket_clearance,
            start_speed=[s.rates.cage for s in setups],
        )
        model.add_contributor(cage)
    return EnsembleModel(list(cases), list(meshes), setups, mesh, model, contact, cage, tables)


def _member_mass_scaling(model, mesh: Mesh, k: int) -> dict:
    """:func:`~taichi_bearing.simulation.simulate.mass_scaling` of member ``k`` (its
    parts, under their own names)."""
    n_parts = len(mesh.part_names)
    parts = slice(k * n_parts, (k + 1) * n_parts)
    return mass_scaling_entry(model.added_mass[parts], model.part_mass[parts], mesh.part_names,
                              int(np.count_nonzero(model.added_mass[parts])))  # fmt: skip


def simulate_ensemble(
    cases: Sequence[Case],
    out_dirs: Sequence[str | Path],
    *,
    arch: str | None = None,
    threads: int | None = None,
    quiet: bool = False,
    progress_interval: float | None = LOG_INTERVAL_S,
    log=print,
) -> list[Simulated | SimulationError]:
    """:func:`~taichi_bearing.simulation.simulate.simulate` of every member of an
    ensemble, stepped as one model: each member's run folder as its case run alone
    writes it, up to the histories (the same rows, bit for bit).

    Returns
    -------
    list
        Per member, its :class:`Simulated`, or the :class:`SimulationError` that stopped
        it (its folder then holds what it recorded, its summary the reason).
    """
    from taichi_bearing.simulation.engine import RunConfig, run_members
    from taichi_bearing.simulation.members import (
        EnsembleSample,
        MemberCage,
        MemberContact,
    )
    from taichi_bearing.solver import relax_members

    say = (lambda *a: None) if quiet else log
    check_members(cases)
    case = cases[0]
    outs = [Path(o) for o in out_dirs]
    if len(outs) != len(cases) or len(set(outs)) != len(outs):
        raise InputError("an ensemble needs one run folder per member, each its own")
    arch = arch or case.run.arch
    threads = case.run.threads if threads is None else threads
    times: dict[str, float] = {}
    t0 = time.perf_counter()
    staged = [stage_mesh(c) for c in cases]
    meshes = [m for m, _ in staged]
    for c, out, (mesh, stats) in zip(cases, outs, staged, strict=True):
        open_run_folder(c, out, mesh, stats)
    times["mesh"] = time.perf_counter() - t0
    say(f"ensemble: {len(cases)} members of {meshes[0].n_elements} elements each")
    t0 = time.perf_counter()
    em = build_ensemble_model(cases, meshes, arch, threads)
    model = em.model
    times["model"] = time.perf_counter() - t0
    model.set_dt(fitted_step(model, case))
    say(f"model: dt {model.dt:.3g} s ({model.time_step} estimate), one for every member")

    t0 = time.perf_counter()
    with RelaxProgress(case.preload.ke_ratio_tol, case.preload.max_steps,
                       enabled=False if quiet else None,
                       log_every_s=progress_interval) as bar:  # fmt: skip
        relaxed = relax_members(model, case.preload.ke_ratio_tol, case.preload.max_steps,
                                progress=bar.update,
                                scale_masses=case.preload.mass_scaling)  # fmt: skip
    times["preload"] = time.perf_counter() - t0
    nn = model.member_nodes
    x, f_nodes = model.positions(), em.contact.nodal_forces()
    resultants = em.contact.current_resultants()
    errors: list[SimulationError | None] = []
    pres = []
    for k, (c, mesh, res) in enumerate(zip(cases, meshes, relaxed, strict=True)):
        part = slice(k * nn, (k + 1) * nn)
        try:
            if res.error:
                raise SimulationError(res.error)
            pre = preload_entries(c, mesh, res, resultants[em.pair_tables[k]], x[part],
                                  f_nodes[part])  # fmt: skip
        except SimulationError as exc:
            errors.append(exc)
            pres.append(None)
            continue
        pre["wall_s"] = times["preload"]
        pre.update(check_entries(c, mesh))
        write_json(outs[k] / PRELOAD_FILE, pre)
        errors.append(None)
        pres.append(pre)
    say(f"preload: {sum(e is None for e in errors)} of {len(cases)} members at rest "
        f"({times['preload']:.1f} s)")  # fmt: skip
    model.set_initial_velocities()

    # every member's rollers in one device read-out a sample (roller j of member k: row
    # k Z + j), in the node order of each member's own
    z = em.setups[0].n_rollers
    nodes, owner = roller_kinematics_matrix(meshes[0], z)
    per_roller = [nodes[owner == j] for j in range(z)]
    readout = RollerReadout([ids + k * nn for k in range(len(cases)) for ids in per_roller],
                            model.mass_np)  # fmt: skip
    sample = EnsembleSample(model, em.contact, em.cage, readout)
    recorders = []
    n_pairs = len(em.setups[0].contact_pairs)
    for k, setup in enumerate(em.setups):
        rollers = RollerMotionRecorder(
            setup.n_rollers, lambda k=k: sample.get("rollers")[k * z : (k + 1) * z]
        )
        recorders.append([
            ContactForceRecorder(MemberContact(sample, k, n_pairs), setup.pair_table),
            rollers,
            CageRecorder(MemberCage(sample, k) if em.cage is not None else None, rollers),
        ])  # fmt: skip
    config = RunConfig(duration=case.run.duration, sample_rate=case.run.sample_rate,
                       csv=case.output.csv, progress=False if quiet else None,
                       progress_interval=progress_interval)  # fmt: skip
    size = {"n_elements": meshes[0].n_elements, "n_nodes": nn}
    summaries = []
    for k, (c, out, (_, stats)) in enumerate(zip(cases, outs, staged, strict=True)):
        s = {"case_name": c.name, "stage_times_s": dict(times), "status": STATUS_RUNNING,
             "ensemble": {"members": len(cases), "member": k}, **size,
             "mesh_statistics": stats, "preload": pres[k],
             "setup_notes": em.setups[k].notes}  # fmt: skip
        summaries.append(s)
        write_partial_summary(out, s)
    for k, e in enumerate(errors):
        if e is not None:
            _stopped(outs[k], summaries[k], e)
    t0 = time.perf_counter()
    results = run_members(model, config, outs, recorders, sample=sample,
                          active=[e is None for e in errors])  # fmt: skip
    wall = time.perf_counter() - t0
    done: list[Simulated | SimulationError] = []
    for k, (res, out, s) in enumerate(zip(results, outs, summaries, strict=True)):
        if errors[k] is not None:
            done.append(errors[k])
            continue
        s["stage_times_s"]["transient"] = wall
        s.update(transient_entries(model))
        s["mass_scaling"] = _member_mass_scaling(model, meshes[k], k)
        s["n_steps"] = int(model.step_count)
        s["wall_time_s"] = wall
        # the ensemble's pace: every member's elements stepped in the wall time
        s["element_steps_per_s"] = model.n_elements * model.step_count / max(wall, 1e-9)
        if res.error is not None:
            _stopped(out, s, res.error)
            done.append(res.error)
            continue
        done.append(Simulated(s, meshes[k].info, pres[k]))
    say(f"transient: {model.step_count} steps of {len(cases)} members in {wall:.1f} s")
    return done


def _stopped(out: Path, summary: dict, error: SimulationError) -> None:
    """A member's folder marked stopped, with the reason (its histories so far kept)."""
    summary["status"] = STATUS_STOPPED
    summary["stop_reason"] = str(error)
    write_partial_summary(out, summary)
