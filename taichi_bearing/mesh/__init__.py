"""Parametric 2-D meshing of the bearing; returns a :class:`Mesh` of plain arrays."""

from taichi_bearing.mesh.types import Mesh

__all__ = ["Mesh"]
