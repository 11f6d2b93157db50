"""How the steps are launched: how many steps per kernel launch, on how many threads.

:func:`advance` is the one time loop of the solver; the transient driver
(:func:`taichi_bearing.simulation.engine.run_transient`, per output sample) and dynamic
relaxation (:func:`taichi_bearing.solver.relaxation.relax`, per damping update) call it.
Every mode runs the same step body (:func:`taichi_bearing.solver.step_phases.step_phase`, phase
by phase); they differ only in how the phases are launched:

``serial``
    Chunks of steps in one launch on the calling thread (one CPU thread, or a mesh small
    enough that dispatching a parallel loop costs more than the loop).
``team``
    Chunks of steps in one launch on several CPU threads, the members meeting at spin
    barriers between phases (:mod:`taichi_bearing.solver.team`).
``parallel``
    Each shared phase a parallel loop over many members (a GPU, or more CPU threads than
    cores), :func:`parallel_steps` steps (their phases unrolled) a launch; with a Python
    contributor
    (:class:`~taichi_bearing.solver.contributor.ForceContributor` with ``in_kernel``
    False), two launches per step with its :meth:`add_forces` between.

A chunk ends where a contributor asks for Python again (the contact's search-grid check).
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import os

import numpy as np
import taichi as ti

from taichi_bearing.errors import InputError
from taichi_bearing.solver import backend, transfer
from taichi_bearing.solver.backend import (
    current_arch,
    current_threads,
    parallel_members,
    serial_loops,
)
from taichi_bearing.solver.element_forces import record_element_energies, seed_strain_history
from taichi_bearing.solver.step_phases import GATHER, N_PHASES, SHARED, step_phase, step_times
from taichi_bearing.solver.team import TEAM_MAX_THREADS, barrier, join

__all__ = [
    "DEFAULT_STEPS_PER_GRAPH",
    "MODES",
    "STEPS_PER_GRAPH_ENV",
    "STEPS_PER_LAUNCH_ENV",
    "SERIAL_MAX_ELEMENTS",
    "advance",
    "advance_phases",
    "choose_mode",
    "graph_steps",
    "parallel_steps",
    "team_size",
]

MODES = ("serial", "team", "parallel")
# Below this many elements a chunk of steps runs serially (launch-bound regime).
SERIAL_MAX_ELEMENTS = 3000
# Other processes keeping more than this many cores busy make the team stand down: a
# member spinning at a barrier while another waits for a core wastes its time slices
# (one other CPU-bound process made team stepping 18x slower on 2 cores).
OTHER_LOAD_LIMIT = 0.3
# Steps a parallel launch unrolls (default 1): fewer launches, each of whose Python costs
# ~100 us on an H200's host. Measured there (issue 17 note): 8 made the CUDA compile
# 113 s instead of ~3 s, for a transient 1.2-1.5x faster together with another change,
# so the default waits for a measurement that separates the two.
STEPS_PER_LAUNCH_ENV = "TAICHI_BEARING_STEPS_PER_LAUNCH"
# Steps a parallel launch's compute graph dispatches from C++ (1: no graph): the Python
# of a launch paid once for that many steps, each compiled once (see _StepGraph).
STEPS_PER_GRAPH_ENV = "TAICHI_BEARING_STEPS_PER_GRAPH"
# 16: on an H200 a step 48 us against 100 from Python (docs/results/gpu), histories alike
DEFAULT_STEPS_PER_GRAPH = 16


@ti.kernel
def _k_chunk(m: ti.template(), n: ti.i32, step0: ti.i32, dt: ti.f64, first0: ti.i32,
             c_mass: ti.f64, rec_last: ti.i32, relax: ti.i32, damped: ti.template(),
             n_members: ti.template(), p0: ti.template(), p1: ti.template()):  # fmt: skip
    """``n`` steps in one launch, on the calling thread (``n_members`` 1) or by a team;
    phases ``p0 <= p < p1`` of each (all of them, but for a profile of one phase)."""
    if ti.static(n_members == 1):
        ti.loop_config(serialize=True)
        for k in range(n):
            first, dt_v, rec, t_load, t_rot, moving = step_times(
                k, n, step0, dt, first0, rec_last, relax, m.multirate_levels
            )
            for p in ti.static(range(p0, p1)):
                step_phase(m, p, 0, 1, dt, first, dt_v, rec, t_load, t_rot, moving, c_mass,
                           damped)  # fmt: skip
    else:
        ti.loop_config(serialize=True)
        for _ in range(1):
            m.team.reset()
        for _item in range(n_members * 1024):
            member = ti.global_thread_idx()
            if join(m.team, member):
                _team_member(m, member, n, step0, dt, first0, c_mass, rec_last, relax,
                             damped, n_members, p0, p1)  # fmt: skip


@ti.func
def _team_member(m: ti.template(), member, n, step0, dt, first0, c_mass, rec_last, relax,
                 damped: ti.template(), n_members: ti.template(), p0: ti.template(),
                 p1: ti.template()):  # fmt: skip
    """Member ``member``'s ``n`` steps: each phase (its share, or member 0 alone), then a
    barrier. The sensors (member 0) need none before the next step's clearing."""
    passed = 0
    for k in range(n):
        first, dt_v, rec, t_load, t_rot, moving = step_times(
            k, n, step0, dt, first0, rec_last, relax, m.multirate_levels
        )
        for p in ti.static(range(p0, p1)):
            if passed >= 0:
                if ti.static(SHARED[p]):
                    step_phase(m, p, member, n_members, dt, first, dt_v, rec, t_load, t_rot,
                               moving, c_mass, damped)  # fmt: skip
                elif member == 0:
                    step_phase(m, p, 0, 1, dt, first, dt_v, rec, t_load, t_rot, moving,
                               c_mass, damped)  # fmt: skip
                if ti.static(p < N_PHASES - 1):
                    passed = barrier(m.team, passed, n_members)


@ti.kernel
def _k_phases(m: ti.template(), p0: ti.template(), p1: ti.template(), n: ti.template(),
              step0: ti.i32, dt: ti.f64, first0: ti.i32, c_mass: ti.f64, rec_last: ti.i32,
              relax: ti.i32, damped: ti.template(), n_members: ti.template()):  # fmt: skip
    """Phases ``p0 <= p < p1`` of ``n`` steps (unrolled), each a loop over ``n_members``
    members (parallel, but for one member) or member 0 alone."""
    _phases(m, p0, p1, n, step0, dt, first0, c_mass, rec_last, relax, damped, n_members)


@ti.func
def _phases(m: ti.template(), p0: ti.template(), p1: ti.template(), n: ti.template(), step0,
            dt, first0, c_mass, rec_last, relax, damped: ti.template(),
            n_members: ti.template()):  # fmt: skip
    """The body of :func:`_k_phases` (inlined: its loops are the kernel's outermost)."""
    for k in ti.static(range(n)):
        for p in ti.static(range(p0, p1)):
            if ti.static(SHARED[p]):
                ti.loop_config(serialize=n_members == 1)
                for member in range(n_members):
                    first, dt_v, rec, t_load, t_rot, moving = step_times(
                        k, n, step0, dt, first0, rec_last, relax, m.multirate_levels
                    )
                    step_phase(m, p, member, n_members, dt, first, dt_v, rec, t_load,
                               t_rot, moving, c_mass, damped)  # fmt: skip
            else:
                ti.loop_config(serialize=True)
                for _ in range(1):
                    first, dt_v, rec, t_load, t_rot, moving = step_times(
                        k, n, step0, dt, first0, rec_last, relax, m.multirate_levels
                    )
                    step_phase(m, p, 0, 1, dt, first, dt_v, rec, t_load, t_rot, moving,
                               c_mass, damped)  # fmt: skip


class _StepGraph:
    """``n`` steps dispatched from C++ in one call: a Taichi compute graph
    (:mod:`taichi.graph`) of ``n`` launches of ``kernel``, one step of a model
    (:func:`_one_step_kernel`).

    A launch from Python costs Taichi's argument handling (the template arguments above
    all), some 100 us on a GPU's host, where the device's step is shorter; a graph pays it
    once for ``n`` steps, and unlike unrolled steps (:func:`parallel_steps`) it compiles
    one step only. The kernel is the same body as :func:`_k_phases` with ``n`` 1, the
    model and the static choices bound when it is made: every step as before, bit for bit.
    """

    def __init__(self, kernel, n: int) -> None:
        self.n = n
        scalar = ti.graph.ArgKind.SCALAR
        shared = {
            name: ti.graph.Arg(scalar, name, dtype)
            for name, dtype in (("dt", ti.f64), ("c_mass", ti.f64), ("relax", ti.i32))
        }
        builder = ti.graph.GraphBuilder()
        for j in range(n):
            builder.dispatch(
                kernel,
                ti.graph.Arg(scalar, f"step{j}", ti.i32),
                shared["dt"],
                ti.graph.Arg(scalar, f"first{j}", ti.i32),
                shared["c_mass"],
                ti.graph.Arg(scalar, f"rec{j}", ti.i32),
                shared["relax"],
            )
        self._graph = builder.compile()

    def run(self, step0: int, dt: float, first: int, c_mass: float, rec: int,
            relax: int) -> None:  # fmt: skip
        """Steps ``step0 .. step0 + n - 1``: ``first`` for the first, ``rec`` the last."""
        args = {"dt": dt, "c_mass": c_mass, "relax": relax}
        for j in range(self.n):
            args[f"step{j}"] = step0 + j
            args[f"first{j}"] = first if j == 0 else 0
            args[f"rec{j}"] = rec if j == self.n - 1 else 0
        self._graph.run(args)


def _one_step_kernel(model, damped: int, n_members: int):
    """One step of ``model`` as a kernel of scalar arguments only (a graph takes no
    template argument): the model and the static choices are bound here."""

    @ti.kernel
    def one_step(step0: ti.i32, dt: ti.f64, first0: ti.i32, c_mass: ti.f64, rec_last: ti.i32,
                 relax: ti.i32):  # fmt: skip
        _phases(model, 0, N_PHASES, 1, step0, dt, first0, c_mass, rec_last, relax, damped,
                n_members)  # fmt: skip

    return one_step


def parallel_steps() -> int:
    """Steps per launch in ``parallel`` stepping: ``$TAICHI_BEARING_STEPS_PER_LAUNCH``
    (:data:`STEPS_PER_LAUNCH_ENV`), default 1. Each value compiles its own kernel, with
    that many copies of the step."""
    return _steps_from_env(STEPS_PER_LAUNCH_ENV)


def graph_steps() -> int:
    """Steps per compute graph in ``parallel`` stepping: ``$TAICHI_BEARING_STEPS_PER_GRAPH``
    (:data:`STEPS_PER_GRAPH_ENV`), default :data:`DEFAULT_STEPS_PER_GRAPH`; 1 launches
    each step from Python. Above 1, that many one-step launches go from C++ in one call
    (a shorter remainder of a chunk: the largest power of 2 that fits, then the next),
    without a Python contributor (whose forces come between launches); it replaces
    :func:`parallel_steps`' unrolling. The histories are the same either way."""
    return _steps_from_env(STEPS_PER_GRAPH_ENV, DEFAULT_STEPS_PER_GRAPH)


def _steps_from_env(name: str, default: int = 1) -> int:
    value = os.environ.get(name, str(default))
    try:
        n = int(value)
    except ValueError:
        n = 0
    if n < 1:
        raise InputError(f"{name}: a whole number >= 1, got {value!r}")
    return n


def team_size(model) -> int:
    """Threads for team stepping (0: not possible): the CPU with several threads, no more
    than the cores this process may run on, and no Python contributor."""
    threads = current_threads()
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else threads
    if current_arch() != "cpu" or not 2 <= threads <= min(cores, TEAM_MAX_THREADS):
        return 0
    if model.python_contributors:
        return 0
    return threads


def oversubscribed() -> bool:
    """Whether other processes keep the cores busy (:data:`OTHER_LOAD_LIMIT`): then a
    team's spinning members would wait on each other's time slices."""
    return backend.other_load() > OTHER_LOAD_LIMIT


def choose_mode(model, mode: str | None = None) -> str:
    """The stepping mode for ``model``: ``mode`` if given (checked), else ``serial`` on
    one CPU thread or a small mesh, else ``team`` where possible, else ``parallel``.
    A Python contributor always means ``parallel`` (its forces come between launches).
    Where ``team`` would be chosen but other processes keep the cores busy
    (:func:`oversubscribed`), ``serial``: one thread that does not spin keeps its share of
    the machine (about half of the quiet team's speed on 2 cores beside one other
    CPU-bound process, where a team slows down many times). Checked again at every call,
    so the team comes back when the machine is free. The results do not depend on it."""
    if mode is not None and mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
    if model.python_contributors:
        if mode not in (None, "parallel"):
            raise ValueError(f"{mode} stepping cannot call a Python contributor's add_forces")
        return "parallel"
    if mode == "team" and team_size(model) == 0:
        raise ValueError("team stepping needs the CPU with 2 or more threads, within the cores")
    if mode is not None:
        return mode
    if model.n_elements <= SERIAL_MAX_ELEMENTS or serial_loops()[1]:
        return "serial"
    if team_size(model):
        return "serial" if oversubscribed() else "team"
    return "parallel"


def advance(model, n: int, record_last: bool = False, mode: str | None = None,
            relax_damping=None) -> None:  # fmt: skip
    """Take ``n`` steps of ``model`` (see :meth:`Model.advance`)."""
    if n <= 0:
        return
    mode = choose_mode(model, mode)
    if record_last:
        # The element energies at the start of the recorded step (the positions its
        # forces come from) by a kernel of their own, the same in every mode; the step
        # itself records the nodes' share (velocities at t_n).
        advance(model, n - 1, False, mode, relax_damping)
        record_element_energies(model)
        n = 1
    model.steps_by_mode[mode] = model.steps_by_mode.get(mode, 0) + n
    model.freeze_contributors()
    model.prepare_step_classes()
    relax = relax_damping is not None
    _seed_history(model, relax)
    c_mass = _relax_damping(model, relax_damping)
    dt, damped = model.dt, int(model.damped)
    contributors = model.kernel_contributors
    if mode != "parallel":
        n_members = 1 if mode == "serial" else team_size(model)
        done = 0
        while done < n:
            chunk = n - done
            for c in contributors:
                chunk = max(1, min(chunk, c.before_steps(model, chunk)))
            last = int(record_last and done + chunk == n)
            _k_chunk(model, chunk, model.step_count, dt, int(model.first), c_mass, last,
                     int(relax), damped, n_members, 0, N_PHASES)  # fmt: skip
            if n_members > 1 and model.team.failed[None]:
                raise RuntimeError(
                    f"team stepping: a barrier waited in vain for one of {n_members} CPU "
                    "threads; run with one thread (--threads 1)"
                )
            _after(model, contributors, chunk, relax)
            done += chunk
        return
    members = parallel_members()
    python = model.python_contributors
    per_graph = 1 if python else graph_steps()
    per_launch = 1 if python or per_graph > 1 else parallel_steps()
    done = 0
    while done < n:
        chunk = n - done
        for c in contributors:
            chunk = max(1, min(chunk, c.before_steps(model, chunk)))
        if per_graph > 1 and chunk >= 2:
            # The largest graph that fits: per_graph steps, else the largest power of 2
            # below it (a chunk's remainder, e.g. 185 = 11 x 16 + 8 + 1).
            g = per_graph if chunk >= per_graph else 1 << (chunk.bit_length() - 1)
            rec = int(record_last and done + g == n)
            graph = _step_graph(model, g, damped, members)
            graph.run(model.step_count, dt, int(model.first), c_mass, rec, int(relax))
            _after(model, contributors, g, relax)
            done += g
            continue
        k = per_launch if chunk >= per_launch else 1
        rec = int(record_last and done + k == n)
        args = (model.step_count, dt, int(model.first), c_mass, rec, int(relax), damped, members)
        if python:
            _k_phases(model, 0, GATHER, 1, *args)
            for c in python:
                c.add_forces(model, model.step_count * dt)
            _k_phases(model, GATHER, N_PHASES, 1, *args)
        else:
            _k_phases(model, 0, N_PHASES, k, *args)
        _after(model, contributors, k, relax)
        done += k


def _step_graph(model, n: int, damped: int, n_members: int) -> _StepGraph:
    """The model's graph of ``n`` steps for these static choices (made once; the graphs of
    every ``n`` share one kernel, compiled once)."""
    graphs = model.step_graphs
    if (n, damped, n_members) not in graphs:
        kernel_key = ("kernel", damped, n_members)
        if kernel_key not in graphs:
            graphs[kernel_key] = _one_step_kernel(model, damped, n_members)
        graphs[n, damped, n_members] = _StepGraph(graphs[kernel_key], n)
    return graphs[n, damped, n_members]


def advance_phases(model, n: int, p0: int, p1: int, n_members: int = 1) -> None:
    """Run phases ``p0 <= p < p1`` only of ``n`` transient steps from the model's state, on
    the calling thread or by a team of ``n_members`` CPU threads: a profile of some
    phases (``benchmarks/taichi_bearing/profile_step.py``, ``profile_team.py``). The
    model's clock and contributors' counts are left as they were; what the phases write is
    not undone."""
    model.freeze_contributors()
    model.prepare_step_classes()
    _seed_history(model, False)
    _k_chunk(model, n, model.step_count, model.dt, 0, 0.0, 0, 0, int(model.damped),
             n_members, p0, p1)  # fmt: skip


def _relax_damping(model, relax_damping) -> float:
    """The relaxation damping the kernels take (0: none). An ensemble's members each read
    their own from ``model.relax_c`` (uploaded here when it changes; zeros outside a
    relaxation), so the kernels' argument is 0 for them."""
    if model.ensemble_size == 1:
        if relax_damping is None:
            return 0.0
        c = np.asarray(relax_damping, dtype=float).ravel()
        return float(c[0])
    c = np.zeros(model.ensemble_size)
    if relax_damping is not None:
        c = np.broadcast_to(np.asarray(relax_damping, dtype=float), c.shape).copy()
    if not np.array_equal(c, getattr(model, "_relax_c_set", None)):
        transfer.upload([(model.relax_c, c)])
        model._relax_c_set = c
    return 0.0


def _seed_history(model, relax: bool) -> None:
    """Seed the damped elements' strain history from the velocities
    (:func:`~taichi_bearing.solver.element_forces.seed_strain_history`) where it does not
    hold the last steps: after a restart, a new state or step, or where the elements'
    steps change (relaxation is single-rate; a multi-rate transient steps class :math:`c`
    every :math:`2^c` steps). A history read from a checkpoint is kept (bit-for-bit resume)."""
    if not model.damped:
        return
    multirate = int(model.multirate_levels > 0 and not relax)
    key = (model.dt, multirate)
    if model.history_stale or model.history_key not in (key, None):
        seed_strain_history(model, model.dt, multirate)
        model.history_stale = False
    model.history_key = key


def _after(model, contributors, n: int, relax: bool) -> None:
    """Bookkeeping after ``n`` steps ran: contributors' counts, the clock."""
    for c in contributors:
        c.after_steps(model, n)
    model.first = False
    if not relax:
        model.step_count += n
