"""Team stepping (many steps per launch on persistent CPU threads meeting at barriers)
gives the same motion, contact and cage forces as one launch of parallel loops per step,
bit for bit (the threads split the contact's work differently in the two), and every
thread takes part."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np
import pytest
import taichi as ti
from test_contact_cage import OMEGA, orbiting_roller
from test_contact_disk import thrown_disk

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.primitives import rectangle_mesh
from taichi_bearing.solver import stepping
from taichi_bearing.solver.backend import GPU_MEMBERS, current_threads, init_taichi
from taichi_bearing.solver.contact import ContactParameters
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.loads import FixedNodes, NodalForces, RigidPlate, uniform_load
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.team import share

STEEL = Material(210e9, 0.3, 7850.0)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")
    if current_threads() < 2:
        pytest.skip("team stepping needs two CPU threads")


def run(build, team: bool, chunks: int, steps: int) -> tuple[Model, list]:
    """Build a model and step it in chunks, by team launches or by one launch per step;
    returns the model and what ``build``'s reader gave after each chunk."""
    model, read = build()
    out = []
    for _ in range(chunks):
        model.advance(steps, record_last=True, mode="team" if team else "parallel")
        out.append(read())
    return model, out


def disk_run(mode: str, steps: int = 60, chunks: int = 30) -> dict:
    """A spinning disk thrown onto a block with friction (it bounces, slides and rolls),
    stepped ``chunks`` times ``steps`` steps in ``mode``: the contact's normal forces after
    each chunk, and the model's state, energies and element energies at the end."""
    params = ContactParameters(friction_static=0.3, friction_dynamic=0.2)
    model, contact, _ = thrown_disk(params, (2.0, -1.0), omega=-300.0)
    fn = []
    for _ in range(chunks):
        model.advance(steps, record_last=True, mode=mode)
        fn.append(contact.contact_state()["fn"].copy())
    return {
        "fn": np.array(fn),
        "x": model.positions(),
        "v": model.velocities(),
        "energies": model.energies(),
        "contact_energies": contact.energies(),
        "e_int": model.e_int.to_numpy(),
        "joined": model.team.joined.to_numpy() if mode == "team" else None,
        "steps": model.step_count,
        "graphs": bool(model.step_graphs),
    }


@pytest.fixture(scope="module")
def disk_runs() -> dict[str, dict]:
    """The thrown disk in 60-step chunks, once in each mode (several tests compare them)."""
    return {mode: disk_run(mode) for mode in ("serial", "team", "parallel")}


def test_team_steps_match_one_launch_per_step_with_contact(disk_runs):
    """A spinning disk thrown onto a block: bounces, slides and rolls."""
    team, ref = disk_runs["team"], disk_runs["parallel"]
    # every thread ran one member (each took its own task of the launch's items)
    assert np.count_nonzero(team["joined"]) == current_threads()
    assert team["steps"] == ref["steps"] == 1800
    assert ref["fn"].max() > 0  # it touched
    # The contact's forces are summed in fixed point (order-free), the element forces
    # gathered in a fixed order: the same arithmetic bit for bit, however the threads
    # split the work.
    np.testing.assert_array_equal(team["fn"], ref["fn"])
    np.testing.assert_array_equal(team["x"], ref["x"])
    np.testing.assert_array_equal(team["v"], ref["v"])
    assert team["energies"] == ref["energies"]
    assert team["contact_energies"] == ref["contact_energies"]


@pytest.mark.slow  # ~45 s; the contact's team test and the cage's in-step test stay in CI
def test_team_steps_match_one_launch_per_step_with_the_cage():
    """A roller orbiting in its pocket drives the cage (the cage's part runs on member 0
    between the force shares and the node updates)."""

    def build():
        model, cage = orbiting_roller(OMEGA)
        return model, lambda: (cage.angle, cage.speed, *cage.pop_sample_means()[0])

    team, out_team = run(build, True, 40, 100)
    _, out_ref = run(build, False, 40, 100)
    out_team, out_ref = np.array(out_team), np.array(out_ref)
    assert np.abs(out_ref[:, 2:]).max() > 0  # the pocket pushed
    np.testing.assert_array_equal(out_team, out_ref)
    assert np.count_nonzero(team.team.joined.to_numpy()) == current_threads()


def test_element_energies_are_the_same_in_every_mode(disk_runs):
    """The recorded step's element energies, summed by the compiler in its own order in
    each kernel (fast math), come from one code path: equal in every mode to the last bit
    (without it 90 of the disk's 936 elements differed between serial and team)."""
    for mode in ("serial", "team", "parallel"):
        assert disk_runs[mode]["energies"]["internal"] > 0
    np.testing.assert_array_equal(disk_runs["serial"]["e_int"], disk_runs["team"]["e_int"])
    np.testing.assert_array_equal(disk_runs["serial"]["e_int"], disk_runs["parallel"]["e_int"])


@pytest.mark.parametrize(
    "members",
    [
        # one member steps the same phases as two, in serial mode: ~23 s, run with -m slow
        pytest.param(1, marks=pytest.mark.slow),
        2,
    ],
)
def test_phases_run_one_by_one_step_as_the_whole_step(members):
    """The profiling entry (``advance_phases``) runs the step body's phases: all of them,
    one launch per phase, move the model exactly as ``advance`` does, here while the
    disk presses into the block with friction."""
    params = ContactParameters(friction_static=0.3, friction_dynamic=0.2)
    runs = []
    for by_phase in (False, True):
        model, contact, _ = thrown_disk(params, (2.0, -1.0), omega=-300.0)
        model.advance(100)
        for _ in range(20):
            if by_phase:
                contact.before_steps(model, 1)
                for p in range(stepping.N_PHASES):
                    stepping.advance_phases(model, 1, p, p + 1, members)
                contact.after_steps(model, 1)
                model.step_count += 1
            else:
                model.advance(1, mode="serial" if members == 1 else "team")
        assert np.abs(contact.contact_state()["fn"]).max() > 0  # in contact
        runs.append((model.positions(), model.velocities()))
    (x_ref, v_ref), (x, v) = runs
    np.testing.assert_array_equal(x, x_ref)
    np.testing.assert_array_equal(v, v_ref)


@ti.kernel
def _shares(lo: ti.types.ndarray(), hi: ti.types.ndarray(), count: ti.i32, n_members: ti.i32):
    for member in range(n_members):
        lo[member], hi[member] = share(count, member, n_members)


@pytest.mark.parametrize("count", [7, 28_401, 32_768, 1_000_003])
def test_shares_tile_the_items_with_a_gpus_member_count(count):
    """The members' shares cover ``[0, count)`` once, in order, as even as integers allow,
    with a GPU's 65,536 members (their product passes the i32 range above 32,767 items)."""
    n = GPU_MEMBERS
    lo, hi = np.zeros(n, np.int32), np.zeros(n, np.int32)
    _shares(lo, hi, count, n)
    member = np.arange(n, dtype=np.int64)
    np.testing.assert_array_equal(lo, member * count // n)
    np.testing.assert_array_equal(hi, (member + 1) * count // n)
    assert lo[0] == 0 and hi[-1] == count and (hi[:-1] == lo[1:]).all()


def gpu_split(monkeypatch, launch: str) -> None:
    """Parallel stepping as on a GPU: each phase split among 65,536 members, 4 steps a
    launch, unrolled in one kernel (``launch`` "unrolled") or dispatched by a compute
    graph ("graph")."""
    monkeypatch.setattr(stepping, "parallel_members", lambda: GPU_MEMBERS)
    monkeypatch.setattr(stepping, "parallel_steps", lambda: 4 if launch == "unrolled" else 1)
    monkeypatch.setattr(stepping, "graph_steps", lambda: 4 if launch == "graph" else 1)


@pytest.fixture(scope="module")
def disk_serial_61() -> dict:
    """The thrown disk on one thread in 61-step chunks (the reference of both launches)."""
    return disk_run("serial", steps=61)


@pytest.mark.parametrize(
    "launch",
    [
        # unrolled launches are not the default (the graph is): ~35 s, run with -m slow
        pytest.param("unrolled", marks=pytest.mark.slow),
        "graph",
    ],
)
def test_a_gpus_split_of_the_step_gives_the_same_motion(monkeypatch, launch, disk_serial_61):
    """Launches of several steps (unrolled, or a compute graph of one-step kernels), each
    phase split among a GPU's 65,536 members (most with nothing to do), run here on the
    CPU, move the disk as one thread does, bit for bit (61 steps a call, the contact's
    grid checks between: launches of 4 steps and single steps)."""
    serial = disk_serial_61
    assert not serial["graphs"]
    gpu_split(monkeypatch, launch)
    split = disk_run("parallel", steps=61)
    assert split["graphs"] is (launch == "graph")
    assert serial["fn"].max() > 0  # it touched
    np.testing.assert_array_equal(split["x"], serial["x"])
    np.testing.assert_array_equal(split["fn"], serial["fn"])
    assert split["energies"] == serial["energies"]


def loaded_block(repeat_a_node: bool) -> Model:
    """A steel block on a fixed base, pressed down through a rigid plate on its top by a
    ramped load (every load on a node of its own, or one node loaded twice)."""
    mesh = rectangle_mesh(0.02, 0.01, 40, 20)
    top = mesh.node_sets["top"]
    loads = [uniform_load(top, (0.0, -2.0e6), ramp_time=2e-6)]
    if repeat_a_node:
        loads.append(NodalForces([top[3]], [(1.0e4, -5.0e4)]))
    return Model(mesh, STEEL, constraints=[FixedNodes(mesh.node_sets["bottom"]),
                                           RigidPlate(top, (0.0, 1.0))],
                 loads=loads, damping=StiffnessDamping(0.02, 20e3))  # fmt: skip


@pytest.mark.parametrize(
    "repeat_a_node",
    [
        # loads each on a node of their own beside a plate, in serial, team and parallel
        # stepping: also the bearing's, shown by test_ensemble_model.py; ~22 s, -m slow
        pytest.param(False, marks=pytest.mark.slow),
        True,
    ],
)
def test_the_plate_and_the_loads_are_the_same_in_every_mode(monkeypatch, repeat_a_node):
    """The loads (split among the members, or member 0's where a node has two) and the
    rigid plate (each plate node sums the plate's velocity from the plate forces) step
    alike on one thread, in a team and split among a GPU's members 4 steps a launch
    (unrolled, or by a compute graph); the plate stays rigid and is pushed down."""
    out = {}
    for mode in ("serial", "team", "parallel", "graph"):
        if mode in ("parallel", "graph"):
            gpu_split(monkeypatch, "unrolled" if mode == "parallel" else mode)
        model = loaded_block(repeat_a_node)
        assert model.loads_unique is not repeat_a_node
        for _ in range(20):
            model.advance(25, record_last=True, mode="parallel" if mode == "graph" else mode)
        out[mode] = (model.positions(), model.velocities(), model.energies())
        assert bool(model.step_graphs) is (mode == "graph")
        # past the ramp, every load is on its node (a node loaded twice carries both)
        total = sum(load.total for load in model.loads)
        np.testing.assert_allclose(model.f_load.to_numpy().sum(axis=0), total, rtol=1e-12)
    top = model.plate.nodes
    vy = out["serial"][1][top, 1]
    assert vy.min() < 0 and np.ptp(vy) == 0.0  # one velocity for the whole plate, downward
    for mode in ("team", "parallel", "graph"):
        np.testing.assert_array_equal(out[mode][0], out["serial"][0])
        np.testing.assert_array_equal(out[mode][1], out["serial"][1])
        assert out[mode][2] == out["serial"][2]
