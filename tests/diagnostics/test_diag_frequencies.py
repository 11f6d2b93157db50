"""Bearing kinematics against the CWRU drive-end bearing's published multiples."""

from __future__ import annotations

import pytest

from diagnostics import BearingGeometry, bearing_frequencies

INCH = 25.4e-3
# SKF 6205-2RS JEM: 9 balls, 0.3126 in balls on a 1.537 in pitch diameter, contact angle 0.
CWRU_DE = BearingGeometry(9, 0.3126 * INCH, 1.537 * INCH)
# Multiples of the shaft frequency listed by the CWRU Bearing Data Center.
CWRU_MULTIPLES = {"bpfi": 5.4152, "bpfo": 3.5848, "ftf": 0.39828, "bsf": 2.3567}


@pytest.mark.parametrize("name", sorted(CWRU_MULTIPLES))
@pytest.mark.parametrize("shaft_hz", [1.0, 29.95])
def test_cwru_multiples_to_four_digits(name, shaft_hz):
    freqs = bearing_frequencies(CWRU_DE, shaft_hz)
    assert getattr(freqs, name) / shaft_hz == pytest.approx(CWRU_MULTIPLES[name], rel=1e-4)
    assert freqs.shaft == shaft_hz


def test_kinematic_identities():
    # Ball pass frequencies add up to n times the shaft rate; BPFO is n times the cage rate.
    f = bearing_frequencies(CWRU_DE, 30.0)
    assert f.bpfo + f.bpfi == pytest.approx(9 * 30.0, rel=1e-12)
    assert f.bpfo == pytest.approx(9 * f.ftf, rel=1e-12)


def test_contact_angle_lowers_the_diameter_ratio():
    tilted = BearingGeometry(9, 0.3126 * INCH, 1.537 * INCH, contact_angle_deg=40.0)
    assert bearing_frequencies(tilted, 1.0).bpfo > bearing_frequencies(CWRU_DE, 1.0).bpfo


@pytest.mark.parametrize(
    "args",
    [
        (0, 7.94e-3, 39.04e-3),  # no rollers
        (9.5, 7.94e-3, 39.04e-3),  # fractional count
        (9, -7.94e-3, 39.04e-3),  # negative diameter
        (9, 40e-3, 39.04e-3),  # roller larger than the pitch circle
        (9, float("nan"), 39.04e-3),
    ],
)
def test_bad_geometry_raises(args):
    with pytest.raises(ValueError):
        BearingGeometry(*args)


def test_bad_contact_angle_and_speed_raise():
    with pytest.raises(ValueError, match="contact_angle_deg"):
        BearingGeometry(9, 7.94e-3, 39.04e-3, contact_angle_deg=90.0)
    with pytest.raises(ValueError, match="shaft_hz"):
        bearing_frequencies(CWRU_DE, 0.0)
