"""A verdict that knows when it is unsure (issue 44): the candidates and their evidence, a
fault named only where the evidence decides between families, and the undecided verdict."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic_records import modulated_noise

from diagnostics import Candidate, bearing_frequencies, diagnose
from diagnostics._candidates import _explained_by
from diagnostics._comb import FamilyScore
from diagnostics.app.datasets import CWRU_FAN_END
from diagnostics.app.report import verdict_words

SHAFT = 29.95
FE = bearing_frequencies(CWRU_FAN_END, SHAFT)


def _diagnose(lines: dict[float, float], seed: int):
    return diagnose(modulated_noise(lines, seconds=4.0, seed=seed), 12000.0, CWRU_FAN_END, SHAFT)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_lines_both_families_explain_give_an_undecided_verdict(seed):
    """On the fan-end bearing BPFI - fr lies 1 % below 2 x BSF. Lines of equal strength at
    BPFI - fr, its double, BPFI and its double are an inner-race fault with shaft-rate
    sidebands as well as a ball fault with shaft-rate sidebands: each family's pair rests
    on lines the other explains, so the verdict names both and no fault."""
    a = 0.2
    d = _diagnose({FE.bpfi - SHAFT: a, 2 * (FE.bpfi - SHAFT): a, FE.bpfi: a, 2 * FE.bpfi: a}, seed)
    assert d.ambiguous and set(d.undecided) == {"inner", "ball"}
    assert d.fault in ("inner or ball", "ball or inner")
    detected = {c.family: c for c in d.candidates if c.detected}
    assert set(detected) == {"inner", "ball"}
    assert not any(c.decides for c in detected.values())
    assert detected["inner"].explained_by == ("ball",)
    assert detected["ball"].explained_by == ("inner",)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_an_inner_race_fault_with_a_weak_sideband_is_named(seed):
    """The same bearing, an inner-race fault's three harmonics and a weak first lower
    sideband (at BPFI - fr, in the ball comb's window): the inner race decides."""
    d = _diagnose({FE.bpfi - SHAFT: 0.08, FE.bpfi: 0.2, 2 * FE.bpfi: 0.2, 3 * FE.bpfi: 0.2}, seed)
    assert (d.fault, d.undecided, d.ambiguous) == ("inner", (), False)
    first = d.candidates[0]
    assert isinstance(first, Candidate)
    assert (first.family, first.comb, first.detected, first.decides) == (
        "inner",
        "BPFI",
        True,
        True,
    )
    assert {1, 2, 3} <= set(first.harmonics)
    assert first.p_value <= d.alpha
    assert first.unique_evidence == pytest.approx(first.evidence)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_an_outer_race_fault_with_strong_shaft_sidebands_is_named_outer(seed):
    """An outer-race fault whose lines carry upper shaft-rate sidebands at 0.8 of their
    strength: BPFO + fr lies 1.6 % above 2 x BSF on this bearing, so the ball comb finds a
    pair there (CWRU 295 was named ball for it). Its lines are the outer race's sidebands,
    while the outer race's third and fourth harmonics are no ball line: outer decides."""
    a = 0.2
    lines = {k * FE.bpfo: a for k in range(1, 5)}
    lines.update({FE.bpfo + SHAFT: 0.8 * a, 2 * FE.bpfo + 2 * SHAFT: 0.8 * a})
    d = _diagnose(lines, seed)
    assert (d.fault, d.undecided) == ("outer", ())
    ball = next(c for c in d.candidates if c.family == "ball")
    assert ball.detected and not ball.decides and ball.explained_by == ("outer",)


def test_a_fault_free_record_has_no_detected_candidate():
    d = diagnose(np.random.default_rng(3).standard_normal(48000), 12000.0, CWRU_FAN_END, SHAFT)
    assert d.fault == "none" and d.undecided == ()
    assert len(d.candidates) == 3 and not any(c.detected or c.decides for c in d.candidates)
    assert all(c.p_value > d.alpha for c in d.candidates)


def _score(comb, lines_hz, z, depth, band=(2000.0, 2500.0)):
    lines_hz, z = np.asarray(lines_hz, dtype=float), np.asarray(z, dtype=float)
    return FamilyScore(
        family={"BPFO": "outer", "BPFI": "inner"}.get(comb, "ball"), band=band,
        expected_hz=lines_hz[0], found_hz=lines_hz[0], lines_hz=lines_hz, z=z,
        threshold=np.full(z.size, 6.0), n_significant=int((z > 6.0).sum()),
        evidence=float(z[z > 6.0].sum()), modulation=np.asarray(depth, dtype=float),
        resolution_hz=0.1, comb=comb,
    )  # fmt: skip


def test_the_carrier_rule_compares_depths_not_normalised_values():
    """CWRU 295 (fan end, outer race at 6 o'clock, prewhitened band): BPFO 90.73 Hz at 319
    times its background and depth 0.572; the ball comb's line at BPFO + fr, 120.3 Hz, at
    355 times its own background but depth 0.463. The normalised values divide by
    different local backgrounds; the depths are amplitudes of one spectrum. The line is
    weaker than its carrier: it can be the carrier's sideband. One significantly deeper
    is not."""
    shaft = 29.585
    outer = _score("BPFO", [90.73, 181.46], [319.4, 126.3], [0.572, 0.312])
    ball = _score("2xBSF", [120.31, 240.62], [354.7, 72.4], [0.463, 0.154])
    assert _explained_by(ball, outer, shaft).tolist() == [True, True]
    deeper = _score("2xBSF", [120.31, 240.62], [354.7, 72.4], [0.9, 0.154])
    assert _explained_by(deeper, outer, shaft).tolist() == [False, True]
    # In another band the depths do not compare: any line at a sideband's place is one.
    elsewhere = _score("2xBSF", [120.31, 240.62], [354.7, 72.4], [0.9, 0.154], (3e3, 4e3))
    assert _explained_by(elsewhere, outer, shaft).tolist() == [True, True]


def test_a_race_fault_explains_the_cage_rate_series():
    """Rolling elements that differ strike a race defect each in its own way, once per cage
    turn: beside a detected race fault the cage-rate series is no ball evidence; the race
    comb's lines are not the cage series'."""
    shaft = 29.95
    outer = _score("BPFO", [FE.bpfo, 2 * FE.bpfo], [300.0, 100.0], [0.5, 0.3])
    cage = _score("FTF", FE.ftf * np.arange(1, 6), [0, 9.0, 12.0, 3.0, 2.0], [0.1] * 5)
    assert _explained_by(cage, outer, shaft).all()
    assert not _explained_by(outer, cage, shaft).any()


def test_the_undecided_verdict_in_words():
    assert verdict_words("outer or ball") == "outer or ball: the evidence does not decide"
    assert verdict_words("inner") == "inner fault"
    assert verdict_words("none") == "no bearing fault found"
