"""A rigid roller over a spall profile: how far its centre drops, and where it touches.

The roller (radius ``r``) sits inside the outer raceway (radius ``R``) with its centre on
the ray at polar angle ``phi``; it moves outward along the ray until it first touches the
profile (:class:`~taichi_bearing.geometry.spall_profile.SpallProfile`). Its drop is how much
further out the centre is than on the healthy raceway, ``rho - (R - r)``. On an inner
raceway (``outward=False``) the roller sits outside it and moves inward: the first touch
is the largest ``rho`` and the drop is ``(R + r) - rho``. With ``s`` the profile's sign
(+1 outer, -1 inner) both read ``s (rho - (R - s r))``. Each part of
the profile gives its own first touch in closed form: the raceway circle (or the floor)
straight under the roller, a corner (circle on a point: the roller pivots on it), a
rounded edge (circle on a circle) and a wall (circle on a line: the centre lies ``r`` from
the line). The roller meets whichever comes first. Numpy only; arrays of any shape.
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.geometry.spall_profile import EdgeGeometry, Piece, SpallProfile, unit

__all__ = ["Touch", "centre_drop", "side_touch", "wall_touch"]

Touch = tuple[np.ndarray, np.ndarray]
"""``(rho, contact)``: the centre's distance from the bearing centre at first touch
(``s * inf`` where this part is never touched) and the contact point, shapes ``(...)``,
``(..., 2)``."""


def _point(e: np.ndarray, point: np.ndarray, reach: float, sign: float = 1.0) -> Touch:
    """Circle of radius ``reach`` about a point, met by a centre moving along ``sign * e``:
    ``|rho e - K| = reach``, the smaller root moving out (``sign`` +1), the larger moving
    in (-1), ahead of the bearing centre."""
    ek = e @ point
    disc = ek * ek - point @ point + reach * reach
    with np.errstate(invalid="ignore"):
        rho = ek - sign * np.sqrt(disc)
    ok = (disc >= 0.0) & (ek > 0.0)
    return np.where(ok, rho, sign * np.inf), np.broadcast_to(point, e.shape)


def _arc_contains(piece: Piece, direction: np.ndarray) -> np.ndarray:
    """Whether unit ``direction`` (from the arc's centre) lies within its angles."""
    angle = np.arctan2(direction[..., 1], direction[..., 0])
    span = piece.a1 - piece.a0
    rel = (angle - piece.a0 + math.pi) % (2 * math.pi) - math.pi
    return (rel * np.sign(span) >= 0.0) & (np.abs(rel) <= abs(span))


def _fillet(e: np.ndarray, piece: Piece, r: float, sign: float = 1.0) -> Touch:
    """A rounded edge (material inside its circle): the centres are ``r + rho`` apart."""
    rho, _ = _point(e, piece.centre, r + piece.radius, sign)
    c = np.where(np.isfinite(rho), rho, 0.0)[..., None] * e
    d = c - piece.centre
    d = d / np.maximum(np.linalg.norm(d, axis=-1, keepdims=True), 1e-300)
    rho = np.where(_arc_contains(piece, d), rho, sign * np.inf)
    return rho, piece.centre + piece.radius * d


def wall_touch(e: np.ndarray, edge: EdgeGeometry, r: float, sign: float = 1.0) -> Touch:
    """A wall (the line from the edge's ``T2`` to its foot, material on the side of its
    ``normal``): the centre ``r`` from the line, the contact the foot of the normal
    through it, within the wall. ``sign``: the profile's (the centre moves out, or in)."""
    n = edge.normal
    ne = e @ n
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = (float(n @ edge.tangent_end) - r) / ne
    contact = rho[..., None] * e + r * n
    along = (contact - edge.tangent_end) @ edge.wall
    length = float(np.linalg.norm(edge.floor_corner - edge.tangent_end))
    # the centre moving along sign * e must be approaching the material
    ok = (sign * ne > 0.0) & (along >= 0.0) & (along <= length) & (length > 0.0)
    return np.where(ok, rho, sign * np.inf), contact


def _circle(
    e: np.ndarray, phi: np.ndarray, radius: float, lo: float, hi: float, r: float, sign: float
) -> Touch:
    """The raceway (or the floor) straight under the roller, for polar angles in
    ``[lo, hi]``."""
    ok = (phi >= lo) & (phi <= hi)
    return np.where(ok, radius - sign * r, sign * np.inf), radius * e


def _first(touches: list[Touch], sign: float = 1.0) -> Touch:
    """The touch met first: the smallest ``rho`` moving out, the largest moving in."""
    rho = np.stack([t[0] for t in touches])
    contact = np.stack([np.broadcast_to(t[1], touches[0][1].shape) for t in touches])
    k = np.argmin(sign * rho, axis=0)
    return np.take_along_axis(rho, k[None], 0)[0], np.take_along_axis(
        contact, k[None, ..., None], 0
    )[0]


def side_touch(phi: np.ndarray, profile: SpallProfile, r: float, start: bool, raceway: bool):
    """First touch of the roller with one edge of the spall: its corner (sharp) or its
    rounded edge with both tangent points, and with ``raceway`` the raceway on the far
    side of that edge (up to the edge, or to the fillet's start).

    Parameters
    ----------
    phi : ndarray
        Polar angles of the roller centre, rad from +x.
    profile : SpallProfile
        On an outer or an inner raceway.
    r : float
        Roller radius, m.
    start : bool
        The edge at the smaller angle (True) or the larger.
    raceway : bool
        Include the raceway beyond the edge.
    """
    e = unit(phi)
    s = profile.sign
    edge = profile.start_edge if start else profile.end_edge
    touches = [_point(e, edge.tangent_start, r, s), _point(e, edge.tangent_end, r, s)]
    if edge.fillet_centre is not None:
        piece = profile.pieces[0 if start else -1]
        touches.append(_fillet(e, piece, r, s))
    if raceway:
        t1 = math.atan2(edge.tangent_start[1], edge.tangent_start[0])
        lo, hi = (-np.inf, t1) if start else (t1, np.inf)
        touches.append(_circle(e, phi, profile.raceway_radius, lo, hi, r, s))
    return _first(touches, s)


def centre_drop(phi, profile: SpallProfile, r: float) -> tuple[np.ndarray, np.ndarray]:
    """The rigid roller's path over the whole spall: the drop of its centre below the
    healthy raceway, towards the floor (m), and where it touches, first touch of the
    raceway on either side, both edges, both walls and the floor.

    Parameters
    ----------
    phi : array_like
        Polar angles of the roller centre, rad from +x (near the spall).
    profile : SpallProfile
        On an outer raceway (``outward=True``: the roller inside it) or an inner one (the
        roller outside it).
    r : float
        Roller radius, m.
    """
    phi = np.asarray(phi, dtype=float)
    e = unit(phi)
    s = profile.sign
    lo, hi = profile.floor_angles
    touches = [
        side_touch(phi, profile, r, True, True),
        side_touch(phi, profile, r, False, True),
        wall_touch(e, profile.start_edge, r, s),
        wall_touch(e, profile.end_edge, r, s),
        _circle(e, phi, profile.floor_radius, lo, hi, r, s),
    ]
    rho, contact = _first(touches, s)
    return s * (rho - (profile.raceway_radius - s * r)), contact
