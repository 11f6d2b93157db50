"""Bearing geometry and its kinematic fault frequencies: :class:`BearingGeometry`,
:class:`FaultFrequencies` and :func:`bearing_frequencies` (a stationary outer ring, pure
rolling; the formulas are in the function's notes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

__all__ = ["BearingGeometry", "FaultFrequencies", "bearing_frequencies"]

# Largest sizes a real bearing has, in metres: the balls of the largest slewing rings are
# about 0.2 m, their pitch diameters under 20 m. A value above these is a length given in
# the wrong unit (millimetres or inches to an API that takes metres).
MAX_ROLLER_DIAMETER_M = 0.5
MAX_PITCH_DIAMETER_M = 20.0


@dataclass(frozen=True)
class BearingGeometry:
    """Geometry of a rolling element bearing, in metres.

    Parameters
    ----------
    n_rollers : int
        Number of rolling elements.
    roller_diameter : float
        Rolling element diameter d, m.
    pitch_diameter : float
        Pitch (cage) diameter D, m.
    contact_angle_deg : float, optional
        Contact angle alpha in degrees (0 for radial roller bearings).

    Raises
    ------
    ValueError
        On a non-positive count or length, a rolling element not smaller than the pitch
        diameter, a contact angle outside [0, 90), or lengths no bearing has (an element
        over 0.5 m, a pitch diameter over 20 m: millimetres given for metres).

    Examples
    --------
    >>> BearingGeometry(9, 7.94e-3, 39.04e-3).diameter_ratio      # CWRU drive end, SKF 6205
    0.2033811475409836
    """

    n_rollers: int
    roller_diameter: float
    pitch_diameter: float
    contact_angle_deg: float = 0.0

    def __post_init__(self) -> None:
        if int(self.n_rollers) != self.n_rollers or self.n_rollers < 1:
            raise ValueError(f"n_rollers must be a positive integer, got {self.n_rollers!r}")
        for name in ("roller_diameter", "pitch_diameter"):
            value = getattr(self, name)
            if not (isinstance(value, Real) and math.isfinite(value) and value > 0):
                raise ValueError(
                    f"{name} must be a positive finite length in metres, got {value!r}"
                )
        for name, limit in (
            ("roller_diameter", MAX_ROLLER_DIAMETER_M),
            ("pitch_diameter", MAX_PITCH_DIAMETER_M),
        ):
            value = getattr(self, name)
            if value > limit:
                raise ValueError(
                    f"{name} = {value:g} m is larger than any bearing has (over {limit:g} m): "
                    f"BearingGeometry takes metres; {value:g} mm is {value * 1e-3:g} m"
                )
        if self.roller_diameter >= self.pitch_diameter:
            raise ValueError(
                f"roller_diameter ({self.roller_diameter} m) must be smaller than "
                f"pitch_diameter ({self.pitch_diameter} m)"
            )
        if not (0.0 <= self.contact_angle_deg < 90.0):
            raise ValueError(
                f"contact_angle_deg must be in [0, 90), got {self.contact_angle_deg!r}"
            )

    @property
    def diameter_ratio(self) -> float:
        """d cos(alpha) / D, the ratio that sets every fault frequency."""
        return (
            self.roller_diameter
            * math.cos(math.radians(self.contact_angle_deg))
            / self.pitch_diameter
        )


@dataclass(frozen=True)
class FaultFrequencies:
    """Characteristic frequencies in Hz (stationary outer ring, turning inner ring)."""

    shaft: float
    ftf: float
    bpfo: float
    bpfi: float
    bsf: float

    def as_dict(self) -> dict[str, float]:
        return {
            "shaft_hz": self.shaft,
            "ftf_hz": self.ftf,
            "bpfo_hz": self.bpfo,
            "bpfi_hz": self.bpfi,
            "bsf_hz": self.bsf,
        }


def bearing_frequencies(geometry: BearingGeometry, shaft_hz: float) -> FaultFrequencies:
    r"""Fault frequencies of a bearing turning at ``shaft_hz``.

    Parameters
    ----------
    geometry : BearingGeometry
        Bearing dimensions.
    shaft_hz : float
        Shaft (inner ring) rotation frequency in Hz; the outer ring is stationary.

    Returns
    -------
    FaultFrequencies
        FTF (cage), BPFO, BPFI and BSF (roller spin) in Hz.

    Notes
    -----
    With ``n`` rolling elements of diameter ``d`` on a pitch diameter ``D``, contact angle
    :math:`\alpha` and shaft rate :math:`f_r`, in pure rolling with the outer ring fixed:

    .. math::

        \mathrm{FTF} = \frac{f_r}{2}\Bigl(1 - \frac{d}{D}\cos\alpha\Bigr), \quad
        \mathrm{BPFO} = n\,\mathrm{FTF}, \quad
        \mathrm{BPFI} = \frac{n f_r}{2}\Bigl(1 + \frac{d}{D}\cos\alpha\Bigr), \quad
        \mathrm{BSF} = \frac{D f_r}{2 d}\Bigl(1 - \Bigl(\frac{d}{D}\cos\alpha\Bigr)^2\Bigr).

    A real bearing slips by 1-2 %, so measured rates sit a little off these.

    References
    ----------
    Harris, T. A. and Kotzalas, M. N. (2007). *Essential Concepts of Bearing Technology*
    (Rolling Bearing Analysis, 5th ed., vol. 1). CRC Press, Boca Raton.

    Randall, R. B. and Antoni, J. (2011). Rolling element bearing diagnostics: a tutorial.
    *Mechanical Systems and Signal Processing* 25(2), 485-520.

    Examples
    --------
    >>> g = BearingGeometry(9, 7.94e-3, 39.04e-3)
    >>> round(bearing_frequencies(g, 1.0).bpfo, 3)
    3.585
    """
    if not (isinstance(shaft_hz, Real) and math.isfinite(shaft_hz) and shaft_hz > 0):
        raise ValueError(f"shaft_hz must be a positive finite frequency, got {shaft_hz!r}")
    ratio = geometry.diameter_ratio
    n = geometry.n_rollers
    ftf = 0.5 * shaft_hz * (1.0 - ratio)
    return FaultFrequencies(
        shaft=float(shaft_hz),
        ftf=ftf,
        bpfo=n * ftf,
        bpfi=0.5 * n * shaft_hz * (1.0 + ratio),
        bsf=0.5 * geometry.pitch_diameter / geometry.roller_diameter * shaft_hz * (1.0 - ratio**2),
    )
