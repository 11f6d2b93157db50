"""docs/architecture.md's force-contributor example runs as written: a body force added
as a kernel contributor moves a free body as ``u = g t^2 / 2`` in every stepping mode."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import importlib.util
import re
from pathlib import Path

import numpy as np
import pytest

from taichi_bearing.mesh.primitives import disk_mesh
from taichi_bearing.solver import Material, Model, init_taichi
from taichi_bearing.solver.backend import current_threads

DOC = Path(__file__).resolve().parents[1] / "docs" / "architecture.md"


@pytest.fixture(scope="module")
def body_force_class(tmp_path_factory):
    init_taichi("cpu")
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)
    example = [b for b in blocks if "class BodyForce" in b]
    assert len(example) == 1
    # A module file of its own: Taichi reads a function's source from its file.
    path = tmp_path_factory.mktemp("doc") / "architecture_example.py"
    path.write_text(example[0])
    spec = importlib.util.spec_from_file_location("architecture_example", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.BodyForce


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
