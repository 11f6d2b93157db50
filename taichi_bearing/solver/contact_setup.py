"""Plain-numpy set-up of penalty contact: parameters, pairs, segment stiffness, the query
list and the size of the search grid. No Taichi here (the kernels are in ``contact.py``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from taichi_bearing.mesh.types import Mesh

__all__ = [
    "ContactPair",
    "ContactParameters",
    "GridSpec",
    "PENALTY_METHODS",
    "grid_spec",
    "query_corners",
    "query_neighbours",
    "segment_curvature",
    "segment_end_corners",
    "turn_angle",
    "segment_elements",
]

PENALTY_METHODS = ("segment", "soft", "pressure")


@dataclass(frozen=True)
class ContactParameters:
    r"""Penalty, friction and damping constants shared by every contact pair.

    Attributes
    ----------
    penalty_method : {"segment", "soft", "pressure"}
        ``"segment"``: LS-DYNA's segment-based stiffness :math:`k = f_s K A^2 / V` of the
        master segment, with :math:`K = \lambda + 2 \mu / 3` the bulk modulus of the
        element the segment bounds, :math:`A = L t` the segment area (length x thickness)
        and :math:`V = \mathrm{area} \, t` the element volume, i.e.
        :math:`k = f_s K L^2 t / \mathrm{area}`.
        ``"soft"``: :math:`k = f_s m_\mathrm{eff} / \Delta t^2` with
        :math:`m_\mathrm{eff} = m_s m_m / (m_s + m_m)`, the slave node mass and the master
        mass interpolated at the contact point, and the model's current time step
        (LS-DYNA's SOFT=1 idea).
        ``"pressure"``: a pressure per unit overlap ``penalty_pressure`` on every mesh
        (:class:`~taichi_bearing.solver.laws.contact.PressurePenalty`).
    penalty_scale : float
        :math:`f_s` above (LS-DYNA's default is 0.1); the pressure law does not read it.
    penalty_pressure : float
        The pressure law's :math:`p_s`, Pa/m (required by it, unused by the others).
    friction_static, friction_dynamic : float
        Coulomb coefficients;
        :math:`\mu = \mu_d + (\mu_s - \mu_d) \exp(-\mathrm{decay} \, |v_\mathrm{slip}|)`.
    friction_decay : float
        Exponential decay coefficient, s/m.
    damping_ratio : float
        Viscous contact damping :math:`c = 2 \zeta \sqrt{k m_\mathrm{eff}}` as a fraction
        of critical.
    smoothing : bool
        Contact against the arc each master segment had in the mesh rather than against
        its chord (see :func:`segment_curvature`): removes the polygon's facet ripple
        (sagitta :math:`L^2 / (8 R)`) from rolling contact. Flat segments and segments at
        corners stay straight, so ``False`` and ``True`` agree on them.
    """

    penalty_method: str = "segment"
    penalty_scale: float = 0.1
    penalty_pressure: float = 0.0
    friction_static: float = 0.0
    friction_dynamic: float = 0.0
    friction_decay: float = 0.0
    damping_ratio: float = 0.0
    smoothing: bool = True

    def __post_init__(self) -> None:
        if self.penalty_method not in PENALTY_METHODS:
            raise ValueError(
                f"penalty_method must be one of {PENALTY_METHODS}, got {self.penalty_method!r}"
            )
        if not self.penalty_scale > 0:
            raise ValueError(f"penalty_scale must be positive, got {self.penalty_scale!r}")
        if self.penalty_method == "pressure" and not self.penalty_pressure > 0:
            raise ValueError(
                f"the pressure law needs penalty_pressure > 0 (Pa/m), got {self.penalty_pressure!r}"
            )
        if not 0 <= self.friction_dynamic <= self.friction_static:
            raise ValueError(
                "need 0 <= friction_dynamic <= friction_static, got "
                f"{self.friction_dynamic!r}, {self.friction_static!r}"
            )
        if not self.friction_decay >= 0:
            raise ValueError(f"friction_decay must be >= 0, got {self.friction_decay!r}")
        if not 0 <= self.damping_ratio <= 1:
            raise ValueError(f"damping_ratio must lie in [0, 1], got {self.damping_ratio!r}")

    @classmethod
    def from_case(cls, contact, penalty_pressure: float = 0.0) -> ContactParameters:
        """From a case's ``contact`` section (:class:`taichi_bearing.case.Contact`) and,
        for the pressure law, its pressure per unit overlap (Pa/m,
        :func:`taichi_bearing.analytic.penalty.pressure_penalty` of the case)."""
        return cls(
            penalty_method=contact.penalty_method,
            penalty_scale=contact.penalty_scale,
            penalty_pressure=penalty_pressure,
            friction_static=contact.friction_static,
            friction_dynamic=contact.friction_dynamic,
            friction_decay=contact.friction_decay,
            damping_ratio=contact.damping_ratio,
            smoothing=bool(getattr(contact, "smoothing", True)),
        )

    def friction_coefficient(self, slip_speed: float | np.ndarray) -> float | np.ndarray:
        r""":math:`\mu_d + (\mu_s - \mu_d) \exp(-\mathrm{decay} \, |v|)`."""
        mu_s, mu_d = self.friction_static, self.friction_dynamic
        return mu_d + (mu_s - mu_d) * np.exp(-self.friction_decay * np.abs(slip_speed))


@dataclass(frozen=True)
class ContactPair:
    """Two surfaces of ``Mesh.surfaces`` that may touch.

    Resultants are reported as the force exerted BY the slave body ON the master body.
    With ``two_pass`` the master's nodes are also checked against the slave's segments.
    """

    name: str
    slave_surface: str
    master_surface: str
    two_pass: bool = True


def segment_elements(mesh: Mesh, segments: np.ndarray) -> np.ndarray:
    """The element each boundary segment belongs to (the one holding both its nodes)."""
    elements = np.asarray(mesh.elements, dtype=np.int64)
    n = np.int64(mesh.n_nodes)
    # each element edge as the key a n + b, both directions (a segment may run either way)
    a, b = elements.ravel(), np.roll(elements, -1, axis=1).ravel()
    keys = np.concatenate([a * n + b, b * n + a])
    owner = np.tile(np.repeat(np.arange(len(elements)), 4), 2)
    order = np.argsort(keys, kind="stable")
    keys, owner = keys[order], owner[order]
    seg = np.asarray(segments, dtype=np.int64).reshape(-1, 2)
    want = seg[:, 0] * n + seg[:, 1]
    pos = np.minimum(np.searchsorted(keys, want), len(keys) - 1)
    missing = keys[pos] != want
    if np.any(missing):
        a0, b0 = seg[np.argmax(missing)]
        raise ValueError(f"segment ({a0}, {b0}) is not an element edge")
    return owner[pos]


def _vertex_curvature(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Signed curvature of the circle through p, a, b (rows), positive when the chain
    p -> a -> b turns left (a convex body on the chain's left)."""
    u, w, c = a - p, b - a, b - p
    cross = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    norm = np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1) * np.linalg.norm(c, axis=1)
    return 2.0 * cross / norm


def _chain_neighbours(segs: np.ndarray, surface: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index of the previous and the next segment of each segment along its surface's
    chain (-1 at an open end)."""
    n = len(segs)
    prev = np.full(n, -1)
    nxt = np.full(n, -1)
    by_start = {(int(surface[k]), int(a)): k for k, (a, _) in enumerate(segs)}
    for k, (_, b) in enumerate(segs):
        j = by_start.get((int(surface[k]), int(b)), -1)
        if j >= 0 and j != k:
            nxt[k] = j
            prev[j] = k
    return prev, nxt


def turn_angle(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Unsigned angle (rad, 0..pi) from each direction in ``u`` to the one in ``w`` (rows)."""
    cross = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    return np.abs(np.arctan2(cross, np.einsum("ij,ij->i", u, w)))


def segment_end_corners(
    nodes: np.ndarray, segments: np.ndarray, surface: np.ndarray, max_turn: float = 0.2
) -> tuple[np.ndarray, np.ndarray]:
    """Whether each segment's start (a) and end (b) is a corner: an open end, or a vertex
    where the surface turns by more than ``max_turn`` radians (a spall's edges).

    Contact against a segment's arc stops at a corner: beyond it the body's surface goes
    elsewhere (along a smooth surface the next segment carries on, nearly in line).
    """
    segs = np.asarray(segments, dtype=np.int64)
    X = np.asarray(nodes, dtype=float)
    prev, nxt = _chain_neighbours(segs, surface)
    d = X[segs[:, 1]] - X[segs[:, 0]]

    def turn(j):  # angle between segment j's neighbour and the segment itself
        t = turn_angle(d[np.where(j >= 0, j, 0)], d)
        return np.where(j >= 0, t, np.inf)

    return turn(prev) > max_turn, turn(nxt) > max_turn


def segment_curvature(
    nodes: np.ndarray,
    segments: np.ndarray,
    surface: np.ndarray,
    rel_tol: float = 0.05,
    max_turn: float = 0.5,
) -> np.ndarray:
    """Signed curvature of each segment's arc, from the reference nodes, 1/m.

    A segment (a, b) gets the curvature of its neighbours' circle when the circle
    through (previous node, a, b) and the one through (a, b, next node) agree within
    ``rel_tol`` (nodes of one circular arc give equal values whatever their spacing) and
    the segment turns by less than ``max_turn`` radians; otherwise (an open end, a
    corner such as a spall's edge, a flat) 0, i.e. straight. Positive: convex (the body
    on the chain's left bulges out), negative: concave (an outer raceway).

    The curvature is a property of the undeformed surface: applied to the current chord
    it moves with the body and leaves the deformation to the nodes.
    """
    segs = np.asarray(segments, dtype=np.int64)
    X = np.asarray(nodes, dtype=float)
    n = len(segs)
    prev, nxt = _chain_neighbours(segs, surface)
    ok = (prev >= 0) & (nxt >= 0)
    kappa = np.zeros(n)
    if not ok.any():
        return kappa
    idx = np.flatnonzero(ok)
    a, b = X[segs[idx, 0]], X[segs[idx, 1]]
    ka = _vertex_curvature(X[segs[prev[idx], 0]], a, b)
    kb = _vertex_curvature(a, b, X[segs[nxt[idx], 1]])
    km = 0.5 * (ka + kb)
    agree = np.abs(ka - kb) <= rel_tol * np.maximum(np.abs(ka), np.abs(kb))
    length = np.linalg.norm(b - a, axis=1)
    keep = agree & (np.abs(km) * length < max_turn) & (np.abs(km) > 0)
    kappa[idx[keep]] = km[keep]
    return kappa


@dataclass(frozen=True)
class GridSpec:
    """A uniform grid of square search cells: origin, cell size, counts, and the distances
    that make a grid built at one instant valid until a node has moved ``margin / 2``."""

    origin: tuple[float, float]
    cell: float
    nx: int
    ny: int
    capture: float  # deepest penetration still treated as contact, m
    margin: float  # motion allowance before a rebuild, m

    @property
    def n_cells(self) -> int:
        return self.nx * self.ny


def grid_spec(
    points: np.ndarray, seg_lengths: np.ndarray, pad: float = 0.15, density: float = 4.0
) -> GridSpec:
    r"""Size the search grid for surfaces with these node positions and segment lengths.

    The cell is at least the longest segment plus twice (capture + margin), so a segment,
    with its bounding box grown by capture + margin, overlaps at most 4 cells; and at least
    :math:`\sqrt{\mathrm{box\ area} / (\mathrm{density} \cdot n_\mathrm{segments})}`, so
    there are at most ``density`` cells per segment (the search stays linear in the surface
    size). The box is padded by ``pad`` of its size; points outside it fall into the border
    cells (still correct). Capture depth: 0.3 x the longest segment; margin: 0.25 x the
    median segment.
    """
    l_max = float(seg_lengths.max())
    capture = 0.3 * l_max
    margin = 0.25 * float(np.median(seg_lengths))
    lo = points.min(axis=0)
    hi = points.max(axis=0)
    size = np.maximum(hi - lo, l_max)
    lo = lo - pad * size - 2 * (capture + margin)
    hi = hi + pad * size + 2 * (capture + margin)
    ext = hi - lo
    cell = max(
        l_max + 2.0 * (capture + margin),
        math.sqrt(ext[0] * ext[1] / (density * len(seg_lengths))),
    )
    nx = max(1, math.ceil(ext[0] / cell))
    ny = max(1, math.ceil(ext[1] / cell))
    return GridSpec((float(lo[0]), float(lo[1])), cell, nx, ny, capture, margin)


def query_corners(
    nodes: np.ndarray,
    q_node: np.ndarray,
    q_prev: np.ndarray,
    q_next: np.ndarray,
    max_turn: float = 0.2,
) -> np.ndarray:
    """Whether each query node is a corner of its own surface: its two segments turn by
    more than ``max_turn`` radians there (a spall's edges). Open ends are not corners.

    A corner's tributary patch would run along the chord between its neighbours, which
    cuts across the corner and stands out of the body; it contacts as a point instead.
    """
    X = np.asarray(nodes, dtype=float)
    a = X[q_node] - X[q_prev]
    b = X[q_next] - X[q_node]
    both = (np.abs(a).sum(axis=1) > 0) & (np.abs(b).sum(axis=1) > 0)
    return both & (turn_angle(a, b) > max_turn)


def query_neighbours(
    mesh: Mesh, surfaces: list[str], nodes: np.ndarray, smoothing: bool
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each query node (of these surfaces, in this order): the previous and the next
    node along its own surface (itself at an open end) and the surface's reference
    curvature there (mean of its two segments' :func:`segment_curvature`; 0 at corners,
    ends, or without ``smoothing``)."""
    prev = np.asarray(nodes, dtype=np.int32).copy()
    nxt = prev.copy()
    kappa = np.zeros(len(nodes))
    start = 0
    for name in surfaces:
        seg = np.asarray(mesh.surfaces[name], dtype=np.int64)
        own = np.unique(seg.ravel())
        pos = {int(n): start + k for k, n in enumerate(own)}
        k_seg = np.zeros(len(seg))
        if smoothing:
            k_seg = segment_curvature(mesh.nodes, seg, np.zeros(len(seg)))
        k_sum = np.zeros(len(own))
        k_cnt = np.zeros(len(own))
        for (a, b), kap in zip(seg, k_seg, strict=True):
            ia, ib = pos[int(a)], pos[int(b)]
            nxt[ia] = b
            prev[ib] = a
            for j in (ia, ib):
                k_sum[j - start] += kap
                k_cnt[j - start] += 1
        # Mean of the node's two segments (half the arc's next to a straight one); an
        # open end stays flat. Corners contact as points (query_corners).
        both = k_cnt == 2
        kappa[start : start + len(own)] = np.where(both, k_sum / np.maximum(k_cnt, 1), 0.0)
        start += len(own)
    return prev, nxt, kappa
