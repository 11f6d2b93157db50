"""Bearing rings: graded polar layers from the raceway into the ring, with an optional
rectangular notch (the line spall) cut into the raceway.

The raceway is level 0. Level ``k`` lies at depth ``D_k`` behind it (outward for the outer
ring, inward for the inner ring). Near the notch the first levels are pulled up so that
level ``n_thin`` lies exactly at the notch depth; the pull fades out over a short arc, so
the thin layers stay local to the spall and do not shrink the time step of the whole ring.
The notch walls are radial lines through the spall edges and its floor is the circle at
the notch depth: edges and depth are mesh lines by construction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from taichi_bearing.mesh.grid import merge_nodes
from taichi_bearing.mesh.layers import coarsening_rows, graded_layers, notch_depths
from taichi_bearing.mesh.strip import between_levels, build_strip, plan_row

TWO_PI = 2 * math.pi


@dataclass(frozen=True)
class Notch:
    """A rectangular notch: from angle ``start`` counter-clockwise over ``span`` (rad)."""

    start: float
    span: float
    depth: float

    def contains(self, theta: np.ndarray) -> np.ndarray:
        return np.mod(np.asarray(theta) - self.start, TWO_PI) < self.span

    def distance(self, theta: np.ndarray) -> np.ndarray:
        """Angular distance to the notch's arc (0 inside), rad."""
        a = np.mod(np.asarray(theta) - self.start, TWO_PI)
        after = a - self.span
        before = TWO_PI - a
        return np.where(a <= self.span, 0.0, np.minimum(after, before))


@dataclass
class RingMesh:
    """A meshed ring: nodes, CCW quads and the node ids of its back face (bore or outside)."""

    nodes: np.ndarray
    elements: np.ndarray
    back_ids: np.ndarray
    back_theta: np.ndarray
    raceway_cells: int
    level_depths: np.ndarray
    n_thin: int = 0
    info: dict = field(default_factory=dict)


def raceway_positions(radius: float, breakpoints: list[float], size: float) -> np.ndarray:
    """Angles of the raceway nodes: every breakpoint is a node, arcs between them are
    split evenly into cells of about ``size`` arc length.

    Returns
    -------
    ndarray
        Increasing angles covering one turn, starting at the first breakpoint.
    """
    b = np.unique(np.mod(np.asarray(breakpoints, dtype=float), TWO_PI))
    if len(b) == 0:
        b = np.array([0.0])
    ends = np.append(b[1:], b[0] + TWO_PI)
    out = []
    for a0, a1 in zip(b, ends, strict=True):
        n = max(1, round(radius * (a1 - a0) / size))
        out.append(a0 + (a1 - a0) * np.arange(n) / n)
    return np.concatenate(out)


def ring_mesh(
    raceway_radius: float,
    thickness: float,
    outward: bool,
    breakpoints: list[float],
    size: float,
    max_size: float,
    growth: float,
    notch: Notch | None = None,
    layers: np.ndarray | None = None,
) -> RingMesh:
    """Mesh a ring graded from its raceway.

    Parameters
    ----------
    raceway_radius : float
        Radius of the contact surface (level 0), m.
    thickness : float
        Radial thickness of the ring, m.
    outward : bool
        True for the outer ring (layers grow outward from its bore, the raceway); False for
        the inner ring (layers grow inward from its outside, the raceway).
    breakpoints : list of float
        Angles (from +x) that must be nodes on every level (spall edges, adapter corners).
    size, max_size, growth : float
        Surface element size, largest element size (m) and layer growth ratio.
    notch : Notch, optional
        The spall to cut into the raceway.
    layers : ndarray, optional
        Layer thicknesses from the raceway, summing to ``thickness``; default graded
        from ``size`` by ``growth`` up to ``max_size``.
    """
    sign = 1.0 if outward else -1.0
    if notch is not None:
        breakpoints = list(breakpoints) + [notch.start, notch.start + notch.span]
    theta0 = raceway_positions(raceway_radius, breakpoints, size)
    arcs = _arc_cells(theta0, breakpoints)
    t = graded_layers(thickness, size, growth, max_size) if layers is None else layers
    far = np.concatenate([[0.0], np.cumsum(t)])
    far[-1] = thickness  # exact back face
    n_thin = 0
    near = far
    frozen = 1
    if notch is not None:
        near, n_thin = notch_depths(far, notch.depth)
        frozen = n_thin + 1
    ratios, plans = plan_rows(arcs, t, far, raceway_radius, sign, size, max_size, frozen)

    def weight(theta: np.ndarray) -> np.ndarray:
        # The thin notch layers end within one cell of the walls: only the elements that
        # touch the walls are thin, and the time step they set stays as large as it can.
        if notch is None:
            return np.zeros_like(theta)
        s = raceway_radius * notch.distance(theta) / size
        return np.clip(1.0 - s, 0.0, 1.0)

    def level_point(k: int, theta: np.ndarray) -> np.ndarray:
        w = weight(theta)
        depth = (1 - w) * far[k] + w * near[k]
        r = raceway_radius + sign * depth
        return r[:, None] * np.stack([np.cos(theta), np.sin(theta)], axis=1)

    strip = build_strip(
        theta0,
        plans,
        between_levels(level_point),
        periodic=True,
        breaks=np.mod(np.asarray(breakpoints, dtype=float), TWO_PI),
        period=TWO_PI,
    )
    elements = strip.elements
    if notch is not None:
        centroid = strip.nodes[elements].mean(axis=1)
        phi = np.arctan2(centroid[:, 1], centroid[:, 0])
        cut = (strip.row_of_element < n_thin) & notch.contains(phi)
        elements = elements[~cut]
    nodes, elements, new_index = merge_nodes(strip.nodes, elements, tol=1e-12 * raceway_radius)
    back = new_index[strip.levels[-1]]
    return RingMesh(
        nodes=nodes,
        elements=elements,
        back_ids=back,
        back_theta=strip.level_u[-1],
        raceway_cells=len(theta0),
        level_depths=far,
        n_thin=n_thin,
        info={"coarsening_rows": [k for k, r in enumerate(ratios) if r > 1]},
    )


def plan_rows(
    arcs: list[int],
    layers: np.ndarray,
    depths: np.ndarray,
    radius: float,
    sign: float,
    size: float,
    max_size: float,
    frozen: int,
) -> tuple[list[float], list]:
    """The coarsening ratio of every row of a ring (``layers`` thick, at ``depths`` behind
    the raceway of ``radius``, deeper by ``sign``) and each row's template plan (None
    for a plain row), from the raceway's cell count per arc; the first ``frozen`` rows
    stay plain."""
    mid = 0.5 * (depths[1:] + depths[:-1])
    widths = size * (radius + sign * mid) / radius
    ratios = coarsening_rows(layers, widths, max_size, frozen=frozen)
    plans = []
    for ratio in ratios:
        plan, arcs = plan_row(arcs, ratio)
        plans.append(plan if ratio > 1 else None)
    return ratios, plans


def _arc_cells(theta: np.ndarray, breakpoints: list[float]) -> list[int]:
    """Cell counts of the arcs between consecutive breakpoints along ``theta``."""
    b = np.unique(np.mod(np.asarray(breakpoints, dtype=float), TWO_PI))
    idx = sorted(int(np.argmin(np.abs(np.mod(theta - a + np.pi, TWO_PI) - np.pi))) for a in b)
    if not idx:
        return [len(theta)]
    idx.append(idx[0] + len(theta))
    return [j - i for i, j in zip(idx[:-1], idx[1:], strict=True)]
