"""Dynamic relaxation settles at the linear static solution of the same mesh."""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.mesh.primitives import rectangle_mesh
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.linear_reference import assemble_stiffness, linear_static
from taichi_bearing.solver.loads import FixedNodes, line_load
from taichi_bearing.solver.materials import Material
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.relaxation import relax

STEEL = Material(E=210e9, nu=0.3, rho=7850.0)


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
