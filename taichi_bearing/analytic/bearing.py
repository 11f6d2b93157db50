r"""Bearing kinematics and Hertz line contact (pure numpy, SI units).

Kinematics assume pure rolling with a stationary outer ring and the inner ring turning
counter-clockwise at the shaft speed; the fault frequencies come from
:func:`diagnostics.bearing_frequencies` (one copy of the formulas).

Contact (Johnson, *Contact Mechanics*, 1985, section 4.3; Harris & Kotzalas, *Rolling
Bearing Analysis*, 5th ed., 2007):

- effective modulus :math:`1/E^* = (1 - \nu_1^2)/E_1 + (1 - \nu_2^2)/E_2`;
- effective radius :math:`1/R = 1/r + 1/R_i` (roller on the convex inner raceway) and
  :math:`1/R = 1/r - 1/R_o` (roller in the concave outer raceway);
- half-width :math:`b = \sqrt{4 P R / (\pi E^*)}` and peak pressure
  :math:`p_\mathrm{max} = 2 P / (\pi b)` for a load :math:`P` per unit length;
- load-deflection (Palmgren): :math:`Q = K \delta^{10/9}` per roller-raceway contact with
  :math:`K = 8.06 \cdot 10^4 \, l^{8/9}` in N, mm units (Palmgren 1959, the inverse of
  :math:`\delta = 3.84 \cdot 10^{-5} \, Q^{0.9} / l^{0.8}`; Harris & Kotzalas eq. 6.46),
  which is :math:`K = 8.06 \cdot 10^{10} \, l^{8/9}` :math:`\mathrm{N/m^{10/9}}` with
  :math:`l` in m. It holds for bearing steel; other materials are scaled by
  :math:`E^* / E^*_\mathrm{steel}` (deflection at a given load varies as :math:`1/E^*`).
"""

from __future__ import annotations

import math

import numpy as np

from diagnostics import FaultFrequencies, bearing_frequencies
from taichi_bearing.case import Bearing, Material

__all__ = [
    "LINE_CONTACT_EXPONENT",
    "PALMGREN_K_SI",
    "contact_radius",
    "effective_modulus",
    "fault_frequencies",
    "hertz_half_width",
    "hertz_peak_pressure",
    "cage_speed",
    "palmgren_stiffness",
    "roller_angles",
    "roller_spacing",
    "rolling_surface_speed",
    "series_stiffness",
    "wrap_angle",
]

LINE_CONTACT_EXPONENT = 10.0 / 9.0
# Palmgren's K = 8.06e4 N/mm^(10/9) * l_mm^(8/9): with delta and l in m,
# K_SI = 8.06e4 * 1e3^(8/9) * 1e3^(10/9) = 8.06e10 N/m^(10/9) * l_m^(8/9).
PALMGREN_K_SI = 8.06e10
# The steel Palmgren's constant was fitted to (Harris: E = 2.075e5 MPa, nu = 0.3).
STEEL_E_STAR = 2.075e11 / (2.0 * (1.0 - 0.3**2))


# ----------------------------------------------------------------------------- kinematics


def fault_frequencies(bearing: Bearing, shaft_hz: float) -> FaultFrequencies:
    """FTF, BPFO, BPFI and BSF in Hz (stationary outer ring), via ``diagnostics``.

    Examples
    --------
    The default bearing (20 rollers of 24 mm on a 200 mm pitch circle) at 500 rpm:

    >>> from taichi_bearing.case import Bearing
    >>> b = Bearing(n_rollers=20, roller_diameter=0.024, pitch_diameter=0.2,
    ...             roller_length=0.05, radial_clearance=0.0, outer_ring_thickness=0.014,
    ...             inner_ring_thickness=0.012, adapter_width=0.12, adapter_height=0.03)
    >>> f = fault_frequencies(b, 500 / 60)
    >>> print(f"FTF {f.ftf:.3f} Hz, BPFO {f.bpfo:.2f} Hz, BPFI {f.bpfi:.2f} Hz")
    FTF 3.667 Hz, BPFO 73.33 Hz, BPFI 93.33 Hz
    """
    return bearing_frequencies(bearing.geometry, shaft_hz)


def cage_speed(bearing: Bearing, shaft_speed: float) -> float:
    r"""Cage angular speed, rad/s, for a shaft speed in rad/s (:math:`2 \pi \, \mathrm{FTF}`)."""
    return 2.0 * math.pi * fault_frequencies(bearing, shaft_speed / (2.0 * math.pi)).ftf


def rolling_surface_speed(bearing: Bearing, shaft_speed: float) -> float:
    r"""Speed at which the contacts travel over the roller surface and the raceways, m/s.

    With pure rolling the roller surface speed relative to the cage,
    :math:`2 \pi \, \mathrm{BSF} \, d/2`, equals the speed of the contact along the outer
    raceway, :math:`\omega_\mathrm{cage} R_o`.
    """
    f = fault_frequencies(bearing, shaft_speed / (2.0 * math.pi))
    return 2.0 * math.pi * f.bsf * bearing.roller_radius


def roller_spacing(bearing: Bearing) -> float:
    """Angle between neighbouring rollers, rad."""
    return 2.0 * math.pi / bearing.n_rollers


def wrap_angle(angle):
    r"""Angle(s) wrapped into :math:`[-\pi, \pi)`."""
    return (np.asarray(angle, dtype=float) + np.pi) % (2.0 * np.pi) - np.pi


def roller_angles(
    bearing: Bearing, t=0.0, shaft_speed: float = 0.0, first_angle: float = 0.0
) -> np.ndarray:
    r"""Angular positions of the roller centres, rad from 12 o'clock, counter-clockwise.

    Parameters
    ----------
    bearing : Bearing
    t : float or array_like
        Time(s), s.
    shaft_speed : float
        Shaft speed, rad/s (counter-clockwise); the cage turns at :func:`cage_speed`.
    first_angle : float
        Angle of roller 0 at t = 0, rad.

    Returns
    -------
    ndarray
        Shape ``(n_rollers,)`` for a scalar ``t``, else ``t.shape + (n_rollers,)``;
        wrapped into :math:`[-\pi, \pi)`.
    """
    t = np.asarray(t, dtype=float)
    base = first_angle + roller_spacing(bearing) * np.arange(bearing.n_rollers)
    cage = cage_speed(bearing, shaft_speed) * t if shaft_speed else np.zeros_like(t)
    return wrap_angle(base + cage[..., None])


# --------------------------------------------------------------------------------- Hertz


def effective_modulus(e1: float, nu1: float, e2: float | None = None, nu2: float | None = None):
    r"""Contact modulus :math:`E^*`, Pa: :math:`1/E^* = (1 - \nu_1^2)/E_1 + (1 - \nu_2^2)/E_2`
    (the same body twice if the second is omitted)."""
    e2 = e1 if e2 is None else e2
    nu2 = nu1 if nu2 is None else nu2
    return 1.0 / ((1.0 - nu1**2) / e1 + (1.0 - nu2**2) / e2)


def contact_radius(bearing: Bearing, race: str) -> float:
    """Effective radius :math:`R` of the roller-raceway contact, m.

    ``race="inner"``: convex on convex, :math:`1/R = 1/r + 1/R_i`; ``race="outer"``: convex
    in concave, :math:`1/R = 1/r - 1/R_o`.
    """
    r = bearing.roller_radius
    if race == "inner":
        return 1.0 / (1.0 / r + 1.0 / bearing.inner_raceway_radius)
    if race == "outer":
        return 1.0 / (1.0 / r - 1.0 / bearing.outer_raceway_radius)
    raise ValueError(f"race must be 'inner' or 'outer', got {race!r}")


def hertz_half_width(force, length: float, radius: float, e_star: float):
    r"""Half-width :math:`b` of a Hertz line contact, m: :math:`b = \sqrt{4 P R / (\pi E^*)}`,
    :math:`P` = force/length.

    Parameters
    ----------
    force : float or array_like
        Contact force, N (negative values are treated as zero).
    length : float
        Contact length, m.
    radius : float
        Effective radius :math:`R`, m.
    e_star : float
        Contact modulus :math:`E^*`, Pa.

    Examples
    --------
    The default bearing's most loaded roller (15.4 kN over 50 mm) against the outer
    raceway (:math:`R` = 13.44 mm), steel on steel: a contact 0.43 mm wide, 917 MPa at its
    centre.

    >>> from taichi_bearing.analytic.bearing import effective_modulus, hertz_peak_pressure
    >>> e_star = effective_modulus(210e9, 0.3)
    >>> b = hertz_half_width(15.4e3, 0.05, 13.44e-3, e_star)
    >>> p = hertz_peak_pressure(15.4e3, 0.05, 13.44e-3, e_star)
    >>> print(f"2b = {2e3 * b:.2f} mm, p_max = {p / 1e6:.0f} MPa")
    2b = 0.43 mm, p_max = 917 MPa
    """
    p = np.maximum(np.asarray(force, dtype=float), 0.0) / length
    return np.sqrt(4.0 * p * radius / (np.pi * e_star))


def hertz_peak_pressure(force, length: float, radius: float, e_star: float):
    r"""Peak pressure :math:`p_\mathrm{max} = 2 P / (\pi b) = \sqrt{P E^* / (\pi R)}`, Pa
    (:math:`P` = force/length)."""
    p = np.maximum(np.asarray(force, dtype=float), 0.0) / length
    return np.sqrt(p * e_star / (np.pi * radius))


def palmgren_stiffness(bearing: Bearing, material: Material) -> float:
    r"""Palmgren load-deflection constant :math:`K` of one roller-raceway contact,
    :math:`\mathrm{N/m^{10/9}}`.

    :math:`Q = K \delta^{10/9}` with :math:`K = 8.06 \cdot 10^{10} \, l^{8/9}` (:math:`l` in
    m) for bearing steel, scaled by :math:`E^* / E^*_\mathrm{steel}` for other materials.
    """
    e_star = effective_modulus(material.youngs_modulus, material.poissons_ratio)
    return PALMGREN_K_SI * bearing.roller_length ** (8.0 / 9.0) * e_star / STEEL_E_STAR


def series_stiffness(k_outer, k_inner, n: float = LINE_CONTACT_EXPONENT):
    r"""Load-deflection constant of two contacts in series, :math:`Q = K \delta_\mathrm{total}^n`.

    Both contacts carry the same :math:`Q`, so
    :math:`\delta = (Q/K_o)^{1/n} + (Q/K_i)^{1/n}` and
    :math:`K = (K_o^{-1/n} + K_i^{-1/n})^{-n}`. A zero stiffness gives zero.
    """
    k_outer = np.asarray(k_outer, dtype=float)
    k_inner = np.asarray(k_inner, dtype=float)
    with np.errstate(divide="ignore"):
        compliance = k_outer ** (-1.0 / n) + k_inner ** (-1.0 / n)
        return np.where((k_outer > 0) & (k_inner > 0), compliance ** (-n), 0.0)
