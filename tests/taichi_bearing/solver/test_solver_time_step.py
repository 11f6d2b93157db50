"""The global time step: the assembled mesh's highest frequency is the stability limit of
the central-difference steps (free vibration at 0.97 of it stays bounded, at 1.03 it
blows up), it is never below the element estimate, and the contact bound really bounds
the penalty springs."""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.primitives import rectangle_mesh
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.laws.contact import penalty_bounds, window_share
from taichi_bearing.solver.model import Model

STEEL = Material(210e9, 0.3, 7850.0)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def graded_plate():
    """10 x 2 mm plate of 0.4 mm squares with one column 0.2 mm wide: the thin column
    sets the element estimate, while its nodes carry the wide columns' mass too."""
    mesh = rectangle_mesh(10e-3, 2e-3, 25, 5)
    X = mesh.nodes.copy()
    X[np.isclose(X[:, 0], 4.0e-3), 0] = 3.8e-3
    mesh.nodes = X
    return mesh


def free_vibration_growth(model: Model, steps: int = 600) -> float:
    """Largest total energy over ``steps`` of free vibration from random velocities (every
    mode excited), relative to the start; inf once it is no longer finite."""
    rng = np.random.default_rng(11)
    model.set_state(v=rng.normal(0.0, 1e-3, size=(model.n_nodes, 2)))
    model.advance(1, record_last=True, mode="serial")

    def energy():
        e = model.energies()
        return e["kinetic"] + e["internal"] + e["hourglass"]

    e0, worst = energy(), 1.0
    for _ in range(steps // 50):
        model.advance(50, record_last=True, mode="serial")
        e = energy()
        if not np.isfinite(e):
            return np.inf
        worst = max(worst, e / e0)
    return worst


@pytest.mark.parametrize("damped", [False, True], ids=["undamped", "stiffness-damped"])
def test_global_step_is_the_stability_limit(damped):
    mesh = graded_plate()
    # capped stiffness damping: a different beta in the thin and the wide elements
    damping = StiffnessDamping(0.02, 20e3, max_element_ratio=0.1) if damped else None
    element = Model(mesh, STEEL, damping=damping)
    glob = Model(mesh, STEEL, damping=damping, time_step="global")
    print(f"dt element {element.dt:.4e}, global {glob.dt:.4e} s "
          f"(damping factor {glob.damping_step_factor:.4f})")  # fmt: skip
    # the element estimate is a bound: the global step is never smaller, here much larger
    assert glob.dt > 1.2 * element.dt
    below = Model(mesh, STEEL, damping=damping, time_step="global", dt_factor=0.97)
    above = Model(mesh, STEEL, damping=damping, time_step="global", dt_factor=1.03)
    assert free_vibration_growth(below) < 1.5
    assert free_vibration_growth(above) > 1e6


def test_contact_bound_adds_to_the_global_estimate_only():
    mesh = graded_plate()
    element = Model(mesh, STEEL)
    glob = Model(mesh, STEEL, time_step="global")
    dt_e, dt_g = element.dt, glob.dt
    top = np.flatnonzero(np.isclose(mesh.nodes[:, 1], 2e-3))
    k = 4.0 * glob.mass_np[top].max() * (2.0 / dt_g) ** 2  # springs well above the mesh's
    element.add_stiffness_bound(top, np.full(len(top), k))
    glob.add_stiffness_bound(top, np.full(len(top), k))
    assert element.dt == dt_e
    # a node spring k alone gives omega^2 = k / m; the mesh only adds to it
    omega = np.sqrt(k / glob.mass_np[top].min())
    assert 2.0 / omega * 0.9 >= glob.dt
    assert glob.dt < 0.6 * dt_g


@pytest.mark.parametrize("ratio", [0.5, 1.0, 1.4, 2.0, 2.7])
@pytest.mark.parametrize("spacing", ["uniform", "short segments"])
def test_penalty_bound_dominates_every_spring_and_dashpot_arrangement(ratio, spacing):
    # A chain of query nodes pressed onto a chain of segments (ratio = segment length /
    # query spacing), each query node on a spring k to its foot point N1 x1 + N2 x2, and
    # on a dashpot 2 zeta sqrt(k m_eff) (m_eff of the node and the foot point, random
    # masses). The springs' matrix P and the dashpots' matrix C (one direction) must lie
    # below the bound's diagonals for every offset of the two chains: D - P and E - C
    # positive semidefinite. "short segments": two query spacings cut to a fifth (a
    # spall's walls), which the bound takes in only where they are.
    n_seg = 12
    seg_x = np.arange(n_seg + 1, dtype=float)
    zeta = 0.2
    rng = np.random.default_rng(int(10 * ratio))
    for offset in np.linspace(0.0, 1.0, 7):
        gaps = np.full(int(n_seg * ratio) + 2, 1.0 / ratio)
        if spacing == "short segments":
            gaps[len(gaps) // 2 : len(gaps) // 2 + 2] *= 0.2
        q_x = offset + np.concatenate([[0.0], np.cumsum(gaps)])
        q_x = q_x[q_x < n_seg]
        n_q = len(q_x)
        nodes = np.zeros((n_seg + 1 + n_q, 2))
        nodes[: n_seg + 1, 0] = seg_x
        nodes[n_seg + 1 :, 0] = q_x
        mass = rng.uniform(0.5, 2.0, len(nodes))
        segs = np.stack([np.arange(n_seg), np.arange(1, n_seg + 1)], axis=1)
        q_ids = n_seg + 1 + np.arange(n_q)
        q_segs = np.stack([q_ids[:-1], q_ids[1:]], axis=1)
        k = 3.0
        k_node, c_node = penalty_bounds(nodes, [(q_segs, segs, np.full(n_seg, k))], mass, zeta)
        P = np.zeros((len(nodes), len(nodes)))
        C = np.zeros_like(P)
        for j, x in zip(q_ids, q_x, strict=True):
            s = min(int(x), n_seg - 1)
            xi = x - s
            g = np.zeros(len(nodes))
            g[j] = 1.0
            g[s] -= 1.0 - xi
            g[s + 1] -= xi
            P += k * np.outer(g, g)
            m_s = (1.0 - xi) * mass[s] + xi * mass[s + 1]
            m_eff = mass[j] * m_s / (mass[j] + m_s)
            C += 2.0 * zeta * np.sqrt(k * m_eff) * np.outer(g, g)
        worst = np.linalg.eigvalsh(np.diag(k_node) - P)[0]
        assert worst > -1e-9 * k, (offset, worst)
        worst = np.linalg.eigvalsh(np.diag(c_node) - C)[0]
        assert worst > -1e-9 * k, (offset, "dashpots", worst)


def test_window_share_counts_short_segments_only_where_they_are():
    # Query nodes at 0, 1, 2, 3, 3.2, 3.4, 4.4, 5.4 (two short segments in a unit-spaced
    # chain), segments of length 1: the largest sum of hats max(0, 1 - s) is at 3.2:
    # 0.8 + 1 + 0.8 = 2.6. A bound from the shortest spacing alone (as if all were 0.2)
    # would be 1 + 2 (0.8 + 0.6 + 0.4 + 0.2) = 5.
    x = np.array([0.0, 1.0, 2.0, 3.0, 3.2, 3.4, 4.4, 5.4])
    nodes = np.stack([x, np.zeros_like(x)], axis=1)
    chain = np.stack([np.arange(7), np.arange(1, 8)], axis=1)
    assert window_share(nodes, chain, 1.0) == pytest.approx(2.6, rel=1e-12)
    # uniform spacing h: 1 + 2 sum_j (1 - j h / L)
    uniform = np.stack([np.arange(8.0), np.zeros(8)], axis=1)
    assert window_share(uniform, chain, 2.5) == pytest.approx(1 + 2 * (0.6 + 0.2))
