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
    check_signal,
)


def _padlen(n_coeffs: int) -> int:
    # The edge padding scipy's filtfilt uses by default; the signal must be longer than it.
    return 3 * n_coeffs


def notch_filter(x, fs: float, f0: float, Q: float = 30.0) -> np.ndarray:
    """Remove a narrow band around ``f0`` with a zero-phase second-order IIR notch.

    Parameters
    ----------
    x : array_like
        1-D signal.
    fs : float
        Sampling rate in Hz.
    f0 : float
        Frequency to remove, in Hz (0 < f0 < fs/2), e.g. mains hum or a gear mesh tone.
    Q : float
        Quality factor: the -3 dB width of one pass is ``f0 / Q``.

    Returns
    -------
    numpy.ndarray
        The filtered signal, same length as ``x``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs``, ``f0`` or ``Q``, or a signal too short for the filter.
    """
    f0 = check_frequency(f0, fs, "f0")
    Q = check_positive(Q, "Q")
    b, a = signal.iirnotch(f0, Q, fs=fs)
    padlen = _padlen(max(len(a), len(b)))
    x = check_signal(x, fs, min_length=padlen + 1)
    return signal.filtfilt(b, a, x, padlen=padlen)


def _sos_filtfilt(x, fs: float, sos: np.ndarray) -> np.ndarray:
    # sosfiltfilt pads by 3 * (2 * n_sections + 1) samples at each end.
    padlen = _padlen(2 * len(sos) + 1)
    x = check_signal(x, fs, min_length=padlen + 1)
    return signal.sosfiltfilt(sos, x, padlen=padlen)


def bandpass_filter(x, fs: float, f_lo: float, f_hi: float, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth band-pass filter (second-order sections).

    Parameters
    ----------
    x : array_like
        1-D signal.
    fs : float
        Sampling rate in Hz.
    f_lo, f_hi : float
        Band edges in Hz, 0 <= f_lo < f_hi <= fs/2. With ``f_hi == fs/2`` the filter is a
        high-pass at ``f_lo``, with ``f_lo == 0`` a low-pass at ``f_hi``, and the whole
        range (0, fs/2) returns the signal unfiltered.
    order : int
        Butterworth order of one pass (the forward-backward run squares the magnitude).

    Returns
    -------
    numpy.ndarray
        The filtered signal, same length as ``x``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs``, band or order.
    """
    f_lo, f_hi = check_band(f_lo, f_hi, fs)
    order = check_positive_int(order, "order")
    to_nyquist = f_hi >= fs / 2.0
    if f_lo <= 0.0 and to_nyquist:
        return check_signal(x, fs).copy()
    if f_lo <= 0.0:
        return lowpass_filter(x, fs, f_hi, order)
    if to_nyquist:
        sos = signal.butter(order, f_lo, btype="highpass", output="sos", fs=fs)
    else:
        sos = signal.butter(order, [f_lo, f_hi], btype="bandpass", output="sos", fs=fs)
    return _sos_filtfilt(x, fs, sos)


def lowpass_filter(x, fs: float, f_hi: float, order: int = 4) -> np.ndarray:
    """Zero-phase Butterworth low-pass filter (second-order sections).

    Parameters
    ----------
    x : array_like
        1-D signal.
    fs : float
        Sampling rate in Hz.
    f_hi : float
        Cut-off frequency in Hz (0 < f_hi < fs/2).
    order : int
        Butterworth order of one pass.

    Returns
    -------
    numpy.ndarray
        The filtered signal, same length as ``x``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs``, cut-off or order.
    """
    f_hi = check_frequency(f_hi, fs, "f_hi")
    order = check_positive_int(order, "order")
    sos = signal.butter(order, f_hi, btype="lowpass", output="sos", fs=fs)
    return _sos_filtfilt(x, fs, sos)
