r"""The pressure contact law's penalty from the case's Hertz contact (numpy only).

A penalty :math:`p_s` (pressure per unit overlap, Pa/m) under a Hertz pressure
:math:`p(s) = p_0 \sqrt{1 - s^2 / b^2}` overlaps by :math:`p_0 / p_s` at the centre. With
:math:`p_0 = b E^* / (2 R)` (Johnson, Contact Mechanics, 1985, eq. 4.45) and
:math:`p_s = \alpha E^* / b`, that overlap is :math:`b^2 / (2 R \alpha)`: :math:`1 / \alpha`
of the parabolic gap :math:`b^2 / (2 R)` the bodies close over the half-width, so
:math:`\alpha` says how much stiffer than the contact's own compliance the penalty is,
whatever the mesh.
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.analytic.bearing import effective_modulus
from taichi_bearing.analytic.quasistatic import solve_case

__all__ = ["pressure_penalty", "reference_half_width"]


def reference_half_width(case) -> float:
    r""":math:`b_\mathrm{ref}`, m: the smaller Hertz half-width of the two contacts (outer
    and inner raceway) of the most loaded roller of the healthy bearing at the case's load,
    a roller on the load line (the rigid-ring quasi-static model,
    :func:`~taichi_bearing.analytic.quasistatic.solve_case`). The smaller one, so that
    the penalty's overlap is at most :math:`1 / \alpha` of the gap on both contacts.

    Examples
    --------
    >>> from taichi_bearing.case import load_case
    >>> case = load_case("cases/line_spall.yaml")
    >>> print(f"b_ref = {reference_half_width(case) * 1e3:.3f} mm")
    b_ref = 0.154 mm
    """
    dist = solve_case(case, [0.0], healthy=True)
    on_top = int(np.argmax(dist.outer_force[0]))
    return float(min(dist.outer_half_width[0, on_top], dist.inner_half_width[0, on_top]))


def pressure_penalty(case) -> float:
    r"""The pressure law's :math:`p_s` (Pa/m) of a case: ``contact.penalty_pressure`` when
    given (non-zero), else :math:`\alpha E^* / b_\mathrm{ref}` with :math:`\alpha` the
    ``contact.penalty_scale``, :math:`E^*` the steel pair's contact modulus and
    :math:`b_\mathrm{ref}` :func:`reference_half_width`."""
    contact = case.contact
    if contact.penalty_pressure > 0:
        return float(contact.penalty_pressure)
    mat = case.material
    e_star = effective_modulus(mat.youngs_modulus, mat.poissons_ratio)
    b_ref = reference_half_width(case)
    if not (b_ref > 0 and math.isfinite(b_ref)):
        raise ValueError(f"no Hertz half-width to set the pressure penalty from (b_ref={b_ref})")
    return contact.penalty_scale * e_star / b_ref
