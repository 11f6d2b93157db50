"""Dynamic relaxation settles at the linear static solution of the same mesh, and a
preloaded model starts its transient at rest."""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.primitives import annulus_mesh, rectangle_mesh
from taichi_bearing.simulation.engine import RunConfig, run_transient
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.linear_reference import assemble_stiffness, linear_static
from taichi_bearing.solver.loads import FixedNodes, HeldDirection, line_load
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.relaxation import relax

STEEL = Material(210e9, 0.3, 7850.0)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def test_cantilever_relaxes_to_linear_static_deflection_within_1_percent():
    length, height, thickness = 0.1, 0.01, 0.02
    mesh = rectangle_mesh(length, height, 40, 4)
    X = mesh.nodes
    clamp = np.flatnonzero(np.isclose(X[:, 0], 0.0))
    tip = np.flatnonzero(np.isclose(X[:, 0], length))
    p = 200.0  # N: tip deflection ~1e-4 of the length, so geometric nonlinearity is ~1e-8
    load = line_load(X, tip, (0.0, -p), ramp_time=1e-3)  # the ramp is ignored in relaxation
    model = Model(mesh, STEEL, thickness=thickness, constraints=[FixedNodes(clamp)], loads=[load])
    result = relax(model, ke_ratio_tol=1e-8, max_steps=100_000)
    assert result.converged
    u = model.displacements()

    K = assemble_stiffness(mesh, STEEL, thickness)
    f = np.zeros((mesh.n_nodes, 2))
    np.add.at(f, load.nodes, load.forces)
    fixed = np.concatenate([2 * clamp, 2 * clamp + 1])
    u_ref = linear_static(K, f, fixed)
    err = np.abs(u[tip, 1].mean() / u_ref[tip, 1].mean() - 1)
    field_err = np.linalg.norm(u - u_ref) / np.linalg.norm(u_ref)
    print(f"relaxation: {result.steps} steps, tip error {err:.2e}, field error {field_err:.2e}")
    assert err < 0.01
    assert field_err < 0.01
    # The reference itself is a cantilever: Euler-Bernoulli tip deflection P L^3 / (3 E' I)
    # plus the shear deflection, within a few percent.
    inertia = thickness * height**3 / 12
    euler = p * length**3 / (3 * STEEL.plane_strain_modulus * inertia)
    assert -u_ref[tip, 1].mean() == pytest.approx(euler, rel=0.05)
    # Afterwards the model is at rest and ready for a transient from time 0.
    assert model.step_count == 0 and np.all(model.velocities() == 0)


def test_preloaded_ring_starts_the_transient_at_rest_in_static_equilibrium():
    mesh = annulus_mesh(0.02, 0.03, 48, 3)
    X = mesh.nodes
    r = np.hypot(X[:, 0], X[:, 1])
    bore = np.flatnonzero(np.isclose(r, 0.02))
    top = np.flatnonzero(np.isclose(r, 0.03) & (X[:, 1] > 0.027))
    load = line_load(X, top, (0.0, -2e3))
    thickness = 0.01
    model = Model(
        mesh,
        STEEL,
        thickness=thickness,
        constraints=[FixedNodes(bore), HeldDirection(top, (1.0, 0.0))],
        loads=[load],
        sensors={"top": int(top[np.argmin(np.abs(X[top, 0]))])},
    )
    result = relax(model, ke_ratio_tol=1e-8, max_steps=100_000)
    assert result.converged
    # Linear static reference with the same constraints (bore fixed, top held in x).
    K = assemble_stiffness(mesh, STEEL, thickness)
    f = np.zeros((mesh.n_nodes, 2))
    np.add.at(f, load.nodes, load.forces)
    u_ref = linear_static(K, f, np.concatenate([2 * bore, 2 * bore + 1, 2 * top]))
    u = model.displacements()
    err = np.linalg.norm(u - u_ref) / np.linalg.norm(u_ref)
    print(f"preloaded ring: {result.steps} steps, field error {err:.2e}")
    assert err < 0.01
    # The transient from this state stays put: it was statically loaded.
    res = run_transient(model, RunConfig(duration=2e-4, sample_rate=1e5))
    uy = res.column("top_uy")
    assert np.allclose(uy, u_ref[model.sensor_node.to_numpy()[0], 1], rtol=0.01)
    strain = res.column("energy_internal")
    assert np.all(res.column("energy_kinetic") < 1e-4 * strain)
