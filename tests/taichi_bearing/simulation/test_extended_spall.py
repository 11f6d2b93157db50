"""Extended spalls, longer than the roller spacing: two rollers inside at once. Passages
found roller by roller in synthetic histories; the quasi-static load shared by the
others; what the checks do with such a spall; and a short run of
cases/validation/extended_spall.yaml (about two minutes on one thread)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from synthetic_passages import rolling_histories

from taichi_bearing.analytic.bearing import cage_speed, fault_frequencies
from taichi_bearing.analytic.quasistatic import solve_case, spall_from_case
from taichi_bearing.case import ExtendedDefectWarning, load_case
from taichi_bearing.checks import defect_size_check
from taichi_bearing.checks.passages import detect_spall_events
from taichi_bearing.post.spall_figures import overlaps

EXTENDED = "cases/validation/extended_spall.yaml"


@pytest.fixture(scope="module")
def case():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ExtendedDefectWarning)
        return load_case(EXTENDED)


def test_the_case_is_an_extended_spall_and_the_warning_says_what_the_run_does():
    with pytest.warns(ExtendedDefectWarning) as caught:
        c = load_case(EXTENDED)
    spacing = c.bearing.roller_spacing * c.bearing.outer_raceway_radius
    assert c.defect.length > 1.1 * spacing
    text = str(caught[0].message)
    assert "each roller's entry and exit" in text and "defect_size" in text


def test_each_roller_inside_at_once_is_found_with_its_own_entry_and_exit(case):
    """Rollers 0 and 19 are both inside the spall for a while: each one's entry and exit
    are found when its own contact crosses the edges, and consecutive rollers' events
    are one BPFO period apart."""
    hist, info = rolling_histories(case, 0.0065)
    r_o = case.bearing.outer_raceway_radius
    cage = cage_speed(case.bearing, case.operating.speed)
    events = detect_spall_events(hist, 20, info, case.bearing.roller_radius)
    assert [e["roller"] for e in events] == [0, 19]
    pairs = overlaps(events)
    assert [(a["roller"], b["roller"]) for a, b in pairs] == [(0, 19)]
    start = case.defect.angle - 0.5 * case.defect.length / r_o
    for e in events:
        angle0 = case.run.first_roller_angle + 2 * math.pi * e["roller"] / 20
        if angle0 > math.pi:
            angle0 -= 2 * math.pi
        t_in = (start - angle0) / cage
        t_out = t_in + case.defect.length / r_o / cage
        assert e["entry_time_s"] == pytest.approx(t_in, abs=2e-5)
        # exit: the 0.1 ms mean regains half the load 0.05 ms after the edge
        assert e["exit_time_s"] == pytest.approx(t_out + 5e-5, abs=2e-5)
    bpfo = fault_frequencies(case.bearing, case.operating.shaft_hz).bpfo
    assert np.diff([e["entry_time_s"] for e in events])[0] * bpfo == pytest.approx(1, abs=2e-2)
    # the second roller entered before the first left: both inside
    assert events[1]["entry_time_s"] < events[0]["exit_time_s"]


def test_a_long_record_holds_every_passage_including_a_roller_s_second(case):
    """Over 50 ms (more than a cage turn, 45.5 ms at 3000 rpm) every roller crosses the
    spall once or twice: each crossing whose approach (more than 1 mm before the edge)
    and exit are in the record is one passage, at the time the kinematics give, roller
    0's second one included."""
    duration = 0.05
    hist, info = rolling_histories(case, duration)
    r_o = case.bearing.outer_raceway_radius
    cage = cage_speed(case.bearing, case.operating.speed)
    span = case.defect.length / r_o
    start = case.defect.angle - 0.5 * span
    expected = []
    for j in range(20):
        angle0 = case.run.first_roller_angle + 2 * math.pi * j / 20
        for k in range(-2, 3):
            t_in = (start + 2 * math.pi * k - angle0) / cage
            # recorded: a few samples of the approach (1 mm before the edge) and the exit
            if t_in - 1e-3 / r_o / cage > 3e-5 and t_in + span / cage + 1e-4 < duration:
                expected.append((t_in, j))
    expected.sort()
    events = detect_spall_events(hist, 20, info, case.bearing.roller_radius)
    assert [e["roller"] for e in events] == [j for _, j in expected]
    assert [e["roller"] for e in events].count(0) == 2
    for e, (t_in, _) in zip(events, expected, strict=True):
        assert e["entry_time_s"] == pytest.approx(t_in, abs=2e-5)
        assert e["exit_time_s"] == pytest.approx(t_in + span / cage + 5e-5, abs=2e-5)


def test_quasi_static_load_shared_by_the_rest_while_two_are_inside(case):
    """With the spall spanning two rollers both carry nothing, the others balance the
    load exactly, and each of them carries more than in the healthy bearing."""
    spall = spall_from_case(case)
    pitch = 2 * math.pi / case.bearing.n_rollers
    cage = spall.centre + 0.5 * pitch  # rollers 0 and 19 either side of the centre
    dist = solve_case(case, cage)
    healthy = solve_case(case, cage, healthy=True)
    assert dist.outer_force[0, 0] == 0.0 and dist.outer_force[0, 19] == 0.0
    assert dist.outer_fy.sum() == pytest.approx(case.operating.load, rel=1e-12)
    loaded = healthy.outer_force[0] > 0
    loaded[[0, 19]] = False
    assert np.all(dist.outer_force[0, loaded] > healthy.outer_force[0, loaded])


def test_defect_size_check_is_not_applied_to_an_extended_spall(case):
    got, size = defect_size_check(case, np.zeros(1000), 1e5)
    assert got["passed"] is None and size is None
    assert "longer than the roller spacing" in got["note"]


@pytest.fixture(scope="module")
def extended_run(case, tmp_path_factory):
    from taichi_bearing.pipeline import run_case

    out = tmp_path_factory.mktemp("extended_run")
    summary = run_case(case, out, threads=1, quiet=True, post=False)
    return out, summary


@pytest.mark.slow  # a 5.5 ms run, ~2 min; the detector and quasi-static tests above stay in CI
def test_run_finds_two_rollers_inside_and_the_others_carry_the_load(case, extended_run):
    """The finite element run: roller 0 enters, roller 19 enters one BPFO period later
    while roller 0 is still inside, roller 0 leaves, then roller 19 leaves, each
    passage found from the roller's own force (roller 18, inside at the end of the
    record, has not left: no passage). While both are inside they carry nothing and the
    plate's load is carried by the other rollers."""
    from taichi_bearing.output.histories import read_histories

    out, summary = extended_run
    events = summary["events"]
    assert [e["roller"] for e in events] == [0, 19]
    first, second = events
    bpfo = fault_frequencies(case.bearing, case.operating.shaft_hz).bpfo
    assert (second["entry_time_s"] - first["entry_time_s"]) * bpfo == pytest.approx(1, abs=0.03)
    assert (second["exit_time_s"] - first["exit_time_s"]) * bpfo == pytest.approx(1, abs=0.03)
    assert second["entry_time_s"] < first["first_impact_time_s"]
    # each exit: the roller's contact has travelled the spall's length after its entry
    r_o = case.bearing.outer_raceway_radius
    travel = cage_speed(case.bearing, case.operating.speed) * r_o
    for e in events:
        crossing = (e["exit_time_s"] - e["entry_time_s"]) * travel
        assert crossing == pytest.approx(case.defect.length, rel=0.1)
    hist = read_histories(out)
    t = hist["time_s"].to_numpy()
    # both inside: from roller 19's entry to roller 0's first touch of the exit edge
    both = (t >= second["entry_time_s"]) & (t < first["first_impact_time_s"])
    assert both.sum() >= 10
    fy = np.stack([hist[f"roller{j}_outer_fy"].to_numpy() for j in range(20)])
    fn = np.stack([hist[f"roller{j}_outer_fn"].to_numpy() for j in range(20)])
    inside = np.median(fn[[0, 19]][:, both], axis=1)
    assert np.all(inside < 0.05 * first["force_before_N"])
    # the rest hold the outer ring up against the load: on average over the window (the
    # ring rings after roller 19 lets go: the sum swings by about 15 % within it)
    rest = np.delete(fy, [0, 19], axis=0)[:, both].sum(axis=0)
    assert np.mean(rest) == pytest.approx(case.operating.load, rel=0.05)
    assert summary["checks"]["defect_size"]["passed"] is None


@pytest.mark.slow  # a 5.5 ms run, ~2 min; the detector and quasi-static tests above stay in CI
def test_the_report_shows_the_two_inside_unloaded_and_their_neighbours_taking_the_load(
    case, extended_run
):
    """The report's load-sharing figure and table (post.spall_figures.load_sharing) over
    the window in which rollers 0 and 19 are both inside: both carry little (their floor
    bounces) against the ~10 kN the healthy bearing gives them, the quasi-static model
    unloads them and balances the load, and the neighbours either side (rollers 18 and
    1) take more than in the healthy bearing."""
    from taichi_bearing.output.run_folder import load_run
    from taichi_bearing.post.spall_figures import load_sharing

    out, summary = extended_run
    _, caption, values = load_sharing(load_run(out))
    first, second = summary["events"]
    assert values["rollers_inside"] == [0, 19]
    assert values["window_s"] == [second["entry_time_s"], first["first_impact_time_s"]]
    rows = {r["roller"]: r for r in values["rollers"]}
    for j in (0, 19):
        assert rows[j]["quasi_static_spall_N"] == 0.0
        assert rows[j]["fe_N"] < 0.25 * rows[j]["quasi_static_healthy_N"]
    for j in (18, 1):
        assert rows[j]["quasi_static_spall_N"] > 1.3 * rows[j]["quasi_static_healthy_N"]
        assert rows[j]["fe_N"] > 1.5 * rows[j]["quasi_static_healthy_N"]
    assert "rollers 0 and 19 were both inside" in caption
