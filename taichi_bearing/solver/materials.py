"""Per-element material constants for the solver.

The material itself is :class:`taichi_bearing.case.material.Material` (the case's
``material`` section), re-exported here.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.types import Mesh

__all__ = ["Material", "materials_per_element"]


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
    rho = np.array([m.density for m in mats])[mesh.element_part]
    eprime = np.array([m.plane_strain_modulus for m in mats])[mesh.element_part]
    return lam, mu, rho, eprime
