"""Rollers: O-grid disks graded from the rolling surface to a square core.

Circular layers follow the surface (their thicknesses grow by the growth ratio and the
rows coarsen 2:1 as the circumference shrinks), then a few rows blend the last circle into
the core square, which is a plain grid. Nothing degenerates at the centre.
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.mesh.layers import coarsening_rows, graded_layers
from taichi_bearing.mesh.ogrid import o_grid_disk

# Radius where the circular layers end, and half side of the core square, over the radius.
CIRCULAR_FRACTION = 0.62
CORE_HALF_FRACTION = 0.36
# The core keeps at least this many cells per side.
MIN_CORE_CELLS = 4
# Elements narrower than this fraction of the surface size are coarsened away.
MIN_WIDTH = 0.75


def roller_surface_cells(diameter: float, size: float) -> int:
    """Segments on a roller surface: circumference / size, rounded to an even number
    (an all-quad mesh always has an even number of boundary edges)."""
    return max(8, 2 * round(math.pi * diameter / (2 * size)))


def roller_mesh(
    radius: float,
    size: float,
    max_size: float,
    growth: float,
    centre: tuple[float, float] = (0.0, 0.0),
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mesh one roller.

    Returns
    -------
    nodes, elements, surface_ids
        Coordinates (m), counter-clockwise quads, and the surface nodes in
        counter-clockwise order.
    """
    n = roller_surface_cells(2 * radius, size)
    h = 2 * math.pi * radius / n
    r_c = CIRCULAR_FRACTION * radius
    t = graded_layers(radius - r_c, h, growth, max_size)
    depth = np.concatenate([[0.0], np.cumsum(t)])
    depth[-1] = radius - r_c
    mid = 0.5 * (depth[1:] + depth[:-1])
    widths = h * (radius - mid) / radius
    max_rows = max(0, int(math.log2(n / (4 * MIN_CORE_CELLS))))
    ratios = coarsening_rows(
        t, widths, max_size, frozen=1, max_rows=max_rows, min_width=MIN_WIDTH * size
    )
    factor = float(np.prod(ratios))
    # Blend rows: about one element width each across the gap to the core square.
    half = CORE_HALF_FRACTION * radius
    width_core = h * factor * r_c / radius
    gap = r_c - half * (1 + math.sqrt(2)) / 2
    n_blend = max(1, round(gap / width_core))
    rho = list(radius - depth) + [r_c] * n_blend
    blend = [0.0] * len(depth) + list(np.arange(1, n_blend + 1) / n_blend)
    ratios = list(ratios) + [1.0] * n_blend
    return o_grid_disk(radius, n, rho, blend, half, coarsen=ratios, centre=centre)
