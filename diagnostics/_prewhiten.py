"""Cepstral prewhitening: a record with its spectrum set to unit modulus, its phase kept.

The first step of :func:`diagnostics.diagnose`: shaft, gear and electrical tones and the
resonances' shape are flattened, the timing of impulses kept.
"""

from __future__ import annotations

import numpy as np
from scipy import fft as sp_fft
from scipy import signal

from diagnostics._checks import check_signals, check_varying, normalise

__all__ = ["prewhiten"]

# Prewhitening tapers the record ends over this time and then drops them: the circular FFT
# would otherwise see a step where the end wraps onto the start, and whitening turns that
# step into a huge spurious impulse.
_TAPER_S = 0.05


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

    References
    ----------
    Randall, R. B. and Sawalhi, N. (2011). A new method for separating discrete components
    from a signal. *Sound and Vibration* 45(5), 6-9.

    Borghesani, P., Pennacchi, P., Randall, R. B., Sawalhi, N. and Ricci, R. (2013).
    Application of cepstrum pre-whitening for the diagnosis of bearing faults under variable
    speed conditions. *Mechanical Systems and Signal Processing* 36(2), 370-384.

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
    # The result has unit variance whatever the record's unit.
    x, _ = normalise(check_varying(check_signals(x, fs, axis=axis, min_length=16)))
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
