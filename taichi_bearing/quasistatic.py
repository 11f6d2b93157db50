"""Quasi-static load distribution of a radially loaded roller bearing, with a line spall.

Healthy bearing (Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., ch. 7): the outer
ring (under the adapter) is pushed down by the radial load W and moves by delta_r relative
to the inner ring, which is held by the shaft. Roller j at angle psi_j (from 12 o'clock)
is squeezed by

    delta_j = delta_r cos(psi_j) - P_d / 2           (P_d: radial internal clearance)

and carries Q_j = K_n delta_j^n (zero when delta_j <= 0), K_n being the two
roller-raceway contacts in series. delta_r is solved so that the vertical components of the
roller forces on the outer ring add up to W to rounding error; the horizontal components
are taken by the adapter's horizontal constraint (as in the finite element model).

Line spall on the outer raceway (rectangular notch, arc length L, depth H, sharp edges).
The rollers move counter-clockwise, so they enter at the lower angle. Each roller may bear
on three supports, each with its own drop h of the roller centre (the rigid geometric
path: pivot on the entry edge, floor, pivot on the exit edge):

- the raceway before the notch, ending at the entry corner: once the roller's foot has
  passed the corner the rigid roller pivots on it and its centre drops by
  ``h = rho_corner - (R_o - r)`` (exact circle-on-corner geometry on the curved raceway);
- the floor of the notch, drop H;
- the raceway after the notch, starting at the exit corner (mirror image of the first).

The Hertz patch of the roller (half-width b, the healthy contact width at that
deflection, centred on the roller's foot) is shared by the supports: each carries the
share ``phi`` of the semi-elliptic pressure that lies over it, and

    Q = K_n * sum_k phi_k (delta_j - h_k)^n

along the line from the roller centre to the contact point (radial on a surface, towards
the corner while pivoting). The shares add up to one, so a spall of zero depth is the
healthy raceway; as the patch crosses an edge its share moves gradually (phi = 0.5 with
the patch centred on the edge) and the force is continuous in cage angle. Where the drop
exceeds the deflection (the usual spall) the floor carries nothing: the roller de-stresses
over about 2b at the entry edge and re-stresses over about 2b at the exit edge.

The inner contact carries the radial component of the roller's outer force; the
tangential component (non-zero only while pivoting) is taken by the cage pocket.

The "step" model, for comparison, ignores the roller size and contact width: a roller
whose contact point is inside the notch drops straight by H.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from taichi_bearing.bearing import (
    LINE_CONTACT_EXPONENT,
    contact_radius,
    effective_modulus,
    hertz_half_width,
    hertz_peak_pressure,
    palmgren_stiffness,
    series_stiffness,
    wrap_angle,
)
from taichi_bearing.case import Bearing, Case, Material
from taichi_bearing.spall_profile import SpallProfile

__all__ = [
    "ContactModel",
    "LoadDistribution",
    "analytical_roller_forces",
    "Spall",
    "contact_model",
    "defect_sweep",
    "load_distribution_factor",
    "solve_case",
    "solve_load_distribution",
    "spall_from_case",
    "static_contact_table",
    "stribeck_ratio",
    "support_fraction",
]

MODES = ("patch", "step")


@dataclass(frozen=True)
class ContactModel:
    """Everything the load distribution needs from the bearing and material (SI)."""

    k_outer: float  # Palmgren constant of the outer contact, N/m^n
    k_inner: float
    exponent: float
    roller_length: float
    roller_radius: float
    outer_raceway_radius: float
    clearance: float  # radial internal clearance P_d (negative = preload)
    e_star: float
    outer_radius_eff: float
    inner_radius_eff: float

    @property
    def k_series(self) -> float:
        return float(series_stiffness(self.k_outer, self.k_inner, self.exponent))


def contact_model(
    bearing: Bearing, material: Material, exponent: float = LINE_CONTACT_EXPONENT
) -> ContactModel:
    """Contact model of a bearing: Palmgren stiffness of both contacts and Hertz radii.

    ``exponent`` 10/9 is line contact (default); 3/2 gives point-contact behaviour with
    the same K, for checking against Stribeck's ball-bearing constant.
    """
    k = palmgren_stiffness(bearing, material)
    return ContactModel(
        k_outer=k,
        k_inner=k,
        exponent=exponent,
        roller_length=bearing.roller_length,
        roller_radius=bearing.roller_radius,
        outer_raceway_radius=bearing.outer_raceway_radius,
        clearance=bearing.radial_clearance,
        e_star=effective_modulus(material.youngs_modulus, material.poissons_ratio),
        outer_radius_eff=contact_radius(bearing, "outer"),
        inner_radius_eff=contact_radius(bearing, "inner"),
    )


@dataclass(frozen=True)
class Spall:
    """A line spall on the outer raceway: angular extent (rad, from 12 o'clock, between
    its edges at the raceway), depth (m), the walls' angles from the raceway (rad; pi/2:
    radial) and the radius rounding both edges (m; 0: sharp)."""

    entry: float  # angle of the entry edge (rollers arrive here first)
    exit: float
    depth: float
    entry_slope: float = 0.5 * math.pi
    exit_slope: float = 0.5 * math.pi
    edge_radius: float = 0.0

    @property
    def centre(self) -> float:
        return 0.5 * (self.entry + self.exit)

    @property
    def half_angle(self) -> float:
        return 0.5 * (self.exit - self.entry)

    def profile(self, raceway_radius: float) -> SpallProfile:
        """The cross-section, angles from +x, centred on the bearing's 12 o'clock
        branch of the spall's centre (see :mod:`taichi_bearing.spall_profile`)."""
        return SpallProfile(
            raceway_radius,
            self.entry + 0.5 * math.pi,
            self.exit + 0.5 * math.pi,
            self.depth,
            outward=True,
            start_slope=self.entry_slope,
            end_slope=self.exit_slope,
            edge_radius=self.edge_radius,
        )

    @property
    def rectangular(self) -> bool:
        """Radial walls and sharp edges: the model of design section 4 as it was first
        written (:func:`_supports`)."""
        right = 0.5 * math.pi
        return (
            abs(self.entry_slope - right) < 1e-12
            and abs(self.exit_slope - right) < 1e-12
            and self.edge_radius == 0.0
        )


def spall_from_case(case: Case) -> Spall | None:
    """The case's outer-race spall, or None for a healthy bearing.

    Raises
    ------
    ValueError
        For an inner-race defect, which this model does not cover.
    """
    d = case.defect
    if not d.present:
        return None
    if d.race != "outer":
        raise ValueError(
            f"defect.race: the analytical model covers outer-race spalls, got {d.race!r}"
        )
    half = 0.5 * d.length / case.bearing.outer_raceway_radius
    return Spall(
        entry=d.angle - half,
        exit=d.angle + half,
        depth=d.depth,
        entry_slope=d.entry_slope,
        exit_slope=d.exit_slope,
        edge_radius=d.edge_radius,
    )


@dataclass(frozen=True)
class LoadDistribution:
    """Roller forces at a series of cage angles; arrays are (n_angles, n_rollers).

    Forces are those the rollers exert ON the outer ring (x right, y up, N); the sum of
    ``outer_fy`` over the rollers equals the load at every cage angle.
    """

    load: float
    cage_angle: np.ndarray  # (A,) angle of roller 0, rad
    roller_angle: np.ndarray  # (A, Z)
    ring_displacement: np.ndarray  # (A,) delta_r, m
    outer_fx: np.ndarray
    outer_fy: np.ndarray
    outer_force: np.ndarray  # magnitude
    inner_force: np.ndarray  # normal force at the inner contact
    deflection: np.ndarray  # elastic approach of both contacts together, m
    outer_half_width: np.ndarray
    inner_half_width: np.ndarray
    outer_pmax: np.ndarray
    inner_pmax: np.ndarray

    @property
    def n_rollers(self) -> int:
        return int(self.outer_fx.shape[1])

    def balance_error(self) -> np.ndarray:
        """Relative error of the vertical equilibrium at each cage angle."""
        return np.abs(self.outer_fy.sum(axis=1) - self.load) / self.load


def support_fraction(xi):
    """Share of a Hertz (semi-elliptic) pressure over [-1, 1] that lies below ``xi``.

    0 for xi <= -1, 0.5 at 0, 1 for xi >= 1: the fraction of a contact patch still on a
    support whose edge is at ``xi`` half-widths from the patch centre.
    """
    x = np.clip(np.asarray(xi, dtype=float), -1.0, 1.0)
    return 0.5 + (x * np.sqrt(1.0 - x * x) + np.arcsin(x)) / np.pi


def _corner_drop(delta_angle, r: float, r_o: float):
    """Outward drop of a rigid roller centre pivoting on a raceway corner, m.

    The corner is at radius ``r_o``; the roller centre is ``delta_angle`` (>= 0) past it.
    |centre - corner| = r gives rho = r_o cos(d) - sqrt(r^2 - r_o^2 sin^2(d)); the drop is
    measured from the healthy position r_o - r. Infinite where the roller cannot reach it.
    """
    s = r_o * np.sin(delta_angle)
    with np.errstate(invalid="ignore"):
        rho = r_o * np.cos(delta_angle) - np.sqrt(r * r - s * s)
    return np.where((s < r) & (delta_angle < 0.5 * np.pi), rho - (r_o - r), np.inf)


def _unit(angle):
    """Outward unit vector at angles from 12 o'clock, counter-clockwise, (..., 2)."""
    return np.stack([-np.sin(angle), np.cos(angle)], axis=-1)


def _supports(psi, b, cm: ContactModel, spall: Spall | None, mode: str):
    """Drops h, support fractions phi and force directions u of each roller's supports.

    Returns arrays of shape (S, A, Z), (S, A, Z), (S, A, Z, 2).
    """
    radial = _unit(psi)
    if spall is None:
        return np.zeros((1, *psi.shape)), np.ones((1, *psi.shape)), radial[None]
    if not spall.rectangular:
        return _profile_supports(psi, b, cm, spall, mode)
    r, r_o, depth = cm.roller_radius, cm.outer_raceway_radius, spall.depth
    rel = wrap_angle(psi - spall.centre)
    half = spall.half_angle
    if mode == "step":
        h = np.where(np.abs(rel) < half, depth, 0.0)
        return h[None], np.ones((1, *psi.shape)), radial[None]

    past_entry = rel + half  # angle the roller centre is past the entry edge
    before_exit = half - rel  # angle before the exit edge

    def edge_support(past, corner_angle):
        # on the raceway up to the edge, then pivoting on the corner; never lower than the
        # floor, which stops the rigid roller first (and a zero-depth spall is flat)
        corner = _corner_drop(np.maximum(past, 0.0), r, r_o)
        pivoting = (past > 0.0) & (corner < depth)
        h = np.where(past <= 0.0, 0.0, np.minimum(corner, depth))
        centre = (r_o - r + h)[..., None] * radial
        to_corner = r_o * _unit(np.full_like(psi, corner_angle)) - centre
        to_corner /= np.linalg.norm(to_corner, axis=-1, keepdims=True)
        u = np.where(pivoting[..., None], to_corner, radial)
        return h, u

    h_a, u_a = edge_support(past_entry, spall.entry)
    h_b, u_b = edge_support(before_exit, spall.exit)
    # shares of the Hertz patch (centred on the roller's foot) over each support: they
    # partition the patch, so a spall of zero depth is exactly the healthy raceway
    below_entry = support_fraction(-r_o * past_entry / b)
    below_exit = support_fraction(r_o * before_exit / b)
    h = np.stack([h_a, np.full_like(psi, depth), h_b])
    phi = np.stack([below_entry, below_exit - below_entry, 1.0 - below_exit])
    u = np.stack([u_a, radial, u_b])
    return h, phi, u


def _profile_supports(psi, b, cm: ContactModel, spall: Spall, mode: str):
    """:func:`_supports` for a spall with sloped walls or rounded edges.

    The roller follows its rigid path over the profile (:mod:`taichi_bearing.roller_path`):
    each support's drop is its first touch. Entry: the raceway before the edge and the
    edge itself (corner, or rounded edge). Floor: the floor (drop = depth, as in the
    rectangular model), the walls, and each edge that is not a sharp radial one, on which
    the roller keeps pivoting after its patch has crossed the edge until it meets the wall
    or the floor (a sharp radial edge is as in the rectangular model: the patch loses its
    support as it crosses it). Exit: the edge and the raceway after it. The Hertz patch
    is shared at the edges at the raceway as in the rectangular model, so a side with a
    sharp radial wall behaves exactly as there. The "step" model drops the roller by the
    profile's depth at its foot.
    """
    from taichi_bearing.roller_path import side_touch, wall_touch

    r, r_o, depth = cm.roller_radius, cm.outer_raceway_radius, spall.depth
    radial = _unit(psi)
    # angles near the spall on one branch, from +x
    phi = spall.centre + wrap_angle(psi - spall.centre) + 0.5 * np.pi
    profile = spall.profile(r_o)
    if mode == "step":
        return profile.depth_at(phi)[None], np.ones((1, *psi.shape)), radial[None]
    healthy = r_o - r

    def support(touches):
        rho = np.stack([t[0] for t in touches])
        k = np.argmin(rho, axis=0)
        rho = np.take_along_axis(rho, k[None], 0)[0]
        contact = np.stack([np.broadcast_to(t[1], (*psi.shape, 2)) for t in touches])
        contact = np.take_along_axis(contact, k[None, ..., None], 0)[0]
        h = np.minimum(rho - healthy, depth)  # the floor stops the rigid roller first
        centre = (healthy + h)[..., None] * radial
        u = contact - centre
        u /= np.maximum(np.linalg.norm(u, axis=-1, keepdims=True), 1e-300)
        return h, np.where((h < depth)[..., None], u, radial)

    right = 0.5 * np.pi
    pivots = [
        side_touch(phi, profile, r, start, False)
        for start, slope in ((True, spall.entry_slope), (False, spall.exit_slope))
        if not (abs(slope - right) < 1e-12 and spall.edge_radius == 0.0)
    ]
    e = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    walls = [wall_touch(e, edge, r) for edge in (profile.start_edge, profile.end_edge)]
    floor = (np.full(psi.shape, healthy + depth), (r_o + depth) * radial)
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


def _roller_forces(delta_r, psi, cm: ContactModel, spall: Spall | None, mode: str):
    """Force vectors (A, Z, 2) on the outer ring, and elastic deflections (A, Z)."""
    n = cm.exponent
    approach = delta_r[:, None] * np.cos(psi) - 0.5 * cm.clearance
    k_n = cm.k_series
    q_healthy = k_n * np.maximum(approach, 0.0) ** n
    # contact width the healthy patch would have, which sets how fast support is lost
    b = np.maximum(
        hertz_half_width(q_healthy, cm.roller_length, cm.outer_radius_eff, cm.e_star), 1e-9
    )
    h, phi, u = _supports(psi, b, cm, spall, mode)
    interference = np.maximum(approach[None] - h, 0.0)
    q = k_n * phi * interference**n
    force = np.sum(q[..., None] * u, axis=0)
    # deflection of the support carrying most of the force (zero when nothing carries)
    main = np.argmax(q, axis=0)[None]
    deflection = np.where(
        np.max(q, axis=0) > 0.0, np.take_along_axis(interference, main, axis=0)[0], 0.0
    )
    return force, deflection


def solve_load_distribution(
    cm: ContactModel,
    n_rollers: int,
    load: float,
    cage_angles,
    spall: Spall | None = None,
    mode: str = "patch",
) -> LoadDistribution:
    """Roller forces balancing a radial load, at each cage angle.

    Parameters
    ----------
    cm : ContactModel
        From :func:`contact_model`.
    n_rollers : int
        Number of rollers, equally spaced.
    load : float
        Radial load W, N (> 0), pushing the outer ring down.
    cage_angles : array_like
        Angle(s) of roller 0, rad from 12 o'clock, counter-clockwise.
    spall : Spall, optional
        Outer-raceway spall; None for a healthy bearing.
    mode : {"patch", "step"}
        ``"patch"``: finite roller and contact width (gradual); ``"step"``: the roller
        drops by the full depth as soon as its contact point is over the notch.

    Returns
    -------
    LoadDistribution
    """
    if mode not in MODES:
        raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
    if not (load > 0 and math.isfinite(load)):
        raise ValueError(f"load must be a positive finite force in N, got {load!r}")
    cage = np.atleast_1d(np.asarray(cage_angles, dtype=float))
    psi = wrap_angle(cage[:, None] + 2.0 * np.pi / n_rollers * np.arange(n_rollers))

    def residual(delta_r):
        force, _ = _roller_forces(delta_r, psi, cm, spall, mode)
        return force[..., 1].sum(axis=1) - load

    # bracket the ring displacement, then bisect to the last bit (robust: the vertical
    # force is continuous and increasing in delta_r)
    scale = (load / cm.k_series) ** (1.0 / cm.exponent) + abs(cm.clearance)
    lo = np.full(cage.shape, min(0.0, 0.5 * cm.clearance) - scale)
    hi = np.full(cage.shape, 0.5 * max(cm.clearance, 0.0) + scale)
    for _ in range(60):
        f_hi = residual(hi)
        if np.all(f_hi > 0):
            break
        hi = np.where(f_hi > 0, hi, hi + 2.0 * (hi - lo))
    else:
        raise RuntimeError("could not bracket the equilibrium: too few loaded rollers")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if np.all((mid == lo) | (mid == hi)):
            break  # interval down to adjacent floats
        f_mid = residual(mid)
        lo = np.where(f_mid <= 0, mid, lo)
        hi = np.where(f_mid > 0, mid, hi)
    # pick the end with the smaller residual
    f_lo, f_hi = residual(lo), residual(hi)
    delta_r = np.where(np.abs(f_lo) <= np.abs(f_hi), lo, hi)

    force, deflection = _roller_forces(delta_r, psi, cm, spall, mode)
    fx, fy = force[..., 0], force[..., 1]
    magnitude = np.hypot(fx, fy)
    inner = np.maximum(np.sum(force * _unit(psi), axis=-1), 0.0)
    length = cm.roller_length
    return LoadDistribution(
        load=float(load),
        cage_angle=cage,
        roller_angle=psi,
        ring_displacement=delta_r,
        outer_fx=fx,
        outer_fy=fy,
        outer_force=magnitude,
        inner_force=inner,
        deflection=deflection,
        outer_half_width=hertz_half_width(magnitude, length, cm.outer_radius_eff, cm.e_star),
        inner_half_width=hertz_half_width(inner, length, cm.inner_radius_eff, cm.e_star),
        outer_pmax=hertz_peak_pressure(magnitude, length, cm.outer_radius_eff, cm.e_star),
        inner_pmax=hertz_peak_pressure(inner, length, cm.inner_radius_eff, cm.e_star),
    )


def stribeck_ratio(dist: LoadDistribution) -> np.ndarray:
    """Q_max Z / W at each cage angle (4.08 for line contact at zero clearance)."""
    return dist.outer_force.max(axis=1) * dist.n_rollers / dist.load


def load_distribution_factor(dist: LoadDistribution, clearance: float) -> np.ndarray:
    """Harris's epsilon = (1 - P_d / (2 delta_r)) / 2: 0.5 at zero clearance, below 0.5
    with clearance (load zone under 180 degrees), above with preload."""
    return 0.5 * (1.0 - clearance / (2.0 * dist.ring_displacement))


def solve_case(
    case: Case, cage_angles, mode: str = "patch", healthy: bool = False
) -> LoadDistribution:
    """Load distribution of a case at the given angles of roller 0 (rad).

    ``healthy=True`` ignores the case's defect.
    """
    spall = None if healthy else spall_from_case(case)
    cm = contact_model(case.bearing, case.material)
    return solve_load_distribution(
        cm, case.bearing.n_rollers, case.operating.load, cage_angles, spall, mode
    )


def defect_sweep(
    case: Case, n_angles: int = 2001, mode: str = "patch", span: float | None = None
) -> LoadDistribution:
    """Load distribution while roller 0 passes the spall.

    Roller 0 sweeps one roller pitch centred on the spall (so every roller position is
    covered once), ``n_angles`` equally spaced cage angles; ``span`` (rad) narrows it.
    """
    spall = spall_from_case(case)
    centre = spall.centre if spall is not None else case.defect.angle
    pitch = 2.0 * np.pi / case.bearing.n_rollers if span is None else span
    angles = centre + np.linspace(-0.5 * pitch, 0.5 * pitch, n_angles)
    return solve_case(case, angles, mode)


def analytical_roller_forces(case: Case, cage_angle: float | None = None) -> np.ndarray:
    """Outer contact force of each roller (N), spall included, for comparison with the
    finite element preload (``summary.json: analytical_roller_forces_N``).

    Roller 0 sits at ``cage_angle`` (default ``case.run.first_roller_angle``).
    """
    angle = case.run.first_roller_angle if cage_angle is None else cage_angle
    return solve_case(case, angle).outer_force[0]


STATIC_COLUMNS = (
    "roller",
    "angle_deg",
    "outer_force_N",
    "inner_force_N",
    "outer_half_width_m",
    "inner_half_width_m",
    "outer_pmax_Pa",
    "inner_pmax_Pa",
    "deflection_m",
)


def static_contact_table(case: Case, cage_angle: float = 0.0) -> dict[str, np.ndarray]:
    """Static contact parameters of the healthy bearing at the case load, loaded rollers.

    Roller 0 sits at ``cage_angle`` (default 12 o'clock, where the most loaded roller is).
    Returns a mapping column -> array in the order of :data:`STATIC_COLUMNS`.
    """
    dist = solve_case(case, cage_angle, healthy=True)
    # cos(90 deg) is not exactly zero in floating point: ignore round-off forces
    loaded = np.flatnonzero(dist.outer_force[0] > 1e-9 * dist.load)
    columns = (
        loaded,
        np.degrees(dist.roller_angle[0, loaded]),
        dist.outer_force[0, loaded],
        dist.inner_force[0, loaded],
        dist.outer_half_width[0, loaded],
        dist.inner_half_width[0, loaded],
        dist.outer_pmax[0, loaded],
        dist.inner_pmax[0, loaded],
        dist.deflection[0, loaded],
    )
    return dict(zip(STATIC_COLUMNS, columns, strict=True))
