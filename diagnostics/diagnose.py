"""Automatic bearing fault diagnosis from one vibration record.

Method (Randall and Antoni 2011; Smith and Randall 2015, the CWRU benchmark):

1. Cepstral prewhitening (CPW): the spectrum is divided by its own modulus, which flattens
   it and removes the discrete components (shaft harmonics, gear and electrical tones) that
   otherwise dominate the envelope, while the impulsive bearing content keeps its timing.
2. Candidate demodulation bands: the whole prewhitened band, and the best band of the
   infogram of the squared envelope spectrum (Antoni 2016; on the fast kurtogram's filter
   tree, over the cyclic frequencies the race and spin combs cover, shaft harmonics left
   out) among the bands wide enough to hold two harmonics of the fault frequencies and
   lying above the range the combs cover (below it, beats between deterministic
   low-frequency lines are no impacts), and the infogram's best band apart from that one
   (where another source's lines take the first, a fault ringing another resonance holds
   the next). The evidence of the stronger band is kept. The
   kurtogram's best band (the most impulsive, ``band_selector="kurtogram"``) is what Smith
   and Randall used; a few strong impacts at random times win it, and their band holds no
   fault lines: beside such impacts up to 20 times a fault's
   (``benchmarks/aperiodic_impulse_scenarios.py``) it named 2 faults of 30 and the
   infogram's bands 21, no healthy record called faulty either way. With ``use_drs`` a
   further one: the kurtogram's band of the random part left by discrete/random separation
   (Smith and Randall's third method); off by default (it was added as an option when it
   made the ball-fault record CWRU 118 read as outer; the infogram's band now finds that
   record's BPFO series too, 3.5-4 kHz, which the healthy baseline 97 does not show).
3. Squared envelope spectrum (SES) of each band, normalised by its local background: the
   running median over a window of a fraction of the fault frequencies, divided by ln 2. For
   a random (fault-free) signal each SES bin is then close to an exponential variable of unit
   mean, so a normalised value ``z`` has the tail probability ``exp(-z)``.
4. Each fault family is a harmonic comb with one common fundamental searched within
   +-``slip`` of its kinematic value (rollers slip by 1-2 %, and a logged speed is not exact):
   outer race k*BPFO, inner race k*BPFI, rolling element k*2*BSF, and for the rolling
   element also the cage-rate series k*FTF: a damaged ball goes round with the cage and
   strikes only in the load zone, and where its strikes are too irregular to form lines at
   2 BSF (its spin axis wanders) the bursts still repeat once per cage turn. Shaft harmonics
   are masked out, since they are present in every record.
5. Statistics. The p-value of a harmonic is at most ``W exp(-z)``, W being the number of
   bins its slip window spans (Bonferroni bound on the largest of W exponential bins). A
   family is detected when two of its harmonics are jointly significant: the most
   significant pair's p-values have a product c with ``c (1 - ln c)`` (the chance of so small
   a product from two independent uniform p-values, Fisher's method) at most ``alpha_pair``,
   and the weaker of the two is itself below 0.01. A single line near a fault frequency is no
   evidence of a fault (a healthy bearing's varying compliance, or any other periodic source,
   can give one); a series of harmonics is the mark of repetitive impacts. The pair must mark
   the comb's own period: harmonics 2 and 4 (any two with a common factor g) are also the 1st
   and 2nd of a series at g times the fault frequency, no fault of this bearing, so such a
   pair counts only where a harmonic below it that g does not divide was masked (a shaft
   harmonic) and could not tell the two series apart. Conversely, impacts at half or a
   third of a fault frequency put a line on every harmonic of its comb, and lines between
   them: where those in-between lines (multiples of the found fundamental over 2 or 3) hold
   a significant pair of their own and a series at least a quarter as strong as the
   comb's, the period is the slower one, no fault of this bearing, and the race or spin
   family is not detected (``FamilyScore.slower_period``; a real outer-race fault, CWRU
   135, shows such lines at 0.02-0.05 of its BPFO series). For 2 BSF thirds and odd
   quarters are tested, not halves (its half is BSF, where a damaged ball strikes one race
   harder than the other), and the cage-rate comb not at all (lines at half the cage rate
   show in measured records of all three faults, CWRU 189, 250, 262). The rolling
   elements' 2 x BSF comb has a second kind of pair: a harmonic and the stronger of its two
   cage-rate sidebands (``FamilyScore.sideband_pair_p``), judged by the same rule with the
   sideband's p-value at most ``8 exp(-z)`` (four bins a side, the better side). The cage
   carries a damaged ball in and out of the load zone, so its impacts come with cage-rate
   sidebands; where a narrow band or a weak record holds a single harmonic, the line and
   its sideband still mark the fault. A side stronger than its line is no sideband of it,
   and where the record's shaft lines do not confirm the speed the line must stand clear
   of every shaft harmonic by the slip tolerance. The inner race's shaft-rate sidebands
   do not pair: any source turning with the shaft has them. ``alpha_pair`` is ``alpha``
   divided by the number of tests (harmonic pairs, and harmonics with their sideband for
   2 x BSF), families and candidate bands (union bound), so that a fault-free record is
   called faulty with probability at most ``alpha`` (1e-4 by default): the healthy
   threshold comes from that false-alarm probability, not from example records.
   Significance alone grows with the record length: a long enough record makes even the
   few-percent ball-pass modulation of a healthy loaded bearing (varying compliance)
   significant (the CWRU baseline record 97 shows 1.5 % at BPFO and 1.2 % at 2 BPFO, which
   10 s of record would make significant). A detection therefore
   also needs an effect size: a supporting harmonic must modulate the squared envelope by
   at least ``min_modulation`` (5 %), its amplitude over the mean squared envelope, which
   does not depend on the record length. Localised faults modulate it by tens of percent
   (50-120 % on the CWRU outer- and inner-race records), the healthy baseline by 1-2 %.
6. Verdict: among the detected families, the one whose own lines carry the most evidence
   (the sum of the normalised values of its supporting harmonics, each close to -ln p of
   that line), counting only lines that no other detected family's comb explains: 2 BPFI is
   within 0.7 % of 3 BPFO on many bearings, and since BPFO + BPFI is n times the shaft rate
   an outer-race fault with shaft-rate modulation has a line at exactly BPFI. A race or
   spin comb also explains the first two shaft-rate sidebands of its lines (BPFO - 2 fr is
   within 0.5 % of 4 FTF on the CWRU drive-end bearing: the cage series of an outer-race
   record is explained by its BPFO comb, not the other way round). Sidebands (BPFI +- shaft
   rate, 2 BSF +- cage rate) are measured at the found lines and reported.
7. Another source. An accelerometer also hears the machine's other components: beside a
   damaged drive-end bearing, the fan-end bearing's combs (slip windows up to +-8 % wide at
   the 4th harmonic) catch some of the many harmonics and shaft sidebands of its ball-pass
   series, and the pair test, which assumes a random background, passes. So each band is
   also scanned for the strongest harmonic series at a rate that no fault of this bearing
   explains (from 0.3 times the slowest to 1.3 times the fastest fault frequency, on the
   spectrum less the detected fault combs' own lines; the fault frequencies, their doubles
   and triples, BSF and the cage rate times 1-3 left out; the rate found may be a
   sub-multiple of that series' where a comb took its lines). A family whose series (the sum of its
   three strongest harmonics' normalised values) is weaker than that one is named only
   where its detection holds on lines the other series does not explain (its harmonics and
   their first two shaft-rate sidebands, within two bins and 0.1 %); otherwise it is
   listed in ``Diagnosis.dominated``. Read with the fan-end bearing, the CWRU fan-end
   channel beside a damaged drive end (135) called the healthy fan-end bearing's balls
   faulty (a pair from harmonic 3, which is 3 BPFO + fr of the drive end, and harmonic 4);
   now it is healthy. Over 240 synthetic records beside another impact train 1-4 times as
   strong (``benchmarks/other_source_scenarios.py``), healthy ones were called faulty 58
   times in 120 before and never now, and faults were named 86 times in 120 before and
   97 after (103 with the infogram's band). Every verdict on the 31 development records
   stands at 1.12 or more of the other series' strength (262; 1.35 with the kurtogram's
   band), none set aside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import fft as sp_fft
from scipy import ndimage, signal

from diagnostics._checks import (
    check_positive,
    check_positive_int,
    check_signal,
    check_signals,
    check_varying,
)
from diagnostics.envelope import envelope
from diagnostics.frequencies import BearingGeometry, FaultFrequencies, bearing_frequencies
from diagnostics.kurtosis import kurtogram, kurtogram_and_infogram
from diagnostics.separation import discrete_random_separation
from diagnostics.speed import ShaftLines, check_speed_profile, order_track, shaft_angle, speed_check

__all__ = [
    "FAMILIES",
    "FamilyScore",
    "BandScore",
    "Diagnosis",
    "diagnose",
    "prewhiten",
    "kurtogram_band",
    "check_bearing_inputs",
    "normalised_envelope_spectrum",
]

FAMILIES = ("outer", "inner", "ball")

# Prewhitening tapers the record ends over this time and then drops them: the circular FFT
# would otherwise see a step where the end wraps onto the start, and whitening turns that
# step into a huge spurious impulse.
_TAPER_S = 0.05
# Background window half-width, as a fraction of the lowest comb fundamental.
_BACKGROUND_FRACTION = 0.1
# Bins either side of a shaft harmonic that are masked out of every comb.
_SHAFT_MASK_BINS = 2.5
# Harmonics are sought only up to this fraction of a band's width: the squared envelope of
# a band of width B holds modulation frequencies up to B, with a triangular weight.
_USABLE_FRACTION = 0.8
# A harmonic supports a detection when its own p-value is at most this.
_SUPPORT_P = 0.01
# A harmonic and its sideband make a detecting pair where the sideband stands at least this
# many bins from the line (its four bins then clear the line's two).
_SIDEBAND_MIN_BINS = 3.0
_SIDEBAND_PAIR_FAMILIES = ("ball",)
# Lines between a comb's harmonics mark a slower period where their series is at least
# this share of the comb's (_slower_period).
_SLOWER_SHARE = 0.25
# A line counts as another series' harmonic or sidebands within two bins and this share of
# its frequency (measured lines stand up to 0.07 % off the places a fitted fundamental
# predicts: the speed drifts over the record).
_LINE_SPREAD = 1e-3
# Slower periods tested per comb (_slower_period). Half of 2 x BSF is the ball spin rate
# itself, where a damaged ball strikes one race harder than the other: ball evidence; a
# quarter of it is tested instead (its odd multiples). The
# cage-rate comb is not tested: lines at half the cage rate show in measured records of
# every fault (CWRU 189, 250, 262), for reasons this analysis does not model.
_SLOWER = {"BPFO": (2, 3), "BPFI": (2, 3), "2xBSF": (3, 4), "FTF": ()}
# A series' strength: the sum of its strongest harmonics, this many of those tested.
_STRENGTH_TOP = 3
# The record's own shaft lines are sought within this share of the speed given, and the
# series found there weighed against the best within _SPEED_NEAR of the slip tolerance of it.
# The analysis then runs at the rate of the stronger: CWRU files' RPM lies up to 0.2 % from
# their lines, which puts the 5th shaft harmonic of the envelope spectrum (10 s records)
# outside its +-2.5-bin mask already.
_SPEED_TOLERANCE = 0.05
_SPEED_NEAR = 0.25
# How the demodulation band beside the whole prewhitened one is chosen.
_SELECTORS = ("infogram", "kurtogram")


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
        Normalised SES value at k * found_hz - sideband_hz and + sideband_hz (2 x K).
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
class Diagnosis:
    """Result of :func:`diagnose`.

    Attributes
    ----------
    fault : str
        ``"outer"``, ``"inner"``, ``"ball"`` or ``"none"``.
    band : tuple of float
        Demodulation band (Hz) of the verdict: the band of the winning family, or for
        ``"none"`` the band where the strongest (undetected) evidence was seen.
    scores : dict
        Evidence per family (sum of the normalised SES values of its supporting harmonics,
        best band); 0 where no harmonic supports it.
    confidence : float
        In [0, 1]. For a fault: the evidence of its own lines that no other detected family
        explains, over that plus the same for the next detected family (1 when no other
        family is detected). For ``"none"``: one minus the ``near_miss`` of the nearest
        family.
    frequencies : FaultFrequencies
        Kinematic frequencies at the shaft rate analysed: ``shaft_hz``, or the record's own
        shaft lines where ``correct_speed`` moved to them (see ``shaft_lines``).
    families : dict
        Best :class:`FamilyScore` per family (over the candidate bands).
    bands : tuple of BandScore
        Every candidate band.
    kurtogram : object
        Fast kurtogram of the prewhitened signal (``diagnostics.kurtosis.Kurtogram``), or None.
    alpha : float
        False-alarm probability the detection thresholds were set for.
    domain : str
        ``"time"``: frequencies and bands in Hz. ``"order"``: the record was order-tracked
        (a varying speed), and every frequency and band is in orders (cycles per shaft
        revolution), ``frequencies`` at a shaft rate of 1 (or of the record's shaft lines,
        see ``shaft_lines``).
    samples_per_rev : float or None
        Angular sampling of the order-domain record analysed (None in time): the orders it
        holds, up to half of it, are those present all through the record.
    dominated : tuple of str
        Families whose harmonic pair was significant but which were not named: in each band
        where it was, a stronger series at a rate that no fault of this bearing explains
        accounts for the lines the pair rests on (its harmonics or their shaft sidebands).
    other_series : tuple of float
        ``(fundamental, strength)`` of the strongest series at a rate that no fault of this
        bearing explains (see :class:`BandScore`; the fundamental may be a sub-multiple of
        that series' own), in the band of the first dominated family, or else of the
        verdict.
    shaft_lines : ShaftLines or None
        The record's own shaft harmonics near the given rate
        (:func:`diagnostics.speed.shaft_lines`; in orders in the order domain); where
        ``correct_speed`` moved the analysis to them, ``frequencies.shaft`` is their rate.
    infogram : object
        Infogram of the squared envelope spectrum of the prewhitened signal over the combs'
        cyclic frequencies (``diagnostics.kurtosis.Infogram``), or None.
    """

    fault: str
    band: tuple[float, float]
    scores: dict[str, float]
    confidence: float
    frequencies: FaultFrequencies
    families: dict[str, FamilyScore | None] = field(repr=False)
    bands: tuple[BandScore, ...] = field(repr=False)
    kurtogram: object | None = field(default=None, repr=False)
    alpha: float = 1e-4
    domain: str = "time"
    samples_per_rev: float | None = None
    dominated: tuple[str, ...] = ()
    other_series: tuple[float, float] = (0.0, 0.0)
    shaft_lines: ShaftLines | None = field(default=None, repr=False)
    infogram: object | None = field(default=None, repr=False)

    @property
    def speed_change(self) -> float:
        """Relative change of the shaft rate analysed from the one given (0 where the
        record's shaft lines were not used)."""
        lines = self.shaft_lines
        return 0.0 if lines is None else self.frequencies.shaft / lines.given_hz - 1.0

    @property
    def best_band(self) -> BandScore:
        """The candidate band the verdict came from."""
        for b in self.bands:
            if b.band == self.band:
                return b
        return self.bands[0]


def check_bearing_inputs(geometry, fs: float, shaft_hz: float) -> tuple[float, float]:
    """Check the arguments every bearing analysis takes; return ``(fs, shaft_hz)`` as floats.

    Raises
    ------
    ValueError
        If ``geometry`` is not a BearingGeometry or a rate is not finite and positive.
    """
    if not isinstance(geometry, BearingGeometry):
        raise ValueError(f"geometry must be a BearingGeometry, got {type(geometry).__name__}")
    fs = check_positive(fs, "fs", unit=" in Hz")
    shaft_hz = check_positive(shaft_hz, "shaft_hz", unit=" in Hz")
    return fs, shaft_hz


def record_requirements(
    geometry: BearingGeometry, shaft_hz: float, slip: float = 0.02
) -> tuple[float, float]:
    """Lowest sampling rate and shortest record :func:`diagnose` accepts for a bearing.

    The squared envelope must hold two harmonics of the highest fault frequency within
    0.8 of the Nyquist band, and the record must hold 20 periods of the slowest one (plus
    the prewhitening tapers).

    Parameters
    ----------
    geometry : BearingGeometry
        Bearing dimensions (metres).
    shaft_hz : float
        Shaft speed in Hz.
    slip : float
        Relative tolerance on the fault frequencies.

    Returns
    -------
    min_fs_hz, min_duration_s : float

    Examples
    --------
    >>> fs_min, t_min = record_requirements(BearingGeometry(9, 7.94e-3, 39.04e-3), 29.95)
    >>> round(fs_min), round(t_min, 3)
    (827, 0.286)
    """
    freqs = bearing_frequencies(geometry, check_positive(shaft_hz, "shaft_hz", unit=" in Hz"))
    fundamentals = _family_fundamentals(freqs)
    f_low = min(f0 for f0, _ in fundamentals.values())
    f_high = max(f0 for f0, _ in fundamentals.values()) * (1.0 + slip)
    return 2.0 * 2.0 * f_high / _USABLE_FRACTION, 20.0 / f_low + 2.0 * _TAPER_S


def _random_part(x: np.ndarray, fs: float, shaft_hz: float) -> np.ndarray | None:
    """Random part of the record by discrete/random separation, resolving a quarter of the
    shaft rate; None for a record too short for it."""
    nfft = int(2 ** math.ceil(math.log2(4.0 * fs / shaft_hz)))
    if x.size < 9 * nfft:
        return None
    return discrete_random_separation(x, fs, nfft=nfft).random


def _fast_length(n: int) -> int:
    """Largest length <= n whose real FFT is fast (no large prime factor)."""
    m = n
    while m > 1 and sp_fft.next_fast_len(m, real=True) != m:
        m -= 1
    return m


def prewhiten(x, fs: float, taper_s: float = _TAPER_S, axis: int = -1) -> np.ndarray:
    """Cepstral prewhitening: the signal with its spectrum set to unit modulus.

    Equivalent to removing the real cepstrum except at quefrency zero (Sawalhi and Randall):
    the spectral envelope (resonances) and the discrete components are flattened while the
    phases, hence the timing of impulses, are kept. The record ends are tapered over
    ``taper_s`` seconds before the transform and dropped afterwards.

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis`` (each channel prewhitened on its own).
    fs : float
        Sampling rate in Hz.
    taper_s : float
        Taper length at each end, in seconds (at most 5 % of the record).
    axis : int
        Axis of ``x`` along which the samples run.

    Returns
    -------
    numpy.ndarray
        Prewhitened signal of unit variance (each channel), shorter than ``x`` along
        ``axis`` by the two tapers and a few samples that keep every later FFT fast.

    Raises
    ------
    ValueError
        On an invalid or constant signal, ``fs`` or axis.

    Examples
    --------
    A tone and its harmonic over noise: prewhitened, every frequency has the same level.

    >>> fs, rng = 8000.0, np.random.default_rng(0)
    >>> t = np.arange(16000) / fs
    >>> x = 50 * np.sin(2 * np.pi * 200 * t) + 20 * np.sin(2 * np.pi * 400 * t)
    >>> white = prewhiten(x + rng.standard_normal(t.size), fs)
    >>> spec = np.abs(np.fft.rfft(white))
    >>> bool(spec.max() < 3 * np.median(spec))
    True
    """
    x = check_varying(check_signals(x, fs, axis=axis, min_length=16))
    size = x.shape[-1]
    m = int(min(round(taper_s * fs), 0.05 * size))
    # Drop a few samples so that this and every later FFT has a fast (5-smooth) length.
    n = _fast_length(size - 2 * m) + 2 * m
    x = x[..., :n]
    window = signal.windows.tukey(n, 2.0 * m / n) if m > 0 else np.ones(n)
    spec = np.fft.rfft((x - x.mean(axis=-1, keepdims=True)) * window, axis=-1)
    mag = np.abs(spec)
    peak = mag.max(axis=-1, keepdims=True)
    floor = np.where(peak > 0, 1e-12 * peak, 1.0)
    white = np.fft.irfft(spec / np.maximum(mag, floor), n, axis=-1)
    white = white[..., m : n - m] if m > 0 else white
    # Unit variance: the kurtogram compares band powers with machine epsilon.
    white = white / white.std(axis=-1, keepdims=True)
    return white if white.ndim == 1 else np.moveaxis(white, -1, axis)


def normalised_envelope_spectrum(
    y, fs: float, band: tuple[float, float] | None, f_max: float, half_window_hz: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Squared envelope spectrum up to ``f_max``, normalised two ways.

    ``z`` is the power of each bin over the local background: the running median over
    +-``half_window_hz`` divided by ln 2 (the median of a unit-mean exponential variable),
    so random bins read about 1. ``m`` is the amplitude of each bin over the mean squared
    envelope: a squared envelope ``mu (1 + m cos 2 pi f t)`` reads ``m`` at ``f`` (the
    modulation depth, independent of the record length).

    Returns
    -------
    f, z, m : numpy.ndarray
        Frequencies (Hz), normalised power and modulation depth.
    """
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
    ``8 exp(-z)``. A side stronger than its harmonic (``line_z``) is no sideband of it:
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
    """``(q, share)``: the ``q`` of ``periods`` (2, 3 or 4) where the lines at ``j * fc / q``
    (``j`` not a multiple of ``q``, odd for ``q`` = 4, below the comb's top harmonic) hold a
    significant pair, as a comb's pair is judged, and a series at least a quarter as strong
    as the comb's own (``z_comb``), and that strength over the comb's; else ``(0, 0.0)``.

    Their places are fixed by the comb, so each line's p-value is over a window of four bins
    (the line between two bins, and a bin of spread either side). A train of impacts at
    ``fc / q`` gives lines there nearly as strong as on the comb (0.32 or more of its
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
    p = np.where(explained, 1.0, s.p_values)
    lo = np.clip(np.floor(s.lines_hz / df).astype(int), 0, b.f.size - 2)
    masked = _shaft_mask(b.f, shaft_hz)
    observed = ~(masked[lo] & masked[lo + 1])
    evidence = _pair_evidence(p, observed, s.modulation)
    if _detects(*evidence, alpha_pair, min_modulation):
        return True
    if not _sideband_pairs(s.family, s.sideband_hz, df):
        return False
    sides = s.lines_hz[None, :] + np.array([-s.sideband_hz, s.sideband_hz])[:, None]
    off = np.min(np.abs(sides[..., None] - lattice[None, None, :]), axis=-1)
    p_sb = _sideband_p(s.sideband_z, s.z, off <= 2.0 * df + _LINE_SPREAD * sides)
    p = np.where(observed & _off_shaft(s.lines_hz, shaft_hz, shaft_tolerance), p, 1.0)
    return _sideband_closeness(p, p_sb, s.modulation, alpha_pair, min_modulation)[0] >= 1.0


def series_strength(z: np.ndarray):
    """Strength of a harmonic series: the sum of its strongest normalised harmonic values
    (three, or as many as were tested), along the last axis (one per row of a 2-D ``z``)."""
    return np.sort(np.asarray(z, dtype=float), axis=-1)[..., -_STRENGTH_TOP:].sum(axis=-1)


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


def _family_fundamentals(freqs: FaultFrequencies) -> dict[str, tuple[float, float]]:
    """Comb fundamental and sideband spacing of each family."""
    return {
        "outer": (freqs.bpfo, 0.0),
        "inner": (freqs.bpfi, freqs.shaft),
        "ball": (2.0 * freqs.bsf, freqs.ftf),
    }


def kurtogram_band(
    kg, min_bandwidth_hz: float = 0.0, min_low_hz: float = 0.0, apart_from=None
) -> tuple[tuple[float, float], float] | None:
    """Best band of a fast kurtogram among the bands that meet two constraints.

    Parameters
    ----------
    kg : diagnostics.kurtosis.Kurtogram
        The kurtogram.
    min_bandwidth_hz : float
        Narrowest band accepted.
    min_low_hz : float
        Lowest lower edge accepted.
    apart_from : tuple of float, optional
        A band ``(f_lo, f_hi)`` in Hz that the band found must not overlap.

    Returns
    -------
    ((f_lo, f_hi), kurtosis) or None
        None when no band qualifies.
    """
    fs = float(kg.fs)
    levels = np.asarray(kg.levels, dtype=float)
    bws = fs / 2.0 / 2.0**levels
    centres = np.asarray(kg.freqs, dtype=float)
    # Bands tile 0..fs/2 at every level; a column belongs to the band holding its centre.
    lows = np.floor(centres[None, :] / bws[:, None]) * bws[:, None]
    tol = 1e-9 * fs
    ok = (bws[:, None] >= min_bandwidth_hz) & (lows >= min_low_hz - tol)
    if apart_from is not None:
        ok &= (lows + bws[:, None] <= apart_from[0] + tol) | (lows >= apart_from[1] - tol)
    if not ok.any():
        return None
    masked = np.where(ok, np.asarray(kg.K, dtype=float), -np.inf)
    r, c = np.unravel_index(int(np.argmax(masked)), masked.shape)
    lo = float(lows[r, c])
    return (lo, float(min(lo + bws[r], fs / 2.0))), float(masked[r, c])


def _demod_band(band: tuple[float, float], fs: float) -> tuple[float, float] | None:
    """A band as envelope_spectrum takes it; None for the whole band."""
    lo, hi = band
    if lo <= 0.0 and hi >= fs / 2.0:
        return None
    # A band from 0 Hz becomes a band-pass from a low edge (the filter needs one).
    return max(lo, 1e-3 * fs), min(hi, fs / 2.0)


def diagnose(
    x,
    fs: float,
    geometry: BearingGeometry,
    shaft_hz,
    *,
    slip: float = 0.02,
    n_harmonics: int = 5,
    alpha: float = 1e-4,
    min_modulation: float = 0.05,
    nlevel: int = 7,
    use_kurtogram: bool = True,
    band_selector: str = "infogram",
    use_drs: bool = False,
    samples_per_rev: float | None = None,
    correct_speed: bool = True,
) -> Diagnosis:
    """Diagnose a rolling element bearing from one vibration record.

    At a steady speed the record is analysed in time. Where ``shaft_hz`` is a speed profile
    that varies by more than half the slip tolerance over the record, the record is first
    resampled at uniform shaft-angle increments (:func:`diagnostics.speed.order_track`) and
    analysed in the order domain: the same method with frequencies in orders (cycles per
    shaft revolution), the sampling rate in samples per revolution and a shaft rate of 1.

    Parameters
    ----------
    x : array_like
        1-D acceleration (any unit), at least 20 periods of the slowest fault frequency.
    fs : float
        Sampling rate in Hz.
    geometry : BearingGeometry
        Bearing dimensions (metres).
    shaft_hz : float or array_like
        Shaft (inner ring) speed in Hz: one value, or the instantaneous rate at every sample
        of ``x`` (see :func:`diagnostics.speed.speed_from_tacho` and
        :func:`diagnostics.speed.estimate_speed`).
    slip : float
        Relative tolerance on every fault frequency (rolling slip and speed error).
    n_harmonics : int
        Harmonics per comb (fewer in a band too narrow to hold them).
    alpha : float
        Probability of calling a fault-free (random) record faulty, over all families and
        candidate bands.
    min_modulation : float
        Smallest modulation depth of the squared envelope, at a fault harmonic, that counts
        as a fault (effect-size floor; see the module notes).
    nlevel : int
        Depth of the fast kurtogram (reduced for a record too short for it).
    use_kurtogram : bool
        Add a band chosen on the fast kurtogram's filter bank (``band_selector``) to the
        whole prewhitened band.
    band_selector : {"infogram", "kurtogram"}
        How that band is chosen: the best band of the infogram of the squared envelope
        spectrum over the cyclic frequencies the race and spin combs cover, shaft harmonics
        left out (:func:`diagnostics.kurtosis.infogram`: the band where the record's repetitive
        impacts show), or the kurtogram's (the most impulsive band, which a few strong
        impacts at no period can win). With the infogram, its best band that does not
        overlap the first is a candidate too. ``Diagnosis.kurtogram`` holds the kurtogram
        either way, ``Diagnosis.infogram`` the infogram (None with ``"kurtogram"``).
    use_drs : bool
        Add the kurtogram's best band of the random part of the record after
        discrete/random separation (:func:`diagnostics.separation.discrete_random_separation`).
    samples_per_rev : float, optional
        Angular sampling of the order tracking; default ``fs / min(shaft_hz)``, which keeps
        the record's whole band at the slowest speed. The analysis then keeps only the orders
        present all through the record, up to ``fs / 2 / max(shaft_hz)`` (and the tracking's
        anti-aliasing cut-off): above them the content comes and goes with the speed, which
        the kurtogram would take for impulsiveness. ``Diagnosis.samples_per_rev`` is the
        angular sampling of what was analysed.
    correct_speed : bool
        Check the speed on the record's own shaft harmonics
        (:func:`diagnostics.speed.speed_check`; in orders in the order domain) and analyse
        at their rate: the stronger of the series found within a quarter of ``slip`` of the
        rate given and the one found within 5 % of it. A speed read off a name plate or a
        nominal value can be a few percent off, and the fault combs and shaft masks with
        it. A record without such harmonics is analysed at the rate given
        (``Diagnosis.shaft_lines`` says which). Turn it off for a speed known exactly (a
        tachometer's) on a machine with another shaft turning within 5 % of this one's.

    Returns
    -------
    Diagnosis
        Verdict, band, scores, confidence and the details behind them; ``domain`` says
        whether they are in Hz (``"time"``) or in orders (``"order"``).

    Raises
    ------
    ValueError
        On an invalid signal, sampling rate, speed or speed profile, option, or a record
        too short.

    Examples
    --------
    A synthetic record of the CWRU drive-end bearing (SKF 6205) with an outer-race fault:
    2 s at 12 kHz, one impact ringing a 3 kHz resonance per BPFO period, the impacts
    jittered by the rollers' slip, in noise.

    >>> fs, geometry = 12000.0, BearingGeometry(9, 7.94e-3, 39.04e-3)
    >>> order = bearing_frequencies(geometry, 1.0).bpfo       # impacts per shaft turn
    >>> n, rng = int(2 * fs), np.random.default_rng(0)
    >>> ring = np.exp(-900 * np.arange(120) / fs) * np.sin(2 * np.pi * 3000 * np.arange(120) / fs)
    >>> def record(rate):
    ...     hits = np.flatnonzero(np.diff(np.floor(np.cumsum(rate) / fs * order)))
    ...     hits = hits + rng.integers(-4, 5, hits.size)      # slip: about 1 % jitter
    ...     impacts = np.convolve(np.bincount(hits, minlength=n)[:n], ring)[:n]
    ...     return impacts + 0.3 * rng.standard_normal(n)
    >>> d = diagnose(record(np.full(n, 29.95)), fs, geometry, 29.95)
    >>> d.fault, round(d.confidence, 2), d.domain
    ('outer', 1.0, 'time')

    At a varying speed, give the shaft rate per sample (here a ramp from 25 to 35 rev/s;
    from a tachometer, :func:`~diagnostics.speed.speed_from_tacho`): the record is
    order-tracked and diagnosed in orders.

    >>> rate = np.linspace(25.0, 35.0, n)
    >>> d = diagnose(record(rate), fs, geometry, rate)
    >>> d.fault, d.domain, round(d.frequencies.bpfo, 3)      # BPFO in orders
    ('outer', 'order', 3.585)
    """
    options = dict(
        slip=slip,
        n_harmonics=n_harmonics,
        alpha=alpha,
        min_modulation=min_modulation,
        nlevel=nlevel,
        use_kurtogram=use_kurtogram,
        band_selector=band_selector,
        use_drs=use_drs,
        correct_speed=correct_speed,
    )
    if np.ndim(shaft_hz) == 0:
        return _diagnose_steady(x, fs, geometry, shaft_hz, **options)
    fs = check_positive(fs, "fs", unit=" in Hz")
    x = check_varying(check_signal(x, fs))
    rate = check_speed_profile(shaft_hz, x.size)
    if np.ptp(rate) <= 0.5 * check_positive(slip, "slip") * float(rate.mean()):
        return _diagnose_steady(x, fs, geometry, float(rate.mean()), **options)
    spr = float(math.ceil(fs / float(rate.min()))) if samples_per_rev is None else samples_per_rev
    spr = check_positive(spr, "samples_per_rev")
    orders = bearing_frequencies(geometry, 1.0)
    slowest = min(orders.bpfo, orders.bpfi, 2.0 * orders.bsf)
    revolutions = float(shaft_angle(rate, fs)[-1])
    # The prewhitening's taper covers the same time at the mean speed as in the time domain.
    taper = _TAPER_S * float(rate.mean())
    needed = 20.0 / slowest + 2.0 * taper
    if revolutions < needed:
        raise ValueError(
            f"x is too short: the record covers {revolutions:.3g} shaft revolutions; diagnose "
            f"needs {needed:.3g} (20 periods of the slowest fault order, {slowest:.4g})"
        )
    return _diagnose_orders(x, fs, geometry, rate, spr, taper, options)


def _diagnose_orders(
    x: np.ndarray,
    fs: float,
    geometry: BearingGeometry,
    rate: np.ndarray,
    spr: float,
    taper: float,
    options: dict,
) -> Diagnosis:
    """:func:`diagnose` in the order domain: order-track at ``spr`` samples per revolution,
    keep the orders held all through the record, diagnose at a shaft rate of 1."""
    tracked = order_track(x, fs, rate, spr)
    # Only the orders held all through the record are analysed: above them the content comes
    # and goes with the speed (and the prewhitening would raise an empty band to unit level),
    # which the kurtogram reads as impulsiveness. An FFT resampling keeps exactly that band.
    kept = int(round(tracked.x.size * 2.0 * tracked.cutoff_order / spr))
    if kept < tracked.x.size:
        band_limited = signal.resample(tracked.x, kept)
        spr = spr * kept / tracked.x.size
    else:
        band_limited = tracked.x
    d = _diagnose_steady(band_limited, spr, geometry, 1.0, taper=taper, **options)
    return replace(d, domain="order", samples_per_rev=spr)


def _fault_rates(geometry: BearingGeometry, shaft_hz: float, slip: float):
    """``(freqs, fundamentals, f_low, f_high)`` at a shaft rate: the fault frequencies, the
    comb fundamentals per family, the slowest fundamental and the fastest one plus the slip."""
    freqs = bearing_frequencies(geometry, shaft_hz)
    fundamentals = _family_fundamentals(freqs)
    f_low = min(f0 for f0, _ in fundamentals.values())
    f_high = max(f0 for f0, _ in fundamentals.values()) * (1.0 + slip)
    return freqs, fundamentals, f_low, f_high


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


def _check_options(
    geometry, fs, shaft_hz, slip, n_harmonics, min_modulation, alpha, band_selector
) -> tuple[float, float, float, int, float, float]:
    """``(fs, shaft_hz, slip, n_harmonics, min_modulation, alpha)`` checked; a ValueError
    naming the first bad one."""
    fs, shaft_hz = check_bearing_inputs(geometry, fs, shaft_hz)
    slip = check_positive(slip, "slip")
    if slip >= 0.1:
        raise ValueError(f"slip must be below 0.1 (10 %), got {slip!r}")
    n_harmonics = check_positive_int(n_harmonics, "n_harmonics", minimum=2)
    min_modulation = check_positive(min_modulation, "min_modulation")
    alpha = check_positive(alpha, "alpha")
    if alpha >= 1.0:
        raise ValueError(f"alpha must be a probability below 1, got {alpha!r}")
    if band_selector not in _SELECTORS:
        raise ValueError(f"band_selector must be one of {_SELECTORS}, got {band_selector!r}")
    return fs, shaft_hz, slip, n_harmonics, min_modulation, alpha


def _candidate_bands(
    x: np.ndarray,
    white: np.ndarray,
    fs: float,
    freqs: FaultFrequencies,
    f_low: float,
    f_high: float,
    f_max: float,
    n_harmonics: int,
    nlevel: int,
    use_kurtogram: bool,
    band_selector: str,
    use_drs: bool,
) -> tuple[list[tuple[str, tuple[float, float], float, np.ndarray]], object, object]:
    """``(candidates, kurtogram, infogram)``: the demodulation bands tried, each as ``(name,
    band, kurtosis, signal)``: the whole prewhitened band, the infogram's best band and its
    best apart from that one (or the kurtogram's best), the kurtogram's band of the random
    part with ``use_drs``."""
    candidates: list[tuple[str, tuple[float, float], float, np.ndarray]] = [
        ("prewhitened", (0.0, fs / 2.0), 0.0, white)
    ]
    kg_white = info = None
    # The fast kurtogram needs 2**(nlevel + 7) samples; a short record gets fewer levels.
    levels = min(nlevel, int(math.log2(white.size)) - 7)
    bw_min = 2.0 * f_high / _USABLE_FRACTION
    # Demodulate above the fault frequencies' own range: below it the band holds the
    # deterministic low-frequency vibration, whose beats are not impacts.
    f_floor = (n_harmonics + 1) * f_high
    if use_kurtogram and levels >= 1:
        if band_selector == "infogram":
            # The band whose squared envelope holds the most lines over the race and spin
            # combs' range (from half the slowest fault frequency), shaft harmonics aside;
            # the kurtogram, shown beside it, takes the most impulsive band, which a few
            # strong impacts at no period can win. Down to half the cage rate instead:
            # 1 more of 40 sub-multiple scenarios, but CWRU 118's band, and verdict, then
            # differed between time and orders.
            cyclic = (0.5 * f_low, f_max)
            kg_white, info = kurtogram_and_infogram(white, fs, levels, cyclic, freqs.shaft)
            chosen = info
        else:
            chosen = kg_white = kurtogram(white, fs, nlevel=levels)
        found = kurtogram_band(chosen, min_bandwidth_hz=bw_min, min_low_hz=f_floor)
        if found is not None:
            candidates.append((band_selector, found[0], found[1], white))
            if band_selector == "infogram":
                # And its best band apart from that one: where another source's lines take
                # the first, the fault's impacts, ringing another resonance, hold the next.
                second = kurtogram_band(info, bw_min, f_floor, apart_from=found[0])
                if second is not None:
                    candidates.append(("infogram, second", second[0], second[1], white))
    if use_drs and levels >= 1:
        separated = _random_part(x, fs, freqs.shaft)
        if separated is not None:
            kg_random = kurtogram(separated, fs, nlevel=levels)
            found = kurtogram_band(kg_random, min_bandwidth_hz=bw_min, min_low_hz=f_floor)
            if found is not None:
                candidates.append(("drs-kurtogram", found[0], found[1], separated))
    return candidates, kg_white, info


def _score_band(
    name: str, band: tuple[float, float], kurt: float, y: np.ndarray, fs: float, s: _Setting
) -> BandScore:
    """Every comb scored in one band's squared envelope spectrum, and the band's strongest
    series at a rate no fault explains."""
    f, z, m = normalised_envelope_spectrum(y, fs, _demod_band(band, fs), s.f_max, s.half_window)
    masked = _shaft_mask(f, s.freqs.shaft)
    z_masked = np.where(masked, 0.0, z)
    width = band[1] - band[0]
    scores: dict[str, FamilyScore | None] = {}
    for comb, (family, f0, sb_hz) in s.combs.items():
        n_harm = min(s.n_harmonics, int(_USABLE_FRACTION * width // (f0 * (1.0 + s.slip))))
        if n_harm < 2:
            scores[comb] = None
            continue
        score = _score_family(
            family,
            f,
            z_masked,
            masked,
            m,
            f0,
            n_harm,
            s.slip,
            s.alpha_pair,
            s.min_modulation,
            band,
            sb_hz,
            _SLOWER.get(comb, (2, 3)),
            s.freqs.shaft,
            s.shaft_tolerance,
        )
        scores[comb] = replace(score, comb=comb)
    other = _other_series_scan(
        f,
        z_masked,
        s.freqs,
        s.slip,
        s.n_harmonics,
        s.f_high,
        width,
        [sc for sc in scores.values() if sc is not None and sc.detected],
    )
    return BandScore(name, band, kurt, f, z, scores, *other)


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


def _diagnose_steady(
    x,
    fs: float,
    geometry: BearingGeometry,
    shaft_hz: float,
    *,
    slip: float,
    n_harmonics: int,
    alpha: float,
    min_modulation: float,
    nlevel: int,
    use_kurtogram: bool,
    use_drs: bool,
    band_selector: str = "infogram",
    correct_speed: bool = True,
    taper: float = _TAPER_S,
) -> Diagnosis:
    """:func:`diagnose` at one shaft rate (Hz, or 1 in the order domain, where ``taper`` is
    in revolutions): the speed checked on the record, the candidate bands, each band's
    scores, the verdict."""
    fs, shaft_hz, slip, n_harmonics, min_modulation, alpha = _check_options(
        geometry, fs, shaft_hz, slip, n_harmonics, min_modulation, alpha, band_selector
    )
    freqs, fundamentals, f_low, f_high = _fault_rates(geometry, shaft_hz, slip)
    if 2.0 * f_high >= _USABLE_FRACTION * fs / 2.0:
        raise ValueError(
            f"fs = {fs:g} Hz is too low for these fault frequencies (up to {f_high:.4g} Hz)"
        )
    x = check_varying(check_signal(x, fs))
    min_len = int(math.ceil(20.0 * fs / f_low + 2 * taper * fs))
    if x.size < min_len:
        raise ValueError(
            f"x is too short: {x.size} samples last {x.size / fs:.3g} s at fs = {fs:g} Hz; "
            f"diagnose needs {min_len / fs:.3g} s (20 periods of {f_low:.4g} Hz, the slowest "
            "fault frequency, and the tapers)"
        )

    lines = speed_check(x, fs, shaft_hz, near=_SPEED_NEAR * slip, wide=_SPEED_TOLERANCE)
    if correct_speed and lines.present:
        freqs, fundamentals, f_low, f_high = _fault_rates(geometry, lines.found_hz, slip)

    white = prewhiten(x, fs, taper)
    f_max = (n_harmonics + 1) * f_high + freqs.shaft
    candidates, kg_white, info = _candidate_bands(
        x, white, fs, freqs, f_low, f_high, f_max, n_harmonics, nlevel, use_kurtogram,
        band_selector, use_drs,
    )  # fmt: skip

    combs = _combs(freqs, fundamentals, x.size / fs)
    # Union bound over the tests of every candidate band: each comb's pairs of harmonics,
    # and each harmonic with its sideband where that is a detecting pair.
    per_band = sum(
        math.comb(n_harmonics, 2) + (n_harmonics if _sideband_pairs(fam, sb) else 0)
        for fam, _, sb in combs.values()
    )
    setting = _Setting(
        freqs=freqs,
        combs=combs,
        slip=slip,
        n_harmonics=n_harmonics,
        alpha_pair=alpha / (len(candidates) * per_band),
        min_modulation=min_modulation,
        f_high=f_high,
        f_max=f_max,
        half_window=_BACKGROUND_FRACTION * f_low,
        # Shaft harmonics stand where the masks put them once the record's own lines
        # confirm the speed; otherwise anywhere within the slip tolerance.
        shaft_tolerance=0.0 if (correct_speed and lines.present) else slip,
    )
    bands = [_score_band(name, band, kurt, y, fs, setting) for name, band, kurt, y in candidates]
    v = _verdict(bands, setting)
    return Diagnosis(
        fault=v.fault,
        band=v.band,
        scores=v.scores,
        confidence=v.confidence,
        frequencies=freqs,
        families=v.best,
        bands=tuple(bands),
        kurtogram=kg_white,
        infogram=info,
        alpha=alpha,
        dominated=v.dominated,
        other_series=(v.shown.other_hz, v.shown.other_strength),
        shaft_lines=lines,
    )
