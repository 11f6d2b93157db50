"""Spectral estimates: the short-time Fourier transform (:func:`stft`), Welch's PSD
(:func:`psd`) and one-third-octave band levels (:func:`third_octave`,
:func:`third_octave_centres`)."""

from __future__ import annotations

import math

import numpy as np
from scipy import signal

from diagnostics._checks import (
    check_fs,
    check_positive,
    check_positive_int,
    check_signals,
    normalise,
)

# IEC 61260-1 base-ten band ratio: centres 1000 * 10**(k/10), edges at centre * 10**(+-1/20).
_OCTAVE_RATIO_EXPONENT = 0.1
_EDGE_EXPONENT = 0.05


def stft(
    x,
    fs: float,
    nperseg: int = 256,
    noverlap: int | None = None,
    window: str = "hann",
    axis: int = -1,
):
    """Short-time Fourier transform, frames taken from the signal only (no edge padding).

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis``.
    fs : float
        Sampling rate in Hz.
    nperseg : int
        Frame length in samples.
    noverlap : int, optional
        Overlap between frames in samples; ``nperseg // 2`` when omitted.
    window : str
        Window name understood by ``scipy.signal.get_window``.
    axis : int
        Axis of ``x`` along which the samples run.

    Returns
    -------
    f : numpy.ndarray
        Frequencies in Hz (``nperseg // 2 + 1`` values).
    t : numpy.ndarray
        Frame centres in seconds.
    Z : numpy.ndarray
        Complex STFT, shape ``(len(f), len(t))`` for a 1-D ``x``; for more dimensions the
        other axes of ``x`` (channels) first, then frequency and time, as
        ``scipy.signal.stft`` gives them. Scaled as scipy does (a sinusoid of amplitude A
        reads A/2 at its bin).

    Raises
    ------
    ValueError
        On an invalid signal, ``fs`` or axis, a frame longer than the signal, or an overlap
        not in 0..nperseg-1.

    Examples
    --------
    >>> fs = 1000.0
    >>> x = np.cos(2 * np.pi * 125.0 * np.arange(1024) / fs)
    >>> f, t, Z = stft(np.stack([x, 3 * x]), fs, nperseg=64)
    >>> Z.shape, float(f[np.argmax(np.abs(Z[1, :, 5]))]), round(float(np.abs(Z[1, 8, 5])), 2)
    ((2, 33, 31), 125.0, 1.5)
    """
    nperseg = check_positive_int(nperseg, "nperseg", minimum=2)
    x, scale = normalise(check_signals(x, fs, axis, min_length=nperseg))
    if noverlap is None:
        noverlap = nperseg // 2
    noverlap = check_positive_int(noverlap, "noverlap", minimum=0)
    if noverlap >= nperseg:
        raise ValueError(f"noverlap ({noverlap}) must be smaller than nperseg ({nperseg})")
    try:
        signal.get_window(window, nperseg)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"window {window!r} is not a valid window: {exc}") from None
    f, t, Z = signal.stft(
        x,
        fs=fs,
        window=window,
        nperseg=nperseg,
        noverlap=noverlap,
        boundary=None,
        padded=False,
        axis=-1,
    )
    return f, t, scale.restore(Z, what="the STFT of x", trailing=2)


def _frequency_axis_back(y: np.ndarray, axis: int) -> np.ndarray:
    """Put a result's last (frequency) axis where the time axis ``axis`` was."""
    return y if y.ndim == 1 else np.moveaxis(y, -1, axis)


def psd(x, fs: float, nperseg: int = 4096, axis: int = -1):
    """Power spectral density by Welch's method (Hann window, 50 % overlap).

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis``.
    fs : float
        Sampling rate in Hz.
    nperseg : int
        Segment length in samples; must not exceed the signal length.
    axis : int
        Axis of ``x`` along which the samples run; the frequency axis of ``Pxx`` takes its
        place.

    Returns
    -------
    f : numpy.ndarray
        Frequencies in Hz.
    Pxx : numpy.ndarray
        One-sided PSD in units**2/Hz; its integral over f is the signal's mean square.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs`` or axis, a segment longer than the signal, or a PSD
        outside the range of float64 numbers in the record's unit squared (a record of
        values near 1e300 or 1e-300): give ``x`` in another unit.

    References
    ----------
    Welch, P. D. (1967). The use of fast Fourier transform for the estimation of power
    spectra: a method based on time averaging over short, modified periodograms. *IEEE
    Transactions on Audio and Electroacoustics* 15(2), 70-73.

    Examples
    --------
    >>> x = np.random.default_rng(0).standard_normal((2, 48000)) * [[1.0], [2.0]]
    >>> f, p = psd(x, 48000.0, nperseg=1024)
    >>> np.round(p.sum(axis=-1) * f[1], 1)             # mean squares 1 and 4
    array([1., 4.])
    """
    nperseg = check_positive_int(nperseg, "nperseg", minimum=2)
    data, scale = normalise(check_signals(x, fs, axis, min_length=nperseg))
    f, p = signal.welch(data, fs=fs, window="hann", nperseg=nperseg, scaling="density", axis=-1)
    return f, _frequency_axis_back(scale.restore(p, power=2, what="the PSD of x"), axis)


def third_octave_centres(f_min: float, f_max: float) -> np.ndarray:
    r"""Exact IEC 61260-1 base-ten one-third-octave centres whose band overlaps f_min..f_max.

    Parameters
    ----------
    f_min, f_max : float
        Frequency range in Hz, 0 < f_min < f_max.

    Returns
    -------
    numpy.ndarray
        Centres :math:`1000 \cdot 10^{k/10}` Hz in increasing order.

    References
    ----------
    IEC 61260-1:2014. *Electroacoustics - Octave-band and fractional-octave-band filters -
    Part 1: Specifications*. International Electrotechnical Commission, Geneva.
    """
    f_min = check_positive(f_min, "f_min")
    f_max = check_positive(f_max, "f_max")
    if f_min >= f_max:
        raise ValueError(f"f_min ({f_min:g} Hz) must be below f_max ({f_max:g} Hz)")
    # Band k spans 1000 * 10**((k -+ 0.5)/10); keep every band that overlaps the range.
    k_lo = math.floor(10.0 * math.log10(f_min / 1000.0) + 0.5)
    k_hi = math.ceil(10.0 * math.log10(f_max / 1000.0) - 0.5)
    k = np.arange(k_lo, k_hi + 1)
    return 1000.0 * 10.0 ** (_OCTAVE_RATIO_EXPONENT * k)


def third_octave(
    x,
    fs: float,
    f_min: float = 20.0,
    f_max: float | None = None,
    ref: float = 1.0,
    axis: int = -1,
):
    r"""One-third-octave band levels (IEC 61260-1 base-ten bands) from the signal's spectrum.

    The power of each band is the sum of the periodogram bins inside its edges
    :math:`f_c 10^{-0.05} \le f < f_c 10^{0.05}`. Adjacent bands share their edges, so the band
    powers add up to the signal's power over the range they cover (Parseval).

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis``.
    fs : float
        Sampling rate in Hz.
    f_min : float
        Lowest frequency of interest in Hz; the first band is the one containing it.
    f_max : float, optional
        Highest frequency of interest in Hz (default fs/2). Bands reaching above fs/2 are
        dropped, since the spectrum ends there.
    ref : float
        Reference value: levels are :math:`10 \log_{10}(\mathrm{power} / \mathrm{ref}^2)` dB.
    axis : int
        Axis of ``x`` along which the samples run; the band axis of ``level_db`` takes its
        place.

    Returns
    -------
    fc : numpy.ndarray
        Exact band centres in Hz.
    level_db : numpy.ndarray
        Band levels in dB re ``ref``; ``-inf`` for a band holding no power.

    Raises
    ------
    ValueError
        On an invalid signal or ``fs``, a range that holds no complete band, or a record
        too short to resolve the lowest band (its bins are farther apart than the band is
        wide): raise ``f_min`` or give a longer record.

    References
    ----------
    IEC 61260-1:2014. *Electroacoustics - Octave-band and fractional-octave-band filters -
    Part 1: Specifications*. International Electrotechnical Commission, Geneva.

    Examples
    --------
    >>> fs = 8000.0
    >>> x = np.sin(2 * np.pi * 1000.0 * np.arange(8000) / fs)
    >>> fc, level = third_octave(x, fs, f_min=800.0, f_max=1300.0)
    >>> [round(float(v), 1) for v in fc], round(float(level[1]), 2)   # A^2/2 = -3 dB
    ([794.3, 1000.0, 1258.9], -3.01)
    """
    fs = check_fs(fs)
    x, scale = normalise(check_signals(x, fs, axis, min_length=2))
    ref = check_positive(ref, "ref")
    nyquist = fs / 2.0
    f_max = nyquist if f_max is None else check_positive(f_max, "f_max")
    if f_max > nyquist:
        raise ValueError(f"f_max = {f_max:g} Hz is above fs/2 = {nyquist:g} Hz")
    fc = third_octave_centres(f_min, f_max)
    upper = fc * 10.0**_EDGE_EXPONENT
    keep = upper <= nyquist * (1.0 + 1e-12)
    fc = fc[keep]
    if fc.size == 0:
        raise ValueError(
            f"no complete one-third-octave band between f_min = {f_min:g} Hz and fs/2 = "
            f"{nyquist:g} Hz"
        )
    _check_band_resolution(x.shape[-1], fs, fc)
    band_power = _band_powers(x, fs, fc)
    with np.errstate(divide="ignore"):
        level_db = 10.0 * np.log10(band_power / ref**2)
    # In dB the record's rescaling is an offset, which no level overflows.
    level_db = level_db + scale.decibels(power=2)
    return fc, _frequency_axis_back(level_db, axis)


def _check_band_resolution(n: int, fs: float, fc: np.ndarray) -> None:
    """Raise unless every band holds at least one bin of an ``n``-point spectrum."""
    f = np.fft.rfftfreq(n, d=1.0 / fs)
    lower, upper = fc * 10.0**-_EDGE_EXPONENT, fc * 10.0**_EDGE_EXPONENT
    counts = np.searchsorted(f, upper, side="left") - np.searchsorted(f, lower, side="left")
    if np.all(counts > 0):
        return
    first = int(np.argmax(counts == 0))
    width = upper[first] - lower[first]
    raise ValueError(
        f"x is too short for one-third-octave bands from {fc[first]:.4g} Hz: {n} samples "
        f"({n / fs:.3g} s) give spectral bins {fs / n:.3g} Hz apart, wider than that band "
        f"({width:.3g} Hz); give at least {math.ceil(fs / width)} samples or a higher f_min"
    )


def _band_powers(x: np.ndarray, fs: float, fc: np.ndarray) -> np.ndarray:
    r"""Mean-square power of ``x`` (last axis) inside each band :math:`f_c 10^{\pm 0.05}`."""
    n = x.shape[-1]
    spectrum = np.fft.rfft(x, axis=-1)
    # One-sided power per bin, normalised so that the bins sum to mean(x**2).
    power = np.abs(spectrum) ** 2 / n**2
    power[..., 1 : (n + 1) // 2] *= 2.0
    f = np.fft.rfftfreq(n, d=1.0 / fs)
    edges = np.append(fc * 10.0**-_EDGE_EXPONENT, fc[-1] * 10.0**_EDGE_EXPONENT)
    # Half-open bins [lo, hi): each bin lands in exactly one band; bins are sorted, so a
    # band's power is a difference of the running sum at its first and last bins.
    first = np.searchsorted(f, edges, side="left")
    running = np.concatenate([np.zeros(power.shape[:-1] + (1,)), np.cumsum(power, axis=-1)], -1)
    return running[..., first[1:]] - running[..., first[:-1]]
