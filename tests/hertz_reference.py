"""A set-up the contact tests share: a cylinder cap pressed onto a flat block in plane
strain (thickness 1 m) under a line load chosen for a given Hertz half-width, relaxed,
and the pressure read from the block's top nodes."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.bodies import cylinder_cap_mesh, graded_block_mesh, merge_meshes
from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
from taichi_bearing.solver.loads import FixedNodes, HeldDirection, line_load
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.relaxation import relax

E, NU, RHO = 210e9, 0.3, 7850.0
R = 0.01  # cylinder radius, m
B_TARGET = 0.2e-3  # Hertz half-width the load is chosen for, m
E_STAR = E / (2 * (1 - NU**2))  # two identical bodies, plane strain
P = np.pi * E_STAR * B_TARGET**2 / (4 * R)  # line load, N/m (thickness 1 m)


def pressed_cylinder(
    fine: float,
    params: ContactParameters,
    law=None,
    dt_factor: float = 1.0,
    tol: float = 1e-6,
    time_step: str = "element",
):
    """Relax a cylinder cap onto a block under the line load P, elements of ``fine``
    along both surfaces within 2.5 b of the centre; returns mesh, model, contact."""
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
        time_step=time_step,
    )
    pair = ContactPair("cap_on_block", "cap.bottom", "block.top", two_pass=True)
    contact = PenaltyContact(model, [pair], params, law=law)
    model.add_contributor(contact)
    model.set_dt(dt_factor * model.dt_stable)
    res = relax(model, ke_ratio_tol=tol, max_steps=60_000)
    assert res.converged
    model.advance(1)
    return mesh, model, contact


def pressure_profile(mesh, contact):
    """x, nodal contact force (up), pressure and tributary length of the block's top
    nodes."""
    ids = mesh.node_sets["block.top"]
    x = mesh.nodes[ids, 0]
    order = np.argsort(x)
    ids, x = ids[order], x[order]
    fy = contact.nodal_forces()[ids, 1] * -1.0
    trib = np.zeros_like(x)
    trib[1:-1] = 0.5 * (x[2:] - x[:-2])
    trib[0], trib[-1] = 0.5 * (x[1] - x[0]), 0.5 * (x[-1] - x[-2])
    return x, fy, fy / trib, trib
