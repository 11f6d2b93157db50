"""The fault combs: which harmonic series are tested at a shaft rate, the normalised squared
envelope spectrum they are tested in, and each comb's score in one band.

Holds the scores a diagnosis is made of (:class:`FamilyScore`, one comb in one band;
:class:`BandScore`, one candidate band) and the setting every band is scored under.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from diagnostics._checks import check_signal, normalise
from diagnostics._envelope import envelope
from diagnostics._evidence import (
    _SUPPORT_P,
    _closeness,
    _detects,
    _off_shaft,
    _pair_evidence,
    _pair_tail,
    _sideband_closeness,
    _sideband_p,
    _sideband_pairs,
)
from diagnostics._frequencies import BearingGeometry, FaultFrequencies, bearing_frequencies

__all__ = ["FamilyScore", "BandScore", "normalised_envelope_spectrum", "series_strength"]

# Background window half-width, as a fraction of the lowest comb fundamental.
_BACKGROUND_FRACTION = 0.1
# Bins either side of a shaft harmonic that are masked out of every comb.
_SHAFT_MASK_BINS = 2.5
# Harmonics are sought only up to this fraction of a band's width: the squared envelope of
# a band of width B holds modulation frequencies up to B, with a triangular weight.
_USABLE_FRACTION = 0.8
# Lines between a comb's harmonics mark a slower period where their series is at least
# this share of the comb's (_slower_period).
_SLOWER_SHARE = 0.25
# Slower periods tested per comb (_slower_period). Half of 2 x BSF is the ball spin rate
# itself, where a damaged ball strikes one race harder than the other: ball evidence; a
# quarter of it is tested instead (its odd multiples). The
# cage-rate comb is not tested: lines at half the cage rate show in measured records of
# every fault (CWRU 189, 250, 262), for reasons this analysis does not model.
_SLOWER = {"BPFO": (2, 3), "BPFI": (2, 3), "2xBSF": (3, 4), "FTF": ()}
# A series' strength: the sum of its strongest harmonics, this many of those tested.
_STRENGTH_TOP = 3


@dataclass(frozen=True)
class FamilyScore:
    """Evidence for one fault family in one demodulation band.

    Attributes
    ----------
    family : str
        ``"outer"``, ``"inner"`` or ``"ball"``.
    band : tuple of float
        Demodulation band (f_lo, f_hi) in Hz.
    expected_hz : float
        Kinematic comb fundamental (BPFO, BPFI or 2*BSF).
    found_hz : float
        Fundamental of the best comb within the slip tolerance.
    lines_hz : numpy.ndarray
        Harmonic frequencies k * found_hz, k = 1..K.
    z : numpy.ndarray
        Background-normalised SES value at each harmonic.
    threshold : numpy.ndarray
        Value of ``z`` at which each harmonic's p-value is 0.01 (a supporting line).
    n_significant : int
        Supporting harmonics (p-value at most 0.01).
    evidence : float
        Sum of ``z`` over the supporting harmonics (0 when none); each ``z`` is close to
        minus the log of that line's p-value.
    p_values : numpy.ndarray
        Bonferroni p-value of each harmonic over its slip window.
    modulation : numpy.ndarray
        Modulation depth of the squared envelope at each harmonic (amplitude over mean).
    pair_p : float
        Joint p-value (Fisher's product) of the most significant pair of harmonics that
        marks the comb's own period: not two with a common factor, such as the 2nd and 4th,
        unless a harmonic that would tell the comb from one at that multiple was masked.
    detected : bool
        ``pair_p <= alpha_pair``, both lines supporting, and a supporting line modulating
        the squared envelope by at least ``min_modulation``; or the same of a harmonic and
        its own modulation sideband (``sideband_pair_p``).
    near_miss : float
        In [0, 1]: how close the family came to detection on a log-probability scale
        (1 when detected). A comb set aside as a slower period (``slower_period``) came as
        close as a quarter over the in-between lines' share of its strength allows.
    sideband_hz : float
        Modulation rate whose sidebands were measured (shaft rate for the inner race, cage
        rate for the rolling elements, 0 for the outer race).
    sideband_z : numpy.ndarray
        Normalised SES value at ``k * found_hz - sideband_hz`` and ``+ sideband_hz``
        (2 x K).
    n_sidebands_significant : int
        Sidebands whose p-value (a bin either side of the expected offset) is at most
        ``sqrt(alpha_pair)``.
    sideband_pair_p : float
        Joint p-value (Fisher's product) of a harmonic and the stronger of its two
        sidebands, for the harmonic that came closest to detection with its sideband (both
        supporting, the pair within ``alpha_pair``, the harmonic modulating the squared
        envelope by at least ``min_modulation``); 1.0 for the combs that have no such pair
        (all but 2 x BSF). The cage carries a damaged ball through the load zone: where a
        band is too narrow, or a record too weak, for a second harmonic, a line and its
        cage-rate sideband are the pair.
    resolution_hz : float
        Bin spacing of the squared envelope spectrum.
    comb : str
        The comb tested: ``"BPFO"``, ``"BPFI"``, ``"2xBSF"``, or ``"FTF"`` for the
        rolling-element family's second test, the cage-rate series.
    slower_period : int
        2, 3 or 4 where the lines between the comb's harmonics, at multiples of ``found_hz``
        / 2, / 3 or / 4, are themselves a significant series: the impacts repeat at that
        slower rate, which is no fault frequency of the bearing, and the comb's lines are
        that series' harmonics, so the family is not detected. 0 otherwise (and always for
        the cage-rate comb). The 2 x BSF comb is tested at thirds and at odd quarters (4),
        not halves: half of it is BSF, a ball fault's own rate.
    """

    family: str
    band: tuple[float, float]
    expected_hz: float
    found_hz: float
    lines_hz: np.ndarray = field(repr=False)
    z: np.ndarray
    threshold: np.ndarray = field(repr=False)
    n_significant: int
    evidence: float
    p_values: np.ndarray = field(default_factory=lambda: np.ones(0), repr=False)
    modulation: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    pair_p: float = 1.0
    detected: bool = False
    near_miss: float = 0.0
    sideband_hz: float = 0.0
    sideband_z: np.ndarray = field(default_factory=lambda: np.zeros((2, 0)), repr=False)
    n_sidebands_significant: int = 0
    sideband_pair_p: float = 1.0
    resolution_hz: float = 0.0
    comb: str = ""
    slower_period: int = 0


@dataclass(frozen=True)
class BandScore:
    """One candidate demodulation band and the score of every comb in it.

    ``families`` is keyed by comb: ``"BPFO"`` (outer race), ``"BPFI"`` (inner race),
    ``"2xBSF"`` and ``"FTF"`` (rolling elements); ``FamilyScore.family`` names the family.
    ``other_hz`` and ``other_strength``: fundamental and strength (the sum of its three
    strongest of the tested harmonics' normalised values) of the strongest harmonic series
    in this band at a rate that no fault of the bearing explains (0 where none was sought).
    """

    name: str
    band: tuple[float, float]
    kurtosis: float
    f: np.ndarray = field(repr=False)
    z: np.ndarray = field(repr=False)
    families: dict[str, FamilyScore | None] = field(repr=False)
    other_hz: float = 0.0
    other_strength: float = 0.0


@dataclass(frozen=True)
class _Setting:
    """What every band's scoring needs: the fault frequencies at the rate analysed, the
    combs tested and the detection rule's levels."""

    freqs: FaultFrequencies
    combs: dict[str, tuple[str, float, float]]
    slip: float
    n_harmonics: int
    alpha_pair: float
    min_modulation: float
    f_high: float
    f_max: float
    half_window: float
    shaft_tolerance: float
    alpha: float = 1e-4


def _family_fundamentals(freqs: FaultFrequencies) -> dict[str, tuple[float, float]]:
    """Comb fundamental and sideband spacing of each family."""
    return {
        "outer": (freqs.bpfo, 0.0),
        "inner": (freqs.bpfi, freqs.shaft),
        "ball": (2.0 * freqs.bsf, freqs.ftf),
    }


def _fault_rates(geometry: BearingGeometry, shaft_hz: float, slip: float):
    """``(freqs, fundamentals, f_low, f_high)`` at a shaft rate: the fault frequencies, the
    comb fundamentals per family, the slowest fundamental and the fastest one plus the slip."""
    freqs = bearing_frequencies(geometry, shaft_hz)
    fundamentals = _family_fundamentals(freqs)
    f_low = min(f0 for f0, _ in fundamentals.values())
    f_high = max(f0 for f0, _ in fundamentals.values()) * (1.0 + slip)
    return freqs, fundamentals, f_low, f_high


def _combs(
    freqs: FaultFrequencies, fundamentals: dict[str, tuple[float, float]], duration_s: float
) -> dict[str, tuple[str, float, float]]:
    """Harmonic series tested: name -> (family, fundamental, sideband spacing).

    One per family, and for the rolling elements a second one: the cage rate (FTF). A
    damaged ball goes round with the cage and strikes only while it is in the load zone, so
    its impacts come in bursts once per cage turn; where the strikes themselves are too
    irregular to form lines at 2 x BSF (the ball's spin axis wanders), the squared envelope
    still shows the cage-rate series (Randall and Antoni 2011). It is tested where the
    record holds 20 cage periods.
    """
    combs = {
        "BPFO": ("outer", *fundamentals["outer"]),
        "BPFI": ("inner", *fundamentals["inner"]),
        "2xBSF": ("ball", *fundamentals["ball"]),
    }
    if duration_s * freqs.ftf >= 20.0:
        combs["FTF"] = ("ball", freqs.ftf, 0.0)
    return combs


def normalised_envelope_spectrum(
    y, fs: float, band: tuple[float, float] | None, f_max: float, half_window_hz: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Squared envelope spectrum up to ``f_max``, normalised two ways.

    ``z`` is the power of each bin over the local background: the running median over
    +-``half_window_hz`` divided by ln 2 (the median of a unit-mean exponential variable),
    so random bins read about 1. ``m`` is the amplitude of each bin over the mean squared
    envelope: a squared envelope :math:`\mu (1 + m \cos 2 \pi f t)` reads :math:`m` at
    :math:`f` (the
    modulation depth, independent of the record length).

    Returns
    -------
    f, z, m : numpy.ndarray
        Frequencies (Hz), normalised power and modulation depth.

    References
    ----------
    Randall, R. B. and Antoni, J. (2011). Rolling element bearing diagnostics: a tutorial.
    *Mechanical Systems and Signal Processing* 25(2), 485-520.
    """
    y, _ = normalise(check_signal(y, fs))  # z and m have no unit
    sq = envelope(y, fs, band=band) ** 2
    mean_sq = float(sq.mean())
    spectrum = np.fft.rfft(sq - mean_sq)
    f = np.fft.rfftfreq(sq.size, d=1.0 / fs)
    n = int(min(np.searchsorted(f, f_max) + 1, f.size))
    f = f[:n]
    # One-sided amplitude: a component A cos(2 pi f t) reads A at its bin.
    amp = 2.0 * np.abs(spectrum[:n]) / sq.size
    power = amp**2
    df = f[1] - f[0]
    half = max(int(round(half_window_hz / df)), 10)
    background = ndimage.median_filter(power, size=2 * half + 1, mode="nearest") / math.log(2.0)
    tiny = np.finfo(float).tiny
    z = power / np.maximum(background, tiny)
    z[0] = 0.0
    m = amp / max(mean_sq, tiny)
    m[0] = 0.0
    return f, z, m


def _line_values(z: np.ndarray, df: float, freqs: np.ndarray) -> np.ndarray:
    # A line falls between two bins; take the larger (rectangular-window scalloping).
    pos = freqs / df
    lo = np.clip(np.floor(pos).astype(int), 0, z.size - 1)
    hi = np.clip(lo + 1, 0, z.size - 1)
    return np.maximum(z[lo], z[hi])


def _shaft_mask(f: np.ndarray, shaft_hz: float) -> np.ndarray:
    df = f[1] - f[0]
    nearest = np.round(f / shaft_hz) * shaft_hz
    mask = np.abs(f - nearest) <= _SHAFT_MASK_BINS * df
    mask |= f < 0.5 * shaft_hz
    return mask


def series_strength(z: np.ndarray):
    """Strength of a harmonic series: the sum of its strongest normalised harmonic values
    (three, or as many as were tested), along the last axis (one per row of a 2-D ``z``)."""
    return np.sort(np.asarray(z, dtype=float), axis=-1)[..., -_STRENGTH_TOP:].sum(axis=-1)


def _slower_period(
    z_masked: np.ndarray,
    m: np.ndarray,
    df: float,
    fc: float,
    z_comb: np.ndarray,
    n_harm: int,
    alpha_pair: float,
    min_modulation: float,
    periods: tuple[int, ...] = (2, 3),
) -> tuple[int, float]:
    """``(q, share)``: the :math:`q` of ``periods`` (2, 3 or 4) where the lines at
    :math:`j f_c / q` (:math:`j` not a multiple of :math:`q`, odd for :math:`q = 4`, below
    the comb's top harmonic) hold a significant pair, as a comb's pair is judged, and a
    series at least a quarter as strong as the comb's own (``z_comb``), and that strength
    over the comb's; else ``(0, 0.0)``.

    Their places are fixed by the comb, so each line's p-value is over a window of four bins
    (the line between two bins, and a bin of spread either side). A train of impacts at
    :math:`f_c / q` gives lines there nearly as strong as on the comb (0.32 or more of its
    strength, synthetic trains at half or a third of a fault frequency, 12 and 48 kHz); a
    fault at ``fc`` only weak ones (0.12 at most on the 25 development records named by a
    race or spin comb, 262; 0.02-0.05 in 135, whose lines at odd multiples of BPFO / 2
    form a significant pair)."""
    for q in periods:
        # At q = 4 only the odd multiples: the others are those of q = 2 (for 2 x BSF, BSF).
        j = np.array([i for i in range(1, q * n_harm) if i % (2 if q == 4 else q)])
        freqs = j * fc / q
        z = _line_values(z_masked, df, freqs)
        p_line = np.minimum(1.0, 4.0 * np.exp(-z))
        p = np.sort(p_line)
        if p.size < 2 or _pair_tail(p[0] * p[1]) > alpha_pair or p[1] > _SUPPORT_P:
            continue
        ratio = series_strength(z) / series_strength(z_comb)
        if ratio < _SLOWER_SHARE:
            continue
        lo = np.clip(np.floor(freqs / df).astype(int), 0, m.size - 2)
        depth = np.hypot(m[lo], m[lo + 1])
        if depth[p_line <= _SUPPORT_P].max() >= min_modulation:
            return q, ratio
    return 0, 0.0


def _score_family(
    family: str,
    f: np.ndarray,
    z_masked: np.ndarray,
    masked: np.ndarray,
    m: np.ndarray,
    f0: float,
    n_harm: int,
    slip: float,
    alpha_pair: float,
    min_modulation: float,
    band: tuple[float, float],
    sideband_hz: float,
    slower: tuple[int, ...] = (2, 3),
    shaft_hz: float = 0.0,
    shaft_tolerance: float = 0.0,
) -> FamilyScore:
    df = f[1] - f[0]
    k = np.arange(1, n_harm + 1)
    # Comb fundamentals fine enough that the top harmonic moves by half a bin per step.
    step = df / (2.0 * n_harm)
    cands = np.arange(f0 * (1.0 - slip), f0 * (1.0 + slip) + step, step)
    values = _line_values(z_masked, df, np.outer(cands, k))
    # log1p: the comb is placed by the whole series, not dragged by one strong line.
    best = int(np.argmax(np.log1p(values).sum(axis=1)))
    fc = float(cands[best])
    zk = values[best]
    # p-value of each harmonic: the largest of the W exponential bins of its slip window
    # exceeds z with probability at most W exp(-z).
    windows = 2.0 * slip * k * f0 / df + 2.0
    p = np.minimum(1.0, windows * np.exp(-zk))
    pos = k * fc / df
    lo = np.clip(np.floor(pos).astype(int), 0, m.size - 2)
    observed = ~(masked[lo] & masked[lo + 1])
    support = p <= _SUPPORT_P
    # Depth from the power of the two bins around each line: within 1 dB of the true
    # amplitude wherever the line falls (the larger bin alone can lose 4 dB).
    depth = np.hypot(m[lo], m[lo + 1])
    pair_p, p2, strongest = _pair_evidence(p, observed, depth)
    detected = _detects(pair_p, p2, strongest, alpha_pair, min_modulation)
    closeness = _closeness(pair_p, p2, strongest, alpha_pair, min_modulation)
    sb, n_sb, sb_pair_p = np.zeros((2, 0)), 0, 1.0
    if sideband_hz > 0.0:
        # Sidebands sit at a fixed offset from the found line; allow a bin either side.
        offsets = np.array([-sideband_hz, sideband_hz])
        sb_freqs = k[None, :] * fc + offsets[:, None]
        sb = np.stack(
            [
                np.max([_line_values(z_masked, df, sb_freqs[i] + d) for d in (-df, 0.0, df)], 0)
                for i in range(2)
            ]
        )
        n_sb = int((4.0 * np.exp(-sb) <= math.sqrt(alpha_pair)).sum())
        if _sideband_pairs(family, sideband_hz, df):
            single = observed & _off_shaft(k * fc, shaft_hz, shaft_tolerance)
            sb_close, sb_pair_p = _sideband_closeness(
                np.where(single, p, 1.0), _sideband_p(sb, zk), depth, alpha_pair, min_modulation
            )
            detected = detected or sb_close >= 1.0
            closeness = max(closeness, sb_close)
    # Only a detected comb can turn out to be a slower train's: it is then no near miss of
    # this fault in proportion as the in-between lines are strong.
    period, ratio = (0, 0.0)
    if detected:
        period, ratio = _slower_period(
            z_masked, m, df, fc, zk, n_harm, alpha_pair, min_modulation, slower
        )
    if period:
        detected = False
        closeness = min(closeness, _SLOWER_SHARE / ratio)
    return FamilyScore(
        family=family,
        band=band,
        expected_hz=f0,
        found_hz=fc,
        lines_hz=k * fc,
        z=zk,
        threshold=np.log(windows / _SUPPORT_P),
        n_significant=int(support.sum()),
        evidence=float(zk[support].sum()),
        p_values=p,
        modulation=depth,
        pair_p=float(pair_p),
        detected=detected,
        near_miss=1.0 if detected else float(min(max(closeness, 0.0), 1.0)),
        sideband_hz=sideband_hz,
        sideband_z=sb,
        n_sidebands_significant=n_sb,
        sideband_pair_p=sb_pair_p,
        resolution_hz=df,
        slower_period=period,
    )
