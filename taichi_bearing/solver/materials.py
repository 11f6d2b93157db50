"""Isotropic elastic materials in plane strain."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from taichi_bearing.mesh.types import Mesh

__all__ = ["Material", "materials_per_element"]


@dataclass(frozen=True)
class Material:
    """Linear-elastic constants of one part (St Venant-Kirchhoff in large strain).

    Parameters
    ----------
    E : float
        Young's modulus, Pa.
    nu : float
        Poisson's ratio, in (-1, 0.5).
    rho : float
        Density, kg/m^3.
    """

    E: float
    nu: float
    rho: float

    def __post_init__(self) -> None:
        if not self.E > 0:
            raise ValueError(f"Material.E must be positive, got {self.E!r}")
        if not -1.0 < self.nu < 0.5:
            raise ValueError(f"Material.nu must lie in (-1, 0.5), got {self.nu!r}")
        if not self.rho > 0:
            raise ValueError(f"Material.rho must be positive, got {self.rho!r}")

    @property
    def lam(self) -> float:
        """First Lame constant, Pa."""
        return self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))

    @property
    def mu(self) -> float:
        """Shear modulus, Pa."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def plane_strain_modulus(self) -> float:
        """E' = E / (1 - nu^2), the bending modulus of a plane-strain beam, Pa."""
        return self.E / (1.0 - self.nu**2)

    @property
    def wave_speed(self) -> float:
        """Plane-strain dilatational wave speed sqrt((lambda + 2 mu) / rho), m/s."""
        return math.sqrt((self.lam + 2.0 * self.mu) / self.rho)


def materials_per_element(
    mesh: Mesh, materials: Material | Mapping[str, Material]
) -> tuple[np.ndarray, ...]:
    """Per-element (lambda, mu, rho, E') arrays from one material or a part -> material map."""
    if isinstance(materials, Material):
        mats = [materials] * len(mesh.part_names)
    else:
        missing = [p for p in mesh.part_names if p not in materials]
        if missing:
            raise ValueError(f"no material given for parts {missing}")
        mats = [materials[p] for p in mesh.part_names]
    lam = np.array([m.lam for m in mats])[mesh.element_part]
    mu = np.array([m.mu for m in mats])[mesh.element_part]
    rho = np.array([m.rho for m in mats])[mesh.element_part]
    eprime = np.array([m.plane_strain_modulus for m in mats])[mesh.element_part]
    return lam, mu, rho, eprime
