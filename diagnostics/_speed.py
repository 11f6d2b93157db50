"""Shaft speed that varies over a record: the shaft angle, the rate from a tachometer, and
angular resampling (order tracking).

A bearing's fault frequencies are fixed multiples (orders) of the shaft rate. When the speed
changes over a record, each fault line of the envelope spectrum smears over the range the
speed covers; resampled at constant shaft-angle increments, the record turns the fault
frequencies back into fixed orders (cycles per revolution), and its envelope spectrum shows
them as lines again. The rate without a tachometer is estimated in
:mod:`diagnostics._speed_estimate`, a steady speed checked on the record in
:mod:`diagnostics._shaft_lines`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import interpolate, ndimage, signal

from diagnostics._checks import (
    check_positive,
    check_positive_int,
    check_signal,
    check_signals,
    check_varying,
    normalise,
)

__all__ = ["OrderTrack", "check_speed_profile", "order_track", "shaft_angle", "speed_from_tacho"]


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

    References
    ----------
    Fyfe, K. R. and Munck, E. D. S. (1997). Analysis of computed order tracking. *Mechanical
    Systems and Signal Processing* 11(2), 187-205.

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
    given = threshold
    if given is not None:
        given = float(given)
        if not (x.min() < given < x.max()):
            raise ValueError(
                f"threshold {given:g} is outside the tacho signal's range "
                f"({x.min():g} .. {x.max():g})"
            )
    # The edges are where the signal crosses a level: in any unit, at the same samples.
    x, scale = normalise(x)
    low, high = np.percentile(x, [1.0, 99.0])
    if high <= low:  # pulses narrower than 1 % of the record
        low, high = float(x.min()), float(x.max())
    if given is None:
        threshold = 0.5 * (low + high)
        given = float(np.ldexp(threshold, scale.exponent.item()))  # for the message
    else:
        threshold = float(np.ldexp(given, -scale.exponent.item()))
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
            f"tacho holds {edges.size} rising edge(s) through {given:g}; need at least 3 "
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

    References
    ----------
    Fyfe, K. R. and Munck, E. D. S. (1997). Analysis of computed order tracking. *Mechanical
    Systems and Signal Processing* 11(2), 187-205.

    Borghesani, P., Pennacchi, P., Randall, R. B., Sawalhi, N. and Ricci, R. (2013).
    Application of cepstrum pre-whitening for the diagnosis of bearing faults under variable
    speed conditions. *Mechanical Systems and Signal Processing* 36(2), 370-384.

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
    data, scale = normalise(check_signals(x, fs, axis))
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
    resampled = scale.restore(spline(targets), what="the order-tracked record")
    resampled = resampled if resampled.ndim == 1 else np.moveaxis(resampled, -1, axis)
    # Orders held everywhere in the record: up to the filter's cut-off (if any) and the
    # record's own band at its fastest.
    cutoff_order = min(0.4 * spr if filtered else 0.5 * spr, 0.5 * fs / float(rate.max()))
    return OrderTrack(resampled, spr, targets, times, cutoff_order)
