"""The element's constitutive law, behind a small interface (one class per law, in the
manner of FEMcy's materials).

A law gives the element (:mod:`taichi_bearing.solver.element_forces`) what it needs of the
material, as Taichi functions of the element's Lame constants and a strain: the second
Piola-Kirchhoff stress (:meth:`ElementLaw.stress`), the stored energy density
(:meth:`ElementLaw.energy_density`) and the power density of a viscous stress of the same
law on a strain rate (:meth:`ElementLaw.rate_power`, for stiffness-proportional damping);
and, in numpy, its tangent at the reference configuration (:meth:`ElementLaw.tangent`),
from which the stable time step is assembled. The material's constants are
:class:`taichi_bearing.case.material.Material`'s, per element
(:func:`taichi_bearing.solver.element.materials_per_element`).
"""

# No `from __future__ import annotations`: Taichi reads annotations at definition.
import numpy as np
import taichi as ti

from taichi_bearing.solver.element import hooke_tangent

__all__ = ["ElementLaw", "StVenantKirchhoff"]


@ti.data_oriented
class ElementLaw:
    """Base of the element's constitutive laws (plane strain, in the Green strain ``E``).

    A subclass overrides every method; its Taichi functions are inlined into the element
    loop.
    """

    name = ""

    @ti.func
    def stress(self, lam, mu, E):
        """Second Piola-Kirchhoff stress of the Green strain ``E`` (2 x 2), and ``tr(E)``."""
        raise NotImplementedError

    @ti.func
    def energy_density(self, lam, mu, E):
        """Stored energy per unit reference volume at ``E``."""
        raise NotImplementedError

    @ti.func
    def rate_power(self, lam, mu, Ed):
        """``S(Ed) : Ed``, the power density of the law's stress of a strain rate ``Ed``
        (the stiffness-proportional damping's, per unit ``beta``)."""
        raise NotImplementedError

    def tangent(self, lam: np.ndarray, mu: np.ndarray) -> np.ndarray:
        """The law's tangent at zero strain in Voigt form (xx, yy, xy engineering shear),
        shape (n, 3, 3) for arrays of the constants."""
        raise NotImplementedError


@ti.data_oriented
class StVenantKirchhoff(ElementLaw):
    r"""St Venant-Kirchhoff: :math:`S = \lambda \operatorname{tr}(E) I + 2 \mu E`, energy
    :math:`\lambda \operatorname{tr}(E)^2 / 2 + \mu E : E`: Hooke's law in the Green strain,
    exact for large rotations with small strains (a rolling bearing's)."""

    name = "st_venant_kirchhoff"

    @ti.func
    def stress(self, lam, mu, E):
        tr = E[0, 0] + E[1, 1]
        return lam * tr * ti.Matrix.identity(ti.f64, 2) + 2.0 * mu * E, tr

    @ti.func
    def energy_density(self, lam, mu, E):
        tr = E[0, 0] + E[1, 1]
        return 0.5 * lam * tr * tr + mu * (E * E).sum()

    @ti.func
    def rate_power(self, lam, mu, Ed):
        tr = Ed[0, 0] + Ed[1, 1]
        return lam * tr * tr + 2.0 * mu * (Ed * Ed).sum()

    def tangent(self, lam: np.ndarray, mu: np.ndarray) -> np.ndarray:
        return hooke_tangent(lam, mu)
