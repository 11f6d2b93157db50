"""The verdict from every candidate band's scores: each family's best comb, the families
another source's series sets aside, and among those detected the one whose own lines carry
the most evidence."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from diagnostics._comb import BandScore, FamilyScore, _Setting, series_strength
from diagnostics._other_source import _holds_apart

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
    sidebands.
    """
    keep = score.z > score.threshold
    for other in others:
        # A race or spin comb explains its harmonics beyond those tested (3 BPFO is 2 BPFI)
        # and their shaft sidebands; the cage-rate series only its own lines (n FTF is BPFO
        # itself, and 4 FTF + 2 fr is BPFO again for 9 balls at d/D = 0.2).
        cage = other.comb == "FTF"
        reach = other.z.size if cage else 3 * other.z.size
        offsets = np.zeros(1) if cage else shaft_hz * np.arange(-2, 3)
        harmonics = other.found_hz * np.arange(1, reach + 1)
        lines = (harmonics[:, None] + offsets[None, :]).ravel()
        tol = 2.0 * max(score.resolution_hz, other.resolution_hz)
        near = np.abs(score.lines_hz[:, None] - lines[None, :]) <= tol
        if other.band == score.band:
            # A sideband of a tested harmonic in the same band is no stronger than that
            # harmonic (amplitude modulation by a window nowhere negative): a line stronger
            # than the carrier is not its sideband.
            # (Harmonics beyond those tested have no measured strength: no limit.)
            strength = np.full(reach, np.inf)
            strength[: other.z.size] = other.z
            carrier = np.repeat(strength, offsets.size)
            side = np.tile(offsets != 0.0, reach)
            near &= ~(side & (score.z[:, None] > carrier[None, :]))
        keep &= ~near.any(axis=1)
    return float(score.z[keep].sum())


@dataclass(frozen=True)
class _Verdict:
    """The verdict and what :class:`Diagnosis` reports beside it (``shown``: the band whose
    other series is reported)."""

    fault: str
    band: tuple[float, float]
    confidence: float
    scores: dict[str, float]
    best: dict[str, FamilyScore | None]
    dominated: tuple[str, ...]
    shown: BandScore


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
    unique = {
        sc.family: _unique_evidence(sc, [o for o in detected if o is not sc], s.freqs.shaft)
        for sc in detected
    }
    scores = {fam: (best[fam].evidence if best[fam] is not None else 0.0) for fam in FAMILIES}
    if detected:
        # The verdict goes to the family whose own (unshared) lines carry most evidence.
        ranked = sorted(detected, key=lambda sc: (unique[sc.family], sc.evidence), reverse=True)
        win = ranked[0]
        second = unique[ranked[1].family] if len(ranked) > 1 else 0.0
        fault, band = win.family, win.band
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
    return _Verdict(fault, band, float(confidence), scores, best, dominated, shown)
