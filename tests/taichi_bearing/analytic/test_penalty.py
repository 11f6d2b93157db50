"""The pressure law's penalty from a case: ``alpha E* / b_ref`` with ``b_ref`` the smaller
Hertz half-width of the most loaded roller, or the value the case gives."""

import math

import pytest

from taichi_bearing.analytic.bearing import contact_radius, effective_modulus
from taichi_bearing.analytic.penalty import pressure_penalty, reference_half_width
from taichi_bearing.case import load_case
from taichi_bearing.solver.contact_setup import ContactParameters

CASE = "cases/line_spall.yaml"


def test_reference_half_width_is_the_inner_contact_of_stribecks_roller():
    """Zero clearance, line contact: Q_max = 4.08 W / Z (Harris's Stribeck constant for
    line contact), and the inner contact (convex on convex) is the narrower one:
    b = sqrt(4 Q R / (pi l E*))."""
    case = load_case(CASE)
    b, mat = case.bearing, case.material
    e_star = effective_modulus(mat.youngs_modulus, mat.poissons_ratio)
    q_max = 4.08 * case.operating.load / b.n_rollers
    r_in = contact_radius(b, "inner")
    expect = math.sqrt(4 * q_max * r_in / (math.pi * b.roller_length * e_star))
    assert reference_half_width(case) == pytest.approx(expect, rel=0.005)


def test_alpha_sets_the_overlap_under_the_hertz_peak():
    """p_s = alpha E* / b: under Hertz's peak p0 = b E* / (2 R) the penalty overlaps by
    b^2 / (2 R alpha), 1 / alpha of the gap the bodies close over the half-width."""
    case = load_case(CASE, ["contact.penalty_method=pressure", "contact.penalty_scale=30"])
    mat = case.material
    e_star = effective_modulus(mat.youngs_modulus, mat.poissons_ratio)
    b, r = reference_half_width(case), contact_radius(case.bearing, "inner")
    p_s = pressure_penalty(case)
    assert p_s == pytest.approx(30 * e_star / b, rel=1e-12)
    p0 = b * e_star / (2 * r)
    assert p0 / p_s == pytest.approx(b**2 / (2 * r) / 30, rel=1e-12)


def test_a_given_pressure_wins_and_reaches_the_contact_parameters():
    case = load_case(
        CASE, ["contact.penalty_method=pressure", "contact.penalty_pressure_GPa_mm=5000"]
    )
    assert pressure_penalty(case) == pytest.approx(5e15)
    params = ContactParameters.from_case(case.contact, pressure_penalty(case))
    assert params.penalty_pressure == pytest.approx(5e15)


def test_the_pressure_law_without_a_pressure_is_refused():
    with pytest.raises(ValueError, match="penalty_pressure"):
        ContactParameters(penalty_method="pressure")
