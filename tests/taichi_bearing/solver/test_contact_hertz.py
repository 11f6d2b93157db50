"""Penalty contact against Hertz: a cylinder pressed onto a flat block in plane strain."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.bodies import cylinder_cap_mesh, graded_block_mesh, merge_meshes
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
from taichi_bearing.solver.loads import FixedNodes, HeldDirection, line_load
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.relaxation import relax

E, NU, RHO = 210e9, 0.3, 7850.0
R = 0.01  # cylinder radius, m
B_TARGET = 0.2e-3  # Hertz half-width the load is chosen for, m
E_STAR = E / (2 * (1 - NU**2))  # two identical bodies, plane strain
P = np.pi * E_STAR * B_TARGET**2 / (4 * R)  # line load, N/m (thickness 1 m)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def pressed_cylinder(fine: float, scale: float, dt_factor: float, tol: float = 1e-6):
    """Relax a cylinder cap onto a block under the line load P; return mesh, contact."""
    kw = dict(fine=fine, fine_half_width=2.5 * B_TARGET, growth=1.3)
    block = graded_block_mesh(4e-3, 4e-3, **kw)
    cap = cylinder_cap_mesh(R, 4e-3, 4e-3, **kw)
    mesh = merge_meshes({"block": block, "cap": cap})
    top, bottom = mesh.node_sets["cap.top"], mesh.node_sets["block.bottom"]
    model = Model(
        mesh,
        Material(E, NU, RHO),
        constraints=[FixedNodes(bottom), HeldDirection(top, (1.0, 0.0))],
        loads=[line_load(mesh.nodes, top, (0.0, -P))],
    )
    pair = ContactPair("cap_on_block", "cap.bottom", "block.top", two_pass=True)
    contact = PenaltyContact(model, [pair], ContactParameters(penalty_scale=scale))
    model.add_contributor(contact)
    # The penalty adds stiffness of the order of the elements': a shorter step keeps it stable.
    model.set_dt(dt_factor * model.dt_stable)
    res = relax(model, ke_ratio_tol=tol, max_steps=60_000)
    assert res.converged
    model.advance(1)
    return mesh, model, contact


def pressure_profile(mesh, contact):
    """x, nodal contact force (up) and pressure of the block's top nodes."""
    ids = mesh.node_sets["block.top"]
    x = mesh.nodes[ids, 0]
    order = np.argsort(x)
    ids, x = ids[order], x[order]
    fy = contact.nodal_forces()[ids, 1] * -1.0
    trib = np.zeros_like(x)
    trib[1:-1] = 0.5 * (x[2:] - x[:-2])
    trib[0], trib[-1] = 0.5 * (x[1] - x[0]), 0.5 * (x[-1] - x[-2])
    return x, fy, fy / trib


def test_cylinder_on_block_matches_hertz():
    mesh, model, contact = pressed_cylinder(fine=B_TARGET / 10, scale=1.0, dt_factor=0.5)
    x, fy, p = pressure_profile(mesh, contact)
    # The elliptic Hertz pressure has second moment b^2 / 4 about its centre.
    b = 2.0 * np.sqrt((x**2 * fy).sum() / fy.sum())
    b_hertz = np.sqrt(4 * P * R / (np.pi * E_STAR))
    p_hertz = 2 * P / (np.pi * b_hertz)
    err_b = b / b_hertz - 1
    err_p = p.max() / p_hertz - 1
    print(f"half-width error {err_b:+.4f}, peak pressure error {err_p:+.4f}")
    assert abs(err_b) < 0.05
    assert abs(err_p) < 0.05
    # Force balance: the contact carries the load, on the block and as the pair resultant.
    fx, fy_pair, fn, _ = contact.current_resultants()[0]
    print(f"force balance error {fy.sum() / P - 1:+.2e}, resultant {-fy_pair / P - 1:+.2e}")
    assert fy.sum() == pytest.approx(P, rel=0.01)
    assert -fy_pair == pytest.approx(P, rel=0.01)  # by the cap on the block: downwards
    assert fn == pytest.approx(P, rel=0.01)
    assert abs(fx) < 1e-3 * P
    # No penetration beyond the penalty estimate: peak nodal force over the two-pass
    # stiffness (both passes push; the smaller segment stiffness bounds the gap).
    gap = contact.contact_state()["gap"]
    k_min = contact.seg_k.to_numpy()[: contact.n_seg].min()
    assert -gap.min() <= fy.max() / k_min
