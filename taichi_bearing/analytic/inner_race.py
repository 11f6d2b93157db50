r"""An inner-race spall turns with the shaft: where it is and how a roller passes over it
(numpy only); the load it meets on the way round is
:func:`taichi_bearing.analytic.quasistatic.load_zone`.

The inner ring turns at the shaft speed :math:`\omega_s` and the rollers at the cage speed
:math:`\omega_c` (both counter-clockwise, :math:`\omega_c < \omega_s`), so the spall
overtakes the rollers: relative to the ring a roller moves clockwise and meets the spall's
edge at the larger angle first. A roller passes over the spall when the spall's angle in
the fixed frame, :math:`\theta_s(t) = \theta_{s0} + \omega_s t` (:math:`\theta_{s0}`:
``defect.angle``, in the ring's frame at :math:`t = 0`), crosses the roller's, once every
:math:`2 \pi / (Z (\omega_s - \omega_c)) = 1 / \mathrm{BPFI}`; between two passages the
spall turns :math:`\omega_s / \mathrm{BPFI}` in the fixed frame (32.1 degrees on the
default bearing). Each passage meets the load of the roller at that angle: full under the
load, nothing outside the load zone. The impacts are therefore modulated once per shaft
turn, which puts shaft-rate sidebands :math:`k \, \mathrm{BPFI} \pm m f_s` in the envelope
spectrum (:func:`sideband_ratio`).
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.analytic.bearing import cage_speed, wrap_angle
from taichi_bearing.case import Case

__all__ = [
    "passage_angles",
    "passage_spall_angles",
    "sideband_ratio",
]


def _rates(case: Case) -> tuple[float, float]:
    """Shaft and cage speeds, rad/s."""
    shaft = case.operating.speed
    return shaft, cage_speed(case.bearing, shaft)


def passage_angles(
    case: Case,
    centre: float,
    n_angles: int = 2001,
    span: float | None = None,
    around: float = 0.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Roller 0 passing over the inner-race spall, which turns while it does.

    Parameters
    ----------
    case : Case
    centre : float
        Angle of the spall's centre (fixed frame, rad from 12 o'clock) at the instant
        roller 0 is on it.
    n_angles : int
        Instants, equally spaced in time.
    span : float, optional
        Relative angle covered (rad, default one roller pitch, so every relative position
        of the rollers and the spall is met once).
    around : float
        Travel at the middle of the span, rad (0: roller 0 on the spall's centre; minus
        the half-angle of the spall: on its entry edge).

    Returns
    -------
    cage_angles, spall_angles, travel : ndarray
        Roller 0's angle and the spall centre's at each instant (rad from 12 o'clock) and
        the travel ``spall - roller 0``, which grows through the passage: roller 0 meets
        the entry edge at ``travel = -half`` and leaves over the exit edge at ``+half``.
    """
    shaft, cage = _rates(case)
    pitch = 2.0 * math.pi / case.bearing.n_rollers if span is None else span
    travel = around + np.linspace(-0.5 * pitch, 0.5 * pitch, n_angles)
    tau = travel / (shaft - cage)  # time from the instant roller 0 is on the centre
    return centre + cage * tau, centre + shaft * tau, travel


def passage_spall_angles(case: Case, first_roller_angle: float, start: float, count: int):
    """The spall's angles (fixed frame, rad, wrapped) and times (s) of the first ``count``
    passages after t = 0: the spall starts at ``start``, roller 0 at ``first_roller_angle``
    and roller j ``j`` pitches ahead; the spall reaches roller j after it reached j - 1."""
    shaft, cage = _rates(case)
    pitch = 2.0 * math.pi / case.bearing.n_rollers
    # the roller the spall reaches first: the nearest ahead of it (relative angle >= 0)
    gap0 = (first_roller_angle - start) % pitch
    gaps = gap0 + pitch * np.arange(count)
    times = gaps / (shaft - cage)
    return wrap_angle(start + shaft * times), times


def sideband_ratio(angles: np.ndarray, weight: np.ndarray, order: int = 1) -> float:
    r"""Shaft-rate sideband over the carrier of a pulse train modulated by ``weight``.

    Impulses at BPFI whose strength follows :math:`\mathrm{weight}(\theta_s)`, the spall's
    angle, make lines at :math:`k \, \mathrm{BPFI} + m f_s` of amplitude proportional to the
    :math:`m`-th Fourier coefficient of ``weight`` over one shaft turn: the ``order``-th
    sideband over the line at :math:`k \, \mathrm{BPFI}` is :math:`|c_m| / c_0`. In the
    squared envelope an impulse counts with its square: impulses growing with the load
    :math:`Q` give a ``weight`` of :math:`Q^2`.

    Parameters
    ----------
    angles : ndarray
        Equally spaced over one turn, rad.
    weight : ndarray
        Non-negative, same shape.
    order : int
        ``m``.
    """
    w = np.asarray(weight, dtype=float)
    c0 = float(np.mean(w))
    if not c0 > 0:
        return math.nan
    cm = np.mean(w * np.exp(-1j * order * np.asarray(angles, dtype=float)))
    return float(abs(cm) / c0)
