"""The shaft rate at every sample estimated from the vibration itself (no tachometer): the
ridge of the shaft harmonics in a whitened spectrogram, with a confidence.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import interpolate, ndimage, signal

from diagnostics._checks import (
    check_positive,
    check_positive_int,
    check_signal,
    check_varying,
    normalise,
)

__all__ = ["SpeedEstimate", "estimate_speed"]


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
    x, _ = normalise(check_varying(check_signal(x, fs)))  # a rate has no unit
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
