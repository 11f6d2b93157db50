"""The contact model of the quasi-static load distribution: Palmgren stiffness of both
roller contacts and their Hertz radii, from a case's bearing and material (numpy only).
Shared by :mod:`taichi_bearing.analytic.quasistatic` and
:mod:`taichi_bearing.analytic.spall_contact`."""

from __future__ import annotations

from dataclasses import dataclass

from taichi_bearing.analytic.bearing import (
    LINE_CONTACT_EXPONENT,
    contact_radius,
    effective_modulus,
    palmgren_stiffness,
    series_stiffness,
)
from taichi_bearing.case import Bearing, Material

__all__ = ["ContactModel", "contact_model"]


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
    inner_raceway_radius: float = 0.0

    @property
    def k_series(self) -> float:
        return float(series_stiffness(self.k_outer, self.k_inner, self.exponent))

    def raceway(self, race: str) -> tuple[float, float, float]:
        """Raceway radius, effective Hertz radius and sign of the spall's depth (+1: the
        outer ring's material lies outside its raceway, -1: the inner ring's inside)."""
        if race == "outer":
            return self.outer_raceway_radius, self.outer_radius_eff, 1.0
        return self.inner_raceway_radius, self.inner_radius_eff, -1.0


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
        inner_raceway_radius=bearing.inner_raceway_radius,
    )
