"""Zero-phase filters: IIR notch and Butterworth band-pass / low-pass in second-order sections.

Every filter is run forwards and backwards (``filtfilt``), so it shifts no event in time: the
timing of impacts, which bearing diagnostics relies on, is preserved.
"""

from __future__ import annotations

import numpy as np
from scipy import signal

from diagnostics._checks import (
    check_band,
    check_frequency,
    check_positive,
    check_positive_int,
    check_signals,
    normalise,
)


def _padlen(n_coeffs: int) -> int:
    # The edge padding scipy's filtfilt uses by default; the signal must be longer than it.
    return 3 * n_coeffs


def _time_axis_back(y: np.ndarray, axis: int) -> np.ndarray:
    """Put the last (time) axis of a result back where ``axis`` had it."""
    return y if y.ndim == 1 else np.moveaxis(y, -1, axis)


def notch_filter(x, fs: float, f0: float, Q: float = 30.0, axis: int = -1) -> np.ndarray:
    """Remove a narrow band around ``f0`` with a zero-phase second-order IIR notch.

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis`` (several channels at once for an N-D ``x``).
    fs : float
        Sampling rate in Hz.
    f0 : float
        Frequency to remove, in Hz (0 < f0 < fs/2), e.g. mains hum or a gear mesh tone.
    Q : float
        Quality factor: the -3 dB width of one pass is :math:`f_0 / Q`.
    axis : int
        Axis of ``x`` along which the samples run.

    Returns
    -------
    numpy.ndarray
        The filtered signal, same shape as ``x``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs``, ``f0``, ``Q`` or ``axis``, or a signal too short for
        the filter.

    Examples
    --------
    >>> fs = 1000.0
    >>> t = np.arange(10000) / fs
    >>> hum = np.sin(2 * np.pi * 50.0 * t)
    >>> y = notch_filter(np.stack([hum, 2 * hum]), fs, 50.0)    # two channels
    >>> y.shape, bool(np.abs(y[:, 3000:-3000]).max() < 0.01)  # away from the ends
    ((2, 10000), True)
    """
    f0 = check_frequency(f0, fs, "f0")
    Q = check_positive(Q, "Q")
    b, a = signal.iirnotch(f0, Q, fs=fs)
    padlen = _padlen(max(len(a), len(b)))
    data, scale = normalise(check_signals(x, fs, axis, min_length=padlen + 1))
    y = signal.filtfilt(b, a, data, axis=-1, padlen=padlen)
    return _time_axis_back(scale.restore(y, what="the filtered signal"), axis)


def _sos_filtfilt(x, fs: float, sos: np.ndarray, axis: int) -> np.ndarray:
    # sosfiltfilt pads by 3 * (2 * n_sections + 1) samples at each end.
    padlen = _padlen(2 * len(sos) + 1)
    data, scale = normalise(check_signals(x, fs, axis, min_length=padlen + 1))
    y = signal.sosfiltfilt(sos, data, axis=-1, padlen=padlen)
    return _time_axis_back(scale.restore(y, what="the filtered signal"), axis)


def bandpass_filter(
    x, fs: float, f_lo: float, f_hi: float, order: int = 4, axis: int = -1
) -> np.ndarray:
    """Zero-phase Butterworth band-pass filter (second-order sections).

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis``.
    fs : float
        Sampling rate in Hz.
    f_lo, f_hi : float
        Band edges in Hz, 0 <= f_lo < f_hi <= fs/2. With ``f_hi == fs/2`` the filter is a
        high-pass at ``f_lo``, with ``f_lo == 0`` a low-pass at ``f_hi``, and the whole
        range (0, fs/2) returns the signal unfiltered.
    order : int
        Butterworth order of one pass (the forward-backward run squares the magnitude).
    axis : int
        Axis of ``x`` along which the samples run.

    Returns
    -------
    numpy.ndarray
        The filtered signal, same shape as ``x``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs``, band, order or axis.

    Examples
    --------
    >>> fs = 1000.0
    >>> t = np.arange(4000) / fs
    >>> x = np.sin(2 * np.pi * 10.0 * t) + np.sin(2 * np.pi * 200.0 * t)
    >>> y = bandpass_filter(x, fs, 100.0, 300.0)
    >>> round(float(np.std(y[500:-500]) * np.sqrt(2)), 2)        # the 200 Hz tone alone
    1.0
    """
    f_lo, f_hi = check_band(f_lo, f_hi, fs)
    order = check_positive_int(order, "order")
    to_nyquist = f_hi >= fs / 2.0
    if f_lo <= 0.0 and to_nyquist:
        return _time_axis_back(check_signals(x, fs, axis).copy(), axis)
    if f_lo <= 0.0:
        return lowpass_filter(x, fs, f_hi, order, axis=axis)
    if to_nyquist:
        sos = signal.butter(order, f_lo, btype="highpass", output="sos", fs=fs)
    else:
        sos = signal.butter(order, [f_lo, f_hi], btype="bandpass", output="sos", fs=fs)
    return _sos_filtfilt(x, fs, sos, axis)


def lowpass_filter(x, fs: float, f_hi: float, order: int = 4, axis: int = -1) -> np.ndarray:
    """Zero-phase Butterworth low-pass filter (second-order sections).

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis``.
    fs : float
        Sampling rate in Hz.
    f_hi : float
        Cut-off frequency in Hz (0 < f_hi < fs/2).
    order : int
        Butterworth order of one pass.
    axis : int
        Axis of ``x`` along which the samples run.

    Returns
    -------
    numpy.ndarray
        The filtered signal, same shape as ``x``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs``, cut-off, order or axis.

    Examples
    --------
    >>> fs = 1000.0
    >>> x = np.ones((3, 500))                 # three channels of a constant
    >>> bool(np.allclose(lowpass_filter(x, fs, 50.0), 1.0))
    True
    """
    f_hi = check_frequency(f_hi, fs, "f_hi")
    order = check_positive_int(order, "order")
    sos = signal.butter(order, f_hi, btype="lowpass", output="sos", fs=fs)
    return _sos_filtfilt(x, fs, sos, axis)
