"""Kinematics and Hertz line contact against hand-checked numbers and textbook formulas."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from taichi_bearing.analytic.bearing import (
    cage_speed,
    contact_radius,
    effective_modulus,
    fault_frequencies,
    hertz_half_width,
    hertz_peak_pressure,
    palmgren_stiffness,
    roller_angles,
    roller_spacing,
    rolling_surface_speed,
    series_stiffness,
)
from taichi_bearing.case import load_case


@pytest.fixture(scope="module")
def case(default_case_path):
    return load_case(default_case_path)


def test_fault_frequencies_by_hand(case):
    # d/D = 24/200 = 0.12, fr = 500/60 Hz
    fr = 500.0 / 60.0
    f = fault_frequencies(case.bearing, fr)
    assert f.ftf == pytest.approx(0.5 * fr * 0.88)  # 3.6667 Hz
    assert f.bpfo == pytest.approx(73.3333, rel=1e-5)
    assert f.bpfi == pytest.approx(93.3333, rel=1e-5)
    assert f.bsf == pytest.approx(200 / 48 * fr * (1 - 0.12**2))  # 34.22 Hz
    assert f.bpfo + f.bpfi == pytest.approx(case.bearing.n_rollers * fr)


def test_cage_and_surface_speed(case):
    w = case.operating.speed
    wc = cage_speed(case.bearing, w)
    assert wc == pytest.approx(w / 2 * 0.88)
    v = rolling_surface_speed(case.bearing, w)
    # pure rolling: contact speed along the outer raceway = cage speed x R_o
    assert v == pytest.approx(wc * case.bearing.outer_raceway_radius)
    # and = inner raceway speed relative to the cage x R_i
    assert v == pytest.approx((w - wc) * case.bearing.inner_raceway_radius)
    assert v == pytest.approx(2.5803, rel=1e-4)


def test_roller_angles(case):
    b = case.bearing
    assert roller_spacing(b) == pytest.approx(2 * math.pi / 20)
    a0 = roller_angles(b, 0.0, first_angle=math.radians(-5))
    assert a0.shape == (20,)
    assert math.degrees(a0[0]) == pytest.approx(-5.0)
    assert math.degrees(a0[1]) == pytest.approx(13.0)
    w = case.operating.speed
    ftf = fault_frequencies(b, w / (2 * math.pi)).ftf
    t = np.array([0.0, 0.25 / ftf, 1.0 / ftf])
    a = roller_angles(b, t, w)
    assert a.shape == (3, 20)
    assert math.degrees(a[1, 0]) == pytest.approx(90.0)  # a quarter cage turn, ccw
    np.testing.assert_allclose(a[2], a[0], atol=1e-9)  # a whole turn
    # one roller passes a fixed point every 1/BPFO
    a_pass = roller_angles(b, 1.0 / fault_frequencies(b, w / (2 * math.pi)).bpfo, w)
    assert math.degrees(a_pass[0]) == pytest.approx(18.0)


def test_effective_modulus_and_radii(case):
    assert effective_modulus(210e9, 0.3) == pytest.approx(210e9 / (2 * 0.91))
    # rigid second body: E* = E / (1 - nu^2)
    assert effective_modulus(210e9, 0.3, 1e30, 0.0) == pytest.approx(210e9 / 0.91)
    assert contact_radius(case.bearing, "outer") == pytest.approx(12 * 112 / 100 * 1e-3)
    assert contact_radius(case.bearing, "inner") == pytest.approx(12 * 88 / 100 * 1e-3)
    with pytest.raises(ValueError, match="race"):
        contact_radius(case.bearing, "cage")


def test_hertz_line_contact_by_hand():
    # 10 kN over 50 mm on R = 13.44 mm, E* = 115.38 GPa:
    # b = sqrt(4 * 2e5 * 0.01344 / (pi * 1.1538e11)) = 0.17222 mm, p_max = 739.3 MPa
    e_star = 210e9 / (2 * 0.91)
    b = hertz_half_width(1e4, 0.05, 0.01344, e_star)
    p = hertz_peak_pressure(1e4, 0.05, 0.01344, e_star)
    assert b == pytest.approx(1.72225e-4, rel=1e-5)
    assert p == pytest.approx(7.3929e8, rel=1e-4)
    # the semi-elliptic pressure integrates to the load per length: pi b p_max / 2 = P
    assert math.pi * b * p / 2 == pytest.approx(1e4 / 0.05)
    # b ~ sqrt(P), p_max ~ sqrt(P)
    assert hertz_half_width(4e4, 0.05, 0.01344, e_star) == pytest.approx(2 * b)
    assert hertz_half_width(-1.0, 0.05, 0.01344, e_star) == 0.0


def test_palmgren_stiffness_units(case):
    # with Palmgren's own steel (E = 207.5 GPa) K must equal 8.06e4 l^(8/9) in N, mm units
    steel = dataclasses.replace(case.material, youngs_modulus=207.5e9)
    k = palmgren_stiffness(case.bearing, steel)
    k_mm = 8.06e4 * 50.0 ** (8 / 9)  # N / mm^(10/9)
    q = k * (1e-5) ** (10 / 9)  # delta = 0.01 mm
    assert q == pytest.approx(k_mm * 0.01 ** (10 / 9), rel=1e-12)
    assert q == pytest.approx(15642.6, rel=1e-5)
    # inverse of Palmgren's delta = 3.84e-5 Q^0.9 / l^0.8 (mm), to the rounding of 8.06e4
    assert 3.84e-5 * q**0.9 / 50**0.8 == pytest.approx(0.01, rel=2e-4)
    # stiffer material, stiffer contact (E* ratio)
    assert palmgren_stiffness(case.bearing, case.material) == pytest.approx(k * 210 / 207.5)


def test_series_stiffness():
    n = 10 / 9
    k = 3.0e9
    assert series_stiffness(k, k, n) == pytest.approx(k / 2**n)
    ko, ki = 2.0e9, 5.0e9
    ks = series_stiffness(ko, ki, n)
    q = 1234.0
    # same force in both contacts: deflections add
    assert (q / ks) ** (1 / n) == pytest.approx((q / ko) ** (1 / n) + (q / ki) ** (1 / n))
    assert series_stiffness(0.0, ki, n) == 0.0
