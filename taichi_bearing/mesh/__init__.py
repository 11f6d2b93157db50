"""Parametric 2-D meshing of the bearing; returns a :class:`Mesh` of plain arrays.

``build_bearing_mesh(spec_from_case(case))`` meshes a case; ``rectangle_mesh``,
``annulus_mesh`` and ``disk_mesh`` give single bodies for tests; ``mesh_statistics``
reports sizes, quality and the critical time step. Names are imported on first use, so
``import taichi_bearing.mesh.types`` stays light and free of import cycles.
"""

from __future__ import annotations

import importlib

from taichi_bearing.mesh.types import Mesh

_WHERE = {
    "BearingMeshSpec": "spec",
    "spec_from_case": "spec",
    "build_bearing_mesh": "bearing_mesh",
    "annulus_mesh": "primitives",
    "disk_mesh": "primitives",
    "rectangle_mesh": "primitives",
    "MeshStatistics": "quality",
    "mesh_statistics": "quality",
}

__all__ = ["Mesh", *sorted(_WHERE)]


def __getattr__(name: str):
    if name in _WHERE:
        return getattr(importlib.import_module(f"taichi_bearing.mesh.{_WHERE[name]}"), name)
    raise AttributeError(f"module 'taichi_bearing.mesh' has no attribute {name!r}")
