"""The fast kurtogram and the infogram of the squared envelope spectrum, on one filter bank:
:func:`kurtogram`, :func:`infogram`, :func:`kurtogram_and_infogram` and their results
(:class:`Kurtogram`, :class:`Infogram`). Spectral kurtosis itself, by the STFT, is in
:mod:`diagnostics._spectral_kurtosis`.

The kurtogram is the reference implementation's, number for number (filters, decimation,
map layout, choice of best band), computed at the kept samples only; how, and the check
against the reference, are in docs/theory/diagnostics.md and
docs/results/diagnostics/README.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from scipy import fft as sp_fft
from scipy import signal

from diagnostics._checks import check_positive, check_positive_int, check_signal, normalise

_EPS = np.finfo(float).eps
# Antoni's generating filters: a 16th-order fir1 half-band low-pass (cut-off 0.4 of Nyquist)
# for the binary splits, and a 24th-order one (cut-off 0.4 * 2/3) for the ternary splits.
_BINARY_ORDER = 16
_BINARY_CUTOFF = 0.4
_TERNARY_ORDER = 24


@dataclass(frozen=True)
class _ModulatedFilter:
    r"""A complex FIR filter :math:`s \, h_k \exp(2 \pi i \, c k / P)`, with :math:`s` the
    ``scale``, :math:`h_k` the real ``taps``, :math:`c` the ``cycles`` and :math:`P` the
    ``period``."""

    taps: np.ndarray
    cycles: int
    period: int
    scale: complex

    def coefficients(self) -> np.ndarray:
        return self.scale * self.taps * self.phasor(self.taps.size)

    def phasor(self, n: int) -> np.ndarray:
        r""":math:`\exp(2 \pi i \, c m / P)` (:math:`c` the ``cycles``, :math:`P` the
        ``period``) for :math:`m = 0, \dots, n - 1`, built from one exact period."""
        one_period = np.exp(2j * np.pi * self.cycles * np.arange(self.period) / self.period)
        return np.tile(one_period, -(-n // self.period))[:n]


def _binary_filters() -> tuple[_ModulatedFilter, _ModulatedFilter]:
    """Low band ``h`` and high band ``g`` of the reference's binary split."""
    prototype = signal.firwin(_BINARY_ORDER + 1, _BINARY_CUTOFF)  # MATLAB fir1(16, 0.4)
    low = _ModulatedFilter(prototype, 1, 8, 1.0)
    # The reference builds g[k] = h[15 - k] * (-1)**(k + 1). With h's real prototype p
    # symmetric, that is exp(19i pi / 4) * p[k + 1] * exp(3i pi k / 4).
    high = _ModulatedFilter(prototype[1:], 3, 8, np.exp(19j * np.pi / 4))
    return low, high


def _ternary_filters() -> tuple[_ModulatedFilter, ...]:
    """The three 1/3-band filters h1, h2, h3 (centres fs/12, fs/4, 5 fs/12)."""
    prototype = signal.firwin(_TERNARY_ORDER + 1, 2.0 / 3.0 * _BINARY_CUTOFF)
    return tuple(_ModulatedFilter(prototype, cycles, 12, 1.0) for cycles in (1, 3, 5))


def analysis_filters() -> dict[str, np.ndarray]:
    """The complex analysis filters of the fast kurtogram, as the reference defines them.

    Returns
    -------
    dict
        ``h`` (17 taps, band 0..fs/4 of its input), ``g`` (16 taps, fs/4..fs/2), and ``h1``,
        ``h2``, ``h3`` (25 taps each, the three thirds of 0..fs/2).
    """
    low, high = _binary_filters()
    h1, h2, h3 = _ternary_filters()
    return {
        "h": low.coefficients(),
        "g": high.coefficients(),
        "h1": h1.coefficients(),
        "h2": h2.coefficients(),
        "h3": h3.coefficients(),
    }


class _DecimatingFilter:
    """One analysis filter followed by decimation, evaluated at the kept samples only.

    ``apply(nodes)`` returns, for every row s of ``nodes``, ``lfilter(f, 1, s)[down-1::down]``
    (the samples the reference keeps), times ``post`` (a per-sample factor). It uses
    conv(p e^{iwk}, s)[m] = e^{iwm} conv(p, s e^{-iwm})[m]: demodulate, filter the real and
    imaginary parts with the real prototype p, remodulate the kept samples. The phasors are
    built once, for the longest input, and sliced for the shorter ones.
    """

    def __init__(self, filt: _ModulatedFilter, down: int, n_max: int, post=None):
        self.down = down
        # A leading zero tap delays the output by one sample, so upfirdn's samples down,
        # 2*down, ... are the samples down-1, 2*down-1, ... the reference keeps.
        self.taps = np.concatenate([[0.0], filt.taps])
        self.demodulation = np.conj(filt.phasor(n_max))
        n_kept = n_max // down
        # exp(i w m) at the kept samples m = down*j + down - 1, periodic in j like the filter.
        kept = down * np.arange(filt.period) + down - 1
        one_period = filt.scale * np.exp(2j * np.pi * filt.cycles * kept / filt.period)
        remodulation = np.tile(one_period, -(-n_kept // filt.period))[:n_kept]
        if post is not None:
            remodulation = remodulation * post(n_kept)
        self.remodulation = remodulation

    def apply(self, nodes: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Filter and decimate every row of ``nodes``; write into ``out`` when given."""
        n_rows, n = nodes.shape
        n_out = n // self.down
        shifted = nodes * self.demodulation[:n]
        # Real and imaginary parts side by side in a trailing axis: real arithmetic only.
        pairs = shifted.view(np.float64).reshape(n_rows, n, 2)
        filtered = signal.upfirdn(self.taps, pairs, up=1, down=self.down, axis=1)
        kept = filtered[:, 1 : n_out + 1].view(np.complex128)[..., 0]
        return np.multiply(kept, self.remodulation[:n_out], out=out)


def _alternating_sign(n: int) -> np.ndarray:
    """(-1)**j for j = 1..n: the reference's shift of the high band after decimation."""
    return np.tile([-1.0, 1.0], (n + 1) // 2)[:n]


def _band_kurtosis(bands: np.ndarray, floor: float) -> np.ndarray:
    r"""Kurtosis of the complex envelope of each row, as Antoni's 'kurt2' computes it.

    The mean is removed first; the result is
    :math:`\overline{|c|^4} / \bigl(\overline{|c|^2}\bigr)^2 - 2` for complex rows
    (:math:`- 3` for a real row), and 0 where the band power is below ``floor`` (the
    reference's machine epsilon, here times the record's mean square: see
    :func:`_kurtosis_statistic`).
    """
    centred = bands - bands.mean(axis=1, keepdims=True)
    if np.iscomplexobj(centred):
        squares = np.square(centred.view(np.float64))
        power = squares[:, 0::2] + squares[:, 1::2]
        gaussian = 2.0
    else:
        power = np.square(centred)
        gaussian = 3.0
    energy = power.mean(axis=1)
    fourth = np.einsum("ij,ij->i", power, power) / power.shape[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        value = fourth / energy**2 - gaussian
    return np.where(energy < floor, 0.0, value)


@dataclass(frozen=True, eq=False)
class Kurtogram:
    """Fast kurtogram: the map and its best band.

    Attributes
    ----------
    K : numpy.ndarray
        Kurtosis map, shape (2*nlevel, 3*2**nlevel). Row r holds level ``levels[r]``; each
        band's value is repeated over the columns it spans (Antoni's layout). Negative values
        are set to 0, as in the reference.
    levels : numpy.ndarray
        Decomposition level of each row: 0, 1, log2(3), 2, 1+log2(3), ..., nlevel.
    freqs : numpy.ndarray
        Centre frequency of each column in Hz.
    level : float
        Level of the best band, :math:`l`; its bandwidth is :math:`f_s 2^{-(l + 1)}`.
    fc : float
        Centre frequency of the best band in Hz.
    bw : float
        Bandwidth of the best band in Hz.
    kurtosis : float
        Kurtosis of the best band (the maximum of ``K``).
    row, column : int
        Indices of the best cell in ``K`` (first column of its band).
    fs : float
        Sampling rate in Hz.
    """

    K: np.ndarray
    levels: np.ndarray
    freqs: np.ndarray
    level: float
    fc: float
    bw: float
    kurtosis: float
    row: int
    column: int
    fs: float

    # What the map holds (plots label their colour scale with it).
    quantity: ClassVar[str] = "kurtosis"

    @property
    def band(self) -> tuple[float, float]:
        """Edges ``(fc - bw/2, fc + bw/2)`` of the best band in Hz."""
        return self.fc - self.bw / 2.0, self.fc + self.bw / 2.0

    @property
    def nlevel(self) -> int:
        """Number of decomposition levels."""
        return self.K.shape[0] // 2


@dataclass(frozen=True, eq=False)
class Infogram(Kurtogram):
    """Infogram of the squared envelope spectrum (:func:`infogram`): the attributes of
    :class:`Kurtogram`, with ``K`` holding the spectral negentropy of each band's squared
    envelope spectrum and ``kurtosis`` the best band's negentropy."""

    quantity: ClassVar[str] = "SES negentropy"


def kurtogram_levels(nlevel: int) -> np.ndarray:
    """Levels of the kurtogram rows: 0, 1, log2(3), 2, 1 + log2(3), ..., nlevel."""
    steps = np.arange(1, nlevel + 1, dtype=float)
    pairs = np.column_stack([steps, steps + np.log2(3.0) - 1.0]).ravel()
    return np.concatenate([[0.0], pairs[: 2 * nlevel - 1]])


def kurtogram(x, fs: float, nlevel: int = 7) -> Kurtogram:
    r"""Fast kurtogram of ``x`` (Antoni 2007), identical to the reference implementation.

    Parameters
    ----------
    x : array_like
        1-D real signal; at least :math:`2^{n + 7}` samples, :math:`n` = ``nlevel`` (the
        reference's limit).
    fs : float
        Sampling rate in Hz.
    nlevel : int
        Number of binary decomposition levels (the finest bands are
        :math:`f_s / 2^{\mathrm{nlevel}+1}` wide).

    Returns
    -------
    Kurtogram
        The map and the best band. A band whose power is below machine epsilon times the
        record's mean square counts as empty (kurtosis 0); the reference compares band
        power with machine epsilon itself, which made the map depend on the record's unit.

    Raises
    ------
    ValueError
        On an invalid signal or ``fs``, ``nlevel`` below 1, a signal too short for
        ``nlevel``, or a constant signal.

    References
    ----------
    Antoni, J. (2007). Fast computation of the kurtogram for the detection of transient
    faults. *Mechanical Systems and Signal Processing* 21(1), 108-124.
    """
    x, nlevel = _tree_input(x, fs, nlevel, "a kurtogram")
    (K,) = _kurtogram_map(x, nlevel, (_kurtosis_statistic(x),))
    return _best_band(K, float(fs), nlevel)


def infogram(
    x, fs: float, nlevel: int = 7, cyclic_range=None, shaft_hz: float | None = None
) -> Infogram:
    r"""Infogram of the squared envelope spectrum: which band holds repetitive transients.

    The kurtogram rewards any impulsiveness, and a few strong impulses at no fault period (a
    knock, a loose part, electrical spikes) win it over a weaker fault's train. The spectral
    negentropy of the squared envelope spectrum (Antoni 2016, "The infogram", MSSP 74)
    rewards lines in the envelope's spectrum instead: isolated impulses give a flat one,
    which reads like noise. Each band of the fast kurtogram's 1/3-binary tree (same filters)
    is scored by the mean of :math:`E \ln E`, :math:`E` being the power of its squared
    envelope's spectrum over its mean at the cyclic frequencies considered. Random noise
    reads about 0.44 in every band but the whole one: 1 - 0.5772 (Euler's constant) = 0.42
    for the exponential values of a flat spectrum, a little more as the filters' passbands
    tilt it (0.61 in the level-0 band, whose envelope spectrum falls linearly to fs/2).

    Parameters
    ----------
    x : array_like
        1-D real signal; at least :math:`2^{n + 7}` samples, :math:`n` = ``nlevel``.
    fs : float
        Sampling rate in Hz.
    nlevel : int
        Number of binary decomposition levels.
    cyclic_range : tuple of float, optional
        ``(low, high)`` cyclic frequencies (Hz) over which the negentropy is taken, e.g. the
        range a bearing's fault combs cover; default every one but 0.
    shaft_hz : float, optional
        Shaft rate whose harmonics (+-2.5 bins) and the cyclic frequencies below half of it
        are left out: shaft-rate modulation is in every record of a rotating machine.

    Returns
    -------
    Infogram
        The map (``K``, negentropy, same layout as :class:`Kurtogram`) and its best band.

    Raises
    ------
    ValueError
        As :func:`kurtogram`, and on a bad ``cyclic_range`` or ``shaft_hz``.

    References
    ----------
    Antoni, J. (2016). The infogram: entropic evidence of the signature of repetitive
    transients. *Mechanical Systems and Signal Processing* 74, 73-94.

    Examples
    --------
    Impacts every 10 ms ringing at 3 kHz, beside eight stronger impacts at random times
    ringing at 1 kHz: the kurtogram takes a band only the random ones reach, the infogram
    the train's.

    >>> fs, n = 12000.0, 2**15
    >>> rng = np.random.default_rng(1)
    >>> t = np.arange(240) / fs
    >>> def ring(f0):
    ...     return np.exp(-300 * t) * np.sin(2 * np.pi * f0 * t)
    >>> train = np.zeros(n)
    >>> train[::120] = 1.0
    >>> spikes = np.zeros(n)
    >>> spikes[rng.choice(n - 300, 8, replace=False)] = 8.0
    >>> x = (np.convolve(train, ring(3000.0))[:n] + np.convolve(spikes, ring(1000.0))[:n]
    ...      + 0.2 * rng.standard_normal(n))
    >>> [round(f) for f in kurtogram(x, fs, nlevel=4).band]
    [375, 750]
    >>> [round(f) for f in infogram(x, fs, nlevel=4).band]
    [3000, 3500]
    """
    x, nlevel = _tree_input(x, fs, nlevel, "an infogram")
    statistic = _negentropy_statistic(float(fs), cyclic_range, shaft_hz)
    (K,) = _kurtogram_map(x, nlevel, (statistic,))
    return _best_band(K, float(fs), nlevel, Infogram)


def kurtogram_and_infogram(
    x, fs: float, nlevel: int = 7, cyclic_range=None, shaft_hz: float | None = None
) -> tuple[Kurtogram, Infogram]:
    """:func:`kurtogram` and :func:`infogram` of ``x`` from one pass of the filter bank.

    The same results as the two calls, for about seven tenths of their time: the bank's
    filtering is shared, only the statistic of each band differs.

    Parameters
    ----------
    x, fs, nlevel
        As :func:`kurtogram`.
    cyclic_range, shaft_hz
        As :func:`infogram`.

    Returns
    -------
    (Kurtogram, Infogram)
        The kurtogram and the infogram, each with its best band.

    Raises
    ------
    ValueError
        As :func:`kurtogram` and :func:`infogram`.

    References
    ----------
    Antoni, J. (2007). Fast computation of the kurtogram for the detection of transient
    faults. *Mechanical Systems and Signal Processing* 21(1), 108-124.

    Antoni, J. (2016). The infogram: entropic evidence of the signature of repetitive
    transients. *Mechanical Systems and Signal Processing* 74, 73-94.
    """
    x, nlevel = _tree_input(x, fs, nlevel, "a kurtogram")
    statistic = _negentropy_statistic(float(fs), cyclic_range, shaft_hz)
    K, N = _kurtogram_map(x, nlevel, (_kurtosis_statistic(x), statistic))
    return _best_band(K, float(fs), nlevel), _best_band(N, float(fs), nlevel, Infogram)


def _tree_input(x, fs: float, nlevel: int, what: str) -> tuple[np.ndarray, int]:
    """The checked, centred signal and level count of a band map."""
    nlevel = check_positive_int(nlevel, "nlevel")
    x, _ = normalise(check_signal(x, fs))  # the maps have no unit
    if x.size < 2 ** (nlevel + 7):
        # The reference's limit: log2(len(x)) - 7 levels at most.
        raise ValueError(
            f"x is too short for {what} with nlevel={nlevel}: {x.size} samples, need at "
            f"least 2**(nlevel+7) = {2 ** (nlevel + 7)}; lower nlevel"
        )
    x = x - x.mean()
    if not np.any(x):
        raise ValueError(f"x is constant: {what} of a signal without variation is undefined")
    return x, nlevel


def _kurtogram_map(x: np.ndarray, nlevel: int, statistics) -> list[np.ndarray]:
    """Maps of band statistics in the reference's layout (before clipping negatives), one
    per statistic, from one pass of the filter bank.

    ``statistic(rows, decimation)`` gives one value per row of band signals (complex, each
    decimated by ``decimation`` from ``x``; the level-0 row is ``x`` itself).
    """
    low, high = _binary_filters()
    n = x.size
    skip_low, skip_high = low.taps.size - 1, high.taps.size - 1
    halves = (_DecimatingFilter(low, 2, n), _DecimatingFilter(high, 2, n, _alternating_sign))
    thirds = [_DecimatingFilter(f, 3, n) for f in _ternary_filters()]
    n_columns = 3 * 2**nlevel
    maps = [np.empty((2 * nlevel, n_columns)) for _ in statistics]

    def put(row: int, groups) -> None:
        # Each group is a set of sibling bands (made one at a time: a generator keeps one
        # filter output in memory); the map's columns interleave them.
        values: list[list[np.ndarray]] = [[] for _ in statistics]
        for rows, down in groups:
            for out, statistic in zip(values, statistics, strict=True):
                out.append(statistic(rows, down))
        for K, out in zip(maps, values, strict=True):
            flat = np.stack(out, axis=1).ravel()
            K[row] = np.repeat(flat, n_columns // flat.size)

    put(0, [(x[None, :], 1)])
    nodes = x[None, :]
    for depth in range(nlevel):
        if depth <= nlevel - 2:
            # Thirds of every band of this depth: level depth + log2(3), row 2 * depth + 2.
            put(2 * depth + 2, ((f.apply(nodes)[:, skip_low:], 3 * 2**depth) for f in thirds))
        # Children in tree order (low, high of each parent): the map's column order.
        children = np.empty((2 * nodes.shape[0], nodes.shape[1] // 2), dtype=np.complex128)
        a = halves[0].apply(nodes, out=children[0::2])
        d = halves[1].apply(nodes, out=children[1::2])
        down = 2 ** (depth + 1)
        put(2 * depth + 1, [(a[:, skip_low:], down), (d[:, skip_high:], down)])
        nodes = children
    return maps


def _kurtosis_statistic(x: np.ndarray):
    """The band statistic of :func:`kurtogram` on the centred record ``x``:
    :func:`_band_kurtosis`, a band empty where its power is below machine epsilon times the
    record's mean square (a threshold relative to the record, so that its unit does not
    change the map)."""
    floor = _EPS * float(np.mean(np.square(x)))

    def statistic(rows: np.ndarray, decimation: int) -> np.ndarray:
        return _band_kurtosis(rows, floor)

    return statistic


# Fewer cyclic frequencies than this leave a band's negentropy unscored (0).
_MIN_CYCLIC_BINS = 10


def _negentropy_statistic(fs: float, cyclic_range, shaft_hz: float | None):
    """The band statistic of :func:`infogram`: spectral negentropy of the squared envelope
    spectrum over ``cyclic_range``, shaft harmonics left out."""
    fs = check_positive(fs, "fs", unit=" in Hz")
    low, high = 0.0, math.inf
    if cyclic_range is not None:
        try:
            low, high = (float(v) for v in cyclic_range)
        except (TypeError, ValueError):
            raise ValueError(
                f"cyclic_range must be a pair (low, high) in Hz, got {cyclic_range!r}"
            ) from None
        if not 0.0 <= low < high:
            raise ValueError(f"cyclic_range must satisfy 0 <= low < high, got {cyclic_range!r}")
    if shaft_hz is not None:
        shaft_hz = check_positive(shaft_hz, "shaft_hz", unit=" in Hz")

    windows: dict[int, np.ndarray] = {}

    def statistic(rows: np.ndarray, decimation: int) -> np.ndarray:
        n = rows.shape[1]
        alpha = np.fft.rfftfreq(n, d=decimation / fs)
        keep = (alpha >= low) & (alpha <= high) & (alpha > 0.0)
        if shaft_hz is not None:
            step = alpha[1] - alpha[0]
            nearest = np.round(alpha / shaft_hz) * shaft_hz
            keep &= (np.abs(alpha - nearest) > 2.5 * step) & (alpha >= 0.5 * shaft_hz)
        if np.count_nonzero(keep) < _MIN_CYCLIC_BINS:
            return np.zeros(rows.shape[0])
        if np.iscomplexobj(rows):
            sq = np.square(rows.view(np.float64))
            se = sq[:, 0::2] + sq[:, 1::2]
        else:  # the whole band: its analytic signal's envelope
            se = np.abs(signal.hilbert(rows, axis=1)) ** 2
        # Hann-windowed: a strong line (the shaft rate's) leaks far into a rectangular
        # window's spectrum, and its leakage would read as order beyond its masked bins.
        if n not in windows:
            windows[n] = signal.get_window("hann", n, fftbins=True)
        centred = (se - se.mean(axis=1, keepdims=True)) * windows[n]
        power = np.abs(sp_fft.rfft(centred, axis=1, workers=-1)) ** 2
        e = power[:, keep]
        mean = e.mean(axis=1, keepdims=True)
        e = e / np.where(mean > 0.0, mean, 1.0)
        with np.errstate(divide="ignore"):
            return np.where(e > 0.0, e * np.log(e), 0.0).mean(axis=1)

    return statistic


def _best_band(K: np.ndarray, fs: float, nlevel: int, cls=None) -> Kurtogram:
    K = np.where(K > 0, K, 0.0)
    levels = kurtogram_levels(nlevel)
    columns = np.arange(K.shape[1])
    freqs = fs * (columns / (3 * 2 ** (nlevel + 1)) + 1.0 / (3 * 2 ** (nlevel + 2)))
    # As the reference's max_IJ: the maximum of each column (first row on ties), then the
    # first column holding the overall maximum, which is the first column of its band.
    row_of_max = np.argmax(K, axis=0)
    column = int(np.argmax(K[row_of_max, columns]))
    row = int(row_of_max[column])
    level = float(levels[row])
    fi = column / 3.0 / 2 ** (nlevel + 1) + 2.0 ** (-2.0 - level)
    return (Kurtogram if cls is None else cls)(
        K=K,
        levels=levels,
        freqs=freqs,
        level=level,
        fc=fs * fi,
        bw=fs * 2.0 ** -(level + 1.0),
        kurtosis=float(K[row, column]),
        row=row,
        column=column,
        fs=fs,
    )
