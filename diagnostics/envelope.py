"""Hilbert envelope and (squared) envelope spectrum.

The squared envelope spectrum of a band that holds the fault's resonance shows the fault's
repetition frequency and its harmonics (Randall and Antoni 2011); squaring rather than taking
the modulus avoids the spurious harmonics the modulus introduces.
"""

from __future__ import annotations

import numpy as np
from scipy import signal

from diagnostics._checks import check_signal
from diagnostics.filters import bandpass_filter


def _band_limited(x, fs: float, band) -> np.ndarray:
    if band is None:
        return check_signal(x, fs)
    try:
        f_lo, f_hi = band
    except (TypeError, ValueError):
        raise ValueError(f"band must be a pair (f_lo, f_hi) in Hz, got {band!r}") from None
    return bandpass_filter(x, fs, f_lo, f_hi)


def envelope(x, fs: float, band=None) -> np.ndarray:
    """Hilbert envelope of ``x``, optionally after a zero-phase band-pass.

    Parameters
    ----------
    x : array_like
        1-D signal.
    fs : float
        Sampling rate in Hz.
    band : tuple of float, optional
        ``(f_lo, f_hi)`` in Hz to band-pass first (Butterworth, 4th order, zero phase).

    Returns
    -------
    numpy.ndarray
        The modulus of the analytic signal, same length as ``x``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs`` or band.
    """
    y = _band_limited(x, fs, band)
    return np.abs(signal.hilbert(y))


def envelope_spectrum(x, fs: float, band=None, squared: bool = True):
    """One-sided amplitude spectrum of the (squared) envelope.

    Parameters
    ----------
    x : array_like
        1-D signal.
    fs : float
        Sampling rate in Hz.
    band : tuple of float, optional
        ``(f_lo, f_hi)`` in Hz to band-pass before demodulation.
    squared : bool
        Use the squared envelope (default, the squared envelope spectrum) rather than the
        envelope itself.

    Returns
    -------
    f : numpy.ndarray
        Frequencies in Hz, 0 to fs/2 in steps of fs/len(x).
    amplitude : numpy.ndarray
        Amplitude of each sinusoidal component of the (squared) envelope after removing its
        mean: a component ``A cos(2 pi f t)`` reads ``A`` at its bin.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs`` or band.
    """
    env = envelope(x, fs, band)
    if squared:
        env = env**2
    env = env - env.mean()
    n = env.size
    amplitude = np.abs(np.fft.rfft(env)) / n
    # One-sided: every bin except DC (and Nyquist for even n) carries half the power.
    amplitude[1 : (n + 1) // 2] *= 2.0
    f = np.fft.rfftfreq(n, d=1.0 / fs)
    return f, amplitude
