r"""The quasi-static Hertz impact of two elastic bodies in plane strain: the reference of
:mod:`taichi_bearing.validation.impact`.

A line contact's approach under line load :math:`P`, measured between the bodies' far faces,
is :math:`\delta = (2 P / (\pi E^*)) \ln(\Lambda / b(P))` (the form from Johnson's
half-space compression; :func:`half_space_size` gives :math:`\Lambda` for two half-spaces,
the impact module calibrates it for finite bodies). The impact is the rigid-body ODE
:math:`M \ddot\delta = -P(\delta)` (:func:`reference_impact`). Numpy and scipy only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq
from scipy.special import lambertw

from taichi_bearing.analytic.bearing import hertz_half_width

__all__ = [
    "LineContactLaw",
    "ReferenceImpact",
    "half_space_size",
    "hertz_nodal_forces",
    "peak_load",
    "reference_impact",
    "speed_for_peak",
]


def half_space_size(depth_1: float, depth_2: float, poissons_ratio: float) -> float:
    r"""Size term :math:`\Lambda` of two half-spaces of one material, each compressed from
    its surface to a point at depth :math:`d_i` below the contact centre (needs
    :math:`d_i \gg b`): :math:`2 \sqrt{d_1 d_2} \exp(-\nu / (2 (1 - \nu)))`, m."""
    nu = poissons_ratio
    return 2.0 * math.sqrt(depth_1 * depth_2) * math.exp(-nu / (2.0 * (1.0 - nu)))


@dataclass(frozen=True)
class LineContactLaw:
    r"""Plane-strain Hertz approach
    :math:`\delta = (2 P / (\pi E^*)) \ln(\mathrm{size} / b(P))`.

    Attributes
    ----------
    e_star : float
        Contact modulus :math:`E^*`, Pa.
    radius : float
        Effective radius :math:`R`, m.
    size : float
        Size term :math:`\Lambda`, m (where the approach is measured; see the module notes).
    """

    e_star: float
    radius: float
    size: float

    def half_width(self, load: float | np.ndarray) -> float | np.ndarray:
        """Hertz half-width :math:`b` of line load ``load`` (N/m), m."""
        return hertz_half_width(load, 1.0, self.radius, self.e_star)

    def approach(self, load: float | np.ndarray) -> float | np.ndarray:
        r"""Approach :math:`\delta` under line load ``load`` (N/m), m."""
        p = np.maximum(np.asarray(load, dtype=float), 0.0)
        b = np.maximum(self.half_width(p), 1e-300)
        return np.where(p > 0, 2.0 * p / (math.pi * self.e_star) * np.log(self.size / b), 0.0)

    def force(self, approach: float | np.ndarray) -> float | np.ndarray:
        r"""Line load (N/m) at ``approach`` (m): the inverse of :meth:`approach`.

        With :math:`q = \pi E^* \Lambda^2 / (4 R)` the law reads
        :math:`\delta = (P / (\pi E^*)) \ln(q / P)`, so
        :math:`P = q \exp(W_{-1}(-\pi E^* \delta / q))` (Lambert W, lower branch: the loads
        below :math:`q / e`, where the approach grows with the load).
        """
        d = np.maximum(np.asarray(approach, dtype=float), 0.0)
        q = math.pi * self.e_star * self.size**2 / (4.0 * self.radius)
        z = -math.pi * self.e_star * d / q
        if np.any(z < -1.0 / math.e):
            raise ValueError("approach beyond the law's range (b would exceed size/sqrt(e))")
        w = np.real(lambertw(np.minimum(z, -1e-300), -1))
        return np.where(d > 0, q * np.exp(w), 0.0)

    def energy(self, load: float) -> float:
        r"""Work :math:`\int P \, d\delta` from zero up to line load ``load``, J/m."""

        def stiffness_inverse(p: float) -> float:  # d(delta)/dP
            return (2.0 * math.log(self.size / self.half_width(p)) - 1.0) / (math.pi * self.e_star)

        return quad(lambda p: p * stiffness_inverse(p), 0.0, load, limit=200)[0]


def hertz_nodal_forces(x: np.ndarray, load: float, b: float, centre: float = 0.0) -> np.ndarray:
    r"""Consistent nodal forces (N/m) of the Hertz pressure :math:`p_0 \sqrt{1 - s^2 / b^2}`
    of resultant ``load`` about ``centre``, on nodes at increasing positions ``x``
    joined by linear segments."""
    x = np.asarray(x, dtype=float)
    # s = b sin(t): the pressure times ds is (2 P / pi) cos^2(t) dt, smooth in t.
    t = np.linspace(-0.5 * math.pi, 0.5 * math.pi, 40_001)
    w = np.cos(t) ** 2 * (t[1] - t[0])
    s = centre + b * np.sin(t)
    j = np.clip(np.searchsorted(x, s, side="right") - 1, 0, len(x) - 2)
    u = (s - x[j]) / (x[j + 1] - x[j])
    f = np.zeros(len(x))
    np.add.at(f, j, w * (1.0 - u))
    np.add.at(f, j + 1, w * u)
    return f * load / f.sum()


def peak_load(law: LineContactLaw, mass: float, v0: float) -> float:
    """Line load (N/m) at which the contact has stored the kinetic energy
    :math:`M v_0^2 / 2`."""
    target = 0.5 * mass * v0**2
    hi = 1.0
    while law.energy(hi) < target:
        hi *= 2.0
    return brentq(lambda p: law.energy(p) - target, 0.0, hi, xtol=1e-12 * hi, rtol=1e-12)


def speed_for_peak(law: LineContactLaw, mass: float, load: float) -> float:
    """Approach speed (m/s) whose impact peaks at line load ``load`` (N/m)."""
    return math.sqrt(2.0 * law.energy(load) / mass)


@dataclass(frozen=True)
class ReferenceImpact:
    """Quasi-static impact history and its summary (forces N/m, times s, lengths m)."""

    time: np.ndarray
    force: np.ndarray
    approach: np.ndarray
    peak: float
    duration: float  # from touch to separation
    duration_above: float  # first to last time above the threshold
    threshold: float


def reference_impact(
    law: LineContactLaw, mass: float, v0: float, threshold: float, n_out: int = 2001
) -> ReferenceImpact:
    r"""Integrate :math:`M \ddot\delta = -P(\delta)` from :math:`\delta = 0`,
    :math:`\dot\delta = v_0` to separation.

    Parameters
    ----------
    law : LineContactLaw
    mass : float
        Moving mass, kg/m.
    v0 : float
        Approach speed, m/s.
    threshold : float
        Force (N/m) that :attr:`ReferenceImpact.duration_above` is measured above, as for
        the finite element histories.
    n_out : int
        Samples of the returned history.
    """

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        return [y[1], -float(law.force(y[0])) / mass]

    def separated(_t: float, y: np.ndarray) -> float:
        return y[0]

    def crossing(_t: float, y: np.ndarray) -> float:
        return float(law.force(y[0])) - threshold

    separated.terminal, separated.direction = True, -1.0
    # The span: four half-periods of the secant stiffness at the peak load (energy).
    p_peak = peak_load(law, mass, v0)
    t_span = 4.0 * math.pi * math.sqrt(mass * float(law.approach(p_peak)) / p_peak)
    sol = solve_ivp(
        rhs,
        (0.0, t_span),
        [0.0, v0],
        events=[separated, crossing],
        dense_output=True,
        rtol=1e-10,
        atol=[1e-16, 1e-12],
        max_step=t_span / 2000,
    )
    if not sol.t_events[0].size:
        raise RuntimeError("the reference impact did not separate; lengthen the span")
    t_sep = float(sol.t_events[0][0])
    t = np.linspace(0.0, t_sep, n_out)
    d = sol.sol(t)[0]
    p = law.force(d)
    up = sol.t_events[1]
    above = float(up[-1] - up[0]) if up.size >= 2 else 0.0
    return ReferenceImpact(t, p, d, float(p.max()), t_sep, above, threshold)
