"""The adapter: a block sitting on top of the outer ring, meshed as one body with it.

Its bottom follows the ring's outside between the two adapter corners, using the ring's
own nodes there (shared nodes, no tie); its top is flat at the adapter height. A Coons
patch fills it with vertical columns above the ring's nodes.
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.mesh.grid import coons_patch, quad_grid


def adapter_corner_angles(ring_radius: float, width: float) -> tuple[float, float]:
    """Angles (from +x) where the adapter's vertical sides meet the ring's outside:
    right corner first."""
    a = math.acos(0.5 * width / ring_radius)
    return a, math.pi - a


def adapter_mesh(
    bottom: np.ndarray, top_y: float, max_size: float, min_size: float = 0.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mesh the adapter above the ring nodes ``bottom``.

    Parameters
    ----------
    bottom : ndarray, shape (n + 1, 2)
        The ring's outside nodes under the adapter, from its left corner to its right.
    top_y : float
        Height of the adapter's flat top, m.
    max_size : float
        Largest element height at the adapter's tall sides, m.
    min_size : float
        Smallest element height at its lowest point (a wide adapter is much lower in the
        middle than at its sides; thin elements there would cut the time step), m.

    Returns
    -------
    nodes, elements, top_ids
        Coordinates, quads (counter-clockwise) and the top face's node ids, left to right.
    """
    bottom = np.asarray(bottom, dtype=float)
    n_u = len(bottom) - 1
    x_left, x_right = bottom[0, 0], bottom[-1, 0]
    tallest = top_y - min(bottom[0, 1], bottom[-1, 1])
    lowest = top_y - bottom[:, 1].max()
    n_v = math.ceil(tallest / max_size - 1e-9)
    if min_size > 0:
        n_v = min(n_v, math.floor(lowest / min_size + 1e-9))
    n_v = max(1, n_v)
    top = np.stack([bottom[:, 0], np.full(n_u + 1, top_y)], axis=1)
    s = np.arange(n_v + 1) / n_v
    left = np.stack([np.full(n_v + 1, x_left), bottom[0, 1] + s * (top_y - bottom[0, 1])], 1)
    right = np.stack([np.full(n_v + 1, x_right), bottom[-1, 1] + s * (top_y - bottom[-1, 1])], 1)
    nodes = coons_patch(bottom, right, top, left)
    elements = quad_grid(n_u, n_v)
    top_ids = n_v * (n_u + 1) + np.arange(n_u + 1)
    return nodes, elements, top_ids
