"""A rolling element's line and its cage-rate sideband as the detecting pair."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from synthetic_records import modulated_noise

from benchmarks.diagnostics.aperiodic_impulse_scenarios import weak_scenario
from diagnostics import FamilyScore, bearing_frequencies, diagnose
from diagnostics._evidence import _off_shaft, _sideband_p
from diagnostics._verdict import _unique_evidence
from diagnostics.app.datasets import CWRU_DRIVE_END, CWRU_FAN_END

FS = 12000.0
SHAFT_HZ = 29.95


def test_sideband_p_takes_the_stronger_side_but_never_one_above_its_line():
    line = np.array([20.0, 20.0, 5.0])
    sides = np.array([[10.0, 25.0, 2.0], [12.0, 3.0, 2.0]])
    p = _sideband_p(sides, line)
    assert p[0] == pytest.approx(8.0 * np.exp(-12.0))
    # 25 > 20: that side is no sideband of the line; the other (3) is what is left.
    assert p[1] == pytest.approx(min(1.0, 8.0 * np.exp(-3.0)))
    explained = np.array([[False, False, False], [True, False, False]])
    assert _sideband_p(sides, line, explained)[0] == pytest.approx(8.0 * np.exp(-10.0))


def test_off_shaft_keeps_lines_clear_of_the_speed_tolerance():
    fan = bearing_frequencies(CWRU_FAN_END, SHAFT_HZ)
    lines = np.array([1.0, 2.0]) * 2.0 * fan.bsf  # 3.99 and 7.98 shaft orders
    assert not _off_shaft(lines, SHAFT_HZ, 0.02).any()
    assert _off_shaft(lines, SHAFT_HZ, 0.0).all()
    drive = bearing_frequencies(CWRU_DRIVE_END, SHAFT_HZ)
    assert _off_shaft(np.array([2.0 * drive.bsf]), SHAFT_HZ, 0.02).all()  # 4.71 orders


def test_ball_line_with_a_weaker_cage_sideband_is_a_ball_fault():
    """One line at 2 x BSF and one at 2 x BSF - FTF, a third of its depth: the load zone
    passing with the cage modulates the ball's impacts. No second harmonic of 2 x BSF, so
    no pair of harmonics can detect it; the line and its sideband do."""
    f = bearing_frequencies(CWRU_DRIVE_END, SHAFT_HZ)
    x = modulated_noise({2.0 * f.bsf: 0.15, 2.0 * f.bsf - f.ftf: 0.05})
    d = diagnose(x, FS, CWRU_DRIVE_END, SHAFT_HZ)
    ball = d.families["ball"]
    assert d.fault == "ball" and ball.comb == "2xBSF"
    assert ball.n_significant == 1 and ball.sideband_pair_p < 1e-10
    assert ball.found_hz == pytest.approx(2.0 * f.bsf, rel=1e-3)


def test_a_stronger_neighbour_is_no_sideband():
    """Two lines, the stronger a cage rate below 2 x BSF: a sideband cannot be stronger
    than the line the cage modulates (the load-zone window is nowhere negative), so this is
    no ball fault, nor any other."""
    f = bearing_frequencies(CWRU_DRIVE_END, SHAFT_HZ)
    x = modulated_noise({2.0 * f.bsf: 0.08, 2.0 * f.bsf - f.ftf: 0.2})
    d = diagnose(x, FS, CWRU_DRIVE_END, SHAFT_HZ)
    assert d.fault == "none"
    assert not d.families["ball"].detected


def test_shaft_rate_sidebands_do_not_pair():
    """A line at BPFI with one at BPFI - fr: any source turning with the shaft makes such a
    pair (the fan-end channel of CWRU 262, a healthy bearing, read inner from lines at shaft
    spacing), so the inner race needs two harmonics of its own."""
    f = bearing_frequencies(CWRU_DRIVE_END, SHAFT_HZ)
    x = modulated_noise({f.bpfi: 0.15, f.bpfi - f.shaft: 0.05})
    d = diagnose(x, FS, CWRU_DRIVE_END, SHAFT_HZ)
    assert d.fault == "none"
    assert all(b.families["BPFI"].sideband_pair_p == 1.0 for b in d.bands)


def test_unconfirmed_speed_keeps_a_shaft_harmonic_from_pairing():
    """Fan-end bearing (2 x BSF = 3.99 fr): a line at the 4th shaft harmonic with a weaker
    one a cage rate below it. Told a speed 1 % low, with the speed check off, the mask
    misses the shaft harmonic, which then stands 1 % from 2 x BSF; within the slip
    tolerance of a shaft harmonic, that line cannot be the ball's one line. With the speed
    check (default) the record's shaft lines set the mask and the line is masked."""
    f = bearing_frequencies(CWRU_FAN_END, SHAFT_HZ)
    shaft = {k * SHAFT_HZ: 0.1 for k in (1, 2, 3)}
    x = modulated_noise({**shaft, 4.0 * SHAFT_HZ: 0.2, 4.0 * SHAFT_HZ - f.ftf: 0.1})
    for options in ({"correct_speed": False}, {}):
        d = diagnose(x, FS, CWRU_FAN_END, 0.99 * SHAFT_HZ, **options)
        assert d.fault == "none", options


def test_weak_ball_faults_gain_from_the_sideband_pair():
    """The benchmark's weak ball faults (impacts 0.8 x the noise, 2 x BSF modulated by the
    cage): four that were `none` before this rule (of the 7 of 56 it gained at that size)
    are named now, by a comb holding a single supporting harmonic, so by the line and its
    sideband."""
    for seed in (20, 56, 68, 81):
        fault, fs, geometry, shaft, x = weak_scenario(seed, 0.8)
        d = diagnose(x, fs, geometry, shaft)
        ball = d.families["ball"]
        assert (fault, d.fault, ball.comb, ball.n_significant) == ("ball", "ball", "2xBSF", 1)


def _comb(family, comb, lines_hz, z, band=(2000.0, 2500.0)):
    lines_hz, z = np.asarray(lines_hz, dtype=float), np.asarray(z, dtype=float)
    return FamilyScore(
        family=family, band=band, expected_hz=lines_hz[0], found_hz=lines_hz[0],
        lines_hz=lines_hz, z=z, threshold=np.full(z.size, 6.0),
        n_significant=int((z > 6.0).sum()), evidence=float(z[z > 6.0].sum()),
        resolution_hz=0.2, comb=comb,
    )  # fmt: skip


def test_a_line_stronger_than_a_carrier_is_not_its_sideband():
    """On the CWRU fan-end bearing BPFI - fr lies 1 % below 2 x BSF, so an inner-race fault's
    first lower sideband falls in the ball comb's window and the ball comb's shaft
    sidebands on the inner race's lines: the two combs explain each other's lines. (The
    fan-end channel of 109 with an inner-race fault added, faults_on_measured_backgrounds:
    BPFI 147.7 and 295.4 Hz at 163 and 50 times their background; the ball comb at 117.7
    Hz, 44.5, 3 and 19.3.) A sideband is no stronger than its carrier: the inner race's
    lines are not the ball comb's sidebands and keep their evidence, while the ball comb's
    first line, weaker than the inner race's, is its sideband; in another band the rule
    does not apply (the values are not comparable)."""
    shaft = 29.93
    inner = _comb("inner", "BPFI", [147.68, 295.36], [163.3, 50.2])
    ball = _comb("ball", "2xBSF", [117.67, 235.34, 353.01], [44.5, 3.0, 19.3])
    assert _unique_evidence(inner, [ball], shaft) == pytest.approx(163.3 + 50.2)
    assert _unique_evidence(ball, [inner], shaft) == pytest.approx(19.3)
    elsewhere = replace(ball, band=(3000.0, 3500.0))
    assert _unique_evidence(inner, [elsewhere], shaft) == 0.0
