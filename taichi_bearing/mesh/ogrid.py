r"""O-grid disks: rings of quads around a square core, so no element degenerates at the
centre.

The disk's surface level has :math:`n = 2 (p + q)` cells split into four arcs of
:math:`p, q, p, q` cells (top, left, bottom, right of the core square). Node positions
:math:`u` count surface cells counter-clockwise from the top-right corner; every level of
the rings keeps those positions (coarser levels keep a subset), and a level :math:`k`
blends a circle of radius :math:`\rho_k` with the core square:
:math:`(1 - w_k) \rho_k e(\theta(u)) + w_k \, \mathrm{square}(u)`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from taichi_bearing.mesh.grid import coons_patch, merge_nodes, orient_ccw, quad_grid
from taichi_bearing.mesh.strip import between_levels, build_strip, plan_row


def side_counts(n_surface: int) -> tuple[int, int]:
    """Cells ``(p, q)`` on the top/bottom and left/right arcs of a surface of ``n`` cells."""
    if n_surface < 4 or n_surface % 2:
        raise ValueError(f"an O-grid surface needs an even cell count >= 4, got {n_surface}")
    half = n_surface // 2
    p = (half + 1) // 2
    return p, half - p


def disk_angle(u: np.ndarray, n_surface: int) -> np.ndarray:
    """Polar angle of surface position ``u``; the top arc is centred on 12 o'clock."""
    p, _ = side_counts(n_surface)
    return np.pi / 2 + 2 * np.pi * (np.asarray(u, dtype=float) - p / 2) / n_surface


def square_point(u: np.ndarray, n_surface: int, half: float) -> np.ndarray:
    """Point of the core square (half side ``half``) at surface position ``u``.

    The corners sit at the arc breakpoints ``0, p, p + q, 2p + q``; positions between two
    corners are spread linearly along that side.
    """
    p, q = side_counts(n_surface)
    corner_u = np.array([0, p, p + q, 2 * p + q, n_surface], dtype=float)
    corners = half * np.array([[1, 1], [-1, 1], [-1, -1], [1, -1], [1, 1]], dtype=float)
    u = np.mod(np.asarray(u, dtype=float), n_surface)
    side = np.clip(np.searchsorted(corner_u, u, side="right") - 1, 0, 3)
    t = (u - corner_u[side]) / (corner_u[side + 1] - corner_u[side])
    return (1 - t)[:, None] * corners[side] + t[:, None] * corners[side + 1]


def o_grid_disk(
    radius: float,
    n_surface: int,
    rho: Sequence[float],
    blend: Sequence[float],
    half: float,
    coarsen: Sequence[float] | None = None,
    centre: tuple[float, float] = (0.0, 0.0),
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mesh a disk as rings of levels around a square core.

    Parameters
    ----------
    radius : float
        Disk radius; level 0 must be the surface (``rho[0] == radius``, ``blend[0] == 0``).
    n_surface : int
        Cells on the surface (even).
    rho, blend : sequence of float
        Circle radius and square weight of every level, surface first; the last level must
        be the square (``blend[-1] == 1``).
    half : float
        Half side of the core square.
    coarsen : sequence of float, optional
        Coarsening ratio of each row (1 = plain row, 2 or 3 = template row); default plain.
    centre : (float, float)
        Centre of the disk.

    Returns
    -------
    nodes, elements, surface_ids
        Counter-clockwise quads; ``surface_ids`` are the surface nodes in order.
    """
    if abs(rho[0] - radius) > 1e-12 * radius or blend[0] != 0 or blend[-1] != 1:
        raise ValueError("levels must run from the surface circle to the core square")
    n_rows = len(rho) - 1
    ratios = list(coarsen) if coarsen is not None else [1.0] * n_rows
    p, q = side_counts(n_surface)
    arcs = [p, q, p, q]
    plans = []
    for ratio in ratios:
        plan, arcs = plan_row(arcs, ratio)
        plans.append(plan if ratio > 1 else None)

    def level_point(k: int, u: np.ndarray) -> np.ndarray:
        theta = disk_angle(u, n_surface)
        circle = rho[k] * np.stack([np.cos(theta), np.sin(theta)], axis=1)
        return (1 - blend[k]) * circle + blend[k] * square_point(u, n_surface, half)

    strip = build_strip(
        np.arange(n_surface, dtype=float),
        plans,
        between_levels(level_point),
        periodic=True,
        breaks=np.array([0, p, p + q, 2 * p + q], dtype=float),
        period=float(n_surface),
    )
    # Core: a Coons patch on the innermost level, p' x q' cells.
    last = strip.nodes[strip.levels[-1]]
    pc, qc = arcs[0], arcs[1]
    n_last = 2 * (pc + qc)
    ring = np.concatenate([last, last[:1]])
    top = ring[0 : pc + 1][::-1]
    left = ring[pc : pc + qc + 1][::-1]
    bottom = ring[pc + qc : 2 * pc + qc + 1]
    right = ring[2 * pc + qc : n_last + 1]
    core_nodes = coons_patch(bottom, right, top, left)
    core_elements = quad_grid(pc, qc) + len(strip.nodes)
    nodes = np.concatenate([strip.nodes, core_nodes])
    elements = np.concatenate([strip.elements, core_elements])
    nodes, elements, new_index = merge_nodes(nodes, elements, tol=1e-9 * radius)
    nodes = nodes + np.asarray(centre, dtype=float)
    return nodes, orient_ccw(nodes, elements), new_index[strip.levels[0]]
