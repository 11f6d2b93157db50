"""The cross-section of a line spall with sloped and rounded edges: exact geometry shared
by the mesher and the quasi-static model (numpy only).

The spall spans the raceway (radius ``R``) from the polar angle ``start`` to ``end``
(counter-clockwise, from +x): these are its sharp edges at the raceway surface, so the
spall's length is ``R (end - start)``. Each wall leaves its edge into the material at
``slope`` from the raceway's tangent (90 degrees: radial, the rectangular notch) down to
the floor, the circle at depth ``d`` (radius ``R + d`` behind an outer raceway, ``R - d``
behind an inner one). An edge radius ``rho`` rounds both edges at the raceway: a circular
arc tangent to the raceway circle (at ``T1``) and to the wall (at ``T2``), its centre in
the material. The concave corners at the floor stay sharp (no roller reaches them).

The profile from ``T1`` of the start edge to ``T1`` of the end edge is a chain of pieces
in order of increasing angle: fillet arc, wall line, floor arc, wall line, fillet arc.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

__all__ = ["EdgeGeometry", "Piece", "SpallProfile", "unit"]

RIGHT = 0.5 * math.pi


def unit(angle) -> np.ndarray:
    """``(cos, sin)`` of polar angles, shape ``(..., 2)``."""
    a = np.asarray(angle, dtype=float)
    return np.stack([np.cos(a), np.sin(a)], axis=-1)


@dataclass(frozen=True)
class EdgeGeometry:
    """One edge of the spall (points in m, bearing centre at the origin).

    ``corner``: the sharp edge on the raceway (virtual when rounded); ``floor_corner``:
    where the wall meets the floor; ``wall``: unit vector from the corner down the wall;
    ``normal``: unit normal of the wall pointing into the material; ``tangent_start``
    (``T1``, on the raceway) and ``tangent_end`` (``T2``, on the wall): the fillet's
    ends, both equal to ``corner`` when sharp; ``fillet_centre``: None when sharp.
    """

    corner: np.ndarray
    floor_corner: np.ndarray
    wall: np.ndarray
    normal: np.ndarray
    tangent_start: np.ndarray
    tangent_end: np.ndarray
    fillet_centre: np.ndarray | None


@dataclass(frozen=True)
class Piece:
    """A piece of the profile: a line from ``p0`` to ``p1``, or an arc about ``centre``
    of ``radius`` from polar angle ``a0`` to ``a1`` (about that centre)."""

    kind: str  # "line", "arc" (a fillet) or "floor" (an arc about the bearing centre)
    p0: np.ndarray
    p1: np.ndarray
    centre: np.ndarray | None = None
    radius: float = 0.0
    a0: float = 0.0
    a1: float = 0.0

    @property
    def length(self) -> float:
        if self.kind == "line":
            return float(np.linalg.norm(self.p1 - self.p0))
        return abs(self.a1 - self.a0) * self.radius

    def at(self, t) -> np.ndarray:
        """Points at fractions ``t`` (0..1) of the piece's length, shape ``(..., 2)``."""
        t = np.asarray(t, dtype=float)[..., None]
        if self.kind == "line":
            return self.p0 + t * (self.p1 - self.p0)
        return self.centre + self.radius * unit(self.a0 + t[..., 0] * (self.a1 - self.a0))


@dataclass(frozen=True)
class SpallProfile:
    """A line spall's cross-section (see the module notes).

    Parameters
    ----------
    raceway_radius : float
        ``R``, m.
    start, end : float
        Polar angles of the edges at the raceway, rad from +x, ``start < end``.
    depth : float
        ``d``, m.
    outward : bool
        True for an outer ring (the material, and the floor, lie outside the raceway).
    start_slope, end_slope : float
        Wall angles from the raceway tangent, rad, in (0, pi/2].
    edge_radius : float
        ``rho``, m (0: sharp).
    side_names : (str, str)
        What the messages call the start and the end edge (e.g. entry and exit).

    Raises
    ------
    ValueError
        When the walls meet before the floor, or an edge radius does not fit its wall.
    """

    raceway_radius: float
    start: float
    end: float
    depth: float
    outward: bool = True
    start_slope: float = RIGHT
    end_slope: float = RIGHT
    edge_radius: float = 0.0
    side_names: tuple[str, str] = field(default=("start", "end"), compare=False)

    def __post_init__(self) -> None:
        for name in ("start_slope", "end_slope"):
            if not 0.0 < getattr(self, name) <= RIGHT + 1e-12:
                raise ValueError(f"{name} must lie in (0, 90] degrees")
        if not (self.depth > 0 and self.end > self.start and self.edge_radius >= 0):
            raise ValueError("a spall needs depth > 0, end > start and edge_radius >= 0")
        a_s, a_e = self.floor_angles
        if not a_e > a_s:
            raise ValueError(
                f"the walls meet before the floor: their slopes take "
                f"{1e3 * self.raceway_radius * (a_s - self.start + self.end - a_e):.3g} mm "
                f"of the {1e3 * self.length:.3g} mm spall at {1e3 * self.depth:.3g} mm depth"
            )
        for k, edge in enumerate((self.start_edge, self.end_edge)):
            run = float((edge.tangent_end - edge.corner) @ edge.wall)
            wall = float(np.linalg.norm(edge.floor_corner - edge.corner))
            if run > wall * (1 + 1e-12):
                raise ValueError(
                    f"an edge radius of {1e3 * self.edge_radius:.3g} mm does not fit the "
                    f"{self.side_names[k]} wall ({1e3 * wall:.3g} mm long at "
                    f"{math.degrees((self.start_slope, self.end_slope)[k]):.3g} degrees)"
                )

    # ------------------------------------------------------------------ geometry

    @property
    def sign(self) -> float:
        """+1 where depth is outward (outer ring), -1 inward."""
        return 1.0 if self.outward else -1.0

    @property
    def floor_radius(self) -> float:
        return self.raceway_radius + self.sign * self.depth

    @property
    def length(self) -> float:
        """Arc length between the edges at the raceway, m."""
        return self.raceway_radius * (self.end - self.start)

    @property
    def rectangular(self) -> bool:
        """Radial walls and sharp edges: the rectangular notch."""
        return (
            abs(self.start_slope - RIGHT) < 1e-12
            and abs(self.end_slope - RIGHT) < 1e-12
            and self.edge_radius == 0.0
        )

    def _edge(self, angle: float, slope: float, into: float) -> EdgeGeometry:
        """The edge at ``angle`` whose spall lies towards ``into`` (+1: larger angles)."""
        r, s = self.raceway_radius, self.sign
        u = unit(angle)
        t = np.array([-u[1], u[0]])
        corner = r * u
        wall = into * math.cos(slope) * t + math.sin(slope) * s * u
        normal = -into * math.sin(slope) * t + math.cos(slope) * s * u
        # |corner + lam wall| = floor radius: the smaller positive root
        b = float(corner @ wall)
        disc = b * b - r * r + self.floor_radius**2
        roots = [-b - math.sqrt(disc), -b + math.sqrt(disc)]
        lam = min(x for x in roots if x > 0)
        floor_corner = corner + lam * wall
        rho = self.edge_radius
        if rho == 0.0:
            return EdgeGeometry(corner, floor_corner, wall, normal, corner, corner, None)
        # centre at |C| = R + s rho (on the raceway's normal through T1) and rho from the
        # wall on the material side: A cos(delta) + B sin(delta) = c, delta = angle change
        big = r + s * rho
        a_, b_ = big * float(u @ normal), big * float(t @ normal)
        c = rho + float(corner @ normal)
        phase, amp = math.atan2(b_, a_), math.hypot(a_, b_)
        spread = math.acos(max(-1.0, min(1.0, c / amp)))
        deltas = [phase + spread, phase - spread]
        deltas = [(d + math.pi) % (2 * math.pi) - math.pi for d in deltas]
        delta = min((d for d in deltas if -into * d >= 0), key=abs)  # behind the edge
        centre = big * unit(angle + delta)
        return EdgeGeometry(
            corner, floor_corner, wall, normal, r * unit(angle + delta), centre - rho * normal,
            centre,
        )  # fmt: skip

    @cached_property
    def start_edge(self) -> EdgeGeometry:
        return self._edge(self.start, self.start_slope, 1.0)

    @cached_property
    def end_edge(self) -> EdgeGeometry:
        return self._edge(self.end, self.end_slope, -1.0)

    @property
    def floor_angles(self) -> tuple[float, float]:
        """Polar angles where the floor begins and ends."""
        a = [self.start_edge.floor_corner, self.end_edge.floor_corner]
        return tuple(self.start + _angle_from(self.start, p) for p in a)

    @cached_property
    def pieces(self) -> list[Piece]:
        """The profile from the start edge's ``T1`` to the end edge's, in order."""
        out = []
        s_edge, e_edge = self.start_edge, self.end_edge
        if s_edge.fillet_centre is not None:
            out.append(_arc(s_edge.fillet_centre, self.edge_radius, s_edge.tangent_start,
                            s_edge.tangent_end))  # fmt: skip
        out.append(Piece("line", s_edge.tangent_end, s_edge.floor_corner))
        a_s, a_e = self.floor_angles
        rf = self.floor_radius
        out.append(Piece("floor", rf * unit(a_s), rf * unit(a_e), np.zeros(2), rf, a_s, a_e))
        out.append(Piece("line", e_edge.floor_corner, e_edge.tangent_end))
        if e_edge.fillet_centre is not None:
            out.append(_arc(e_edge.fillet_centre, self.edge_radius, e_edge.tangent_end,
                            e_edge.tangent_start))  # fmt: skip
        return [p for p in out if p.kind == "floor" or p.length > 1e-12 * self.raceway_radius]

    @property
    def floor_index(self) -> int:
        """Index of the floor among :attr:`pieces`."""
        return next(i for i, p in enumerate(self.pieces) if p.kind == "floor")

    def polyline(self, per_piece: int = 400) -> np.ndarray:
        """Points along the whole profile, ``per_piece`` intervals a piece, shape (n, 2)."""
        t = np.linspace(0.0, 1.0, per_piece + 1)
        pts = [p.at(t[:-1]) for p in self.pieces] + [self.pieces[-1].at([1.0])]
        return np.concatenate(pts)

    def depth_at(self, angle) -> np.ndarray:
        """Depth of the profile below the raceway at polar angles (0 outside the spall),
        m: where a radial line at that angle meets the profile."""
        pts = self.polyline()
        rel = self.start + np.array([_angle_from(self.start, p) for p in pts])
        depth = np.abs(np.hypot(pts[:, 0], pts[:, 1]) - self.raceway_radius)
        a = np.asarray(angle, dtype=float)
        inside = (a > self.start) & (a < self.end)
        return np.where(inside, np.interp(a, rel, depth), 0.0)


def _angle_from(reference: float, point: np.ndarray) -> float:
    """Polar angle of ``point`` relative to ``reference``, in (-pi, pi]."""
    d = math.atan2(point[1], point[0]) - reference
    return (d + math.pi) % (2 * math.pi) - math.pi


def _arc(centre: np.ndarray, radius: float, p0: np.ndarray, p1: np.ndarray) -> Piece:
    """The shorter arc about ``centre`` from ``p0`` to ``p1``."""
    a0 = math.atan2(*(p0 - centre)[::-1])
    a1 = a0 + (math.atan2(*(p1 - centre)[::-1]) - a0 + math.pi) % (2 * math.pi) - math.pi
    return Piece("arc", p0, p1, centre, radius, a0, a1)
