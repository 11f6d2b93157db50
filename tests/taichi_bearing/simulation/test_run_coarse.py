"""The bearing run on the coarse case (cases/validation/coarse_spall.yaml): preload, spin,
one roller through the spall; and resume against the uninterrupted run.

One run (about half a minute on one thread) is shared by the tests of this module.
"""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

from taichi_bearing.analytic.quasistatic import analytical_roller_forces
from taichi_bearing.case import load_case
from taichi_bearing.output.histories import read_histories
from taichi_bearing.simulation.starter import rolling_rates

COARSE = "cases/validation/coarse_spall.yaml"
THREADS = 1  # the same histories as on any thread count; no spinning team on a shared VM


@pytest.fixture(scope="module")
def coarse_run(tmp_path_factory):
    from taichi_bearing.pipeline import run_case

    case = load_case(COARSE)
    out = tmp_path_factory.mktemp("coarse_run")
    summary = run_case(case, out, threads=THREADS, quiet=True, post=False)
    return case, out, summary, read_histories(out)


def test_summary_has_every_design_key(coarse_run):
    from taichi_bearing.output.summary import missing_summary_keys

    _, _, summary, hist = coarse_run
    assert missing_summary_keys(summary) == []
    assert summary["status"] == "finished"
    # a whole number of steps per 10 us sample, plus the first step out of t = 0
    per_sample = round(1e-5 / summary["dt_s"])
    assert per_sample * summary["dt_s"] == pytest.approx(1e-5, rel=1e-12)
    assert summary["n_steps"] == 1 + 200 * per_sample
    # 100 kHz histories over 2 ms, a row every 10 us
    assert len(hist) == 200
    assert np.allclose(np.diff(hist["time_s"]), 1e-5)


def test_preload_balances_the_load_and_follows_the_analytical_load_zone(coarse_run):
    case, _, summary, _ = coarse_run
    pre = summary["preload"]
    fy = np.asarray(pre["outer_fy_N"])
    # the rollers push the outer ring up with the radial load (the plate carries W)
    assert fy.sum() == pytest.approx(case.operating.load, rel=0.01)
    static = np.asarray(summary["static_roller_forces_N"])
    analytical = analytical_roller_forces(case)
    assert np.allclose(summary["analytical_roller_forces_N"], analytical)
    # no roller outside the analytical load zone carries load, the FE's most loaded
    # roller is one of the two next to 12 o'clock, and Q_max is of the analytical size
    # (the coarse mesh's 10 um facets and the flexible outer ring narrow the load zone:
    # the 10 % / 5 % checks are reported, not met, here)
    assert np.all(static[analytical == 0] < 0.01 * static.max())
    assert int(np.argmax(static)) in (0, 1)
    checks = summary["checks"]
    loaded = analytical > 0.05 * analytical.max()
    allowed = np.maximum(0.10 * analytical, 0.05 * analytical.max())
    excess = (np.abs(static - analytical) / allowed)[loaded].max()
    assert checks["static_roller_forces"]["value"] == pytest.approx(excess)
    # the rigid-ring comparison is reported, not applied, to the adapter-hung ring
    assert checks["static_roller_forces"]["passed"] is None
    assert checks["static_q_max"]["passed"] is None


def test_cage_and_roller_speeds_follow_kinematics(coarse_run):
    case, _, summary, hist = coarse_run
    rates = rolling_rates(case)
    checks = summary["checks"]
    assert checks["cage_speed"]["passed"] and checks["cage_speed"]["value"] < 0.02
    assert checks["roller_spin"]["passed"] and checks["roller_spin"]["value"] < 0.02
    # roller 0 rolls (is not dragged): its spin stays near -omega_c R_p / r all along
    spin = hist["roller0_spin_rad_s"].to_numpy()
    assert np.median(spin) == pytest.approx(rates.roller, rel=0.02)


def test_energy_balance(coarse_run):
    _, _, summary, hist = coarse_run
    assert summary["energy_balance_error"] < 0.02
    err = hist["energy_balance_error"].to_numpy()
    assert np.max(np.abs(err)) == pytest.approx(summary["energy_balance_error"])
    # the shaft keeps the bearing turning: positive external work, stored energy bounded
    assert hist["energy_external_work"].iloc[-1] > 0


def test_entry_is_gradual_and_exit_is_a_burst(coarse_run):
    """Entering the spall the roller's force falls with no impulse; leaving it, the
    force returns as several short impulses; the acceleration burst at exit is much
    larger than at entry or at the impact on the floor."""
    case, _, summary, hist = coarse_run
    events = summary["events"]
    assert [e["roller"] for e in events] == [0]
    ev = events[0]
    t = hist["time_s"].to_numpy()
    fn = hist["roller0_outer_fn"].to_numpy()
    f0 = ev["force_before_N"]
    te, tx = ev["entry_time_s"], ev["exit_time_s"]
    assert 0 < te < tx < t[-1]
    # the de-stressing is spread over several samples, not a step: from 90 % down to
    # 10 % of F0 over at least 50 us (the patch rolls over the edge), and nothing at
    # entry rises above the rattling of the facets before it
    k = np.searchsorted(t, te)
    above = np.flatnonzero(fn[:k] > 0.9 * f0)
    below = k + np.flatnonzero(fn[k:] < 0.1 * f0)
    assert t[below[0]] - t[above[-1]] >= 5e-5
    assert ev["entry_force_peak_ratio"] < 1.6
    # inside the spall the roller is (nearly) unloaded
    inside = (t > te + 1e-4) & (t < ev["floor_window_s"][1])
    assert np.median(fn[inside]) < 0.1 * f0
    # the acceleration burst at exit dominates the entry and the floor impact
    assert ev["exit_accel_peak"] > 2.0 * ev["entry_accel_peak"]
    assert ev["exit_accel_peak"] > 2.0 * ev["floor_accel_peak"]
    # one passage cannot decide the run's exit_burst check at 1 % (issue 43 item 6)
    assert summary["checks"]["exit_burst"]["passed"] is None
    assert summary["checks"]["exit_burst"]["value"] > 2.0
    assert math.isfinite(tx)


def test_entry_and_exit_happen_where_the_geometry_puts_them(coarse_run):
    """Entry: the force cannot fall before the contact patch reaches the entry edge, and
    the corner can hold the roller only until it has rolled sqrt(2 r d) past it (further
    on the roller would have to rise above the floor to touch it). Exit: the roller meets
    the exit edge once its top, risen by h into the notch (recorded), is within
    sqrt(2 r (d - h)) of the edge, and not after its centre line has crossed it."""
    from taichi_bearing.analytic.bearing import contact_radius, effective_modulus, hertz_half_width

    case, _, summary, hist = coarse_run
    ev = summary["events"][0]
    b, m, spall = case.bearing, case.material, case.defect
    r, d = b.roller_radius, spall.depth
    speed = rolling_rates(case).cage * b.outer_raceway_radius  # contact point on the race
    a0 = case.run.first_roller_angle
    t_entry_edge = (spall.angle - 0.5 * spall.length / b.outer_raceway_radius - a0) / (
        speed / b.outer_raceway_radius
    )
    t_exit_edge = t_entry_edge + spall.length / speed
    e_star = effective_modulus(m.youngs_modulus, m.poissons_ratio)
    half = hertz_half_width(
        ev["force_before_N"], b.roller_length, contact_radius(b, "outer"), e_star
    )
    assert t_entry_edge - half / speed <= ev["entry_time_s"]
    assert ev["entry_time_s"] <= t_entry_edge + math.sqrt(2 * r * d) / speed
    t = hist["time_s"].to_numpy()
    radius = hist["roller0_radius_m"].to_numpy()
    inside = (t > ev["entry_time_s"]) & (t < ev["first_impact_time_s"])
    rise = min(radius[inside].max() - radius[0], d)
    assert rise > 0  # the roller lifts into the notch (centrifugal force)
    lead = math.sqrt(2 * r * (d - rise)) / speed
    # two samples (0.1 mm of travel): the geometry takes the roller and corner as rigid
    tol = 2 * float(np.median(np.diff(t)))
    assert t_exit_edge - lead - tol <= ev["first_impact_time_s"] <= t_exit_edge + tol


def test_resume_continues_like_the_uninterrupted_run(coarse_run, tmp_path):
    from taichi_bearing.pipeline import run_case

    case, out, summary, hist = coarse_run
    copy = tmp_path / "resumed"
    shutil.copytree(out, copy)
    ckpts = sorted((copy / "checkpoints").glob("checkpoint_*.npz"))
    assert ckpts, "the run must leave checkpoints"
    resumed = run_case(case, copy, resume=True, threads=THREADS, quiet=True, post=False)
    again = read_histories(copy)
    assert len(again) == len(hist)
    assert np.allclose(again["time_s"], hist["time_s"])
    # the rows after the checkpoint were computed again and agree
    for col in ("roller0_outer_fn", "adapter_top_ay", "energy_kinetic", "cage_angle_rad"):
        a, b = again[col].to_numpy(), hist[col].to_numpy()
        scale = np.max(np.abs(b)) + 1e-30
        assert np.max(np.abs(a - b)) / scale < 1e-6, col
    assert resumed["restress_times_s"] == pytest.approx(summary["restress_times_s"])


def test_exit_force_returns_as_several_impulses_above_the_static_force(coarse_run):
    """The re-stressing burst: the roller bounces between the exit edge and the inner
    raceway. Measured: 13 impulses in the millisecond after the first impact, peak
    2.5 F0, against 1.14 F0 at entry."""
    _, _, summary, _ = coarse_run
    ev = summary["events"][0]
    assert ev["exit_impulses"] >= 3
    assert ev["exit_force_peak_ratio"] > 1.8
    assert ev["exit_force_peak_ratio"] > 1.2 * ev["entry_force_peak_ratio"]


def test_preload_q_max_matches_the_flexible_ring_reference(coarse_run):
    """Measured: 15.30 kN against 15.45 kN (-1.0 %). (+12 % while contact patches ran
    past the spall's corners: a roller's flank touched the entry wall's line, and the
    corner node's patch stood out of the raceway.)"""
    _, _, summary, _ = coarse_run
    static = np.asarray(summary["static_roller_forces_N"])
    reference = np.asarray(summary["reference_roller_forces_N"])
    assert static.max() == pytest.approx(reference.max(), rel=0.05)
    assert summary["checks"]["static_q_max_flexible"]["passed"]


@pytest.fixture(scope="module")
def coarse_multirate_run(tmp_path_factory):
    from taichi_bearing.pipeline import run_case

    case = load_case(COARSE, ["run.multirate_levels=2"])
    out = tmp_path_factory.mktemp("coarse_multirate_run")
    summary = run_case(case, out, threads=THREADS, quiet=True, post=False)
    return case, out, summary, read_histories(out)


# Multi-rate stepping is opt-in (run.multirate_levels): its solver-level tests
# (test_solver_multirate) run in CI; this bearing-level run and its resume (~80 s) with
# -m slow, when touching multirate stepping.
@pytest.mark.slow
def test_multirate_run_keeps_the_passage_and_the_energy(coarse_run, coarse_multirate_run):
    """Multi-rate stepping (up to 4 steps) on the coarse case: whole cycles per sample,
    the energy balanced, the same roller de-stressing at the same time and leaving the
    spall at the same time (its exit burst is chaotic: judged by its timing only)."""
    _, _, ref, ref_hist = coarse_run
    _, _, summary, hist = coarse_multirate_run
    assert summary["status"] == "finished"
    info = summary["multirate"]
    assert info["levels"] == 2 and 0.9 < info["element_work"] < 1.0
    assert sum(info["element_share"][1:]) > 0.05  # the slower classes are exercised
    per_sample = round(1e-5 / summary["dt_s"])
    assert per_sample % 4 == 0 and summary["n_steps"] == 1 + 200 * per_sample
    assert summary["energy_balance_error"] < 0.02
    [ev], [ev_ref] = summary["events"], ref["events"]
    assert ev["roller"] == ev_ref["roller"]
    for key in ("entry_time_s", "exit_time_s"):
        assert ev[key] == pytest.approx(ev_ref[key], abs=2e-5), key
    assert ev["force_before_N"] == pytest.approx(ev_ref["force_before_N"], rel=0.01)
    cage = hist["cage_angle_rad"].iloc[-1]
    assert cage == pytest.approx(ref_hist["cage_angle_rad"].iloc[-1], rel=1e-3)


@pytest.mark.slow
def test_multirate_resume_continues_bit_for_bit(coarse_multirate_run, tmp_path):
    """A multi-rate run resumed from its checkpoint (a sample's end, where every class
    moves) recomputes the same rows, bit for bit."""
    from taichi_bearing.pipeline import run_case

    case, out, _, hist = coarse_multirate_run
    copy = tmp_path / "resumed"
    shutil.copytree(out, copy)
    assert sorted((copy / "checkpoints").glob("checkpoint_*.npz"))
    run_case(case, copy, resume=True, threads=THREADS, quiet=True, post=False)
    again = read_histories(copy)
    assert len(again) == len(hist)
    for col in ("roller0_outer_fn", "adapter_top_ay", "energy_kinetic", "cage_angle_rad"):
        assert np.array_equal(again[col].to_numpy(), hist[col].to_numpy()), col
