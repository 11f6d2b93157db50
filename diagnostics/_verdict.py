"""The verdict from every candidate band's scores: each family's best comb, the families
another source's series sets aside, and among those detected the one whose own lines carry
the most evidence."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from diagnostics._candidates import (
    Candidate,
    _candidate,
    _explained_by,
    _sidebands_explained_by,
    unique_evidence,
)
from diagnostics._comb import BandScore, FamilyScore, _Setting, series_strength
from diagnostics._other_source import _holds_apart, _holds_without

FAMILIES = ("outer", "inner", "ball")


def _unique_evidence(score: FamilyScore, others: list[FamilyScore], shaft_hz: float) -> float:
    """Evidence of ``score`` from significant lines that no other family's comb explains.

    Kinematics makes some lines common to two families: BPFO + BPFI is n times the shaft
    rate, so 2 BPFI lies within 1 % of 3 BPFO on many bearings, and an outer-race fault with
    shaft-rate modulation has a line at exactly BPFI. A detected family explains its
    harmonics; a race or spin comb also those above the ones it tested and their first two
    shaft-rate sidebands (k f0 +- j fr, j <= 2: a fault modulated by the turning shaft).
    With 9 balls and d/D = 0.2, BPFO - 2 fr falls within 0.5 % of 4 FTF, a line of the
    cage-rate series: an outer-race fault explains it. A shared line is evidence for neither.
    But a sideband is no stronger than its carrier (amplitude modulation by a window nowhere
    negative), so a line stronger than the other comb's tested harmonic in the same band is
    not that harmonic's sideband: on the CWRU fan-end bearing BPFI - fr lies 1 % below
    2 x BSF, and an inner-race fault's lines would otherwise all be the ball comb's
    sidebands. (Strength: the modulation depth, :func:`diagnostics._candidates._explained_by`.)
    """
    return unique_evidence(score, [_explained_by(score, o, shaft_hz) for o in others])


@dataclass(frozen=True)
class _Verdict:
    """The verdict and what :class:`Diagnosis` reports beside it (``shown``: the band whose
    other series is reported; ``undecided``: the families the evidence does not decide
    between, where ``fault`` names them all)."""

    fault: str
    band: tuple[float, float]
    confidence: float
    scores: dict[str, float]
    best: dict[str, FamilyScore | None]
    dominated: tuple[str, ...]
    shown: BandScore
    candidates: tuple[Candidate, ...] = ()
    undecided: tuple[str, ...] = ()


def _verdict(bands: list[BandScore], s: _Setting) -> _Verdict:
    """The verdict from every band's scores: each family's best comb in its best band, a
    family weaker than its band's other series named only where it holds apart from it,
    and among those detected the one whose own (unshared) lines carry most evidence."""
    by_band = {b.band: b for b in bands}

    def share(sc: FamilyScore) -> float:
        # The family's strength over that of the band's strongest other series.
        ref = by_band[sc.band].other_strength
        return series_strength(sc.z) / ref if ref > 0 else math.inf

    def apart(sc: FamilyScore) -> bool:
        # A family at least as strong as the other series stands; a weaker one only where
        # its detection holds on lines that series does not explain.
        if share(sc) >= 1.0:
            return True
        return _holds_apart(
            sc, by_band[sc.band], s.freqs.shaft, s.alpha_pair, s.min_modulation, s.shaft_tolerance
        )

    best: dict[str, FamilyScore | None] = {}
    for family in FAMILIES:
        # A family's evidence is its best comb in its best band (one where it is not
        # dominated, if any).
        options = [
            b.families[comb]
            for b in bands
            for comb, (fam, _, _) in s.combs.items()
            if fam == family and b.families[comb] is not None
        ]
        best[family] = max(
            options,
            key=lambda sc: (sc.detected and apart(sc), sc.detected, sc.evidence, sc.near_miss),
            default=None,
        )
    detected = [sc for sc in best.values() if sc is not None and sc.detected]
    dominated = tuple(sc.family for sc in detected if not apart(sc))
    detected = [sc for sc in detected if apart(sc)]
    candidates = _candidates(best, detected, by_band, s)
    unique = {c.family: c.unique_evidence for c in candidates if c.detected}
    scores = {fam: (best[fam].evidence if best[fam] is not None else 0.0) for fam in FAMILIES}
    undecided: tuple[str, ...] = ()
    if detected:
        # The verdict goes to the family whose detection holds on lines no other detected
        # family explains, where only one does; where none or several do, the evidence
        # does not decide between them (ranked by the evidence of their own lines).
        ranked = [c for c in candidates if c.detected]
        deciding = [c for c in ranked if c.decides]
        # Where several hold on their own lines, the best decides only where its own lines'
        # evidence (the sum of their normalised values, each about -ln of its p-value)
        # exceeds every other's by -ln(alpha_pair): its lines are at least 1 / alpha_pair
        # times less likely by chance, the level at which a pair detects at all.
        margin = -math.log(s.alpha_pair)
        close = (
            [c for c in deciding if c.unique_evidence > deciding[0].unique_evidence - margin]
            if deciding
            else []
        )
        if len(close) == 1:
            win = best[close[0].family]
        else:
            win = best[ranked[0].family]
            undecided = tuple(c.family for c in (close or ranked))
        second = max((unique[f] for f in unique if f != win.family), default=0.0)
        band = win.band
        fault = " or ".join(undecided) if undecided else win.family
        total = unique[win.family] + second
        confidence = unique[win.family] / total if total > 0 else 0.5
    else:
        fault = "none"
        # A family detected but dominated by another source's series came as close as its
        # share of that series allows.
        closeness = {
            sc.family: min(sc.near_miss, share(sc)) if sc.detected else sc.near_miss
            for sc in best.values()
            if sc is not None
        }
        present = [sc for sc in best.values() if sc is not None]
        nearest = max(present, key=lambda sc: (closeness[sc.family], sc.evidence), default=None)
        band = nearest.band if nearest is not None else bands[0].band
        confidence = 1.0 - (closeness[nearest.family] if nearest is not None else 0.0)
    # The other series shown: in the band of the first family it set aside, else the verdict's.
    shown = by_band[best[dominated[0]].band if dominated else band]
    return _Verdict(
        fault, band, float(confidence), scores, best, dominated, shown, candidates, undecided
    )


def _in_band(other: FamilyScore, band: BandScore) -> FamilyScore:
    """A detected family's comb as scored in ``band``, where it found the same fundamental
    there (within two bins at its top harmonic): its lines' strengths then compare with
    those of the band's other combs (a sideband is no stronger than its carrier); else the
    comb as detected, in its own band."""
    there = band.families.get(other.comb)
    if there is None or there.band == other.band:
        return other
    tol = 2.0 * max(there.resolution_hz, other.resolution_hz) / max(there.z.size, 1)
    return there if abs(there.found_hz - other.found_hz) <= tol else other


def _candidates(
    best: dict[str, FamilyScore | None],
    detected: list[FamilyScore],
    by_band: dict[tuple[float, float], BandScore],
    s: _Setting,
) -> tuple[Candidate, ...]:
    """Every family's :class:`Candidate`, ranked: the detected first, those whose detection
    holds on their own lines before the others, then by the evidence of their own lines."""
    shaft = s.freqs.shaft
    out = []
    for sc in best.values():
        if sc is None:
            continue
        is_detected = any(sc is d for d in detected)
        others = [_in_band(o, by_band[sc.band]) for o in detected if o is not sc]
        explained = {o.family: _explained_by(sc, o, shaft) for o in others}
        decides = False
        if is_detected:
            lines = np.zeros(sc.z.size, dtype=bool)
            sides = np.zeros((2, sc.z.size), dtype=bool)
            for o in others:
                lines |= explained[o.family]
                sides |= _sidebands_explained_by(sc, o, shaft)
            decides = not lines.any() or _holds_without(
                sc, by_band[sc.band], lines, sides, shaft, s.alpha_pair, s.min_modulation,
                s.shaft_tolerance,
            )  # fmt: skip
        tests = s.alpha / s.alpha_pair
        out.append(_candidate(sc, is_detected, explained, decides, tests))
    out.sort(key=lambda c: (c.detected, c.decides, c.unique_evidence, c.evidence), reverse=True)
    return tuple(out)
