"""The statistics of the comb tests: p-values of harmonic pairs and of a harmonic with its
sideband, the detection rule, and how close a comb came to it.

Pure functions of p-values, modulation depths and line frequencies (numpy arrays and
floats), shared by the comb scores (:mod:`diagnostics._comb`) and the test against another
source's series (:mod:`diagnostics._other_source`).
"""

from __future__ import annotations

import math

import numpy as np

# A harmonic supports a detection when its own p-value is at most this.
_SUPPORT_P = 0.01
# A harmonic and its sideband make a detecting pair where the sideband stands at least this
# many bins from the line (its four bins then clear the line's two).
_SIDEBAND_MIN_BINS = 3.0
_SIDEBAND_PAIR_FAMILIES = ("ball",)


def _pair_tail(c: float) -> float:
    """P(p1 * p2 <= c) for two independent uniform p-values (Fisher's product, two terms)."""
    return c * (1.0 - math.log(c)) if c > 0.0 else 0.0


def _best_pair(p: np.ndarray, observed: np.ndarray) -> tuple[float, float]:
    """The two p-values of the most significant pair of harmonics that can mark this
    comb's period, the smaller first ((1.0, 1.0) if there is none).

    Harmonics i and j with a common factor g > 1 (2 and 4) are also harmonics i/g and j/g
    of a series at g times the fundamental: with the comb's other lines absent they are
    evidence of that faster series, which is no fault frequency of this bearing. Such a
    pair counts only where a harmonic that would tell the two apart (one not a multiple of
    g, below the pair's upper line) could not be observed (masked as a shaft harmonic).
    """
    best = (1.0, 1.0)
    for i in range(p.size):
        for j in range(i + 1, p.size):
            g = math.gcd(i + 1, j + 1)
            if g > 1 and all(observed[h] for h in range(j) if (h + 1) % g):
                continue
            pair = (min(p[i], p[j]), max(p[i], p[j]))
            if pair[0] * pair[1] < best[0] * best[1]:
                best = pair
    return best


def _pair_evidence(
    p: np.ndarray, observed: np.ndarray, depth: np.ndarray
) -> tuple[float, float, float]:
    """``(pair_p, p2, strongest)`` of a comb's harmonics: the joint p-value of its best pair
    (:func:`_best_pair`), the weaker p-value of that pair, and the deepest modulation among
    the supporting harmonics (0 where none supports)."""
    p1, p2 = _best_pair(p, observed)
    support = p <= _SUPPORT_P
    strongest = float(depth[support].max()) if support.any() else 0.0
    return _pair_tail(p1 * p2), p2, strongest


def _detects(
    pair_p: float, p2: float, strongest: float, alpha_pair: float, min_modulation: float
) -> bool:
    """The detection rule: a jointly significant pair, both lines supporting, and a
    supporting line deep enough."""
    return bool(pair_p <= alpha_pair and p2 <= _SUPPORT_P and strongest >= min_modulation)


def _closeness(
    joint_p: float, weaker_p: float, depth: float, alpha_pair: float, min_modulation: float
) -> float:
    """How close a pair came to :func:`_detects`'s rule on a log-probability scale (1 or
    more: detected): the weakest of the joint p-value against ``alpha_pair``, the weaker
    line's p-value against the support level and the modulation depth against
    ``min_modulation``."""
    return min(
        math.log(max(joint_p, 1e-300)) / math.log(alpha_pair),
        math.log(max(weaker_p, 1e-300)) / math.log(_SUPPORT_P),
        depth / min_modulation,
    )


def _sideband_pairs(family: str, sideband_hz: float, df: float = 0.0) -> bool:
    """Whether a comb's harmonic and its sideband are a detecting pair: for the rolling
    elements' 2 x BSF comb, whose impacts the cage modulates, where the sideband stands
    ``_SIDEBAND_MIN_BINS`` bins of ``df`` Hz or more from its line. (An inner race's
    shaft-rate sidebands are not: any source turning with the shaft has them; with them,
    the fan-end channel of CWRU 262, a healthy bearing, read inner from lines at shaft
    spacing.)"""
    return (
        family in _SIDEBAND_PAIR_FAMILIES
        and sideband_hz > 0.0
        and sideband_hz >= _SIDEBAND_MIN_BINS * df
    )


def _off_shaft(lines_hz: np.ndarray, shaft_hz: float, tolerance: float) -> np.ndarray:
    """Lines farther than ``tolerance`` (a share of their frequency) from every shaft
    harmonic. A harmonic paired with its sideband is one line of the comb: where the speed
    is not confirmed by the record's own shaft lines, the shaft harmonic masked may be off
    by the slip tolerance, and a shaft harmonic next to the line could be that line (on the
    CWRU fan-end bearing 2 x BSF is 3.99 times the shaft rate)."""
    if tolerance <= 0.0 or shaft_hz <= 0.0:
        return np.ones(lines_hz.shape, dtype=bool)
    nearest = np.maximum(np.round(lines_hz / shaft_hz), 1.0) * shaft_hz
    return np.abs(lines_hz - nearest) > tolerance * lines_hz


def _sideband_p(
    sideband_z: np.ndarray, line_z: np.ndarray, explained: np.ndarray | None = None
) -> np.ndarray:
    """p-value of the stronger sideband of each harmonic: each side the largest of four
    bins (its line between two, and a bin either side), the better side of two, so at most
    :math:`8 e^{-z}`. A side stronger than its harmonic (``line_z``) is no sideband of it:
    amplitude modulation by a window that is nowhere negative (the load zone passing with
    the cage) leaves each sideband at most as strong as the line. A side in ``explained``
    (2 x K) counts as absent too."""
    absent = sideband_z > line_z[None, :]
    if explained is not None:
        absent |= explained
    p_side = np.where(absent, 1.0, np.minimum(1.0, 4.0 * np.exp(-sideband_z)))
    return np.minimum(1.0, 2.0 * p_side.min(axis=0, initial=1.0))


def _sideband_closeness(
    p: np.ndarray, p_sb: np.ndarray, depth: np.ndarray, alpha_pair: float, min_modulation: float
) -> tuple[float, float]:
    """``(closeness, joint_p)`` of a comb's best harmonic-and-sideband pair (:func:`_closeness`,
    the harmonic's modulation depth as the pair's), 0.0 and 1.0 where none."""
    if p.size == 0 or p_sb.size != p.size:
        return 0.0, 1.0
    joint = [_pair_tail(a * b) for a, b in zip(p, p_sb, strict=True)]
    close = [
        _closeness(j, max(a, b), d, alpha_pair, min_modulation)
        for j, a, b, d in zip(joint, p, p_sb, depth, strict=True)
    ]
    i = int(np.argmax(close))
    return float(close[i]), float(joint[i])
