"""Automatic bearing fault diagnosis from one vibration record: :func:`diagnose`, its
result :class:`Diagnosis`, and the shortest record and lowest sampling rate it accepts
(:func:`record_requirements`).

:func:`diagnose` runs one routine per step of the method, each in its own module: the speed
checked on the record's shaft lines (:mod:`diagnostics._shaft_lines`), prewhitening
(:mod:`diagnostics._prewhiten`), the candidate bands (:mod:`diagnostics._bands`), each
comb's score in each band (:mod:`diagnostics._comb`, :mod:`diagnostics._evidence`), the
series of another source (:mod:`diagnostics._other_source`) and the verdict
(:mod:`diagnostics._verdict`); at a varying speed, first the order tracking
(:mod:`diagnostics._order_domain`). The method is described in docs/theory/diagnostics.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from diagnostics._bands import _SELECTORS, _candidate_bands, _demod_band
from diagnostics._candidates import Candidate
from diagnostics._checks import (
    check_bearing_inputs,
    check_positive,
    check_positive_int,
    check_signal,
    check_varying,
    normalise,
)
from diagnostics._comb import (
    _BACKGROUND_FRACTION,
    _SLOWER,
    _USABLE_FRACTION,
    BandScore,
    FamilyScore,
    _combs,
    _family_fundamentals,
    _fault_rates,
    _score_family,
    _Setting,
    _shaft_mask,
    normalised_envelope_spectrum,
)
from diagnostics._evidence import _sideband_pairs
from diagnostics._frequencies import BearingGeometry, FaultFrequencies, bearing_frequencies
from diagnostics._order_domain import _angular_sampling, _band_limited_orders
from diagnostics._other_source import _other_series_scan
from diagnostics._prewhiten import _TAPER_S, prewhiten
from diagnostics._shaft_lines import ShaftLines, speed_check
from diagnostics._speed import check_speed_profile
from diagnostics._verdict import _verdict

__all__ = ["Diagnosis", "diagnose", "record_requirements"]

# The record's own shaft lines are sought within this share of the speed given, and the
# series found there weighed against the best within _SPEED_NEAR of the slip tolerance of it.
# The analysis then runs at the rate of the stronger: CWRU files' RPM lies up to 0.2 % from
# their lines, which puts the 5th shaft harmonic of the envelope spectrum (10 s records)
# outside its +-2.5-bin mask already.
_SPEED_TOLERANCE = 0.05
_SPEED_NEAR = 0.25


@dataclass(frozen=True)
class Diagnosis:
    """Result of :func:`diagnose`.

    Attributes
    ----------
    fault : str
        ``"outer"``, ``"inner"``, ``"ball"`` or ``"none"``; or, where more than one family
        is detected and the evidence does not decide between them, those families joined
        by ``" or "`` (``"outer or ball"``, see ``undecided``).
    band : tuple of float
        Demodulation band (Hz) of the verdict: the band of the winning family, or for
        ``"none"`` the band where the strongest (undetected) evidence was seen.
    scores : dict
        Evidence per family (sum of the normalised SES values of its supporting harmonics,
        best band); 0 where no harmonic supports it.
    confidence : float
        In [0, 1]. For a fault: the evidence of its own lines that no other detected family
        explains, over that plus the same for the next detected family (1 when no other
        family is detected). For an undecided verdict, the same for the first family it
        names. For ``"none"``: one minus the ``near_miss`` of the nearest family.
    frequencies : FaultFrequencies
        Kinematic frequencies at the shaft rate analysed: ``shaft_hz``, or the record's own
        shaft lines where ``correct_speed`` moved to them (see ``shaft_lines``).
    families : dict
        Best :class:`FamilyScore` per family (over the candidate bands).
    bands : tuple of BandScore
        Every candidate band.
    kurtogram : object
        Fast kurtogram of the prewhitened signal (``diagnostics.Kurtogram``), or None.
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
        (:func:`diagnostics.shaft_lines`; in orders in the order domain); where
        ``correct_speed`` moved the analysis to them, ``frequencies.shaft`` is their rate.
    infogram : object
        Infogram of the squared envelope spectrum of the prewhitened signal over the combs'
        cyclic frequencies (``diagnostics.Infogram``), or None.
    candidates : tuple of Candidate
        Every family's evidence (:class:`diagnostics.Candidate`: its comb, family-wise
        p-value, supporting harmonics and sidebands, the evidence no other detected family
        explains), the detected first and those that decide before the others.
    undecided : tuple of str
        The detected families the evidence does not decide between, best first: none of
        them, or more than one, holds its detection on lines that no other detected family
        explains (the lines of one can be read as the other's harmonics or shaft-rate
        sidebands: on the CWRU fan-end bearing BPFI - fr lies 1 % below 2 x BSF). Empty
        where a fault is named or none is found.
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
    candidates: tuple[Candidate, ...] = field(default=(), repr=False)
    undecided: tuple[str, ...] = ()

    @property
    def ambiguous(self) -> bool:
        """Whether more than one fault family shows evidence and it does not decide between
        them (``fault`` then names them, ``"outer or ball"``)."""
        return len(self.undecided) > 1

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
    resampled at uniform shaft-angle increments (:func:`diagnostics.order_track`) and
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
        of ``x`` (see :func:`diagnostics.speed_from_tacho` and
        :func:`diagnostics.estimate_speed`).
    slip : float
        Relative tolerance on every fault frequency (rolling slip and speed error).
    n_harmonics : int
        Harmonics per comb (fewer in a band too narrow to hold them).
    alpha : float
        Probability of calling a fault-free (random) record faulty, over all families and
        candidate bands.
    min_modulation : float
        Smallest modulation depth of the squared envelope, at a fault harmonic, that counts
        as a fault (an effect-size floor: significance alone grows with the record
        length; docs/theory/diagnostics.md, *Automatic diagnosis*).
    nlevel : int
        Depth of the fast kurtogram (reduced for a record too short for it).
    use_kurtogram : bool
        Add a band chosen on the fast kurtogram's filter bank (``band_selector``) to the
        whole prewhitened band.
    band_selector : {"infogram", "kurtogram"}
        How that band is chosen: the best band of the infogram of the squared envelope
        spectrum over the cyclic frequencies the race and spin combs cover, shaft harmonics
        left out (:func:`diagnostics.infogram`: the band where the record's repetitive
        impacts show), or the kurtogram's (the most impulsive band, which a few strong
        impacts at no period can win). With the infogram, its best band that does not
        overlap the first is a candidate too. ``Diagnosis.kurtogram`` holds the kurtogram
        either way, ``Diagnosis.infogram`` the infogram (None with ``"kurtogram"``).
    use_drs : bool
        Add the kurtogram's best band of the random part of the record after
        discrete/random separation (:func:`diagnostics.discrete_random_separation`).
    samples_per_rev : float, optional
        Angular sampling of the order tracking; default ``fs / min(shaft_hz)``, which keeps
        the record's whole band at the slowest speed. The analysis then keeps only the orders
        present all through the record, up to ``fs / 2 / max(shaft_hz)`` (and the tracking's
        anti-aliasing cut-off): above them the content comes and goes with the speed, which
        the kurtogram would take for impulsiveness. ``Diagnosis.samples_per_rev`` is the
        angular sampling of what was analysed.
    correct_speed : bool
        Check the speed on the record's own shaft harmonics
        (:func:`diagnostics.speed_check`; in orders in the order domain) and analyse
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

    References
    ----------
    Randall, R. B. and Antoni, J. (2011). Rolling element bearing diagnostics: a tutorial.
    *Mechanical Systems and Signal Processing* 25(2), 485-520.

    Smith, W. A. and Randall, R. B. (2015). Rolling element bearing diagnostics using the
    Case Western Reserve University data: a benchmark study. *Mechanical Systems and Signal
    Processing* 64-65, 100-131.

    Antoni, J. (2007). Fast computation of the kurtogram for the detection of transient
    faults. *Mechanical Systems and Signal Processing* 21(1), 108-124.

    Antoni, J. (2016). The infogram: entropic evidence of the signature of repetitive
    transients. *Mechanical Systems and Signal Processing* 74, 73-94.

    Randall, R. B. and Sawalhi, N. (2011). A new method for separating discrete components
    from a signal. *Sound and Vibration* 45(5), 6-9.

    Borghesani, P., Pennacchi, P., Randall, R. B., Sawalhi, N. and Ricci, R. (2013).
    Application of cepstrum pre-whitening for the diagnosis of bearing faults under variable
    speed conditions. *Mechanical Systems and Signal Processing* 36(2), 370-384.

    Antoni, J. and Randall, R. B. (2004). Unsupervised noise cancellation for vibration
    signals: part II, a novel frequency-domain algorithm. *Mechanical Systems and Signal
    Processing* 18(1), 103-117.

    Fisher, R. A. (1932). *Statistical Methods for Research Workers*, 4th ed. Oliver and
    Boyd, Edinburgh.

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
    from a tachometer, :func:`~diagnostics.speed_from_tacho`): the record is
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
    x, _ = normalise(check_varying(check_signal(x, fs)))  # a verdict has no unit
    rate = check_speed_profile(shaft_hz, x.size)
    if np.ptp(rate) <= 0.5 * check_positive(slip, "slip") * float(rate.mean()):
        return _diagnose_steady(x, fs, geometry, float(rate.mean()), **options)
    spr, taper = _angular_sampling(geometry, rate, fs, samples_per_rev)
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
    band_limited, spr = _band_limited_orders(x, fs, rate, spr)
    d = _diagnose_steady(band_limited, spr, geometry, 1.0, taper=taper, **options)
    return replace(d, domain="order", samples_per_rev=spr)


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
    x, _ = normalise(check_varying(check_signal(x, fs)))  # a verdict has no unit
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
        alpha=alpha,
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
        candidates=v.candidates,
        undecided=v.undecided,
    )
