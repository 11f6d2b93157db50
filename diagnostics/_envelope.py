"""Envelope analysis: the Hilbert envelope of a (band-passed) record, :func:`envelope`, and
the amplitude spectrum of its square or of itself, :func:`envelope_spectrum`. Why the
squared envelope is the one to use is in docs/theory/diagnostics.md.
"""

from __future__ import annotations

import numpy as np
from scipy import signal

from diagnostics._checks import RecordScale, check_signals, normalise
from diagnostics._filters import bandpass_filter


def _scaled_envelope(x, fs: float, band, axis: int) -> tuple[np.ndarray, RecordScale]:
    """The envelope of the record rescaled by :func:`diagnostics._checks.normalise` (band-
    passed first when a band is given), time axis last, and that scale."""
    data, scale = normalise(check_signals(x, fs, axis))
    if band is not None:
        try:
            f_lo, f_hi = band
        except (TypeError, ValueError):
            raise ValueError(f"band must be a pair (f_lo, f_hi) in Hz, got {band!r}") from None
        data = bandpass_filter(data, fs, f_lo, f_hi)
    return np.abs(signal.hilbert(data, axis=-1)), scale


def envelope(x, fs: float, band=None, axis: int = -1) -> np.ndarray:
    """Hilbert envelope of ``x``, optionally after a zero-phase band-pass.

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis``.
    fs : float
        Sampling rate in Hz.
    band : tuple of float, optional
        ``(f_lo, f_hi)`` in Hz to band-pass first (Butterworth, 4th order, zero phase).
    axis : int
        Axis of ``x`` along which the samples run.

    Returns
    -------
    numpy.ndarray
        The modulus of the analytic signal, same shape as ``x``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs``, band or axis.

    References
    ----------
    Randall, R. B. and Antoni, J. (2011). Rolling element bearing diagnostics: a tutorial.
    *Mechanical Systems and Signal Processing* 25(2), 485-520.

    Examples
    --------
    >>> fs = 8000.0
    >>> t = np.arange(8000) / fs
    >>> am = (1.0 + 0.5 * np.cos(2 * np.pi * 10.0 * t)) * np.cos(2 * np.pi * 1000.0 * t)
    >>> env = envelope(am, fs)
    >>> round(float(env[1600]), 3), round(float(env[2000]), 3)     # 1 + 0.5 cos(...)
    (1.5, 0.5)
    """
    env, scale = _scaled_envelope(x, fs, band, axis)
    y = scale.restore(env, what="the envelope")
    return y if y.ndim == 1 else np.moveaxis(y, -1, axis)


def envelope_spectrum(x, fs: float, band=None, squared: bool = True, axis: int = -1):
    r"""One-sided amplitude spectrum of the (squared) envelope.

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis``.
    fs : float
        Sampling rate in Hz.
    band : tuple of float, optional
        ``(f_lo, f_hi)`` in Hz to band-pass before demodulation.
    squared : bool
        Use the squared envelope (default, the squared envelope spectrum) rather than the
        envelope itself.
    axis : int
        Axis of ``x`` along which the samples run; the frequency axis of ``amplitude``
        takes its place.

    Returns
    -------
    f : numpy.ndarray
        Frequencies in Hz, 0 to fs/2 in steps of fs/len(x).
    amplitude : numpy.ndarray
        Amplitude of each sinusoidal component of the (squared) envelope after removing its
        mean: a component :math:`A \cos(2 \pi f t)` reads :math:`A` at its bin.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs``, band or axis, or (squared) a spectrum outside the
        range of float64 numbers in the record's unit squared (a record of values near
        1e300 or 1e-300): give ``x`` in another unit.

    References
    ----------
    Randall, R. B. and Antoni, J. (2011). Rolling element bearing diagnostics: a tutorial.
    *Mechanical Systems and Signal Processing* 25(2), 485-520.

    Examples
    --------
    >>> t = np.arange(4000) / 4000.0                   # 1 s at 4 kHz
    >>> carrier = np.cos(2 * np.pi * 800.0 * t)
    >>> f, amp = envelope_spectrum((1.0 + 0.5 * np.cos(2 * np.pi * 10.0 * t)) * carrier,
    ...                            4000.0, squared=False)
    >>> float(f[np.argmax(amp)]), round(float(amp.max()), 3)  # modulation 10 Hz, depth 0.5
    (10.0, 0.5)
    """
    env, scale = _scaled_envelope(x, fs, band, axis)
    if squared:
        env = env**2
    env = env - env.mean(axis=-1, keepdims=True)
    n = env.shape[-1]
    amplitude = np.abs(np.fft.rfft(env, axis=-1)) / n
    # One-sided: every bin except DC (and Nyquist for even n) carries half the power.
    amplitude[..., 1 : (n + 1) // 2] *= 2.0
    # The squared envelope carries the square of the record's unit.
    amplitude = scale.restore(
        amplitude, power=2 if squared else 1, what="the envelope spectrum of x"
    )
    f = np.fft.rfftfreq(n, d=1.0 / fs)
    return f, (amplitude if amplitude.ndim == 1 else np.moveaxis(amplitude, -1, axis))
