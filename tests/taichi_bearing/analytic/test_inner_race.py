"""Inner-race spalls without a simulation: the quasi-static model with the spall in the
convex inner raceway and turning with the shaft, the passage kinematics against BPFI,
the load-zone modulation, and the passages found in synthetic histories."""

from __future__ import annotations

import math

import numpy as np
import pytest
from geometry_reference import brute_force_drop
from synthetic_passages import Q_MAX, rolling_histories

from taichi_bearing.analytic.bearing import cage_speed, fault_frequencies
from taichi_bearing.analytic.inner_race import (
    passage_angles,
    passage_spall_angles,
    sideband_ratio,
)
from taichi_bearing.analytic.quasistatic import (
    _corner_drop,
    defect_sweep,
    load_zone,
    solve_case,
    spall_from_case,
)
from taichi_bearing.case import load_case
from taichi_bearing.checks import inner_restress_check, restress_check
from taichi_bearing.checks.passages import detect_spall_events, spall_passages
from taichi_bearing.geometry.roller_path import centre_drop
from taichi_bearing.geometry.spall_profile import SpallProfile

INNER = "cases/validation/inner_spall.yaml"


@pytest.fixture(scope="module")
def case():
    return load_case(INNER)


@pytest.fixture(scope="module")
def default_inner(default_case_path):
    return load_case(default_case_path, ["defect.race=inner"])


# ----------------------------------------------------------------------- geometry


def test_inner_spall_spans_its_length_on_the_inner_raceway_and_is_entered_at_its_larger_angle(
    default_inner,
):
    spall = spall_from_case(default_inner)
    r_i = default_inner.bearing.inner_raceway_radius
    assert spall.race == "inner"
    # the rollers move clockwise relative to the faster inner ring
    assert spall.entry > spall.exit
    assert (spall.entry - spall.exit) * r_i == pytest.approx(default_inner.defect.length)
    assert spall.centre == pytest.approx(default_inner.defect.angle)


def test_roller_pivoting_on_an_inner_corner_touches_it_from_outside(default_inner):
    """Circle on a corner of the convex raceway: the centre, r_i + r - h from the bearing
    centre, is r from the corner, and drops faster than on the concave outer raceway."""
    b = default_inner.bearing
    r, r_i = b.roller_radius, b.inner_raceway_radius
    delta = np.array([0.0, 1e-3, 5e-3, 2e-2])
    h = _corner_drop(delta, r, r_i, -1.0)
    assert h[0] == pytest.approx(0.0, abs=1e-15)
    rho = r_i + r - h
    dist = np.hypot(rho * np.sin(delta), rho * np.cos(delta) - r_i)
    np.testing.assert_allclose(dist, r, rtol=1e-12)
    # at the same arc length past the corner: curvature 1/r + 1/r_i against 1/r - 1/r_o
    r_o = b.outer_raceway_radius
    outer = _corner_drop(delta * r_i / r_o, r, r_o, 1.0)
    assert np.all(h[1:] > outer[1:])
    expected = (r_i * delta[1]) ** 2 / 2 * (1 / r + 1 / r_i)
    assert h[1] == pytest.approx(expected, rel=1e-3)


@pytest.mark.parametrize("slope, rho", [(90, 0.0), (45, 0.0), (30, 0.001)])
def test_roller_over_an_inner_profile_follows_its_geometry(slope, rho):
    """The closed-form path on the convex inner raceway (the roller outside, moving in)
    against bisection on a polyline of the profile, across a deep spall's exit edge."""
    R, r, d = 0.088, 0.012, 0.003
    s = math.radians(slope)
    p = SpallProfile(R, 1.5, 1.5 + 0.02 / R, d, False, s, s, rho)
    phis = p.end + np.linspace(-0.0095, 0.002, 17) / R
    drop, _ = centre_drop(phis, p, r)
    expected = [brute_force_drop(p, phi, r) for phi in phis]
    assert np.allclose(drop, expected, atol=2e-9)
    assert drop[0] > 0.9 * d and drop[-1] == 0.0


# ----------------------------------------------------------------------- load distribution


def test_roller_on_an_inner_spall_is_unloaded_and_the_rest_balance_the_load(default_inner):
    spall = spall_from_case(default_inner)
    dist = solve_case(default_inner, spall.centre)
    healthy = solve_case(default_inner, spall.centre, healthy=True)
    assert dist.outer_force[0, 0] == 0.0 and dist.inner_force[0, 0] == 0.0
    assert dist.outer_fy.sum() == pytest.approx(default_inner.operating.load, rel=1e-12)
    for j in (1, 19):  # the neighbours pick up the load
        assert dist.outer_force[0, j] > 1.1 * healthy.outer_force[0, j]


def test_turning_the_inner_spall_is_moving_it(default_case_path):
    """The spall turned to 30 deg by ``spall_angles`` gives the load distribution of a
    case whose spall starts there, at every cage angle."""
    turned = load_case(default_case_path, ["defect.race=inner"])
    there = load_case(default_case_path, ["defect.race=inner", "defect.angle_deg=30"])
    cage = np.radians(np.linspace(20.0, 40.0, 41))
    a = solve_case(turned, cage, spall_angles=np.radians(30.0))
    b = solve_case(there, cage)
    np.testing.assert_allclose(a.outer_force, b.outer_force, rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(a.inner_force, b.inner_force, rtol=1e-9, atol=1e-6)


def test_pivoting_on_an_inner_corner_the_inner_force_is_tilted(default_inner):
    """Past the entry corner the inner contact's force points from the corner to the
    roller: the outer (healthy) contact carries its radial part only."""
    spall = spall_from_case(default_inner)
    r_i = default_inner.bearing.inner_raceway_radius
    sweep = defect_sweep(default_inner, 2001, span=2 * spall.half_angle + 4e-3 / r_i)
    travel = sweep.spall_angle - sweep.cage_angle
    pivot = np.flatnonzero(
        (travel > -spall.half_angle) & (sweep.inner_force[:, 0] > 0) & (travel < 0)
    )
    assert pivot.size
    k = pivot[-1]
    assert sweep.inner_force[k, 0] > sweep.outer_force[k, 0] > 0


def test_passage_sweep_lasts_one_bpfi_period_and_turns_the_spall_at_shaft_speed(case):
    """Over one roller pitch of relative travel the spall turns at the shaft speed and
    roller 0 at the cage speed: the sweep lasts 1/BPFI."""
    cage, spall, travel = passage_angles(case, 0.3, 11)
    shaft = case.operating.speed
    cage_rate = cage_speed(case.bearing, shaft)
    bpfi = fault_frequencies(case.bearing, case.operating.shaft_hz).bpfi
    duration = (spall[-1] - spall[0]) / shaft
    assert duration == pytest.approx(1.0 / bpfi, rel=1e-12)
    assert (cage[-1] - cage[0]) / duration == pytest.approx(cage_rate, rel=1e-12)
    assert travel[5] == 0.0 and cage[5] == spall[5] == 0.3
    np.testing.assert_allclose(spall - cage, travel, atol=1e-15)


def test_passages_come_every_bpfi_period_32_degrees_further_round(case):
    angles, times = passage_spall_angles(case, math.radians(-20), math.radians(-25), 4)
    f = fault_frequencies(case.bearing, case.operating.shaft_hz)
    np.testing.assert_allclose(np.diff(times), 1.0 / f.bpfi, rtol=1e-12)
    step = np.degrees(np.diff(np.unwrap(angles)))
    np.testing.assert_allclose(step, 360.0 * f.shaft / f.bpfi, rtol=1e-12)
    assert step[0] == pytest.approx(32.142857, rel=1e-6)
    # the first passage: roller 0 and the spall meet where both have gone
    cage = cage_speed(case.bearing, case.operating.speed)
    assert math.radians(-20) + cage * times[0] == pytest.approx(angles[0])
    assert np.degrees(angles[:2]) == pytest.approx([-16.0714, 16.0714], abs=1e-3)


def test_sideband_ratio_of_a_rectangular_load_zone_is_its_fourier_coefficient():
    """Impacts at full strength over a zone of width w, none elsewhere: the first
    shaft-rate sideband over the carrier is sin(w/2) / (w/2)."""
    angles = np.linspace(-math.pi, math.pi, 3600, endpoint=False)
    w = math.radians(120.0)
    weight = (np.abs(angles) < 0.5 * w).astype(float)
    assert sideband_ratio(angles, weight) == pytest.approx(math.sin(w / 2) / (w / 2), rel=2e-3)
    assert sideband_ratio(angles, np.ones_like(angles)) == pytest.approx(0.0, abs=1e-12)


def test_load_zone_is_the_healthy_load_of_a_roller_at_each_angle(case):
    angles, load = load_zone(case, 360)  # a degree apart from -180
    top = solve_case(case, 0.0, healthy=True).outer_force[0, 0]
    assert load[180] == pytest.approx(top)  # 12 o'clock
    assert np.all(load[np.abs(angles) > math.radians(91)] == 0.0)  # zero clearance: 180 deg
    np.testing.assert_allclose(load[1:], load[1:][::-1], rtol=1e-9, atol=1e-6)


# ----------------------------------------------------------------------- passages


def test_events_at_bpfi_in_the_load_zone_and_none_outside(case):
    """30 ms: the spall passes 11 rollers, from -16 deg once round to -55 deg; only those
    under the load lose and regain a load (one BPFI period apart, and again when the
    spall comes back into the load zone); the passages list them all with the load they
    carried, 32.1 degrees apart."""
    hist, info = rolling_histories(case, 0.030)
    f = fault_frequencies(case.bearing, case.operating.shaft_hz)
    events = detect_spall_events(hist, 20, info, case.bearing.roller_radius, case.operating.speed)
    passages = spall_passages(hist, 20, info, case.operating.speed)
    assert len(passages) == 11
    assert [p["roller"] for p in passages] == list(range(11))
    step = np.diff(np.unwrap(np.radians([p["spall_angle_deg"] for p in passages])))
    np.testing.assert_allclose(np.degrees(step), 360.0 * f.shaft / f.bpfi, atol=0.2)
    loaded = [p for p in passages if p["force_before_N"] > 0.1 * Q_MAX]
    assert [e["roller"] for e in events] == [p["roller"] for p in loaded] == [0, 1, 2, 10]
    assert passages[3]["spall_angle_deg"] == pytest.approx(80.4, abs=0.2)  # faded: no event
    gaps = np.diff([e["entry_time_s"] for e in events])
    np.testing.assert_allclose(gaps * f.bpfi, [1.0, 1.0, 8.0], atol=2e-5 * f.bpfi)
    gaps = np.diff([e["exit_time_s"] for e in events])
    np.testing.assert_allclose(gaps * f.bpfi, [1.0, 1.0, 8.0], atol=2e-5 * f.bpfi)
    for e in events:
        e["first_impact_time_s"] = e["exit_time_s"]
    got = inner_restress_check(events, f.bpfi)
    # roller 10, back at -55 deg, carries a quarter of the load: an event, left out
    assert got["passed"] and "1 passage(s) below 50% of the largest load" in got["note"]
    # each entry when the spall's entry edge reaches the roller
    _, times = passage_spall_angles(case, case.run.first_roller_angle, case.defect.angle, 11)
    times = times[[0, 1, 2, 10]]
    r_i = case.bearing.inner_raceway_radius
    lag = (
        0.5
        * case.defect.length
        / r_i
        / (case.operating.speed - cage_speed(case.bearing, case.operating.speed))
    )
    np.testing.assert_allclose([e["entry_time_s"] for e in events], times - lag, atol=2e-5)
    at_entry = math.degrees(case.defect.angle + case.operating.speed * (times[0] - lag))
    assert events[0]["spall_angle_deg"] == pytest.approx(at_entry, abs=0.15)  # -19.6


def test_restress_interval_of_consecutive_passages_in_the_load_zone():
    """Only passages one BPFI period apart with a loaded roller count, timed by the
    first touch of the exit edge; the outer race's check counts every interval."""
    f = 373.3

    def event(k, load, late=0.0):
        t = k / f
        return {"first_impact_time_s": t, "exit_time_s": t + late, "force_before_N": load}

    # a faded passage at the zone's edge (2 kN) and a second visit 20 periods later; the
    # exits shift with the load, the first touches do not
    events = [event(0, 14e3), event(1, 15e3, 1e-4), event(2, 2e3), event(22, 12e3)]
    events.append(event(23, 15e3, 1e-4))
    got = inner_restress_check(events, f)
    assert got["passed"] and got["value"] == pytest.approx(0.0, abs=1e-9)
    assert "1 passage(s) below 50% of the largest load" in got["note"]
    assert "1 interval(s) over passages without an event" in got["note"]
    assert "1/BPFI" in got["note"]
    late = [event(0, 14e3), event(1.04, 15e3)]
    assert inner_restress_check(late, f)["passed"] is False
    # the outer race counts every interval: a missed passage fails
    assert restress_check(events, f)["passed"] is False
