"""Spectral kurtosis: :func:`spectral_kurtosis` (the kurtosis of the short-time Fourier
transform at each frequency), its result :class:`SpectralKurtosis`, and the level that
stationary Gaussian noise stays below, :func:`sk_threshold`.
"""

from __future__ import annotations

import numpy as np
from scipy import signal, stats

from diagnostics._checks import check_positive_int, check_signals, normalise

__all__ = ["SpectralKurtosis", "sk_threshold", "spectral_kurtosis"]


class SpectralKurtosis(tuple):
    """Result of :func:`spectral_kurtosis`: unpacks as ``(f, sk)``.

    Attributes
    ----------
    f : numpy.ndarray
        Frequencies in Hz.
    sk : numpy.ndarray
        Spectral kurtosis at each frequency (0 for stationary Gaussian noise).
    n_frames : int
        Number of STFT frames averaged.
    """

    def __new__(cls, f: np.ndarray, sk: np.ndarray, n_frames: int):
        obj = super().__new__(cls, (f, sk))
        obj.n_frames = n_frames
        return obj

    @property
    def f(self) -> np.ndarray:
        return self[0]

    @property
    def sk(self) -> np.ndarray:
        return self[1]

    def threshold(self, p: float = 0.01) -> float:
        """SK level that stationary Gaussian noise exceeds with probability ``p`` per bin."""
        return sk_threshold(self.n_frames, p)


def sk_threshold(n_frames: int, p: float = 0.01) -> float:
    r"""Significance threshold of the STFT spectral kurtosis for Gaussian noise.

    For stationary Gaussian noise the SK estimate at a frequency is asymptotically normal with
    mean 0 and standard deviation :math:`2 / \sqrt{n_\mathrm{frames}}` (Antoni 2006); the
    threshold is its one-sided :math:`1 - p` quantile. It assumes nearly independent frames,
    which holds for the Hann window at 50 % overlap used by :func:`spectral_kurtosis`.

    Parameters
    ----------
    n_frames : int
        Number of STFT frames averaged.
    p : float
        False-alarm probability per frequency bin, 0 < p < 1.

    Returns
    -------
    float
        Threshold on SK.

    References
    ----------
    Antoni, J. (2006). The spectral kurtosis: a useful tool for characterising
    non-stationary signals. *Mechanical Systems and Signal Processing* 20(2), 282-307.
    """
    n_frames = check_positive_int(n_frames, "n_frames")
    if not 0.0 < p < 1.0:
        raise ValueError(f"p must be a probability in (0, 1), got {p!r}")
    return float(stats.norm.isf(p) * 2.0 / np.sqrt(n_frames))


def spectral_kurtosis(x, fs: float, nw: int = 256, axis: int = -1) -> SpectralKurtosis:
    r"""Spectral kurtosis by the STFT estimator of Antoni (2006).

    :math:`\mathrm{SK}(f) = \langle |X(t, f)|^4 \rangle / \langle |X(t, f)|^2 \rangle^2 - 2`
    over the STFT frames (Hann window of
    ``nw`` samples, 50 % overlap). It is 0 for stationary Gaussian noise, -1 for a pure tone
    and large where a band carries impulsive content. At 0 Hz and fs/2 the STFT of a real
    signal is real-valued, the complex estimator does not apply and its real counterpart has
    six times the variance; SK is reported as 0 there.

    Parameters
    ----------
    x : array_like
        Signal, samples along ``axis``; at least ``2 * nw`` samples.
    fs : float
        Sampling rate in Hz.
    nw : int
        Window length in samples (frequency resolution fs/nw).
    axis : int
        Axis of ``x`` along which the samples run; the frequency axis of ``sk`` takes its
        place.

    Returns
    -------
    SpectralKurtosis
        Unpacks as ``(f, sk)``; also carries ``n_frames`` and ``threshold(p)``.

    Raises
    ------
    ValueError
        On an invalid signal, ``fs`` or axis, or ``nw`` not an integer >= 4 or too long for
        ``x``.

    References
    ----------
    Antoni, J. (2006). The spectral kurtosis: a useful tool for characterising
    non-stationary signals. *Mechanical Systems and Signal Processing* 20(2), 282-307.

    Examples
    --------
    >>> fs = 8000.0
    >>> tone = np.cos(2 * np.pi * 1000.0 * np.arange(16000) / fs)
    >>> noise = np.random.default_rng(0).standard_normal(16000)
    >>> f, sk = spectral_kurtosis(np.stack([tone, noise]), fs, nw=64)
    >>> round(float(sk[0, f == 1000.0][0]), 2), bool(abs(sk[1, f == 1000.0][0]) < 0.3)
    (-1.0, True)
    """
    nw = check_positive_int(nw, "nw", minimum=4)
    x, _ = normalise(check_signals(x, fs, axis, min_length=2 * nw))  # SK has no unit
    hop = nw // 2
    frames = np.lib.stride_tricks.sliding_window_view(x, nw, axis=-1)[..., ::hop, :]
    window = signal.get_window("hann", nw)
    spectra = np.fft.rfft(frames * window, axis=-1)
    power = spectra.real**2 + spectra.imag**2
    mean_power = power.mean(axis=-2)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = (power**2).mean(axis=-2) / mean_power**2
    sk = np.where(mean_power > 0, ratio - 2.0, 0.0)
    sk[..., 0] = 0.0
    if nw % 2 == 0:
        sk[..., -1] = 0.0
    f = np.fft.rfftfreq(nw, d=1.0 / fs)
    return SpectralKurtosis(f, sk if sk.ndim == 1 else np.moveaxis(sk, -1, axis), frames.shape[-2])
