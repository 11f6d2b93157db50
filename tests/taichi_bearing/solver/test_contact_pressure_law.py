"""The pressure contact law: a pressure per unit overlap the mesh does not set.

A flat block pressed on another overlaps by ``sigma / p_s`` however fine either is meshed
(the segment law's overlap moves with the element size); a cylinder pressed on a block at
a fixed ``p_s`` gives Hertz's half-width and peak pressure (Johnson, Contact Mechanics,
1985, eqs. 4.43-4.45) as the mesh is refined. Both relax at the stable step the law's
bound allows, so the bound is exercised too (an unstable step would not settle)."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.bodies import merge_meshes
from taichi_bearing.mesh.primitives import rectangle_mesh
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
from taichi_bearing.solver.loads import FixedNodes, HeldDirection, uniform_load
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.relaxation import relax
from taichi_bearing.validation.hertz_static import B_TARGET, E_STAR, NU, RHO, E, P, cylinder_patch


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def pressed_blocks(n: int, law: str, sigma: float = 200e6):
    """A 2 x 1 mm block pressed with ``sigma`` onto a fixed 2 x 1 mm block, both ``n``
    square elements across, no friction, thickness 1 m, relaxed; returns the
    overlaps (m) of the closed contacts away from the blocks' ends, by their nodes' x (m,
    rounded to 1 nm: both surfaces' nodes, so each x twice on like meshes)."""
    top = rectangle_mesh(2e-3, 1e-3, n, n // 2, origin=(0.0, 1e-3))
    base = rectangle_mesh(2e-3, 1e-3, n, n // 2, origin=(0.0, 0.0))
    mesh = merge_meshes({"top": top, "base": base})
    ids = np.unique(mesh.elements[mesh.element_part == mesh.part_id("top")])
    model = Model(
        mesh,
        Material(E, NU, RHO),
        # frictionless: the top block's top edge is held sideways
        constraints=[
            FixedNodes(mesh.node_sets["base.bottom"]),
            HeldDirection(mesh.node_sets["top.top"], (1.0, 0.0)),
        ],
        loads=[uniform_load(ids, (0.0, -sigma * 2e-3))],
        time_step="global",  # the step the contact's springs allow
    )
    params = ContactParameters(
        penalty_method=law, penalty_scale=1.0, penalty_pressure=1e15, smoothing=False
    )
    pair = ContactPair("press", "top.bottom", "base.top", two_pass=True)
    contact = PenaltyContact(model, [pair], params)
    model.add_contributor(contact)
    assert relax(model, ke_ratio_tol=1e-6, max_steps=100_000).converged
    state = contact.contact_state()
    x = mesh.nodes[state["node"], 0]
    inner = (state["segment"] >= 0) & (np.abs(x - 1e-3) <= 0.5e-3 + 1e-9)
    fy = contact.current_resultants()[0, 1]
    assert fy == pytest.approx(-sigma * 2e-3, rel=1e-3)  # the contact carries the load
    return dict(zip(np.round(x[inner], 9), -state["gap"][inner], strict=False))


def test_pressure_law_overlap_is_the_same_on_every_mesh():
    """p_s = 1e15 Pa/m under 200 MPa: 0.2 um of overlap in the middle half of the blocks
    (the pressure there is within a few % of the mean: the fixed base holds its bottom
    from spreading) on 8 and on 16 elements across, the same at the nodes both have; the
    segment law's overlap halves when its elements halve."""
    expect = 200e6 / 1e15
    coarse, fine = (pressed_blocks(n, "pressure") for n in (8, 16))
    for over in (coarse, fine):
        assert len(over) >= 4
        np.testing.assert_allclose(list(over.values()), expect, rtol=0.06)
    # where both meshes have nodes, the same overlap (to the 2 % the pressure's own
    # discretisation moves between the meshes)
    common = sorted(set(coarse) & set(fine))
    assert len(common) >= 3
    ratio = np.array([coarse[x] / fine[x] for x in common])
    print("pressure law, overlap 8 / 16 elements at common nodes:", ratio)
    np.testing.assert_allclose(ratio, 1.0, atol=0.03)
    seg_coarse, seg_fine = (pressed_blocks(n, "segment") for n in (8, 16))
    ratio = np.array([seg_coarse[x] / seg_fine[x] for x in common])
    np.testing.assert_allclose(ratio, 2.0, rtol=0.05)


def test_cylinder_on_block_converges_to_hertz_at_a_fixed_penalty():
    """alpha = 30 (p_s = 30 E* / b): refining from b/2 to b/4 brings the half-width and the
    peak pressure towards Hertz, within 5 % at b/4; the load is carried."""
    p_hertz = 2 * P / (np.pi * B_TARGET)
    errors = []
    for fine in (B_TARGET / 2, B_TARGET / 4):
        patch = cylinder_patch(fine, 30 * E_STAR / B_TARGET)
        assert patch["force_N"] == pytest.approx(P, rel=0.01)
        errors.append(
            (patch["half_width_m"] / B_TARGET - 1, patch["peak_pressure_Pa"] / p_hertz - 1)
        )
    print("half-width, peak pressure errors (b/2, b/4):", errors)
    (b2, p2), (b4, p4) = errors
    assert abs(b4) < 0.05 and abs(p4) < 0.05
    assert abs(b4) <= abs(b2) + 0.005 and abs(p4) <= abs(p2) + 0.005
