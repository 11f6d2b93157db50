"""Multi-rate stepping: the classes keep every element within its stable step, a graded
bar moves as under single-rate stepping and conserves energy (damping counted), dynamic
relaxation stays single-rate bit for bit, and every stepping mode gives the same bits."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import dataclasses

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.primitives import rectangle_mesh
from taichi_bearing.simulation.engine import steps_per_sample
from taichi_bearing.solver.backend import current_threads, init_taichi
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.multirate import step_classes

STEEL = Material(210e9, 0.3, 7850.0)
LENGTH = 0.2


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def graded_bar():
    """A 0.2 m x 10 mm bar whose elements grow from 0.03 mm at x = 0 to 5 mm at x = L."""
    mesh = rectangle_mesh(LENGTH, 0.01, 80, 4)
    nodes = mesh.nodes.copy()
    nodes[:, 0] = LENGTH * (nodes[:, 0] / LENGTH) ** 2
    return dataclasses.replace(mesh, nodes=nodes)


def vibrating_bar(levels: int, damping=None) -> tuple[Model, list[int]]:
    """The free bar started in its first axial mode with a transverse velocity on top;
    sensors at x = 0.15 m (coarse) and x = 2 mm (fine)."""
    mesh = graded_bar()
    x = mesh.nodes
    probes = [int(np.argmin(np.hypot(x[:, 0] - px, x[:, 1] - 0.005))) for px in (0.15, 0.002)]
    model = Model(
        mesh,
        STEEL,
        sensors={"coarse": probes[0], "fine": probes[1]},
        damping=damping,
        multirate_levels=levels,
    )
    v = np.zeros_like(x)
    v[:, 0] = 0.1 * np.cos(np.pi * x[:, 0] / LENGTH)
    v[:, 1] = 0.05 * np.sin(2 * np.pi * x[:, 0] / LENGTH)
    model.set_state(v=v)
    model.restart_accounting()
    return model, probes


def mechanical(e: dict) -> float:
    return e["kinetic"] + e["internal"] + e["hourglass"]


def history(model: Model, probes: list[int], chunks: int, steps: int = 64):
    """Displacements of the probes and the energy residual (E + damping - work) / E0
    after each chunk; the first step is the half step out of t = 0."""
    model.advance(1, record_last=True)
    e0 = mechanical(model.energies())
    rows = []
    for _ in range(chunks):
        model.advance(steps, record_last=True)
        e = model.energies()
        u = (model.positions() - model.mesh.nodes)[probes].ravel()
        rows.append([*u, (mechanical(e) + e["damping"] - e["external_work"]) / e0 - 1.0])
    return np.array(rows), e


def test_classes_keep_every_element_within_its_stable_step():
    model, probes = vibrating_bar(3)
    model.freeze_contributors()
    model.prepare_step_classes()
    c = model.step_classes
    elements = np.asarray(model.mesh.elements)
    limit = model.element_dt * model.critical.dt_factor
    # each node's velocity step is within the stable step of every element it is in
    node_step = 2.0**c.node_class * model.dt
    for k in range(4):
        assert np.all(node_step[elements[:, k]] <= limit * (1 + 1e-9))
    # and each element runs with its fastest node, so at most its own stable step
    assert np.array_equal(c.element_class, c.node_class[elements].min(axis=1))
    assert np.all(2.0**c.element_class * model.dt <= limit * (1 + 1e-9))
    # the grading gives every class; the sensors stay at class 0
    assert set(c.element_class.tolist()) == {0, 1, 2, 3}
    assert c.node_class[probes].tolist() == [0, 0]
    assert c.element_work < 0.25
    # the moving classes' elements lead the order
    sorted_classes = c.element_class[c.element_order]
    assert np.all(np.diff(sorted_classes) >= 0)
    assert c.element_count.tolist() == [int(np.sum(c.element_class <= k)) for k in range(4)]


def test_fast_nodes_and_bad_levels():
    elements = np.array([[0, 1, 3, 2]])
    fast = np.array([False, True, False, False])
    assert step_classes(np.array([8.0]), elements, 1.0, 3, fast).node_class.tolist() == [3, 0, 3, 3]
    with pytest.raises(ValueError, match="levels"):
        step_classes(np.array([8.0]), elements, 1.0, 5, fast)
    with pytest.raises(ValueError, match="multirate_levels"):
        Model(graded_bar(), STEEL, multirate_levels=-1)


@pytest.mark.parametrize("damped", [False, True])
def test_graded_bar_moves_as_single_rate_and_conserves_energy(damped):
    """Up to 8 steps between a coarse node's velocity updates, over 1500 steps (about a
    tenth of the first axial period of the coarse part, thousands of the finest element's):
    the displacements stay within 0.2 % of single-rate stepping's and the energy balance
    within 2e-4 of the initial energy, with stiffness damping's dissipation counted."""
    damping = StiffnessDamping(0.02, 20e3, max_element_ratio=0.1) if damped else None
    single, probes = vibrating_bar(0, damping)
    ref, e_ref = history(single, probes, 24)
    multi, _ = vibrating_bar(3, damping)
    got, e_got = history(multi, probes, 24)
    assert multi.step_classes.element_work < 0.25
    scale = np.abs(ref[:, :4]).max(axis=0)
    assert np.all(np.abs(got[:, :4] - ref[:, :4]).max(axis=0) <= 2e-3 * scale)
    assert np.abs(ref[:, 4]).max() < 1e-5
    assert np.abs(got[:, 4]).max() < 2e-4
    if damped:
        # damping removed a measurable share, the same under both
        assert e_ref["damping"] > 1e-4 * e_ref["kinetic"]
        assert e_got["damping"] == pytest.approx(e_ref["damping"], rel=0.02)


def test_relaxation_stays_single_rate_bit_for_bit():
    """Dynamic relaxation steps every node every step, whatever the levels."""
    a, _ = vibrating_bar(0)
    b, _ = vibrating_bar(2)
    a.advance(200, relax_damping=2e4)
    b.advance(200, relax_damping=2e4)
    assert np.array_equal(a.positions(), b.positions())
    assert np.array_equal(a.velocities(), b.velocities())
    # the transient then differs (the coarse nodes wait for their steps)
    a.advance(64)
    b.advance(64)
    assert not np.array_equal(a.positions(), b.positions())


def test_stepping_modes_give_the_same_bits():
    runs = {}
    modes = ["serial", "parallel"] + (["team"] if current_threads() >= 2 else [])
    for mode in modes:
        model, _ = vibrating_bar(3)
        for _ in range(5):
            model.advance(40, record_last=True, mode=mode)  # not multiples of 8: mid-cycle
        runs[mode] = (model.positions(), model.velocities(), model.energies())
    ref = runs["serial"]
    for mode in modes[1:]:
        assert np.array_equal(runs[mode][0], ref[0]), mode
        assert np.array_equal(runs[mode][1], ref[1]), mode
        assert runs[mode][2] == ref[2], mode


def test_samples_hold_whole_cycles():
    for multiple in (1, 2, 8, 16):
        s, dt = steps_per_sample(1.0e-8, 1.0e5, multiple)
        assert s % multiple == 0 and dt <= 1.0e-8 and s * dt == pytest.approx(1e-5)
    assert steps_per_sample(1.0e-8, 1.0e5, 1) == (1000, 1e-8)
