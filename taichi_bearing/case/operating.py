"""Operating points judged by their physics before any work: the surface speed against
the material's wave speeds, the most loaded contact's pressure against what an elastic solid
carries (and, warned, against the static capacity). Part of
:func:`~taichi_bearing.case.validate.check_case`."""

from __future__ import annotations

import math
import warnings

from taichi_bearing.case.sections import Case
from taichi_bearing.errors import CaseError, CaseWarning

__all__ = [
    "MAX_PRESSURE_RATIO",
    "MAX_SURFACE_SPEED_RATIO",
    "STATIC_CAPACITY_PRESSURE",
    "ContactPressureWarning",
    "check_operating",
    "peak_contact_pressure",
]

MM = 1e3  # m -> mm, for messages

MAX_SURFACE_SPEED_RATIO = 0.1
r"""Fastest inner-raceway surface speed a case may have, as a fraction of the material's
shear wave speed (steel: 10 % of 3.2 km/s, 320 m/s). The inner raceway moves fastest of
all the bearing's material (the rollers' points on it move with it; the contacts roll
over both surfaces at :math:`(R_p + r) / (2 R_p)` of it, :math:`R_p` the pitch radius).
Industrial bearings run below 1 % of the shear wave speed and the fastest built
(aero-engine main shafts, DN ~ 3e6 mm rpm) at 5 to 8 %. At 10 % a ring's centrifugal hoop
stress :math:`\rho v^2` is already :math:`\mu / 100` (0.8 GPa in steel), and nearer the
Rayleigh wave speed (7 % below the shear wave speed) a moving contact load is no longer
the quasi-static Hertz contact that the preload, the analytic model and the penalty's
calibration assume."""

MAX_PRESSURE_RATIO = 0.05
r"""Largest Hertz peak pressure of the most loaded contact (:func:`peak_contact_pressure`),
as a fraction of Young's modulus :math:`E` (steel: :math:`E / 20` = 10.5 GPa). The
contact's half-width is :math:`b = 2 R p_0 / E^* = 4 (1 - \nu^2) R p_0 / E`: :math:`0.18 R`
at :math:`E / 20`, where Hertz's premise of a contact small against its radii is gone; in
steel it is 2.6 times the static-capacity pressure (:data:`STATIC_CAPACITY_PRESSURE`) and
three times the ~3.5 GPa at which hardened bearing steel first yields under a line
contact. A run of it describes no bearing."""

STATIC_CAPACITY_PRESSURE = 4.0e9
"""Hertz peak pressure of a roller bearing's basic static load rating, Pa (ISO 76 sets 4000
MPa at the centre of the most loaded roller contact, which leaves a permanent set of
1e-4 of the roller diameter). Above it a steel bearing is overloaded: warned
(:class:`ContactPressureWarning`) rather than refused, since an overload may be what is
studied; the elastic model ignores the plastic set."""


class ContactPressureWarning(CaseWarning):
    """The load presses the most loaded roller beyond the static capacity
    (:data:`STATIC_CAPACITY_PRESSURE`)."""


_LINE_CONTACT_EXPONENT = 10.0 / 9.0


def peak_contact_pressure(case: Case) -> float:
    r"""Hertz peak pressure of the most loaded contact of the healthy bearing, Pa.

    The roller at 12 o'clock under ``operating.load``, in the rigid-ring model of
    :mod:`taichi_bearing.analytic.quasistatic`, on the inner raceway (the smaller Hertz
    radius, so the higher pressure): :math:`p_0 = \sqrt{Q E^* / (\pi R l)}`. With clearance
    :math:`P_d \ge 0` roller :math:`j` carries at most :math:`Q \cos^n \psi_j`, with equality
    at :math:`P_d = 0`, so :math:`Q \ge W / \sum_j \cos^{n+1} \psi_j` over the rollers in the
    upper half: Stribeck's load of the most loaded roller (:math:`4.08 W / Z` for many
    rollers), exact at zero clearance and a lower bound with clearance; with preload only
    :math:`W / \sum_j \cos \psi_j` is sure.
    A lower bound, so that a case refused on it is refused by the model too.

    Parameters
    ----------
    case : Case
        The loaded case (its bearing, material and ``operating.load``).

    Returns
    -------
    float
        ``p0``, Pa: the quasi-static model's at zero clearance, at most it otherwise
        (:func:`taichi_bearing.analytic.quasistatic.static_contact_table`, cage angle 0).
    """
    b, m = case.bearing, case.material
    power = 1.0 + (_LINE_CONTACT_EXPONENT if b.radial_clearance >= 0.0 else 0.0)
    cosines = (math.cos(j * b.roller_spacing) for j in range(b.n_rollers))
    q_max = case.operating.load / sum(c**power for c in cosines if c > 0.0)
    # convex on convex: 1/R = 1/r + 1/R_i; E* of one material on itself is E' / 2
    radius = 1.0 / (1.0 / b.roller_radius + 1.0 / b.inner_raceway_radius)
    e_star = 0.5 * m.plane_strain_modulus
    return math.sqrt(q_max / b.roller_length * e_star / (math.pi * radius))


def check_operating(case: Case, src: str | None) -> None:
    """The speed against the shear wave speed, the load's contact pressure against what
    an elastic solid carries (and, warned, against the static capacity)."""
    b, m, op = case.bearing, case.material, case.operating
    speed = op.speed * b.inner_raceway_radius
    c_s = m.shear_wave_speed
    fastest = MAX_SURFACE_SPEED_RATIO * c_s
    if speed > fastest:
        raise CaseError(
            "operating.speed_rpm",
            f"{op.shaft_rpm:.4g} rpm moves the inner raceway at {speed:.3g} m/s, "
            f"{speed / c_s:.3g} x the material's shear wave speed ({c_s:.4g} m/s); no "
            f"bearing runs above {100 * MAX_SURFACE_SPEED_RATIO:g} % of it (at most "
            f"{op.shaft_rpm * fastest / speed:.4g} rpm here): the contact would not be "
            "quasi-static",
            src,
        )
    p0 = peak_contact_pressure(case)
    # p0 grows as sqrt(load): the load that would reach a pressure p is load (p / p0)^2
    strongest = MAX_PRESSURE_RATIO * m.youngs_modulus
    where = (
        f"{op.load / 1e3:.4g} kN presses the most loaded roller ({b.roller_length * MM:g} mm "
        f"long) on the inner raceway at {p0 / 1e9:.3g} GPa (Hertz peak pressure)"
    )
    if p0 > strongest:
        raise CaseError(
            "operating.load_kN",
            f"{where}, above E/{1 / MAX_PRESSURE_RATIO:g} ({strongest / 1e9:.3g} GPa, E "
            f"{m.youngs_modulus / 1e9:.4g} GPa) that no elastic solid carries (at most "
            f"{op.load * (strongest / p0) ** 2 / 1e3:.4g} kN here)",
            src,
        )
    if p0 > STATIC_CAPACITY_PRESSURE:
        warnings.warn(
            ContactPressureWarning(
                "operating.load_kN",
                f"{where}, above the {STATIC_CAPACITY_PRESSURE / 1e9:g} GPa of a roller "
                "bearing's static capacity (ISO 76; "
                f"{op.load * (STATIC_CAPACITY_PRESSURE / p0) ** 2 / 1e3:.4g} kN here): steel "
                "would take a permanent set, which the elastic model ignores",
                src,
            ),
            stacklevel=4,
        )
