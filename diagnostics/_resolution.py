"""Analysis resolutions that fit a record's length.

A simulated record may hold only a few milliseconds, a measured one many seconds; these
pick STFT windows, spectral-kurtosis windows, kurtogram levels and the lowest
one-third-octave band so that each analysis has enough data, the same way for both.
"""

from __future__ import annotations

import math

__all__ = ["choose_nperseg", "choose_sk_windows", "choose_nlevel", "third_octave_f_min"]


def choose_nperseg(n: int, target: int = 256, min_frames: int = 32) -> int:
    """STFT window: ``target`` samples, or the power of two giving ``min_frames`` windows
    in ``n`` samples if that is shorter (never below 16)."""
    fit = 2 ** int(math.floor(math.log2(max(n / min_frames, 16))))
    return int(max(16, min(target, fit)))


def choose_sk_windows(
    n: int, candidates: tuple[int, ...] = (64, 128, 256, 512, 1024), min_frames: int = 16
) -> list[int]:
    """Spectral-kurtosis windows giving at least ``min_frames`` frames; never empty."""
    ok = [w for w in candidates if n >= min_frames * w]
    return ok or [choose_nperseg(n, target=candidates[0], min_frames=min_frames)]


def choose_nlevel(n: int, max_level: int = 7) -> int:
    r"""Fast-kurtogram levels a record of ``n`` samples allows (:math:`2^{\mathrm{nlevel}+7}`
    samples, the reference implementation's limit), at most ``max_level``; 0 if none."""
    return int(max(0, min(max_level, math.floor(math.log2(max(n, 1))) - 7)))


def third_octave_f_min(duration_s: float, min_bins: int = 4, f_floor: float = 20.0) -> float:
    """Lowest one-third-octave frequency whose band (0.2316 fc wide) spans ``min_bins``
    spectral bins of a record ``duration_s`` long (bins are 1/duration apart)."""
    return max(f_floor, min_bins / (0.2316 * duration_s))
