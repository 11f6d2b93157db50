r"""Quasi-static load distribution of a radially loaded roller bearing, with a line spall.

Healthy bearing (Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., ch. 7): the outer
ring (under the adapter) is pushed down by the radial load :math:`W` and moves by
:math:`\delta_r` relative to the inner ring, which is held by the shaft. Roller :math:`j` at
angle :math:`\psi_j` (from 12 o'clock) is squeezed by

.. math::

    \delta_j = \delta_r \cos\psi_j - P_d / 2

(:math:`P_d`: radial internal clearance) and carries :math:`Q_j = K_n \delta_j^n` (zero
when :math:`\delta_j \le 0`), :math:`K_n` being the two roller-raceway contacts in series.
:math:`\delta_r` is solved so that the vertical components of the
roller forces on the outer ring add up to :math:`W` to rounding error; the horizontal components
are taken by the adapter's horizontal constraint (as in the finite element model).

Line spall on the outer raceway (rectangular notch, arc length :math:`L`, depth :math:`H`,
sharp edges). The rollers move counter-clockwise, so they enter at the lower angle. Each
roller may bear on three supports, each with its own drop :math:`h` of the roller centre
(the rigid geometric path: pivot on the entry edge, floor, pivot on the exit edge):

- the raceway before the notch, ending at the entry corner: once the roller's foot has
  passed the corner the rigid roller pivots on it and its centre drops by
  :math:`h = \rho_\mathrm{corner} - (R_o - r)` (exact circle-on-corner geometry on the
  curved raceway);
- the floor of the notch, drop :math:`H`;
- the raceway after the notch, starting at the exit corner (mirror image of the first).

The Hertz patch of the roller (half-width :math:`b`, the healthy contact width at that
deflection, centred on the roller's foot) is shared by the supports: each carries the
share :math:`\phi` of the semi-elliptic pressure that lies over it, and

.. math::

    Q = K_n \sum_k \phi_k (\delta_j - h_k)^n

along the line from the roller centre to the contact point (radial on a surface, towards
the corner while pivoting). The shares add up to one, so a spall of zero depth is the
healthy raceway; as the patch crosses an edge its share moves gradually
(:math:`\phi = 0.5` with the patch centred on the edge) and the force is continuous in
cage angle. Where the drop exceeds the deflection (the usual spall) the floor carries
nothing: the roller de-stresses over about :math:`2b` at the entry edge and re-stresses
over about :math:`2b` at the exit edge.

The inner contact carries the radial component of the roller's outer force; the
tangential component (non-zero only while pivoting) is taken by the cage pocket.

Line spall on the inner raceway: the same supports on the convex raceway, the roller
outside it dropping inward (:math:`h = (R_i + r) - \rho_\mathrm{corner}` while pivoting,
the other root of the same circle-on-corner equation;
:mod:`taichi_bearing.analytic.spall_contact`), the Hertz patch of the inner contact. The
inner ring turns faster than the cage, so the rollers
move clockwise relative to it and enter at the edge at the larger angle. The outer
contact, healthy, carries the radial component of the inner contact's force. The spall
turns with the shaft: its position relative to each roller changes with time, and a
load distribution is solved for given spall angles (``spall_angles``;
:mod:`taichi_bearing.analytic.inner_race` gives those of a roller passing over it).

The "step" model, for comparison, ignores the roller size and contact width: a roller
whose contact point is inside the notch drops straight by :math:`H`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from taichi_bearing.analytic.bearing import (
    hertz_half_width,
    hertz_peak_pressure,
    wrap_angle,
)
from taichi_bearing.analytic.contact_model import ContactModel, contact_model
from taichi_bearing.analytic.spall_contact import (
    Spall,
    _corner_drop,  # noqa: F401 (tested here)
    spall_from_case,
    spall_supports,
    support_fraction,
    unit_from_top,
)
from taichi_bearing.case import Case

__all__ = [
    "ContactModel",
    "LoadDistribution",
    "analytical_roller_forces",
    "Spall",
    "contact_model",
    "defect_sweep",
    "load_zone",
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
    # (A,) the spall's centre at each cage angle, rad (given for a turning inner-race spall)
    spall_angle: np.ndarray | None = None

    @property
    def n_rollers(self) -> int:
        return int(self.outer_fx.shape[1])

    def balance_error(self) -> np.ndarray:
        """Relative error of the vertical equilibrium at each cage angle."""
        return np.abs(self.outer_fy.sum(axis=1) - self.load) / self.load


def _rotate(v, angle):
    """Vectors (..., 2) turned counter-clockwise by ``angle`` (broadcast to v[..., 0])."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _roller_forces(delta_r, psi, cm: ContactModel, spall: Spall | None, mode: str, turn=None):
    """Force vectors (A, Z, 2) on the outer ring, normal forces at the inner contact
    (A, Z) and elastic deflections (A, Z).

    ``turn`` (A,): how far an inner-race spall has turned from where ``spall`` puts it,
    rad; the supports are found in the spall's own frame and turned back.
    """
    n = cm.exponent
    approach = delta_r[:, None] * np.cos(psi) - 0.5 * cm.clearance
    k_n = cm.k_series
    q_healthy = k_n * np.maximum(approach, 0.0) ** n
    # contact width the healthy patch would have on the spalled raceway, which sets how
    # fast support is lost
    race = "outer" if spall is None else spall.race
    b = np.maximum(
        hertz_half_width(q_healthy, cm.roller_length, cm.raceway(race)[1], cm.e_star), 1e-9
    )
    if turn is None:
        h, phi, u = spall_supports(psi, b, cm, spall, mode)
    else:
        h, phi, u = spall_supports(wrap_angle(psi - turn[:, None]), b, cm, spall, mode)
        u = _rotate(u, turn[:, None])
    interference = np.maximum(approach[None] - h, 0.0)
    q = k_n * phi * interference**n
    force = np.sum(q[..., None] * u, axis=0)
    radial = unit_from_top(psi)
    if race == "outer":
        inner = np.maximum(np.sum(force * radial, axis=-1), 0.0)
    else:
        # the force on the inner ring; the healthy outer contact carries its radial
        # component (the cage pocket the tangential one while the roller pivots)
        inner = np.linalg.norm(force, axis=-1)
        force = np.maximum(-np.sum(force * radial, axis=-1), 0.0)[..., None] * radial
    # deflection of the support carrying most of the force (zero when nothing carries)
    main = np.argmax(q, axis=0)[None]
    deflection = np.where(
        np.max(q, axis=0) > 0.0, np.take_along_axis(interference, main, axis=0)[0], 0.0
    )
    return force, inner, deflection


def solve_load_distribution(
    cm: ContactModel,
    n_rollers: int,
    load: float,
    cage_angles,
    spall: Spall | None = None,
    mode: str = "patch",
    spall_angles=None,
) -> LoadDistribution:
    """Roller forces balancing a radial load, at each cage angle.

    Parameters
    ----------
    cm : ContactModel
        From :func:`contact_model`.
    n_rollers : int
        Number of rollers, equally spaced.
    load : float
        Radial load :math:`W`, N (> 0), pushing the outer ring down.
    cage_angles : array_like
        Angle(s) of roller 0, rad from 12 o'clock, counter-clockwise.
    spall : Spall, optional
        Spall on the outer or the inner raceway; None for a healthy bearing.
    mode : {"patch", "step"}
        ``"patch"``: finite roller and contact width (gradual); ``"step"``: the roller
        drops by the full depth as soon as its contact point is over the notch.
    spall_angles : array_like, optional
        Angle of the spall's centre at each cage angle, rad from 12 o'clock (an
        inner-race spall turns with the shaft, so its position relative to the rollers
        changes with time: :func:`taichi_bearing.analytic.inner_race.passage_angles`);
        default: where ``spall`` is.

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
    turn = None
    if spall_angles is not None and spall is not None:
        turn = np.broadcast_to(np.asarray(spall_angles, dtype=float), cage.shape) - spall.centre

    def residual(delta_r):
        force, _, _ = _roller_forces(delta_r, psi, cm, spall, mode, turn)
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

    force, inner, deflection = _roller_forces(delta_r, psi, cm, spall, mode, turn)
    fx, fy = force[..., 0], force[..., 1]
    magnitude = np.hypot(fx, fy)
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
        spall_angle=None if turn is None else turn + spall.centre,
    )


def stribeck_ratio(dist: LoadDistribution) -> np.ndarray:
    r""":math:`Q_\mathrm{max} Z / W` at each cage angle (4.08 for line contact at zero clearance).

    Examples
    --------
    Stribeck's constants from the load distribution of the default bearing at zero
    clearance, roller 0 at 12 o'clock: 4.08 for line contact (:math:`Q \propto \delta^{10/9}`) and
    4.37 with the point-contact exponent 3/2 (ball bearings).

    >>> from taichi_bearing.case import Bearing, Material
    >>> b = Bearing(n_rollers=20, roller_diameter=0.024, pitch_diameter=0.2,
    ...             roller_length=0.05, radial_clearance=0.0, outer_ring_thickness=0.014,
    ...             inner_ring_thickness=0.012, adapter_width=0.12, adapter_height=0.03)
    >>> steel = Material(youngs_modulus=210e9, poissons_ratio=0.3, density=7850.0)
    >>> line = solve_load_distribution(contact_model(b, steel), 20, 50e3, [0.0])
    >>> point = solve_load_distribution(contact_model(b, steel, 1.5), 20, 50e3, [0.0])
    >>> print(f"{stribeck_ratio(line)[0]:.2f} {stribeck_ratio(point)[0]:.2f}")
    4.08 4.37
    """
    return dist.outer_force.max(axis=1) * dist.n_rollers / dist.load


def load_distribution_factor(dist: LoadDistribution, clearance: float) -> np.ndarray:
    r"""Harris's :math:`\varepsilon = (1 - P_d / (2 \delta_r)) / 2`: 0.5 at zero clearance,
    below 0.5 with clearance (load zone under 180 degrees), above with preload."""
    return 0.5 * (1.0 - clearance / (2.0 * dist.ring_displacement))


def solve_case(
    case: Case, cage_angles, mode: str = "patch", healthy: bool = False, spall_angles=None
) -> LoadDistribution:
    """Load distribution of a case at the given angles of roller 0 (rad).

    ``healthy=True`` ignores the case's defect; ``spall_angles``: where an inner-race
    spall's centre is at each cage angle (default: where it starts, ``defect.angle``).
    """
    spall = None if healthy else spall_from_case(case)
    cm = contact_model(case.bearing, case.material)
    return solve_load_distribution(
        cm, case.bearing.n_rollers, case.operating.load, cage_angles, spall, mode, spall_angles
    )


def defect_sweep(
    case: Case,
    n_angles: int = 2001,
    mode: str = "patch",
    span: float | None = None,
    spall_angle: float | None = None,
) -> LoadDistribution:
    """Load distribution while roller 0 passes the spall.

    Roller 0 sweeps one roller pitch centred on the spall (so every roller position is
    covered once), ``n_angles`` equally spaced cage angles; ``span`` (rad) narrows it.
    An inner-race spall turns with the shaft while roller 0 crosses it: the sweep covers
    one pitch of their relative motion, the spall's centre at ``spall_angle`` (rad from
    12 o'clock, default ``defect.angle``) when roller 0 is on it
    (:func:`taichi_bearing.analytic.inner_race.passage_angles`).
    """
    spall = spall_from_case(case)
    if spall is not None and spall.race == "inner":
        from taichi_bearing.analytic.inner_race import passage_angles

        centre = spall.centre if spall_angle is None else spall_angle
        cage, at, _ = passage_angles(case, centre, n_angles, span)
        return solve_case(case, cage, mode, spall_angles=at)
    centre = spall.centre if spall is not None else case.defect.angle
    pitch = 2.0 * np.pi / case.bearing.n_rollers if span is None else span
    angles = centre + np.linspace(-0.5 * pitch, 0.5 * pitch, n_angles)
    return solve_case(case, angles, mode)


def analytical_roller_forces(case: Case, cage_angle: float | None = None) -> np.ndarray:
    """Outer contact force of each roller (N), spall included, for comparison with the
    finite element preload (``summary.json: analytical_roller_forces_N``).

    Roller 0 sits at ``cage_angle`` (default ``case.run.first_roller_angle``); an
    inner-race spall where it starts (the preload holds the shaft at angle 0).
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


def load_zone(case: Case, n_angles: int = 721) -> tuple[np.ndarray, np.ndarray]:
    """The load a spall turning with the inner ring meets at each of its angles: the force
    of a roller at that angle in the healthy bearing (rigid-ring Harris model), N.

    Returns the angles (rad from 12 o'clock, one turn) and the forces.
    """
    angles = np.linspace(-math.pi, math.pi, n_angles, endpoint=False)
    return angles, solve_case(case, angles, healthy=True).outer_force[:, 0]
