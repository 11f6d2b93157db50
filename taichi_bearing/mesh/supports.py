"""Which nodes of a bearing mesh the run holds: the rigid plate on the adapter top or the
housing round the outer ring (numpy only, so the Taichi-free modal analysis can use them
as the run does)."""

from __future__ import annotations

import numpy as np

from taichi_bearing.mesh.types import Mesh

__all__ = ["outer_surface_nodes", "support_plate_nodes"]


def outer_surface_nodes(mesh: Mesh, radius: float) -> np.ndarray:
    """Nodes of the outer ring on its outside circle of ``radius`` (m), all the way round
    (under the adapter too: the adapter shares the ring's nodes there)."""
    ids = np.unique(mesh.elements[mesh.element_part == mesh.part_id("outer_ring")])
    r = np.hypot(mesh.nodes[ids, 0], mesh.nodes[ids, 1])
    # a tolerance well below the smallest element, above round-off
    return ids[np.abs(r - radius) < 1e-6 * radius]


def support_plate_nodes(case, mesh: Mesh) -> np.ndarray:
    """Nodes of the rigid plate that carries the load W (one shared vertical motion, x
    held), by ``case.bearing.outer_support``.

    ``adapter``: the adapter top. Holding x alone would leave a zero-energy tilt of the
    outer ring about the top's centre (every top node can move vertically on its own)
    that roller friction would drive; the plate cannot tilt. ``housing``: a rigid
    housing over the outer ring's whole outside (the adapter rides along on it), so the
    outer ring is supported all round as in Harris's rigid-ring load distribution.
    """
    if case.bearing.outer_support == "housing":
        return outer_surface_nodes(mesh, case.bearing.outer_ring_outer_radius)
    return np.asarray(mesh.node_sets["adapter_top"])
