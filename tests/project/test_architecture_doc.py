"""docs/architecture.md's examples run as written: a body force added as a kernel
contributor moves a free body as ``u = g t^2 / 2`` in every stepping mode, and a contact
law added as a ContactLaw subclass pushes each penetrating node with its own stiffness
times the penetration, carrying the load."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import importlib.util
import re
from pathlib import Path

import numpy as np
import pytest

from taichi_bearing.mesh.bodies import merge_meshes
from taichi_bearing.mesh.primitives import disk_mesh, rectangle_mesh
from taichi_bearing.solver import Material, Model, init_taichi
from taichi_bearing.solver.backend import current_threads
from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
from taichi_bearing.solver.loads import FixedNodes, uniform_load
from taichi_bearing.solver.relaxation import relax

DOC = Path(__file__).resolve().parents[2] / "docs" / "architecture.md"


def documented_class(tmp_path_factory, name: str):
    """The class ``name`` of the one Python block of the page that defines it."""
    init_taichi("cpu")
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    example = [b for b in blocks if f"class {name}" in b]
    assert len(example) == 1
    # A module file of its own: Taichi reads a function's source from its file.
    path = tmp_path_factory.mktemp("doc") / f"architecture_{name.lower()}.py"
    path.write_text(example[0])
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return getattr(module, name)


@pytest.fixture(scope="module")
def body_force_class(tmp_path_factory):
    return documented_class(tmp_path_factory, "BodyForce")


@pytest.mark.parametrize("mode", ["serial", "team", "parallel"])
def test_documented_body_force_accelerates_a_free_disk(body_force_class, mode):
    if mode == "team" and current_threads() < 2:
        pytest.skip("team stepping needs two CPU threads")
    g = (3.0, -9.81)
    model = Model(disk_mesh(0.01, 12), Material(210e9, 0.3, 7850.0))
    model.add_contributor(body_force_class(model, g))
    model.advance(400, mode=mode)
    t = model.time
    # Uniform acceleration: leapfrog with a half first step is exact.
    u = model.displacements()
    np.testing.assert_allclose(u, np.broadcast_to(0.5 * np.array(g) * t**2, u.shape), rtol=1e-9)


def test_documented_contact_law_pushes_with_its_own_stiffness(tmp_path_factory):
    """A 2 x 1 mm block pressed with 2 kN (per 1 m thickness) onto a fixed block through
    the page's ConstantPenalty(k): at rest, every closed contact's force is exactly k times
    its penetration (a point contact, no damping), and the contacts carry the load."""
    law_class = documented_class(tmp_path_factory, "ConstantPenalty")
    k, load = 2e9, 2e3
    top = rectangle_mesh(2e-3, 1e-3, 8, 4, origin=(0.0, 1e-3))
    base = rectangle_mesh(4e-3, 1e-3, 16, 4, origin=(-1e-3, 0.0))
    mesh = merge_meshes({"top": top, "base": base})
    ids = np.unique(mesh.elements[mesh.element_part == mesh.part_id("top")])
    model = Model(
        mesh,
        Material(210e9, 0.3, 7850.0),
        constraints=[FixedNodes(mesh.node_sets["base.bottom"])],
        loads=[uniform_load(ids, (0.0, -load))],
    )
    params = ContactParameters(smoothing=False)
    contact = PenaltyContact(
        model, [ContactPair("press", "top.bottom", "base.top")], params, law=law_class(k)
    )
    assert contact.law.name == "constant"
    model.add_contributor(contact)
    assert relax(model, ke_ratio_tol=1e-8).converged
    state = contact.contact_state()
    closed = state["segment"] >= 0
    assert closed.sum() >= 5
    np.testing.assert_array_equal(state["fn"][closed], k * -state["gap"][closed])
    # the resultant on the base (force by the top on it) balances the load
    fy = contact.current_resultants()[0, 1]
    assert fy == pytest.approx(-load, rel=1e-3)
