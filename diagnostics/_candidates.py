"""The candidate faults of a diagnosis and whether the evidence decides between them:
:class:`Candidate`, one fault family with its evidence, and which of a comb's lines another
detected family's lines explain.

Kinematics makes some lines common to two families (on the CWRU fan-end bearing BPFI - fr
lies 1 % below 2 x BSF; BPFO + BPFI is n times the shaft rate), and a fault modulated by the
turning shaft puts sidebands on its lines that can fall on another family's comb. A family
is named only where its detection holds on lines that no other detected family explains
and no other detected family's does; otherwise the verdict says between which families the
evidence does not decide (:func:`diagnostics.diagnose`, ``Diagnosis.undecided``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from diagnostics._comb import FamilyScore

__all__ = ["Candidate"]

# A line is stronger than a carrier where its depth exceeds the carrier's by this many
# standard errors of their difference (about 2 % of equal lines would be told apart by
# chance, one-sided).
_CARRIER_SIGMAS = 2.0
# The race combs (the others: the rolling elements' 2 x BSF and the cage rate FTF).
_RACE_COMBS = ("BPFO", "BPFI")


@dataclass(frozen=True)
class Candidate:
    """One fault family's evidence in a diagnosis (``Diagnosis.candidates``).

    Attributes
    ----------
    family : str
        ``"outer"``, ``"inner"`` or ``"ball"``.
    comb : str
        The comb that carries it (``"BPFO"``, ``"BPFI"``, ``"2xBSF"`` or ``"FTF"``).
    band : tuple of float
        Demodulation band of that comb's best score.
    p_value : float
        Family-wise p-value of its best pair of lines (two harmonics, or for the rolling
        elements a harmonic and its cage-rate sideband): the pair's joint p-value times the
        number of tests the diagnosis made, at most 1; the family is detected where this is
        at most ``Diagnosis.alpha`` (and its lines modulate the envelope enough).
    evidence : float
        Sum of the normalised values of its supporting harmonics (p-value 0.01 or less).
    unique_evidence : float
        The same over the supporting harmonics that no other detected family explains.
    harmonics : tuple of int
        The supporting harmonics (1 for the fundamental).
    sidebands : tuple of int
        The harmonics with a significant sideband at the comb's modulation rate (shaft rate
        for the inner race, cage rate for the rolling elements).
    detected : bool
        Detected, and not set aside for another source's series.
    decides : bool
        Its detection holds on the lines no other detected family explains (a harmonic,
        its shaft-rate sidebands or their multiples); True for a family detected alone.
    explained_by : tuple of str
        The other detected families that explain some of its supporting lines.
    """

    family: str
    comb: str
    band: tuple[float, float]
    p_value: float
    evidence: float
    unique_evidence: float
    harmonics: tuple[int, ...]
    sidebands: tuple[int, ...]
    detected: bool
    decides: bool
    explained_by: tuple[str, ...] = ()


def _explained_by(score: FamilyScore, other: FamilyScore, shaft_hz: float) -> np.ndarray:
    """Which lines of ``score`` the comb ``other`` explains (one boolean per harmonic).

    A race or spin comb explains its harmonics up to three times those it tested and their
    first two shaft-rate sidebands (k f0 +- j fr, j <= 2: a fault modulated by the turning
    shaft); the cage-rate series only its own lines (n FTF is BPFO itself). A race comb
    explains the whole cage-rate series: rolling elements that differ a little strike a race
    defect each in its own way, and the same element comes back to the same place once per
    cage turn (for the outer race exactly, BPFO being n FTF; for the inner race with the load
    zone, at FTF and its combinations with the shaft rate), so a race fault's impacts repeat
    at the cage rate. (The cage-rate series is the ball family's second test, for damaged
    balls whose 2 x BSF lines smear; beside a race fault it tells nothing.) A sideband is no
    stronger than its carrier (amplitude modulation by a window nowhere negative), so in the
    same band a line whose modulation depth exceeds that of the other comb's tested harmonic
    (by ``_CARRIER_SIGMAS`` standard errors of the difference) is not that harmonic's
    sideband. The depth is the amplitude over the band's mean squared
    envelope: two lines of one spectrum compare by it, whatever the background under each
    (their normalised values ``z`` divide by different local backgrounds).
    """
    if score.comb == "FTF" and other.comb in _RACE_COMBS:
        return np.ones(score.z.size, dtype=bool)
    reach, offsets, lines = _comb_lines(other, shaft_hz)
    tol = 2.0 * max(score.resolution_hz, other.resolution_hz)
    near = np.abs(score.lines_hz[:, None] - lines[None, :]) <= tol
    if other.band == score.band:
        mine, mine_err = _strength(score)
        theirs, theirs_err = _strength(other)
        # (Harmonics beyond those tested have no measured strength: no limit.)
        strength = np.full(reach, np.inf)
        strength[: theirs.size] = theirs
        error = np.zeros(reach)
        error[: theirs.size] = theirs_err
        carrier = np.repeat(strength, offsets.size)
        carrier_err = np.repeat(error, offsets.size)
        side = np.tile(offsets != 0.0, reach)
        margin = _CARRIER_SIGMAS * np.hypot(mine_err[:, None], carrier_err[None, :])
        near &= ~(side & (mine[:, None] > carrier[None, :] + margin))
    return near.any(axis=1)


def _comb_lines(other: FamilyScore, shaft_hz: float) -> tuple[int, np.ndarray, np.ndarray]:
    """The lines a detected comb explains: its harmonics up to ``reach`` (three times
    those it tested for a race or spin comb, those tested for the cage-rate series), each
    with the ``offsets`` about it (the first two shaft-rate sidebands; none for the cage
    rate), flattened harmonic by harmonic."""
    cage = other.comb == "FTF"
    reach = other.z.size if cage else 3 * other.z.size
    offsets = np.zeros(1) if cage else shaft_hz * np.arange(-2, 3)
    harmonics = other.found_hz * np.arange(1, reach + 1)
    return reach, offsets, (harmonics[:, None] + offsets[None, :]).ravel()


def unique_evidence(score: FamilyScore, explained: list[np.ndarray]) -> float:
    """Evidence of ``score`` from its supporting lines that none of the ``explained`` masks
    (one per other detected family, :func:`_explained_by`) covers: a shared line is
    evidence for neither."""
    keep = _supporting(score)
    for mask in explained:
        keep = keep & ~mask
    return float(np.asarray(score.z)[keep].sum())


def _strength(score: FamilyScore) -> tuple[np.ndarray, np.ndarray]:
    r"""A comb's line amplitudes for the carrier rule and their standard errors: the
    modulation depth where measured (every comb :func:`diagnostics.diagnose` scores), else
    the normalised value (no error). A line whose power stands ``z`` times over its
    background has an amplitude known to about :math:`1 / \sqrt{z}` of itself (the background's
    amplitude in the bin over the line's)."""
    m = np.asarray(score.modulation, dtype=float)
    z = np.asarray(score.z, dtype=float)
    if m.size != z.size:
        return z, np.zeros(z.size)
    return m, m / np.sqrt(np.maximum(z, 1.0))


def _sidebands_explained_by(score: FamilyScore, other: FamilyScore, shaft_hz: float) -> np.ndarray:
    """Which of ``score``'s sidebands (2 x K, at k f0 -+ its modulation rate) ``other``
    explains: any within two bins of one of its lines or their shaft sidebands (no carrier
    rule: a sideband's depth is not measured)."""
    if score.sideband_z.size == 0:
        return np.zeros((2, score.z.size), dtype=bool)
    _, _, lines = _comb_lines(other, shaft_hz)
    sides = score.lines_hz[None, :] + np.array([-score.sideband_hz, score.sideband_hz])[:, None]
    tol = 2.0 * max(score.resolution_hz, other.resolution_hz)
    return np.min(np.abs(sides[..., None] - lines[None, None, :]), axis=-1) <= tol


def _supporting(score: FamilyScore) -> np.ndarray:
    """The supporting harmonics of a comb (p-value at most 0.01), as a boolean mask."""
    return np.asarray(score.z) > np.asarray(score.threshold)


def _candidate(
    score: FamilyScore,
    detected: bool,
    explained: dict[str, np.ndarray],
    decides: bool,
    tests: float,
) -> Candidate:
    """A family's :class:`Candidate` from its best comb, the lines each other detected
    family explains (``explained``: family -> mask) and whether its detection holds on the
    rest."""
    support = _supporting(score)
    n_sb_side = score.sideband_z.shape[-1] if score.sideband_z.size else 0
    sidebands: tuple[int, ...] = ()
    if n_sb_side:
        strong = (4.0 * np.exp(-np.asarray(score.sideband_z))).min(axis=0) <= 0.01
        sidebands = tuple(int(k) + 1 for k in np.flatnonzero(strong))
    return Candidate(
        family=score.family,
        comb=score.comb,
        band=score.band,
        p_value=float(min(1.0, min(score.pair_p, score.sideband_pair_p) * tests)),
        evidence=float(score.evidence),
        unique_evidence=unique_evidence(score, list(explained.values())),
        harmonics=tuple(int(k) + 1 for k in np.flatnonzero(support)),
        sidebands=sidebands,
        detected=detected,
        decides=decides,
        explained_by=tuple(f for f, mask in explained.items() if (mask & support).any()),
    )
