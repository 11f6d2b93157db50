"""Small multi-body meshes for contact checks: merging single-part meshes and a graded
cylinder-on-block pair (fine at the contact, coarse away from it)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from taichi_bearing.mesh.grid import quad_grid, surface_chain
from taichi_bearing.mesh.types import Mesh

__all__ = ["cylinder_cap_mesh", "graded_block_mesh", "graded_positions", "merge_meshes"]


def merge_meshes(parts: Mapping[str, Mesh]) -> Mesh:
    """One :class:`Mesh` of several single- or multi-part meshes that share no nodes.

    Part names become ``"{key}"`` (one-part meshes) or ``"{key}.{part}"``; surfaces, node
    sets and sensor nodes are renamed ``"{key}.{name}"`` and renumbered.
    """
    nodes, elements, element_part, part_names = [], [], [], []
    surfaces, node_sets, sensors = {}, {}, {}
    off = 0
    for key, m in parts.items():
        nodes.append(np.asarray(m.nodes, dtype=float))
        elements.append(np.asarray(m.elements) + off)
        element_part.append(np.asarray(m.element_part) + len(part_names))
        if len(m.part_names) == 1:
            part_names.append(key)
        else:
            part_names.extend(f"{key}.{p}" for p in m.part_names)
        surfaces.update({f"{key}.{s}": np.asarray(v) + off for s, v in m.surfaces.items()})
        node_sets.update({f"{key}.{s}": np.asarray(v) + off for s, v in m.node_sets.items()})
        sensors.update({f"{key}.{s}": int(v) + off for s, v in m.sensor_nodes.items()})
        off += m.n_nodes
    return Mesh(
        nodes=np.concatenate(nodes),
        elements=np.concatenate(elements).astype(np.int64),
        element_part=np.concatenate(element_part).astype(np.int64),
        part_names=part_names,
        node_sets=node_sets,
        surfaces=surfaces,
        sensor_nodes=sensors,
    )


def graded_positions(fine: float, fine_extent: float, total: float, growth: float) -> np.ndarray:
    """Positions from 0 to ``total``: cells of ``fine`` size up to ``fine_extent``, then
    growing by ``growth`` per cell (the last cell stretched to end exactly at ``total``)."""
    if not 0 < fine <= fine_extent <= total:
        raise ValueError("need 0 < fine <= fine_extent <= total")
    n_fine = max(1, round(fine_extent / fine))
    pos = list(np.linspace(0.0, fine_extent, n_fine + 1))
    h = fine_extent / n_fine
    while pos[-1] < total - 1e-12 * total:
        h *= growth
        pos.append(min(pos[-1] + h, total))
    if len(pos) > 2 and pos[-1] - pos[-2] < 0.5 * (pos[-2] - pos[-3]):
        pos.pop(-2)  # no sliver at the end
    return np.asarray(pos)


def _mapped_mesh(xs: np.ndarray, y_rows: np.ndarray, name: str, sides: dict) -> Mesh:
    """A structured mesh with node (i, j) at (xs[i], y_rows[j, i]); rows bottom to top."""
    nx, ny = len(xs) - 1, len(y_rows) - 1
    gx = np.broadcast_to(xs, y_rows.shape)
    nodes = np.stack([gx.ravel(), y_rows.ravel()], axis=1)
    elements = quad_grid(nx, ny)
    row = nx + 1
    idx = np.arange(nodes.shape[0])
    masks = {
        "bottom": idx < row,
        "top": idx >= ny * row,
        "left": idx % row == 0,
        "right": idx % row == nx,
    }
    surfaces = {key: surface_chain(nodes, elements, lambda m, k=masks[key]: k) for key in sides}
    node_sets = {key: np.flatnonzero(masks[key]) for key in masks}
    return Mesh(
        nodes=nodes,
        elements=elements.astype(np.int64),
        element_part=np.zeros(len(elements), dtype=np.int64),
        part_names=[name],
        node_sets=node_sets,
        surfaces=surfaces,
    )


def _symmetric(half: np.ndarray) -> np.ndarray:
    return np.concatenate([-half[:0:-1], half])


def graded_block_mesh(
    half_width: float, height: float, fine: float, fine_half_width: float, growth: float
) -> Mesh:
    """Block ``[-half_width, half_width] x [-height, 0]``, fine (``fine``) along its top
    within ``|x| < fine_half_width`` and near the top, growing away. Surfaces ``top`` and
    ``bottom``, node sets ``top``, ``bottom``, ``left``, ``right``."""
    xs = _symmetric(graded_positions(fine, fine_half_width, half_width, growth))
    ys = -graded_positions(fine, fine, height, growth)[::-1]
    rows = np.repeat(ys[:, None], len(xs), axis=1)
    return _mapped_mesh(xs, rows, "block", ("top", "bottom"))


def cylinder_cap_mesh(
    radius: float,
    half_width: float,
    height: float,
    fine: float,
    fine_half_width: float,
    growth: float,
    lift: float = 0.0,
) -> Mesh:
    """The lower part of a cylinder of ``radius`` whose lowest point is at ``(0, lift)``:
    bottom on the circle, flat top at ``y = lift + height``; graded like
    :func:`graded_block_mesh`. Surfaces ``bottom`` (the curved contact face) and ``top``."""
    if half_width >= radius:
        raise ValueError("the cap must be narrower than the cylinder")
    xs = _symmetric(graded_positions(fine, fine_half_width, half_width, growth))
    arc = radius - np.sqrt(radius**2 - xs**2)
    s = graded_positions(fine, fine, height, growth) / height
    rows = lift + arc[None, :] + s[:, None] * (height - arc[None, :])
    return _mapped_mesh(xs, rows, "cap", ("top", "bottom"))
