"""The linear elastic material: the case's ``material`` section and what the solver takes.

One class for both: the case file gives it in GPa and kg/m^3, the solver builds its Lame
constants from it (one material for the whole bearing, or one per part).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from taichi_bearing.case.schema import key

__all__ = ["Material"]


@dataclass(frozen=True)
class Material:
    r"""Linear elastic material (St Venant-Kirchhoff in large strain); the case gives one
    for every part of the bearing.

    Parameters
    ----------
    youngs_modulus : float
        Young's modulus :math:`E`, Pa.
    poissons_ratio : float
        Poisson's ratio :math:`\nu`, in (-1, 0.5).
    density : float
        Density :math:`\rho`, kg/m^3.
    """

    youngs_modulus: float = key("GPa", gt=0.0, doc="Young's modulus E")
    poissons_ratio: float = key(ge=0.0, lt=0.5, doc="Poisson's ratio nu")
    density: float = key("kg_m3", gt=0.0, doc="density rho")

    def __post_init__(self) -> None:
        # the bounds of a stable isotropic material (positive definite stiffness); the case
        # file checks its own, narrower ranges before it gets here
        if not self.youngs_modulus > 0:
            raise ValueError(
                f"Material.youngs_modulus must be positive, got {self.youngs_modulus!r}"
            )
        if not -1.0 < self.poissons_ratio < 0.5:
            raise ValueError(
                f"Material.poissons_ratio must lie in (-1, 0.5), got {self.poissons_ratio!r}"
            )
        if not self.density > 0:
            raise ValueError(f"Material.density must be positive, got {self.density!r}")

    @property
    def lam(self) -> float:
        """First Lame constant, Pa."""
        e, nu = self.youngs_modulus, self.poissons_ratio
        return e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))

    @property
    def mu(self) -> float:
        """Shear modulus, Pa."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poissons_ratio))

    @property
    def plane_strain_modulus(self) -> float:
        r""":math:`E' = E / (1 - \nu^2)`, the bending modulus of a plane-strain beam, Pa."""
        return self.youngs_modulus / (1.0 - self.poissons_ratio**2)

    @property
    def wave_speed(self) -> float:
        r"""Plane-strain dilatational wave speed :math:`\sqrt{(\lambda + 2 \mu) / \rho}`, m/s."""
        return math.sqrt((self.lam + 2.0 * self.mu) / self.density)

    @property
    def shear_wave_speed(self) -> float:
        r"""Shear wave speed :math:`\sqrt{\mu / \rho}`, m/s (the Rayleigh wave: 7 % slower at
        :math:`\nu` = 0.3)."""
        return math.sqrt(self.mu / self.density)
