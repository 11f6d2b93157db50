r"""A cylinder pressed onto a flat block, against Hertz: the contact patch's half-width and
peak pressure as the mesh is refined at a fixed penalty.

A cylinder cap of radius :math:`R` = 10 mm on a 4 x 4 mm block in plane strain (thickness
1 m), both steel, under the line load that gives a Hertz half-width of 0.2 mm
(:math:`P = \pi E^* b^2 / (4 R)`; Johnson, Contact Mechanics, 1985, eqs. 4.43-4.45), relaxed to
rest; the pressure is read from the block's top nodes, the shape functions' spread taken
off (:func:`taichi_bearing.analytic.contact_pressure.contact_spread`).

``python -m taichi_bearing.validation.hertz_static`` prints the table of
``docs/results/hertz_static/``.
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import argparse

import numpy as np

from taichi_bearing.analytic.contact_pressure import contact_spread, nodal_patch
from taichi_bearing.case.material import Material
from taichi_bearing.mesh.bodies import cylinder_cap_mesh, graded_block_mesh, merge_meshes
from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
from taichi_bearing.solver.laws import PressurePenalty
from taichi_bearing.solver.loads import FixedNodes, HeldDirection, line_load
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.relaxation import relax

__all__ = ["cylinder_patch", "main", "pressed_cylinder", "pressure_profile"]

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
    max_steps: int = 400_000,
    scale_masses: bool = False,
):
    """Relax a cylinder cap onto a block under the line load P, elements of ``fine``
    along both surfaces within 2.5 b of the centre (with the contact nodes made heavier
    for it where ``scale_masses``: :func:`~taichi_bearing.solver.relaxation.relax`);
    returns mesh, model, contact and the relaxation's result."""
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
    res = relax(model, ke_ratio_tol=tol, max_steps=max_steps, scale_masses=scale_masses)
    if not res.converged:
        raise RuntimeError(f"the cylinder did not come to rest in {max_steps} steps: {res}")
    model.advance(1)
    return mesh, model, contact, res


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


def cylinder_patch(fine: float, pressure: float, scale_masses: bool = False) -> dict:
    """The cylinder relaxed onto its block through the pressure law ``pressure`` (Pa/m)
    at the global stable step (which counts the law's springs; with the contact nodes
    heavier for the relaxation where ``scale_masses``); the patch of
    :func:`~taichi_bearing.analytic.contact_pressure.nodal_patch` read from the block's
    top nodes with the spread of elements ``fine`` taken off. Taichi must be started."""
    mesh, _, contact, _ = pressed_cylinder(
        fine,
        ContactParameters(),
        law=PressurePenalty(pressure),
        time_step="global",
        scale_masses=scale_masses,
    )
    x, fy, _, trib = pressure_profile(mesh, contact)
    return nodal_patch(x, fy, trib, 1.0, float(contact_spread(fine)))


def main(argv: list[str] | None = None) -> int:
    """Print the table: half-width and peak pressure against Hertz by mesh and alpha."""
    p = argparse.ArgumentParser(prog="python -m taichi_bearing.validation.hertz_static")
    p.add_argument("--per-b", default="2,4,8", help="elements per Hertz half-width")
    p.add_argument("--alpha", default="10,30,100", help="p_s = alpha E* / b")
    args = p.parse_args(argv)
    from taichi_bearing.solver.backend import init_taichi

    init_taichi("cpu")
    p_hertz = 2 * P / (np.pi * B_TARGET)
    print("| elements per b | alpha | half-width error | nodal half-width error "
          "| peak pressure error | force error |")  # fmt: skip
    print("|---:|---:|---:|---:|---:|---:|")
    for alpha in (float(a) for a in args.alpha.split(",")):
        for n in (int(k) for k in args.per_b.split(",")):
            patch = cylinder_patch(B_TARGET / n, alpha * E_STAR / B_TARGET)
            print(
                f"| {n} | {alpha:g} | {patch['half_width_m'] / B_TARGET - 1:+.2%} "
                f"| {patch['nodal_half_width_m'] / B_TARGET - 1:+.2%} "
                f"| {patch['peak_pressure_Pa'] / p_hertz - 1:+.2%} "
                f"| {patch['force_N'] / P - 1:+.2%} |"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
