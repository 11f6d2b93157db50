"""The damped elements take their strain rate from their strain history
(``element_forces.seed_strain_history``): the Green strain and hourglass sum of their last
evaluation. Checked against the law written on the nodes' velocities, computed here in
numpy: exactly (to rounding) on the step after the history is seeded from the
velocities (a new state, a restart), within O(dt |grad v|) on the steps after."""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.primitives import rectangle_mesh
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.model import Model

STEEL = Material(210e9, 0.3, 7850.0)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def damped_block() -> Model:
    """A free 20 x 10 mm steel block of 8 x 4 elements with stiffness damping."""
    return Model(rectangle_mesh(0.02, 0.01, 8, 4), STEEL, damping=StiffnessDamping(0.05, 50e3))


def velocity_damping_power(model: Model, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Each element's damping power at positions ``x`` with the Green strain rate
    ``sym(F^T grad v)`` and hourglass rate of velocities ``v`` (the law before the
    history), W."""
    ne = model.n_elements
    conn = np.asarray(model.mesh.elements)
    bx, by = model.bx.to_numpy()[:ne], model.by.to_numpy()[:ne]
    gam, at, khg = (f.to_numpy()[:ne] for f in (model.gam, model.at, model.khg))
    lam, mu, beta = (f.to_numpy()[:ne] for f in (model.lam, model.mu, model.beta_e))
    b = np.stack([bx, by], axis=2)  # (ne, 4, 2)
    F = np.einsum("eki,ekj->eij", x[conn], b)
    Fd = np.einsum("eki,ekj->eij", v[conn], b)
    qd = np.einsum("ek,eki->ei", gam, v[conn])
    Ed = 0.5 * (np.einsum("eki,ekj->eij", F, Fd) + np.einsum("eki,ekj->eij", Fd, F))
    tr = Ed[:, 0, 0] + Ed[:, 1, 1]
    power = at * (lam * tr**2 + 2.0 * mu * np.sum(Ed**2, axis=(1, 2)))
    return beta * (power + khg * np.sum(qd**2, axis=1))


def damping_power_of_next_step(model: Model) -> np.ndarray:
    """The damping power each element takes in the next step (its dissipated energy over
    the step, divided by the step)."""
    before = model.e_damp.to_numpy()[: model.n_elements].copy()
    model.advance(1)
    return (model.e_damp.to_numpy()[: model.n_elements] - before) / model.dt


def deformed_state(model: Model, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Positions 0.1 % strained at random and random velocities of 0.5 m/s."""
    rng = np.random.default_rng(seed)
    X = np.asarray(model.mesh.nodes, dtype=float)
    x = X + 2e-6 * rng.standard_normal(X.shape)
    v = 0.5 * rng.standard_normal(X.shape)
    return x, v


def test_the_step_after_a_new_state_damps_as_its_velocities_say():
    model = damped_block()
    model.advance(10)  # a history that the new state must replace
    for seed in (1, 2):
        x, v = deformed_state(model, seed)
        model.set_state(x=x, v=v)
        expected = velocity_damping_power(model, x, v)
        got = damping_power_of_next_step(model)
        assert expected.min() > 0
        np.testing.assert_allclose(got, expected, rtol=1e-8)


def test_later_steps_follow_the_velocities_to_order_dt():
    model = damped_block()
    x, v = deformed_state(model, 3)
    model.set_state(x=x, v=v)
    model.advance(200)
    worst = 0.0
    for _ in range(5):
        x, v = model.positions(), model.velocities()  # x_n and v_(n-1/2)
        expected = velocity_damping_power(model, x, v)
        got = damping_power_of_next_step(model)
        worst = max(worst, np.max(np.abs(got - expected)) / expected.max())
    # rates over one step against those of its velocity: dt |grad v| ~ 1e-8 s x 1e3 / s
    print(f"history against velocities: {worst:.1e} of the largest element power")
    assert 0 < worst < 1e-4


def test_a_resumed_state_keeps_its_history():
    a, b = damped_block(), damped_block()
    x, v = deformed_state(a, 4)
    a.set_state(x=x, v=v)
    a.advance(37)
    b.load_state_arrays(a.state_arrays())
    a.advance(25)
    b.advance(25)
    assert np.array_equal(a.positions(), b.positions())
    assert np.array_equal(a.e_damp.to_numpy(), b.e_damp.to_numpy())
    # a checkpoint without the history (older) is seeded again from its velocities
    old = {k: w for k, w in a.state_arrays().items() if k not in ("e_prev", "q_prev")}
    c = damped_block()
    c.load_state_arrays(old)
    assert c.history_stale
    expected = velocity_damping_power(c, c.positions(), c.velocities())
    np.testing.assert_allclose(damping_power_of_next_step(c), expected, rtol=1e-8)


def test_a_multirate_element_is_seeded_over_its_own_step():
    """With multi-rate stepping an element of class c steps 2**c dt at a time, and its
    history is seeded that far back: its first evaluation damps as the velocities say."""
    from test_solver_multirate import vibrating_bar

    model, _ = vibrating_bar(3, StiffnessDamping(0.02, 20e3))
    model.prepare_step_classes()
    cls = model.step_classes.element_class
    assert cls.min() == 0 and cls.max() == 3
    x, v = model.positions(), model.velocities()
    expected = velocity_damping_power(model, x, v)
    before = model.e_damp.to_numpy()[: model.n_elements].copy()
    model.advance(1)  # step 0: every class moves
    got = (model.e_damp.to_numpy()[: model.n_elements] - before) / (model.dt * 2.0**cls)
    np.testing.assert_allclose(got, expected, rtol=1e-8, atol=1e-12 * expected.max())
