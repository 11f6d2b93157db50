"""Shaft speed that varies over a record: from a tachometer, from the vibration itself, and
angular resampling (order tracking).

A bearing's fault frequencies are fixed multiples (orders) of the shaft rate. When the speed
changes over a record, each fault line of the envelope spectrum smears over the range the
speed covers; resampled at constant shaft-angle increments, the record turns the fault
frequencies back into fixed orders (cycles per revolution), and the envelope spectrum of the
resampled record shows them as lines again (computed order tracking, Fyfe and Munck 1997;
for bearings under varying speed, Borghesani et al. 2013).

* :func:`speed_from_tacho`: shaft rate per sample from a once- or N-per-revolution pulse train.
* :func:`estimate_speed`: shaft rate per sample from the vibration (no tachometer): the
  ridge of the shaft harmonics in the spectrogram, with a confidence.
* :func:`order_track`: the record at uniform shaft-angle increments, after an anti-aliasing
  low-pass.
* :func:`shaft_angle`: shaft angle (revolutions) at every sample, the integral of the rate.
* :func:`shaft_lines`: at a steady speed, the shaft rate the record's own harmonics show near
  a given one (a name plate or nominal speed can be a few percent off); :func:`speed_check`
  weighs the series near it against the best a little farther, as ``diagnose`` does with
  the speed it is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import interpolate, ndimage, signal, stats

from diagnostics._checks import (
    check_positive,
    check_positive_int,
    check_signal,
    check_signals,
    check_varying,
)

__all__ = [
    "OrderTrack",
    "ShaftLines",
    "SpeedEstimate",
    "check_speed_profile",
    "estimate_speed",
    "order_track",
    "shaft_angle",
    "shaft_lines",
    "speed_check",
    "speed_from_tacho",
]


def check_speed_profile(shaft_hz, n: int, name: str = "shaft_hz") -> np.ndarray:
    """Return a speed profile as a 1-D float array of ``n`` finite positive rates (Hz).

    Raises
    ------
    ValueError
        If the profile is not numeric and 1-D, has another length than the record, or
        holds a rate that is not finite and positive.
    """
    try:
        rate = np.asarray(shaft_hz, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number or an array of rates in Hz") from None
    if rate.ndim != 1:
        raise ValueError(f"{name} must be a scalar or a 1-D array, got shape {rate.shape}")
    if rate.size != n:
        raise ValueError(
            f"{name} holds {rate.size} rates but the record {n} samples: give one rate per "
            "sample (see speed_from_tacho, estimate_speed)"
        )
    bad = ~(np.isfinite(rate) & (rate > 0))
    if bad.any():
        first = int(np.argmax(bad))
        raise ValueError(
            f"{name} must be finite and positive (Hz); sample {first} holds {rate[first]!r}"
        )
    return rate


def shaft_angle(shaft_hz, fs: float) -> np.ndarray:
    """Shaft angle in revolutions at every sample: the trapezoidal integral of the rate.

    Parameters
    ----------
    shaft_hz : array_like
        Shaft rate (Hz) at every sample.
    fs : float
        Sampling rate in Hz.

    Returns
    -------
    numpy.ndarray
        Angle in revolutions, 0 at the first sample.

    Examples
    --------
    >>> shaft_angle(np.full(5, 10.0), 100.0)            # 10 rev/s for 40 ms
    array([0. , 0.1, 0.2, 0.3, 0.4])
    """
    fs = check_positive(fs, "fs", unit=" in Hz")
    rate = np.asarray(shaft_hz, dtype=np.float64)
    steps = 0.5 * (rate[1:] + rate[:-1]) / fs
    return np.concatenate([[0.0], np.cumsum(steps)])


# -------------------------------------------------------------------- a steady speed checked
# A harmonic stands out when the larger of its two bins would be reached by noise with at
# most this probability; the series is there when so many stand out that noise, over every
# candidate searched, would show as many with at most _SHAFT_LINES_P.
_SHAFT_LINE_P = 0.01
_SHAFT_LINES_P = 0.01
# The value of the larger of two exponential bins that noise exceeds with _SHAFT_LINE_P:
# 1 - (1 - exp(-v))**2 = p.
_SHAFT_LINE_Z = -math.log(1.0 - math.sqrt(1.0 - _SHAFT_LINE_P))


@dataclass(frozen=True)
class ShaftLines:
    """Result of :func:`shaft_lines`: the shaft's harmonic series near a given rate.

    Attributes
    ----------
    given_hz : float
        The rate searched around (Hz).
    found_hz : float
        Fundamental of the strongest harmonic series within the tolerance (Hz).
    n_harmonics : int
        Harmonics searched.
    n_standing : int
        Those of ``found_hz`` that stand out of the spectrum's background (each the peak of
        its neighbourhood, and reached by noise with a probability of 1 % at most); 0 where
        no candidate's first or second harmonic stands.
    strength : float
        Sum of ``log1p`` of the standing harmonics' values (each over the background).
    p_value : float
        Probability that noise shows a series with as many standing out at some candidate
        rate (a union bound over the candidates).
    tolerance : float
        Relative half-width of the search.
    """

    given_hz: float
    found_hz: float
    n_harmonics: int
    n_standing: int
    strength: float
    p_value: float
    tolerance: float

    @property
    def present(self) -> bool:
        """Whether the series stands clear of a random spectrum (``p_value`` at most 1 %)."""
        return self.p_value <= _SHAFT_LINES_P

    @property
    def offset(self) -> float:
        """``found_hz / given_hz - 1``."""
        return self.found_hz / self.given_hz - 1.0


def shaft_lines(
    x, fs: float, shaft_hz: float, *, tolerance: float = 0.05, n_harmonics: int = 20
) -> ShaftLines:
    """The shaft rate a steady record's own spectrum shows, near a given rate.

    Every rotating machine vibrates at multiples of its shaft rate, and those lines are
    usually the strongest of its spectrum. A rate from a name plate, a nominal speed or a
    file's RPM field can be off by a percent or more (an induction motor slips by up to a
    few percent under load), and a bearing's fault frequencies with it; an envelope analysis
    that places its fault combs and shaft masks at the given rate then looks in the wrong
    places (on the development records, a speed 1 % off turned 4 of 17 healthy-bearing
    checks into false alarms and 2 % off lost 5 of 31 faults).

    This finds the fundamental, within ``tolerance`` of ``shaft_hz``, whose first
    ``n_harmonics`` multiples stand highest in the record's spectrum (Hann window; each bin
    over the running median of two shaft periods around it, over ln 2, so that noise bins
    read as unit exponential variables). A harmonic stands where the larger of its two bins
    would be reached by noise with a probability of 1 % at most and is the peak of its
    neighbourhood (the skirt of a strong line nearby is no line); a candidate scores the
    ``log1p`` of its standing lines (one loud line, a mains harmonic, cannot carry it), and
    only a candidate whose first or second harmonic stands counts (unbalance, misalignment:
    an impact train near a multiple of the shaft rate puts lines on every third harmonic of
    some rate near it, none on its first). The rate is then fitted to the peaks of the
    standing harmonics (parabolic peaks, least squares; a tenth of a bin at the top
    harmonic). ``p_value`` says whether the series is there at all: a record without shaft
    harmonics at the given rate (a wrong channel, sampling rate or speed) shows no more
    standing lines than noise does.

    Parameters
    ----------
    x : array_like
        1-D vibration record at a steady speed.
    fs : float
        Sampling rate in Hz.
    shaft_hz : float
        The given shaft rate in Hz.
    tolerance : float
        Relative half-width of the search (below 0.5).
    n_harmonics : int
        Harmonics per candidate (fewer where they would pass 80 % of fs/2).

    Returns
    -------
    ShaftLines

    Raises
    ------
    ValueError
        On an invalid signal, rate or option.

    Examples
    --------
    A motor read as 1800 rpm that turns at 1746 rpm (3 % slip): six shaft harmonics in noise.

    >>> fs, rng = 12000.0, np.random.default_rng(0)
    >>> t = np.arange(int(4 * fs)) / fs
    >>> x = sum(np.cos(2 * np.pi * k * 29.1 * t) / k for k in range(1, 7))
    >>> found = shaft_lines(x + rng.standard_normal(t.size), fs, 30.0)
    >>> round(found.found_hz, 2), round(100 * found.offset, 1), found.present
    (29.1, -3.0, True)
    """
    x, fs, shaft_hz = _check_steady_record(x, fs, shaft_hz)
    tolerance = _check_tolerance(tolerance)
    n_harmonics = check_positive_int(n_harmonics, "n_harmonics")
    return _series_near(_line_spectrum(x, fs, shaft_hz), fs, shaft_hz, tolerance, n_harmonics)


def speed_check(
    x, fs: float, shaft_hz: float, *, near: float = 0.005, wide: float = 0.05,
    n_harmonics: int = 20,
) -> ShaftLines:  # fmt: skip
    """The record's shaft series around a given speed: the stronger of the best within
    ``near`` of it and the best within ``wide`` (the wide one where neither is present).

    Another source's lines can form a series at a rate close to the shaft's: impacts at a
    third of a neighbouring bearing's BPFO, 1.8 % above the shaft rate, have lines at every
    multiple of it, and outnumbered six strong shaft harmonics within 5 % (12 harmonics
    standing against 6) though they are weaker (a strength of 38 against 46). The series
    near the speed given is kept where it is the stronger. Both searches are
    :func:`shaft_lines`' on one spectrum.

    Parameters
    ----------
    x : array_like
        1-D vibration record at a steady speed.
    fs : float
        Sampling rate in Hz.
    shaft_hz : float
        The given shaft rate in Hz.
    near, wide : float
        Relative half-widths of the two searches (each below 0.5).
    n_harmonics : int
        Harmonics per candidate.

    Returns
    -------
    ShaftLines

    Raises
    ------
    ValueError
        On an invalid signal, rate or option.
    """
    x, fs, shaft_hz = _check_steady_record(x, fs, shaft_hz)
    near, wide = _check_tolerance(near, "near"), _check_tolerance(wide, "wide")
    n_harmonics = check_positive_int(n_harmonics, "n_harmonics")
    spectrum = _line_spectrum(x, fs, shaft_hz)
    close = _series_near(spectrum, fs, shaft_hz, near, n_harmonics)
    far = _series_near(spectrum, fs, shaft_hz, wide, n_harmonics)
    return close if close.present and close.strength >= far.strength else far


def _check_steady_record(x, fs, shaft_hz) -> tuple[np.ndarray, float, float]:
    fs = check_positive(fs, "fs", unit=" in Hz")
    x = check_varying(check_signal(x, fs))
    return x, fs, check_positive(shaft_hz, "shaft_hz", unit=" in Hz")


def _check_tolerance(value, name: str = "tolerance") -> float:
    value = check_positive(value, name)
    if value >= 0.5:
        raise ValueError(f"{name} must be below 0.5, got {value!r}")
    return value


def _line_spectrum(x: np.ndarray, fs: float, shaft_hz: float) -> tuple:
    """``(df, power, z)``: the Hann power spectrum of ``x`` and each bin over the running
    median of two shaft periods around it, over ln 2 (noise bins: unit exponential)."""
    df = fs / x.size
    power = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size))) ** 2
    half = max(int(round(shaft_hz / df)), 10)
    background = ndimage.median_filter(power, size=2 * half + 1, mode="nearest") / math.log(2.0)
    return df, power, power / np.maximum(background, np.finfo(float).tiny)


def _series_near(
    spectrum: tuple, fs: float, shaft_hz: float, tolerance: float, n_harmonics: int
) -> ShaftLines:
    """:func:`shaft_lines` on a spectrum from :func:`_line_spectrum`."""
    df, power, z = spectrum
    top = (1.0 + tolerance) * shaft_hz
    n_harm = min(n_harmonics, int(0.4 * fs / top))
    if n_harm < 1:
        raise ValueError(f"fs = {fs:g} Hz is too low for a shaft rate of {shaft_hz:g} Hz")
    k = np.arange(1, n_harm + 1)
    # Candidates close enough that the top harmonic moves by half a bin per step.
    grid = np.arange((1.0 - tolerance) * shaft_hz, top, df / (2.0 * n_harm))
    values = _harmonic_values(z, df, grid, k)[1]
    # Only lines that stand out count toward a candidate's score (summed as log1p, so that
    # one loud line, a mains harmonic, cannot carry it); the background's random bins at the
    # other harmonics would otherwise move the best candidate about.
    score = np.where(values >= _SHAFT_LINE_Z, np.log1p(values), 0.0).sum(axis=1)
    # A shaft's series starts at the shaft: its first or second harmonic stands (unbalance,
    # misalignment). Without that rule an impact train near a multiple of the shaft rate,
    # whose lines fall on every third harmonic of a rate close to the shaft's, can outscore
    # a shaft series of few harmonics.
    starts = _harmonic_lines(z, df, grid, k[:2])[1].any(axis=1)
    best = int(np.argmax(np.where(starts, score, -np.inf) if starts.any() else score))
    found = float(grid[best])
    at_found = values[best]
    standing = _harmonic_lines(z, df, grid[best : best + 1], k)[1][0] & starts[best]
    for _ in range(2):
        if not standing.any():
            break
        # The grid places the lines within a bin; their peaks place the rate finer, and a
        # harmonic the grid's step left a bin off stands at the fitted rate.
        found = _fit_fundamental(power, df, found, k[standing])
        at_found, standing = (a[0] for a in _harmonic_lines(z, df, np.array([found]), k))
    if not standing[: min(2, n_harm)].any():
        standing = np.zeros_like(standing)
    n_standing = int(standing.sum())
    tail = stats.binom.sf(n_standing - 1, n_harm, _SHAFT_LINE_P) if n_standing else 1.0
    return ShaftLines(
        given_hz=shaft_hz,
        found_hz=found,
        n_harmonics=n_harm,
        n_standing=n_standing,
        strength=float(np.log1p(at_found[standing]).sum()),
        p_value=float(min(1.0, grid.size * tail)),
        tolerance=tolerance,
    )


def _harmonic_values(
    z: np.ndarray, df: float, fundamentals: np.ndarray, k: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``(lo, values)`` of harmonics ``k`` of each fundamental: the lower of the two bins
    around each line, and the larger of their values (the line falls between them)."""
    lo = np.clip(np.floor(np.outer(fundamentals, k) / df).astype(int), 0, z.size - 2)
    return lo, np.maximum(z[lo], z[lo + 1])


def _harmonic_lines(
    z: np.ndarray, df: float, fundamentals: np.ndarray, k: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``(values, stands)`` of harmonics ``k`` of each fundamental: the larger of the two bins
    around each, and whether it stands out (reached by noise with probability
    _SHAFT_LINE_P at most, and the peak of its neighbourhood: the skirt of a strong line a
    few bins away is no line here)."""
    lo, values = _harmonic_values(z, df, fundamentals, k)
    around = np.clip(lo[:, :, None] + np.arange(-2, 4), 0, z.size - 1)
    stands = (values >= _SHAFT_LINE_Z) & (values >= z[around].max(axis=2))
    return values, stands


def _fit_fundamental(power: np.ndarray, df: float, f0: float, k: np.ndarray) -> float:
    """Fundamental fitted to the peaks of harmonics ``k`` of ``f0``.

    Each peak's frequency comes from a parabola through the log power of its top bin (within
    two bins of ``k * f0``) and their neighbours. The median of ``f_k / k`` gives a first
    rate; peaks more than half a bin from its multiples (a noise peak that stood out, one in
    a hundred of the harmonics sought) are left out, and the rest fitted by least squares of
    ``f_k = k * f``, where a high harmonic weighs most."""
    centre = np.rint(k * f0 / df).astype(int)
    window = np.clip(centre[:, None] + np.arange(-2, 3)[None, :], 1, power.size - 2)
    top = window[np.arange(k.size), np.argmax(power[window], axis=1)]
    tiny = np.finfo(float).tiny
    left, mid, right = (np.log(np.maximum(power[top + d], tiny)) for d in (-1, 0, 1))
    curve = left - 2.0 * mid + right
    shift = np.where(curve < 0.0, 0.5 * (left - right) / np.where(curve < 0.0, curve, -1.0), 0.0)
    f_k = (top + np.clip(shift, -0.5, 0.5)) * df
    first = float(np.median(f_k / k))
    keep = np.abs(f_k - k * first) <= 0.5 * df
    if not keep.any():
        return first
    return float((k[keep] * f_k[keep]).sum() / (k[keep] ** 2).sum())


# ------------------------------------------------------------------------------ tachometer
# Half-width of the trigger's hysteresis band, as a fraction of the signal's 1-99 % range.
_TACHO_HYSTERESIS = 0.2


def speed_from_tacho(
    tacho, fs: float, pulses_per_rev: int = 1, threshold: float | None = None
) -> np.ndarray:
    """Shaft rate at every sample from a tachometer pulse train.

    A pulse starts where the signal rises above ``threshold`` plus a hysteresis band (a fifth
    of the signal's 1-99 % range) after it was last below ``threshold`` less that band, so
    noise near the threshold cannot make pulses of its own (a Schmitt trigger); its edge is
    the threshold crossing that starts the rise, located to a fraction of a sample (linear
    interpolation between the samples either side). Edge ``k`` is at shaft angle
    ``k / pulses_per_rev`` revolutions. A monotone cubic (PCHIP) through these angles is
    differentiated at every sample; before the first and after the last edge the rate is
    held at its value there.

    Parameters
    ----------
    tacho : array_like
        1-D pulse signal (any unit): a once- or N-per-revolution key-phasor or encoder.
    fs : float
        Sampling rate in Hz.
    pulses_per_rev : int
        Pulses per shaft revolution.
    threshold : float, optional
        Level of the rising edges; default halfway between the 1st and 99th percentiles.

    Returns
    -------
    numpy.ndarray
        Shaft rate (Hz) at every sample of ``tacho``.

    Raises
    ------
    ValueError
        On an invalid signal, rate or pulse count, a constant signal, a threshold that no
        edge crosses, fewer than three edges, or an interval between pulses far from those
        around it (a pulse missing or doubled).

    Examples
    --------
    >>> fs = 1000.0
    >>> t = np.arange(2000) / fs
    >>> tacho = (np.sin(2 * np.pi * 5.0 * t) > 0.9).astype(float)     # 5 rev/s, 1 pulse
    >>> rate = speed_from_tacho(tacho, fs)
    >>> round(float(rate[1000]), 3)
    5.0
    """
    x = check_varying(check_signal(tacho, fs, name="tacho"), "tacho")
    fs = float(fs)
    ppr = check_positive_int(pulses_per_rev, "pulses_per_rev")
    low, high = np.percentile(x, [1.0, 99.0])
    if high <= low:  # pulses narrower than 1 % of the record
        low, high = float(x.min()), float(x.max())
    if threshold is None:
        threshold = 0.5 * (low + high)
    else:
        threshold = float(threshold)
        if not (x.min() < threshold < x.max()):
            raise ValueError(
                f"threshold {threshold:g} is outside the tacho signal's range "
                f"({x.min():g} .. {x.max():g})"
            )
    # Hysteresis (a Schmitt trigger): a pulse starts where the signal rises above the upper
    # level after it was last below the lower one, so noise near the threshold cannot make
    # a pulse of its own. The band narrows where a given threshold lies near either end.
    band = max(0.0, min(_TACHO_HYSTERESIS * (high - low), 0.5 * (high - threshold),
                        0.5 * (threshold - low)))  # fmt: skip
    state = np.full(x.size, -1)
    state[x <= threshold - band] = 0
    state[x >= threshold + band] = 1
    known = np.maximum.accumulate(np.where(state >= 0, np.arange(x.size), 0))
    held = np.where(state[known] >= 0, state[known], 0)
    rises = np.flatnonzero((held[:-1] == 0) & (held[1:] == 1)) + 1
    # Each edge at the threshold crossing that starts the rise, to a fraction of a sample
    # (linear interpolation across it).
    last_below = np.maximum.accumulate(np.where(x < threshold, np.arange(x.size), -1))
    edges = last_below[rises]
    edges = edges[(edges >= 0) & (edges < x.size - 1)]
    if edges.size < 3:
        raise ValueError(
            f"tacho holds {edges.size} rising edge(s) through {threshold:g}; need at least 3 "
            "(check the channel, threshold and pulses_per_rev)"
        )
    a, b = x[edges], x[edges + 1]
    times = (edges + (threshold - a) / (b - a)) / fs
    # A pulse missing or doubled shows as one interval far from its neighbours' (a real
    # speed change between two pulses is a few percent).
    intervals = np.diff(times)
    if intervals.size >= 3:
        typical = ndimage.median_filter(intervals, size=5, mode="nearest")
        odd = np.flatnonzero((intervals < 0.6 * typical) | (intervals > 1.6 * typical))
        if odd.size:
            raise ValueError(
                f"tacho pulse interval at {times[odd[0]]:.4g} s is {intervals[odd[0]] * 1e3:.4g} "
                f"ms against {typical[odd[0]] * 1e3:.4g} ms around it: a pulse missing or "
                "doubled, or the speed changing by over 40 % within a few pulses (check the "
                "channel, threshold and pulses_per_rev)"
            )
    angle = np.arange(edges.size) / ppr
    t = np.arange(x.size) / fs
    curve = interpolate.PchipInterpolator(times, angle, extrapolate=False)
    rate = curve.derivative()(np.clip(t, times[0], times[-1]))
    if not np.all(np.isfinite(rate) & (rate > 0)):
        raise ValueError("tacho edges are not in increasing angle (a pulse missing or doubled)")
    return rate


# ----------------------------------------------------------------------- from the vibration
@dataclass(frozen=True)
class SpeedEstimate:
    """Result of :func:`estimate_speed`.

    Attributes
    ----------
    shaft_hz : numpy.ndarray
        Shaft rate (Hz) at every sample of the record.
    confidence : float
        In [0, 1]: the share of spectrogram frames whose ridge stands clearly above the
        frame's other candidate rates (4 robust standard deviations; noise rarely reaches it).
    times : numpy.ndarray
        Frame centres (s).
    ridge_hz : numpy.ndarray
        Shaft rate of each frame.
    salience : numpy.ndarray
        Each frame's ridge value over that frame's median in the search range, in robust
        standard deviations of the frame's candidates.
    """

    shaft_hz: np.ndarray = field(repr=False)
    confidence: float
    times: np.ndarray = field(repr=False)
    ridge_hz: np.ndarray = field(repr=False)
    salience: np.ndarray = field(repr=False)


# A frame counts toward the confidence when its ridge stands this many robust standard
# deviations above the frame's other candidate rates.
_SALIENCE = 4.0
# Frame lengths tried: 2 periods of f_min, then doubled up to this many times.
_FRAME_DOUBLINGS = 4
# Frames needed to tell lines that move from lines that stay.
_MIN_FRAMES_MOVING = 8


def estimate_speed(
    x,
    fs: float,
    f_min: float,
    f_max: float,
    *,
    n_harmonics: int = 8,
    nperseg: int | None = None,
    max_change: float = 0.5,
) -> SpeedEstimate:
    """Shaft rate over a record from the vibration alone: the speed ridge of the spectrogram.

    Every rotating machine vibrates at multiples of its shaft rate. Each spectrogram frame is
    whitened (every bin over the running median of its neighbourhood, compressed by
    ``log1p``, so that a line counts by how far it stands out and one loud resonance or
    fault line cannot carry a candidate alone) and summed over ``n_harmonics`` multiples of
    every candidate rate in ``f_min..f_max``, less the sum half-way between them (harmonic
    summation: the true rate collects all its harmonics, half of it as many but also the
    empty places between, twice it only every other one). The ridge is the path through the
    frames that maximises that sum while the rate changes by at most ``max_change`` of
    itself per second (dynamic programming); each frame's rate is the centroid of its peak
    above half height, which a changing speed flattens. Frames of 2, 4, 8, 16 and 32
    periods of ``f_min`` are tried and the one whose ridge stands highest over the other
    candidates is kept: measured spectra hold lines a few hertz apart (CWRU's, at shaft
    harmonics and a cage rate above them) that only long frames resolve, while a fast speed
    change wants short ones. Lines that keep their frequency through the record (the mains and its
    harmonics, a fixed tone) form series of their own that can outweigh weak shaft
    harmonics; each frame length is therefore also searched with every bin's median over
    the frames taken out, and a ridge found clearly there (half the frames salient; at least
    8 frames) is preferred: one that moves is the shaft's. The rate at every sample is a
    monotone cubic through the frame centres, held at the ends.

    Give the narrowest range the machine allows: a strong fault's lines form harmonic series
    of their own (an inner-race fault's lines ``n BPFI + m fr`` hold one at ``BPFI - 3 fr``)
    that can outweigh weak shaft harmonics. On the 31 development records (CWRU, MFPT),
    sought within 20-35 Hz, the rate is found within 0.2 % of the CWRU files' RPM and 1 % of
    MFPT's nominal 25 Hz in 25 of them; the other six get a confidence of 0 (five of MFPT's
    inner-race records, one record too short). A fast change on such a line-rich spectrum is
    not followed: CWRU records replayed with the shaft slowing from full to half speed in
    13 s read at half the rate or below, since frames short enough to follow the change
    cannot tell the lines a cage rate from the shaft harmonics from those half-way between;
    the confidence stays low there (0.00-0.11).

    Parameters
    ----------
    x : array_like
        1-D vibration record.
    fs : float
        Sampling rate in Hz.
    f_min, f_max : float
        Range of the shaft rate in Hz (``0 < f_min < f_max``, ``n_harmonics * f_max`` below
        fs/2).
    n_harmonics : int
        Shaft harmonics summed per candidate.
    nperseg : int, optional
        Spectrogram frame in samples. Default: the best of 2, 4, 8, 16 and 32 periods of
        ``f_min`` (rounded up to powers of two) that leave two frames in the record.
    max_change : float
        Largest relative change of the rate per second along the ridge.

    Returns
    -------
    SpeedEstimate
        Rate per sample, confidence, and the frame ridge behind it.

    Raises
    ------
    ValueError
        On an invalid signal, rate or range, or a record shorter than two frames.

    Examples
    --------
    >>> fs = 4000.0
    >>> t = np.arange(int(8 * fs)) / fs
    >>> rate = 10.0 + 1.25 * t                               # 10 -> 20 Hz over 8 s
    >>> angle = np.cumsum(rate) / fs
    >>> x = sum(np.cos(2 * np.pi * k * angle) for k in range(1, 6))
    >>> est = estimate_speed(x, fs, 5.0, 30.0)
    >>> bool(np.allclose(est.shaft_hz[4000:-4000], rate[4000:-4000], rtol=0.03))
    True
    >>> est.confidence > 0.9
    True
    """
    x = check_varying(check_signal(x, fs))
    fs = float(fs)
    f_min = check_positive(f_min, "f_min", unit=" in Hz")
    f_max = check_positive(f_max, "f_max", unit=" in Hz")
    if f_min >= f_max:
        raise ValueError(f"f_min ({f_min:g} Hz) must be below f_max ({f_max:g} Hz)")
    n_harmonics = check_positive_int(n_harmonics, "n_harmonics")
    if n_harmonics * f_max >= fs / 2.0:
        raise ValueError(
            f"n_harmonics * f_max = {n_harmonics * f_max:g} Hz must be below fs/2 = {fs / 2:g} Hz"
        )
    max_change = check_positive(max_change, "max_change")
    # Two periods of f_min, the shortest frame tried: a resolution of f_min / 2.
    shortest = int(2 ** math.ceil(math.log2(2.0 * fs / f_min)))
    if nperseg is None:
        frames = [shortest * 2**j for j in range(_FRAME_DOUBLINGS + 1)]
        frames = [n for n in frames if x.size >= 2 * n] or [shortest]
    else:
        frames = [check_positive_int(nperseg, "nperseg", minimum=16)]
    if x.size < 2 * frames[0]:
        raise ValueError(
            f"x is too short to track the speed down to f_min = {f_min:g} Hz: {x.size} "
            f"samples ({x.size / fs:.3g} s), need at least {2 * frames[0]} "
            f"({2 * frames[0] / fs:.3g} s: two frames of {frames[0]}, each two periods of "
            "f_min or more); raise f_min or give nperseg"
        )
    # The frame whose ridge stands highest over its candidates: long frames resolve lines a
    # few hertz apart (measured spectra are full of them), short ones follow a fast change.
    ridges, moving = [], []
    for n in frames:
        times, df, level = _whitened_spectrogram(x, fs, f_min, f_max, n, n_harmonics)
        ridges.append(_ridge(level, times, df, f_min, f_max, n_harmonics, max_change))
        # Lines that keep their frequency all through the record (the mains, a fixed tone)
        # can outweigh weak shaft harmonics: with each bin's median over the frames taken
        # out, a ridge that moves, found clearly, is the shaft's.
        if times.size >= _MIN_FRAMES_MOVING:
            stays = np.median(level, axis=1, keepdims=True)
            found = _ridge(
                np.maximum(level - stays, 0.0), times, df, f_min, f_max, n_harmonics, max_change
            )
            if np.mean(found[2] >= _SALIENCE) >= 0.5:
                moving.append(found)
    times, ridge_hz, frame_salience = max(moving or ridges, key=lambda r: float(np.median(r[2])))
    confidence = float(np.mean(frame_salience >= _SALIENCE))
    t = np.arange(x.size) / fs
    if times.size == 1:
        rate = np.full(x.size, ridge_hz[0])
    else:
        curve = interpolate.PchipInterpolator(times, ridge_hz)
        rate = curve(np.clip(t, times[0], times[-1]))
    return SpeedEstimate(rate, confidence, times, ridge_hz, frame_salience)


def _whitened_spectrogram(
    x: np.ndarray, fs: float, f_min: float, f_max: float, nperseg: int, n_harmonics: int
) -> tuple[np.ndarray, float, np.ndarray]:
    """Frame centres (s), bin spacing (Hz) and whitened, log-compressed spectrogram of one
    frame length, up to the top harmonic of ``f_max``."""
    hop = nperseg // 4
    nfft = 4 * nperseg  # zero-padded: harmonics read between bins without scalloping bias
    df = fs / nfft
    # Whitening reaches this far either side of a bin; harmonics above the top one are unused.
    half = max(int(round(4.0 * f_min / df)), 8)
    top = int(min(nfft // 2 + 1, math.ceil((n_harmonics + 0.5) * f_max / df) + half + 2))
    # Frame by frame, keeping only the bins up to the top harmonic: a long frame's padded
    # spectrum of a long record would not fit in memory whole.
    window = signal.get_window("hann", nperseg)
    starts = np.arange(0, x.size - nperseg + 1, hop)
    times = (starts + nperseg / 2) / fs
    centred = x - x.mean()
    power = np.empty((top, starts.size))
    for j, start in enumerate(starts):
        spectrum = np.fft.rfft(centred[start : start + nperseg] * window, nfft)
        power[:, j] = np.abs(spectrum[:top]) ** 2
    # Each bin over the running median of its frame's spectrum, compressed by log1p: a shaft
    # harmonic counts by how far it stands above its neighbourhood, and a loud line (a
    # resonance, a fault or electrical tone) counts little more than a clear one.
    background = ndimage.median_filter(power, size=(2 * half + 1, 1), mode="nearest")
    return times, df, np.log1p(power / np.maximum(background, np.finfo(float).tiny))


def _ridge(
    level: np.ndarray,
    times: np.ndarray,
    df: float,
    f_min: float,
    f_max: float,
    n_harmonics: int,
    max_change: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Frame centres, ridge rate and ridge salience through a whitened spectrogram."""
    # Candidate rates on a grid finer than the frame's resolution shared by the harmonics.
    step = 4.0 * df / (2.0 * n_harmonics)
    grid = np.arange(f_min, f_max + step / 2, step)
    columns = np.tile(np.arange(times.size), grid.size)

    def at(multiple: float) -> np.ndarray:
        position = np.repeat(multiple * grid / df, times.size)
        return ndimage.map_coordinates(level, [position, columns], order=1).reshape(
            grid.size, times.size
        )

    # Harmonic sum less the sum half-way between harmonics: half the true rate collects
    # every line of it but also the empty places between, so it cannot tie with it.
    summed = np.zeros((grid.size, times.size))
    for k in range(1, n_harmonics + 1):
        summed += at(k) - at(k - 0.5)
    ridge = _best_path(summed, grid, times, max_change)
    # Salience: the ridge over its frame's candidates, in robust standard deviations.
    centre = np.median(summed, axis=0)
    spread = 1.4826 * np.median(np.abs(summed - centre), axis=0)
    on_ridge = summed[ridge, np.arange(times.size)]
    salience = (on_ridge - centre) / np.maximum(spread, np.finfo(float).tiny)
    # The compressed sum flattens a peak where the lines are spread (the speed changes within
    # a frame), so its maximum may sit anywhere on the plateau: the rate is the centroid of
    # the peak above half its height over the frame's median.
    rate_hz = np.empty(times.size)
    for j in range(times.size):
        column, p = summed[:, j], ridge[j]
        if column[p] <= centre[j]:  # no peak (a frame of noise): the path's own rate
            rate_hz[j] = grid[p]
            continue
        level_half = 0.5 * (column[p] + centre[j])
        lo = p
        while lo > 0 and column[lo - 1] > level_half:
            lo -= 1
        hi = p
        while hi < grid.size - 1 and column[hi + 1] > level_half:
            hi += 1
        weight = column[lo : hi + 1] - level_half
        rate_hz[j] = float(np.sum(weight * grid[lo : hi + 1]) / np.sum(weight))
    return times, rate_hz, salience


def _best_path(score: np.ndarray, grid: np.ndarray, times: np.ndarray, max_change: float):
    """Grid index per frame maximising the summed score, the rate changing from one frame to
    the next by at most ``max_change`` of itself per second."""
    n_grid, n_frames = score.shape
    dt = times[1] - times[0] if times.size > 1 else 1.0
    # Cells each candidate may come from: +-max_change * dt of its own rate.
    cells = np.arange(n_grid)
    reach = np.maximum(1, np.ceil(max_change * dt * grid / (grid[1] - grid[0]))).astype(np.int64)
    lo = np.maximum(cells - reach, 0)
    hi = np.minimum(cells + reach, n_grid - 1)
    # Range-maximum queries over [lo, hi] by a sparse table: the larger of two overlapping
    # power-of-two windows.
    span = np.floor(np.log2(hi - lo + 1)).astype(np.int64)
    total = score[:, 0].copy()
    back = np.zeros((n_grid, n_frames), dtype=np.int64)
    for j in range(1, n_frames):
        best = [cells.copy()]  # index of the maximum of total over [i, i + 2**k)
        for k in range(1, int(span.max()) + 1):
            prev = best[-1]
            shifted = np.concatenate([prev[1 << (k - 1) :], prev[-1:].repeat(1 << (k - 1))])
            best.append(np.where(total[shifted] > total[prev], shifted, prev))
        table = np.stack(best)
        left = table[span, lo]
        right = table[span, hi - (1 << span) + 1]
        origin = np.where(total[right] > total[left], right, left)
        back[:, j] = origin
        total = total[origin] + score[:, j]
    path = np.empty(n_frames, dtype=np.int64)
    path[-1] = int(np.argmax(total))
    for j in range(n_frames - 1, 0, -1):
        path[j - 1] = back[path[j], j]
    return path


# --------------------------------------------------------------------------- order tracking
@dataclass(frozen=True)
class OrderTrack:
    """Result of :func:`order_track`.

    Attributes
    ----------
    x : numpy.ndarray
        The record at uniform shaft-angle increments.
    samples_per_rev : float
        Angular sampling rate: samples per shaft revolution (the "fs" of the order domain,
        where frequencies are orders, cycles per revolution).
    angle : numpy.ndarray
        Shaft angle (revolutions) of each resampled point.
    times : numpy.ndarray
        Time (s) of each resampled point.
    cutoff_order : float
        Highest order the result holds over the whole record: the anti-aliasing cut-off, or
        the record's own band (fs/2) at its fastest speed, whichever is lower. Above it,
        orders are held only while the shaft turns slowly enough, or not at all.
    """

    x: np.ndarray = field(repr=False)
    samples_per_rev: float
    angle: np.ndarray = field(repr=False)
    times: np.ndarray = field(repr=False)
    cutoff_order: float


def order_track(x, fs: float, shaft_hz, samples_per_rev: float, *, axis: int = -1) -> OrderTrack:
    """Resample a record at uniform shaft-angle increments (computed order tracking).

    The shaft angle is the integral of ``shaft_hz``; the record is evaluated at angles
    ``k / samples_per_rev`` by cubic interpolation. An angular sampling of ``samples_per_rev``
    holds orders up to ``samples_per_rev / 2``; at the slowest speed that is
    ``samples_per_rev / 2 * min(shaft_hz)`` Hz, so where that lies below fs/2 the record is
    first low-passed (zero-phase Butterworth, 8th order) at 0.8 of that frequency: nothing
    above the angular Nyquist order folds back. Where it does not, nothing can fold and the
    record is not filtered.

    Parameters
    ----------
    x : array_like
        Record, samples along ``axis`` (several channels at once for a 2-D ``x``).
    fs : float
        Sampling rate in Hz.
    shaft_hz : float or array_like
        Shaft rate (Hz): one value, or one per sample.
    samples_per_rev : float
        Angular sampling rate of the result, samples per revolution.
    axis : int
        Axis of ``x`` that runs along time.

    Returns
    -------
    OrderTrack
        ``x`` resampled in angle (same axis), its angles and times.

    Raises
    ------
    ValueError
        On an invalid record, rate, speed profile or angular rate, or a record shorter than
        two revolutions.

    Examples
    --------
    >>> fs = 2000.0
    >>> t = np.arange(int(4 * fs)) / fs
    >>> rate = 5.0 + 2.5 * t                                 # 5 -> 15 rev/s
    >>> x = np.cos(2 * np.pi * 3.0 * shaft_angle(rate, fs))  # order 3
    >>> ot = order_track(x, fs, rate, samples_per_rev=64)
    >>> spectrum = np.abs(np.fft.rfft(ot.x))
    >>> orders = np.fft.rfftfreq(ot.x.size, 1.0 / ot.samples_per_rev)
    >>> round(float(orders[np.argmax(spectrum)]), 2)
    3.0
    """
    fs = check_positive(fs, "fs", unit=" in Hz")
    data = check_signals(x, fs, axis)
    n = data.shape[-1]
    rate = np.asarray(shaft_hz, dtype=np.float64)
    if rate.ndim == 0:
        rate = np.full(n, check_positive(float(rate), "shaft_hz", unit=" in Hz"))
    else:
        rate = check_speed_profile(rate, n)
    spr = check_positive(samples_per_rev, "samples_per_rev")
    angle = shaft_angle(rate, fs)
    if angle[-1] < 2.0:
        raise ValueError(
            f"the record covers {angle[-1]:.3g} shaft revolutions; order tracking needs at least 2"
        )
    # Where the slowest speed's angular Nyquist reaches fs/2 nothing can fold back (the
    # record holds nothing above fs/2), and a low-pass would only cut the top of the band.
    filtered = 0.5 * spr * float(rate.min()) < 0.5 * fs * 0.999
    if filtered:
        cutoff_hz = 0.8 * 0.5 * spr * float(rate.min())
        sos = signal.butter(8, cutoff_hz, btype="lowpass", output="sos", fs=fs)
        padlen = min(3 * (2 * len(sos) + 1), n - 1)
        data = signal.sosfiltfilt(sos, data, axis=-1, padlen=padlen)
    targets = np.arange(0.0, angle[-1], 1.0 / spr)
    times = np.interp(targets, angle, np.arange(n) / fs)
    spline = interpolate.make_interp_spline(angle, data, k=3, axis=-1)
    resampled = spline(targets)
    resampled = resampled if resampled.ndim == 1 else np.moveaxis(resampled, -1, axis)
    # Orders held everywhere in the record: up to the filter's cut-off (if any) and the
    # record's own band at its fastest.
    cutoff_order = min(0.4 * spr if filtered else 0.5 * spr, 0.5 * fs / float(rate.max()))
    return OrderTrack(resampled, spr, targets, times, cutoff_order)
