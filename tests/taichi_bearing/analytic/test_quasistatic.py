"""Quasi-static load distribution: equilibrium, Stribeck, clearance, and the four events of
a roller passing a line spall."""

from __future__ import annotations

import math

import numpy as np
import pytest

from taichi_bearing.analytic.bearing import palmgren_stiffness
from taichi_bearing.analytic.quasistatic import (
    Spall,
    _corner_drop,
    analytical_roller_forces,
    contact_model,
    load_distribution_factor,
    solve_case,
    solve_load_distribution,
    spall_from_case,
    static_contact_table,
    stribeck_ratio,
    support_fraction,
)
from taichi_bearing.case import load_case


@pytest.fixture(scope="module")
def case(default_case_path):
    return load_case(default_case_path)


@pytest.fixture(scope="module")
def cm(case):
    return contact_model(case.bearing, case.material)


@pytest.fixture(scope="module")
def half_width(case):
    table = static_contact_table(case)
    return float(table["outer_half_width_m"].max())


def edge_angles(case, edge: float, b: float, reach: float, n: int) -> np.ndarray:
    """Cage angles putting roller 0's contact point from -reach*b to +reach*b of an edge."""
    return edge + np.linspace(-reach, reach, n) * b / case.bearing.outer_raceway_radius


# ----------------------------------------------------------------------- healthy bearing


@pytest.mark.parametrize("clearance", [0.0, 40e-6, -10e-6])
def test_forces_balance_the_load_exactly(cm, clearance):
    import dataclasses

    model = dataclasses.replace(cm, clearance=clearance)
    angles = np.random.default_rng(1).uniform(-np.pi, np.pi, 50)
    dist = solve_load_distribution(model, 20, 50e3, angles)
    assert dist.balance_error().max() < 1e-9
    assert np.all(dist.outer_force >= 0)


def test_balance_with_spall_and_step_model(case):
    angles = np.random.default_rng(2).uniform(-0.2, 0.2, 200)
    for mode in ("patch", "step"):
        assert solve_case(case, angles, mode).balance_error().max() < 1e-9


@pytest.mark.parametrize(("exponent", "expected"), [(10 / 9, 4.08), (1.5, 4.37)])
def test_stribeck_constant_at_zero_clearance(cm, exponent, expected):
    import dataclasses

    model = dataclasses.replace(cm, exponent=exponent)
    # a roller on the load line carries Q_max
    dist = solve_load_distribution(model, 20, 50e3, 0.0)
    assert stribeck_ratio(dist)[0] == pytest.approx(expected, rel=0.01)
    # two rollers straddling it: Q_max is the load-line value K_n delta_r^n
    dist = solve_load_distribution(model, 20, 50e3, math.pi / 20)
    q_max = model.k_series * dist.ring_displacement[0] ** exponent
    assert q_max * 20 / 50e3 == pytest.approx(expected, rel=0.01)
    assert stribeck_ratio(dist)[0] < q_max * 20 / 50e3


def test_zero_clearance_is_symmetric_with_half_ring_loaded(cm):
    dist = solve_load_distribution(cm, 20, 50e3, 0.0)
    assert abs(dist.outer_fx.sum()) < 1e-9 * dist.load
    loaded = np.abs(np.degrees(dist.roller_angle[0][dist.outer_force[0] > 1e-6]))
    assert loaded.max() < 90.0 and loaded.max() == pytest.approx(72.0)
    assert load_distribution_factor(dist, 0.0)[0] == pytest.approx(0.5)
    # Harris: Q = K_n delta^n with delta = delta_r cos(psi)
    q_expected = cm.k_series * np.maximum(
        dist.ring_displacement[0] * np.cos(dist.roller_angle[0]), 0
    ) ** (10 / 9)
    np.testing.assert_allclose(dist.outer_force[0], q_expected, rtol=1e-12, atol=1e-9)


def test_clearance_narrows_and_preload_widens_the_load_zone(cm):
    import dataclasses

    results = {}
    for clearance in (0.0, 30e-6, -10e-6):
        model = dataclasses.replace(cm, clearance=clearance)
        dist = solve_load_distribution(model, 20, 50e3, 0.0)
        eps = load_distribution_factor(dist, clearance)[0]
        n_loaded = int(np.sum(dist.outer_force[0] > 1e-6))
        # loaded exactly where delta_r cos(psi) > P_d / 2 (Harris's load zone)
        zone = dist.ring_displacement[0] * np.cos(dist.roller_angle[0]) > clearance / 2
        np.testing.assert_array_equal(dist.outer_force[0] > 0, zone)
        results[clearance] = (eps, n_loaded, stribeck_ratio(dist)[0])
    assert results[30e-6][0] < 0.5 < results[-10e-6][0]
    assert results[30e-6][1] < results[0.0][1] < results[-10e-6][1]
    # fewer rollers share the load with clearance: the top roller carries more
    assert results[30e-6][2] > results[0.0][2] > results[-10e-6][2]


def test_static_contact_table(case, cm):
    table = static_contact_table(case)
    top = int(np.argmax(table["outer_force_N"]))
    assert table["angle_deg"][top] == 0.0
    q = table["outer_force_N"][top]
    assert q * 20 / 50e3 == pytest.approx(4.08, rel=0.01)
    assert q == pytest.approx(table["inner_force_N"][top])
    assert table["deflection_m"][top] == pytest.approx((q / cm.k_series) ** 0.9)
    # conformal outer contact: wider and lower pressure than the inner one
    assert np.all(table["outer_half_width_m"] > table["inner_half_width_m"])
    assert np.all(table["outer_pmax_Pa"] < table["inner_pmax_Pa"])
    b, p = table["outer_half_width_m"], table["outer_pmax_Pa"]
    np.testing.assert_allclose(np.pi * b * p / 2, table["outer_force_N"] / 0.05, rtol=1e-12)
    assert len(table["roller"]) == 9  # rollers at 0, +-18, ..., +-72 deg


def test_palmgren_k_is_what_the_model_uses(case, cm):
    assert cm.k_outer == pytest.approx(palmgren_stiffness(case.bearing, case.material))


# ---------------------------------------------------------------------------- the spall


def test_spall_of_zero_depth_is_the_healthy_raceway(cm):
    angles = np.linspace(-0.1, 0.1, 301)
    flat = Spall(entry=-0.04, exit=0.04, depth=0.0)
    with_flat = solve_load_distribution(cm, 20, 5e4, angles, flat)
    healthy = solve_load_distribution(cm, 20, 5e4, angles)
    np.testing.assert_allclose(with_flat.outer_force, healthy.outer_force, rtol=1e-12, atol=1e-6)


def test_analytical_roller_forces_at_the_run_start(case):
    forces = analytical_roller_forces(case)
    # roller 0 starts at -5 deg, 2.44 deg before the spall's entry edge: fully supported
    assert forces.shape == (20,)
    dist = solve_case(case, case.run.first_roller_angle, healthy=True)
    np.testing.assert_allclose(forces, dist.outer_force[0], rtol=1e-9)
    assert forces.sum() > case.operating.load  # components: the sum of magnitudes is more


def test_support_fraction():
    assert support_fraction(-1.0) == 0.0 and support_fraction(1.0) == 1.0
    assert support_fraction(0.0) == pytest.approx(0.5)
    # integral of (2/pi) sqrt(1 - t^2) from -1 to 0.5
    t = np.linspace(-1, 0.5, 200001)
    y = 2 / np.pi * np.sqrt(1 - t * t)
    assert support_fraction(0.5) == pytest.approx(np.sum((y[1:] + y[:-1]) / 2 * np.diff(t)))


def test_corner_pivot_geometry(case):
    r, r_o = case.bearing.roller_radius, case.bearing.outer_raceway_radius
    delta = np.array([0.0, 1e-3, 5e-3, 2e-2])
    h = _corner_drop(delta, r, r_o)
    assert h[0] == pytest.approx(0.0, abs=1e-15)
    assert np.all(np.diff(h) > 0)
    # the rigid roller touches the corner: |centre - corner| = r
    rho = r_o - r + h
    dist = np.hypot(rho * np.sin(delta), r_o - rho * np.cos(delta))
    np.testing.assert_allclose(dist, r, rtol=1e-12)
    # beyond its reach the corner does not hold the roller
    assert np.isinf(_corner_drop(np.array([0.2]), r, r_o))[0]


def test_destressing_at_entry_is_gradual_and_continuous(case, half_width):
    spall = spall_from_case(case)
    b = half_width
    forces = {}
    for n in (401, 801):
        angles = edge_angles(case, spall.entry, b, 2.0, n)
        forces[n] = solve_case(case, angles).outer_force[:, 0]
    f = forces[401]
    q = f[0]
    healthy = solve_case(case, edge_angles(case, spall.entry, b, 2.0, 401), healthy=True)
    # untouched until the patch reaches the edge (at -b), then falling monotonically
    before = np.linspace(-2, 2, 401) < -1.05
    np.testing.assert_allclose(f[before], healthy.outer_force[before, 0], rtol=1e-9)
    within = np.linspace(-2, 2, 401) > -1.0
    assert np.all(np.diff(f[within]) <= 1e-9 * q)
    # the patch centred on the edge still carries part of the load, none once past it
    assert 0.2 * q < f[200] < 0.9 * q
    assert f[-1] == 0.0
    # continuous: the largest step between samples halves with the sample spacing
    jump = {n: np.abs(np.diff(v)).max() for n, v in forces.items()}
    assert jump[401] < 0.05 * q
    assert jump[801] < 0.6 * jump[401]
    # the step model, by contrast, drops the whole load at once
    step = solve_case(case, edge_angles(case, spall.entry, b, 2.0, 401), "step")
    assert np.abs(np.diff(step.outer_force[:, 0])).max() > 0.9 * q


def test_traverse_carries_nothing_when_the_drop_exceeds_the_deflection(case):
    spall = spall_from_case(case)
    dist = solve_case(case, spall.centre)
    top = static_contact_table(case)["deflection_m"].max()
    assert spall.depth > 10 * top  # 0.2 mm against ~13 um
    assert dist.outer_force[0, 0] == 0.0


def test_shallow_spall_roller_rests_on_the_floor(default_case_path):
    # 5 um deep: less than the ~13 um deflection, so the roller bears on the floor with
    # Q = K_n (delta_r cos(psi) - H)^n
    case = load_case(default_case_path, ["defect.depth_mm=0.005"])
    cm = contact_model(case.bearing, case.material)
    dist = solve_case(case, 0.0)
    expected = cm.k_series * (dist.ring_displacement[0] - 5e-6) ** (10 / 9)
    assert dist.outer_force[0, 0] == pytest.approx(expected, rel=1e-9)
    assert 0 < dist.outer_force[0, 0] < solve_case(case, 0.0, healthy=True).outer_force[0, 0]
    # and the passage stays continuous (pivot, landing on the floor, pivot)
    angles = np.linspace(-0.06, 0.06, 2001)
    f = solve_case(case, angles).outer_force[:, 0]
    assert np.abs(np.diff(f)).max() < 0.02 * f.max()


def test_load_compensation(case):
    spall = spall_from_case(case)
    dist = solve_case(case, spall.centre)
    healthy = solve_case(case, spall.centre, healthy=True)
    assert dist.outer_force[0, 0] == 0.0
    for j in (1, 19):  # the two neighbours carry more
        assert dist.outer_force[0, j] > 1.1 * healthy.outer_force[0, j]
    assert np.all(dist.outer_force[0, 1:] >= healthy.outer_force[0, 1:])
    assert dist.ring_displacement[0] > healthy.ring_displacement[0]
    assert dist.outer_fy.sum() == pytest.approx(case.operating.load, rel=1e-9)


def test_restressing_at_exit_mirrors_the_entry(case, half_width):
    spall = spall_from_case(case)
    b = half_width
    exit_angles = edge_angles(case, spall.exit, b, 2.0, 401)
    f_exit = solve_case(case, exit_angles).outer_force[:, 0]
    healthy = solve_case(case, exit_angles, healthy=True).outer_force[:, 0]
    assert f_exit[0] == 0.0
    within = np.linspace(-2, 2, 401) < 1.0
    assert np.all(np.diff(f_exit[within]) >= -1e-9 * healthy.max())
    after = np.linspace(-2, 2, 401) > 1.05
    np.testing.assert_allclose(f_exit[after], healthy[after], rtol=1e-9)
    # spall centred on the load line: the exit is the mirror image of the entry
    f_entry = solve_case(case, -exit_angles).outer_force[:, 0]
    np.testing.assert_allclose(f_exit, f_entry, rtol=1e-9, atol=1e-9 * healthy.max())


def test_pivot_force_points_at_the_corner(case, half_width):
    spall = spall_from_case(case)
    angle = spall.entry + 0.5 * half_width / case.bearing.outer_raceway_radius
    dist = solve_case(case, angle)
    fx, fy = dist.outer_fx[0, 0], dist.outer_fy[0, 0]
    assert dist.outer_force[0, 0] > 0
    # roller centre (just past the corner) -> corner: tilted back towards the entry side,
    # more than the radial direction at the roller's angle
    tilt = math.atan2(-fx, fy)  # direction angle from 12 o'clock, ccw
    assert tilt < angle
    # the inner contact carries only the radial component
    radial = -fx * math.sin(angle) + fy * math.cos(angle)
    assert dist.inner_force[0, 0] == pytest.approx(radial)
    assert dist.inner_force[0, 0] < dist.outer_force[0, 0]


def test_invalid_inputs(case, cm, default_case_path):
    with pytest.raises(ValueError, match="mode"):
        solve_load_distribution(cm, 20, 5e4, 0.0, mode="smooth")
    with pytest.raises(ValueError, match="load"):
        solve_load_distribution(cm, 20, -5e4, 0.0)
    assert spall_from_case(load_case(default_case_path, ["defect.race=none"])) is None
