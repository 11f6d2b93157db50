"""Another source's harmonic series: the strongest in a band at a rate no fault of the
bearing explains, and whether a family's detection holds on the lines it does not explain.
"""

from __future__ import annotations

import math

import numpy as np

from diagnostics._comb import (
    _USABLE_FRACTION,
    BandScore,
    FamilyScore,
    _line_values,
    _shaft_mask,
    series_strength,
)
from diagnostics._evidence import (
    _detects,
    _off_shaft,
    _pair_evidence,
    _sideband_closeness,
    _sideband_p,
    _sideband_pairs,
)
from diagnostics._frequencies import FaultFrequencies

# A line counts as another series' harmonic or sidebands within two bins and this share of
# its frequency (measured lines stand up to 0.07 % off the places a fitted fundamental
# predicts: the speed drifts over the record).
_LINE_SPREAD = 1e-3


def _other_series_scan(
    f: np.ndarray,
    z_masked: np.ndarray,
    freqs: FaultFrequencies,
    slip: float,
    n_harmonics: int,
    f_high: float,
    width: float,
    combs: list[FamilyScore],
) -> tuple[float, float]:
    """Strongest harmonic series at a rate that no fault of the bearing explains.

    Fundamentals from 0.9 times a third of the slowest fault frequency (BPFO, BPFI or 2 BSF)
    to 1.3 times the fastest are scored like a fault comb (:func:`series_strength` of
    ``n_harmonics`` harmonics, those up to 0.8 of a narrow band's width, at least two) on
    the spectrum less the lines of the fault combs detected in the band (``combs``; one set
    aside as a slower period keeps them, they are that train's), except those within twice
    the slip tolerance of a fault frequency, its double or triple, the ball spin rate (BSF),
    or the cage rate (FTF) times 1, 2 or 3. Without the combs' lines, a series at half or a
    third of a fault frequency is scored by the lines between the fault's harmonics alone:
    strong where impacts repeat at that slower rate (no fault of this bearing), empty for
    the fault itself. (A series at a fault frequency plus or minus the shaft rate is not
    excluded: on the development records the sidebands of an inner-race fault form such a
    series at no more than half the fault's own strength.)

    Returns
    -------
    (fundamental, strength) : tuple of float
        (0.0, 0.0) where the band or the spectrum is too narrow for two harmonics.
    """
    df = f[1] - f[0]
    slowest = min(freqs.bpfo, freqs.bpfi, 2.0 * freqs.bsf)
    # Harmonics up to the usable part of the band (as for the fault combs), at least two.
    top = min(_USABLE_FRACTION * width, f[-1])
    lo, hi = 0.3 * slowest, min(1.3 * f_high, top / 2.0)
    if hi <= lo:
        return 0.0, 0.0
    # The fault combs' own lines (two bins either side) are no other source's.
    z_other = z_masked.copy()
    for score in combs:
        centre = np.round(score.lines_hz / df).astype(int)
        for d in range(-2, 3):
            z_other[np.clip(centre + d, 0, z_other.size - 1)] = 0.0
    n = n_harmonics
    grid = np.exp(np.arange(math.log(lo), math.log(hi), df / (2.0 * n * hi)))
    lines = np.outer(grid, np.arange(1, n + 1))
    values = np.where(lines <= top, _line_values(z_other, df, lines), 0.0)
    strength = series_strength(values)
    # A series at a fault frequency's double or triple is made of its harmonics; the
    # cage rate's first multiples likewise; the ball spin rate is a ball fault's own.
    own = [freqs.ftf * m for m in (1, 2, 3)] + [freqs.bsf]
    own += [f0 * m for f0 in (freqs.bpfo, freqs.bpfi, 2.0 * freqs.bsf) for m in (1, 2, 3)]
    explained = np.zeros(grid.size, dtype=bool)
    for c in own:
        explained |= np.abs(grid - c) <= 2.0 * slip * c
    if explained.all():
        return 0.0, 0.0
    i = int(np.argmax(np.where(explained, -np.inf, strength)))
    return float(grid[i]), float(strength[i])


def _holds_apart(
    s: FamilyScore,
    b: BandScore,
    shaft_hz: float,
    alpha_pair: float,
    min_modulation: float,
    shaft_tolerance: float = 0.0,
) -> bool:
    """Whether a family's detection holds on the lines that the band's other series (its
    harmonics and their first two shaft-rate sidebands) does not explain."""
    g = b.other_hz
    if g <= 0.0:
        return True
    df = s.resolution_hz
    k = np.arange(1, int(b.f[-1] // g) + 2)
    lattice = (k[:, None] * g + shaft_hz * np.arange(-2, 3)[None, :]).ravel()
    distance = np.min(np.abs(s.lines_hz[:, None] - lattice[None, :]), axis=1)
    explained = distance <= 2.0 * df + _LINE_SPREAD * s.lines_hz
    sides = s.lines_hz[None, :] + np.array([-s.sideband_hz, s.sideband_hz])[:, None]
    off = np.min(np.abs(sides[..., None] - lattice[None, None, :]), axis=-1)
    sb_explained = off <= 2.0 * df + _LINE_SPREAD * sides
    return _holds_without(
        s, b, explained, sb_explained, shaft_hz, alpha_pair, min_modulation, shaft_tolerance
    )


def _holds_without(
    s: FamilyScore,
    b: BandScore,
    explained: np.ndarray,
    sb_explained: np.ndarray,
    shaft_hz: float,
    alpha_pair: float,
    min_modulation: float,
    shaft_tolerance: float = 0.0,
) -> bool:
    """Whether a family's detection holds with the lines in ``explained`` (one boolean per
    harmonic) and the sidebands in ``sb_explained`` (2 x K) counted as absent: its pair of
    harmonics, or for the rolling elements a harmonic and its cage-rate sideband, judged
    by :func:`diagnostics._evidence._detects` on the rest."""
    df = s.resolution_hz
    p = np.where(explained, 1.0, s.p_values)
    lo = np.clip(np.floor(s.lines_hz / df).astype(int), 0, b.f.size - 2)
    masked = _shaft_mask(b.f, shaft_hz)
    observed = ~(masked[lo] & masked[lo + 1])
    evidence = _pair_evidence(p, observed, s.modulation)
    if _detects(*evidence, alpha_pair, min_modulation):
        return True
    if not _sideband_pairs(s.family, s.sideband_hz, df):
        return False
    p_sb = _sideband_p(s.sideband_z, s.z, sb_explained)
    p = np.where(observed & _off_shaft(s.lines_hz, shaft_hz, shaft_tolerance), p, 1.0)
    return _sideband_closeness(p, p_sb, s.modulation, alpha_pair, min_modulation)[0] >= 1.0
