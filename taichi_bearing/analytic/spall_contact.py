"""A line spall's geometry and how it holds a rigid roller (numpy only): the spall of a
case, and each roller's supports as it crosses it, for the quasi-static load distribution
(:mod:`taichi_bearing.analytic.quasistatic`, where the model is described).

Each roller may bear on three supports, each with its own drop ``h`` of the roller
centre towards the floor (the rigid geometric path: pivot on the entry edge, floor, pivot
on the exit edge), its share ``phi`` of the Hertz patch and the direction ``u`` of the
force it takes. On the outer raceway the roller sits inside the ring and drops outward; on
the inner raceway it sits outside and drops inward (``sign`` -1 below).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from taichi_bearing.analytic.bearing import wrap_angle
from taichi_bearing.geometry.roller_path import side_touch, wall_touch
from taichi_bearing.geometry.spall_profile import SpallProfile

if TYPE_CHECKING:
    from taichi_bearing.analytic.contact_model import ContactModel
    from taichi_bearing.case import Case

__all__ = ["Spall", "spall_from_case", "spall_supports", "support_fraction", "unit_from_top"]


@dataclass(frozen=True)
class Spall:
    r"""A line spall: the angles of its edges at the raceway (rad, from 12 o'clock, in the
    fixed frame), its depth (m), the walls' angles from the raceway (rad; :math:`\pi/2`:
    radial) and the radius rounding both edges (m; 0: sharp).

    ``entry`` is the edge the rollers reach first. On the outer raceway they move
    counter-clockwise with the cage, so ``entry < exit``; on the inner raceway, which
    turns faster than the cage, they move clockwise relative to the ring and enter at
    the edge at the larger angle (``entry > exit``). An inner-race spall turns with the
    shaft: these angles are where it is at one instant (see ``spall_angles`` of
    :func:`solve_load_distribution`).
    """

    entry: float
    exit: float
    depth: float
    entry_slope: float = 0.5 * math.pi
    exit_slope: float = 0.5 * math.pi
    edge_radius: float = 0.0
    race: str = "outer"

    @property
    def centre(self) -> float:
        return 0.5 * (self.entry + self.exit)

    @property
    def half_angle(self) -> float:
        return 0.5 * abs(self.exit - self.entry)

    @property
    def start(self) -> float:
        """The edge at the smaller angle (the entry on the outer raceway)."""
        return min(self.entry, self.exit)

    @property
    def end(self) -> float:
        return max(self.entry, self.exit)

    @property
    def start_slope(self) -> float:
        """The wall's slope at :attr:`start`."""
        return self.entry_slope if self.race == "outer" else self.exit_slope

    @property
    def end_slope(self) -> float:
        return self.exit_slope if self.race == "outer" else self.entry_slope

    @property
    def sign(self) -> float:
        """+1 for a spall in the outer raceway (the floor further out), -1 inner."""
        return 1.0 if self.race == "outer" else -1.0

    def profile(self, raceway_radius: float) -> SpallProfile:
        """The cross-section, angles from +x, centred on the bearing's 12 o'clock
        branch of the spall's centre (see :mod:`taichi_bearing.geometry.spall_profile`)."""
        return SpallProfile(
            raceway_radius,
            self.start + 0.5 * math.pi,
            self.end + 0.5 * math.pi,
            self.depth,
            outward=self.race == "outer",
            start_slope=self.start_slope,
            end_slope=self.end_slope,
            edge_radius=self.edge_radius,
        )

    @property
    def rectangular(self) -> bool:
        """Radial walls and sharp edges: the model of design section 4 as it was first
        written (:func:`spall_supports`)."""
        right = 0.5 * math.pi
        return (
            abs(self.entry_slope - right) < 1e-12
            and abs(self.exit_slope - right) < 1e-12
            and self.edge_radius == 0.0
        )


def spall_from_case(case: Case) -> Spall | None:
    """The case's spall, or None for a healthy bearing.

    An inner-race spall is returned where it is at t = 0: ``defect.angle`` is its centre
    in the inner ring's frame, which coincides with the fixed frame then.
    """
    d = case.defect
    if not d.present:
        return None
    outer = d.race == "outer"
    b = case.bearing
    half = 0.5 * d.length / (b.outer_raceway_radius if outer else b.inner_raceway_radius)
    # the rollers reach the edge at the larger angle first on the inner raceway
    first = -half if outer else half
    return Spall(
        entry=d.angle + first,
        exit=d.angle - first,
        depth=d.depth,
        entry_slope=d.entry_slope,
        exit_slope=d.exit_slope,
        edge_radius=d.edge_radius,
        race=d.race,
    )


def support_fraction(xi):
    """Share of a Hertz (semi-elliptic) pressure over [-1, 1] that lies below ``xi``.

    0 for xi <= -1, 0.5 at 0, 1 for xi >= 1: the fraction of a contact patch still on a
    support whose edge is at ``xi`` half-widths from the patch centre.
    """
    x = np.clip(np.asarray(xi, dtype=float), -1.0, 1.0)
    return 0.5 + (x * np.sqrt(1.0 - x * x) + np.arcsin(x)) / np.pi


def _corner_drop(delta_angle, r: float, r_o: float, sign: float = 1.0):
    r"""Drop (towards the floor) of a rigid roller centre pivoting on a raceway corner, m.

    The corner is at radius ``r_o``; the roller centre is ``delta_angle`` (>= 0) past it.
    In an outer raceway (``sign`` +1) :math:`|\mathrm{centre} - \mathrm{corner}| = r` gives
    :math:`\rho = r_o \cos d - \sqrt{r^2 - r_o^2 \sin^2 d}` (:math:`d` the ``delta_angle``)
    and the drop is measured outward from the healthy position :math:`r_o - r`; on an inner
    raceway (-1) the roller is outside, :math:`\rho` takes the other root and the drop is
    inward from :math:`r_o + r`. Infinite where the roller cannot
    reach the corner.
    """
    s = r_o * np.sin(delta_angle)
    with np.errstate(invalid="ignore"):
        rho = r_o * np.cos(delta_angle) - sign * np.sqrt(r * r - s * s)
    reach = (s < r) & (delta_angle < 0.5 * np.pi)
    return np.where(reach, sign * (rho - (r_o - sign * r)), np.inf)


def unit_from_top(angle):
    """Outward unit vector at angles from 12 o'clock, counter-clockwise, (..., 2)."""
    return np.stack([-np.sin(angle), np.cos(angle)], axis=-1)


def spall_supports(psi, b, cm: ContactModel, spall: Spall | None, mode: str):
    """Drops h, support fractions phi and force directions u of each roller's supports.

    ``u`` is the direction of the force the roller exerts on the spalled ring: outward on
    the outer ring, inward on the inner one (healthy: outward). Returns arrays of shape
    (S, A, Z), (S, A, Z), (S, A, Z, 2).
    """
    radial = unit_from_top(psi)
    if spall is None:
        return np.zeros((1, *psi.shape)), np.ones((1, *psi.shape)), radial[None]
    sign = spall.sign
    normal = sign * radial  # into the spalled ring
    if not spall.rectangular:
        return _profile_supports(psi, b, cm, spall, mode)
    r, depth = cm.roller_radius, spall.depth
    r_o = cm.raceway(spall.race)[0]
    rel = wrap_angle(psi - spall.centre)
    half = spall.half_angle
    if mode == "step":
        h = np.where(np.abs(rel) < half, depth, 0.0)
        return h[None], np.ones((1, *psi.shape)), normal[None]

    past_entry = rel + half  # angle the roller centre is past the start edge
    before_exit = half - rel  # angle before the end edge

    def edge_support(past, corner_angle):
        # on the raceway up to the edge, then pivoting on the corner; never lower than the
        # floor, which stops the rigid roller first (and a zero-depth spall is flat)
        corner = _corner_drop(np.maximum(past, 0.0), r, r_o, sign)
        pivoting = (past > 0.0) & (corner < depth)
        h = np.where(past <= 0.0, 0.0, np.minimum(corner, depth))
        centre = (r_o - sign * r + sign * h)[..., None] * radial
        to_corner = r_o * unit_from_top(np.full_like(psi, corner_angle)) - centre
        to_corner /= np.linalg.norm(to_corner, axis=-1, keepdims=True)
        u = np.where(pivoting[..., None], to_corner, normal)
        return h, u

    h_a, u_a = edge_support(past_entry, spall.start)
    h_b, u_b = edge_support(before_exit, spall.end)
    # shares of the Hertz patch (centred on the roller's foot) over each support: they
    # partition the patch, so a spall of zero depth is exactly the healthy raceway
    below_entry = support_fraction(-r_o * past_entry / b)
    below_exit = support_fraction(r_o * before_exit / b)
    h = np.stack([h_a, np.full_like(psi, depth), h_b])
    phi = np.stack([below_entry, below_exit - below_entry, 1.0 - below_exit])
    u = np.stack([u_a, normal, u_b])
    return h, phi, u


def _profile_supports(psi, b, cm: ContactModel, spall: Spall, mode: str):
    """:func:`spall_supports` for a spall with sloped walls or rounded edges.

    The roller follows its rigid path over the profile (:mod:`taichi_bearing.geometry.roller_path`):
    each support's drop is its first touch. Entry: the raceway before the edge and the
    edge itself (corner, or rounded edge). Floor: the floor (drop = depth, as in the
    rectangular model), the walls, and each edge that is not a sharp radial one, on which
    the roller keeps pivoting after its patch has crossed the edge until it meets the wall
    or the floor (a sharp radial edge is as in the rectangular model: the patch loses its
    support as it crosses it). Exit: the edge and the raceway after it. The Hertz patch
    is shared at the edges at the raceway as in the rectangular model, so a side with a
    sharp radial wall behaves exactly as there. The "step" model drops the roller by the
    profile's depth at its foot. On the inner raceway the same, moving inward.
    """
    r, depth = cm.roller_radius, spall.depth
    r_o = cm.raceway(spall.race)[0]
    sign = spall.sign
    radial = unit_from_top(psi)
    normal = sign * radial
    # angles near the spall on one branch, from +x
    phi = spall.centre + wrap_angle(psi - spall.centre) + 0.5 * np.pi
    profile = spall.profile(r_o)
    if mode == "step":
        return profile.depth_at(phi)[None], np.ones((1, *psi.shape)), normal[None]
    healthy = r_o - sign * r

    def support(touches):
        rho = np.stack([t[0] for t in touches])
        k = np.argmin(sign * rho, axis=0)
        rho = np.take_along_axis(rho, k[None], 0)[0]
        contact = np.stack([np.broadcast_to(t[1], (*psi.shape, 2)) for t in touches])
        contact = np.take_along_axis(contact, k[None, ..., None], 0)[0]
        # the floor stops the rigid roller first
        h = np.minimum(sign * (rho - healthy), depth)
        centre = (healthy + sign * h)[..., None] * radial
        u = contact - centre
        u /= np.maximum(np.linalg.norm(u, axis=-1, keepdims=True), 1e-300)
        return h, np.where((h < depth)[..., None], u, normal)

    right = 0.5 * np.pi
    pivots = [
        side_touch(phi, profile, r, start, False)
        for start, slope in ((True, spall.start_slope), (False, spall.end_slope))
        if not (abs(slope - right) < 1e-12 and spall.edge_radius == 0.0)
    ]
    e = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    walls = [wall_touch(e, edge, r, sign) for edge in (profile.start_edge, profile.end_edge)]
    floor = (np.full(psi.shape, healthy + sign * depth), (r_o + sign * depth) * radial)
    h_a, u_a = support([side_touch(phi, profile, r, True, True)])
    h_b, u_b = support([floor, *walls, *pivots])
    h_c, u_c = support([side_touch(phi, profile, r, False, True)])
    rel = wrap_angle(psi - spall.centre)
    half = spall.half_angle
    below_entry = support_fraction(-r_o * (rel + half) / b)
    below_exit = support_fraction(r_o * (half - rel) / b)
    h = np.stack([h_a, h_b, h_c])
    phi_k = np.stack([below_entry, below_exit - below_entry, 1.0 - below_exit])
    return h, phi_k, np.stack([u_a, u_b, u_c])
