"""A steady speed checked on the record: the shaft rate that the record's own harmonics
show near a given one (a name plate or nominal speed can be a few percent off), and the
check :func:`diagnostics.diagnose` makes of the speed it is given (the series near it
weighed against the best a little farther).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage, stats

from diagnostics._checks import (
    check_positive,
    check_positive_int,
    check_signal,
    check_varying,
    normalise,
)

__all__ = ["ShaftLines", "shaft_lines", "speed_check"]

# -------------------------------------------------------------------- a steady speed checked
# A harmonic stands out when the larger of its two bins would be reached by noise with at
# most this probability; the series is there when so many stand out that noise, over every
# candidate searched, would show as many with at most _SHAFT_LINES_P.
_SHAFT_LINE_P = 0.01
_SHAFT_LINES_P = 0.01
# The value of the larger of two exponential bins that noise exceeds with _SHAFT_LINE_P:
# 1 - (1 - exp(-v))**2 = p.
_SHAFT_LINE_Z = -math.log(1.0 - math.sqrt(1.0 - _SHAFT_LINE_P))


@dataclass(frozen=True)
class ShaftLines:
    """Result of :func:`shaft_lines`: the shaft's harmonic series near a given rate.

    Attributes
    ----------
    given_hz : float
        The rate searched around (Hz).
    found_hz : float
        Fundamental of the strongest harmonic series within the tolerance (Hz).
    n_harmonics : int
        Harmonics searched.
    n_standing : int
        Those of ``found_hz`` that stand out of the spectrum's background (each the peak of
        its neighbourhood, and reached by noise with a probability of 1 % at most); 0 where
        no candidate's first or second harmonic stands.
    strength : float
        Sum of ``log1p`` of the standing harmonics' values (each over the background).
    p_value : float
        Probability that noise shows a series with as many standing out at some candidate
        rate (a union bound over the candidates).
    tolerance : float
        Relative half-width of the search.
    """

    given_hz: float
    found_hz: float
    n_harmonics: int
    n_standing: int
    strength: float
    p_value: float
    tolerance: float

    @property
    def present(self) -> bool:
        """Whether the series stands clear of a random spectrum (``p_value`` at most 1 %)."""
        return self.p_value <= _SHAFT_LINES_P

    @property
    def offset(self) -> float:
        """``found_hz / given_hz - 1``."""
        return self.found_hz / self.given_hz - 1.0


def shaft_lines(
    x, fs: float, shaft_hz: float, *, tolerance: float = 0.05, n_harmonics: int = 20
) -> ShaftLines:
    """The shaft rate a steady record's own spectrum shows, near a given rate.

    Every rotating machine vibrates at multiples of its shaft rate, and those lines are
    usually the strongest of its spectrum. A rate from a name plate, a nominal speed or a
    file's RPM field can be off by a percent or more (an induction motor slips by up to a
    few percent under load), and a bearing's fault frequencies with it; an envelope analysis
    that places its fault combs and shaft masks at the given rate then looks in the wrong
    places (on the development records, a speed 1 % off turned 4 of 17 healthy-bearing
    checks into false alarms and 2 % off lost 5 of 31 faults).

    This finds the fundamental, within ``tolerance`` of ``shaft_hz``, whose first
    ``n_harmonics`` multiples stand highest in the record's spectrum (Hann window; each bin
    over the running median of two shaft periods around it, over ln 2, so that noise bins
    read as unit exponential variables). A harmonic stands where the larger of its two bins
    would be reached by noise with a probability of 1 % at most and is the peak of its
    neighbourhood (the skirt of a strong line nearby is no line); a candidate scores the
    ``log1p`` of its standing lines (one loud line, a mains harmonic, cannot carry it), and
    only a candidate whose first or second harmonic stands counts (unbalance, misalignment:
    an impact train near a multiple of the shaft rate puts lines on every third harmonic of
    some rate near it, none on its first). The rate is then fitted to the peaks of the
    standing harmonics (parabolic peaks, least squares; a tenth of a bin at the top
    harmonic). ``p_value`` says whether the series is there at all: a record without shaft
    harmonics at the given rate (a wrong channel, sampling rate or speed) shows no more
    standing lines than noise does.

    Parameters
    ----------
    x : array_like
        1-D vibration record at a steady speed.
    fs : float
        Sampling rate in Hz.
    shaft_hz : float
        The given shaft rate in Hz.
    tolerance : float
        Relative half-width of the search (below 0.5).
    n_harmonics : int
        Harmonics per candidate (fewer where they would pass 80 % of fs/2).

    Returns
    -------
    ShaftLines

    Raises
    ------
    ValueError
        On an invalid signal, rate or option.

    Examples
    --------
    A motor read as 1800 rpm that turns at 1746 rpm (3 % slip): six shaft harmonics in noise.

    >>> fs, rng = 12000.0, np.random.default_rng(0)
    >>> t = np.arange(int(4 * fs)) / fs
    >>> x = sum(np.cos(2 * np.pi * k * 29.1 * t) / k for k in range(1, 7))
    >>> found = shaft_lines(x + rng.standard_normal(t.size), fs, 30.0)
    >>> round(found.found_hz, 2), round(100 * found.offset, 1), found.present
    (29.1, -3.0, True)
    """
    x, fs, shaft_hz = _check_steady_record(x, fs, shaft_hz)
    tolerance = _check_tolerance(tolerance)
    n_harmonics = check_positive_int(n_harmonics, "n_harmonics")
    return _series_near(_line_spectrum(x, fs, shaft_hz), fs, shaft_hz, tolerance, n_harmonics)


def speed_check(
    x, fs: float, shaft_hz: float, *, near: float = 0.005, wide: float = 0.05,
    n_harmonics: int = 20,
) -> ShaftLines:  # fmt: skip
    """The record's shaft series around a given speed: the stronger of the best within
    ``near`` of it and the best within ``wide`` (the wide one where neither is present).

    Another source's lines can form a series at a rate close to the shaft's: impacts at a
    third of a neighbouring bearing's BPFO, 1.8 % above the shaft rate, have lines at every
    multiple of it, and outnumbered six strong shaft harmonics within 5 % (12 harmonics
    standing against 6) though they are weaker (a strength of 38 against 46). The series
    near the speed given is kept where it is the stronger. Both searches are
    :func:`shaft_lines`' on one spectrum.

    Parameters
    ----------
    x : array_like
        1-D vibration record at a steady speed.
    fs : float
        Sampling rate in Hz.
    shaft_hz : float
        The given shaft rate in Hz.
    near, wide : float
        Relative half-widths of the two searches (each below 0.5).
    n_harmonics : int
        Harmonics per candidate.

    Returns
    -------
    ShaftLines

    Raises
    ------
    ValueError
        On an invalid signal, rate or option.
    """
    x, fs, shaft_hz = _check_steady_record(x, fs, shaft_hz)
    near, wide = _check_tolerance(near, "near"), _check_tolerance(wide, "wide")
    n_harmonics = check_positive_int(n_harmonics, "n_harmonics")
    spectrum = _line_spectrum(x, fs, shaft_hz)
    close = _series_near(spectrum, fs, shaft_hz, near, n_harmonics)
    far = _series_near(spectrum, fs, shaft_hz, wide, n_harmonics)
    return close if close.present and close.strength >= far.strength else far


def _check_steady_record(x, fs, shaft_hz) -> tuple[np.ndarray, float, float]:
    fs = check_positive(fs, "fs", unit=" in Hz")
    x, _ = normalise(check_varying(check_signal(x, fs)))  # lines stand out in any unit
    return x, fs, check_positive(shaft_hz, "shaft_hz", unit=" in Hz")


def _check_tolerance(value, name: str = "tolerance") -> float:
    value = check_positive(value, name)
    if value >= 0.5:
        raise ValueError(f"{name} must be below 0.5, got {value!r}")
    return value


def _line_spectrum(x: np.ndarray, fs: float, shaft_hz: float) -> tuple:
    """``(df, power, z)``: the Hann power spectrum of ``x`` and each bin over the running
    median of two shaft periods around it, over ln 2 (noise bins: unit exponential)."""
    df = fs / x.size
    power = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size))) ** 2
    half = max(int(round(shaft_hz / df)), 10)
    background = ndimage.median_filter(power, size=2 * half + 1, mode="nearest") / math.log(2.0)
    return df, power, power / np.maximum(background, np.finfo(float).tiny)


def _series_near(
    spectrum: tuple, fs: float, shaft_hz: float, tolerance: float, n_harmonics: int
) -> ShaftLines:
    """:func:`shaft_lines` on a spectrum from :func:`_line_spectrum`."""
    df, power, z = spectrum
    top = (1.0 + tolerance) * shaft_hz
    n_harm = min(n_harmonics, int(0.4 * fs / top))
    if n_harm < 1:
        raise ValueError(f"fs = {fs:g} Hz is too low for a shaft rate of {shaft_hz:g} Hz")
    k = np.arange(1, n_harm + 1)
    # Candidates close enough that the top harmonic moves by half a bin per step.
    grid = np.arange((1.0 - tolerance) * shaft_hz, top, df / (2.0 * n_harm))
    values = _harmonic_values(z, df, grid, k)[1]
    # Only lines that stand out count toward a candidate's score (summed as log1p, so that
    # one loud line, a mains harmonic, cannot carry it); the background's random bins at the
    # other harmonics would otherwise move the best candidate about.
    score = np.where(values >= _SHAFT_LINE_Z, np.log1p(values), 0.0).sum(axis=1)
    # A shaft's series starts at the shaft: its first or second harmonic stands (unbalance,
    # misalignment). Without that rule an impact train near a multiple of the shaft rate,
    # whose lines fall on every third harmonic of a rate close to the shaft's, can outscore
    # a shaft series of few harmonics.
    starts = _harmonic_lines(z, df, grid, k[:2])[1].any(axis=1)
    best = int(np.argmax(np.where(starts, score, -np.inf) if starts.any() else score))
    found = float(grid[best])
    at_found = values[best]
    standing = _harmonic_lines(z, df, grid[best : best + 1], k)[1][0] & starts[best]
    for _ in range(2):
        if not standing.any():
            break
        # The grid places the lines within a bin; their peaks place the rate finer, and a
        # harmonic the grid's step left a bin off stands at the fitted rate.
        found = _fit_fundamental(power, df, found, k[standing])
        at_found, standing = (a[0] for a in _harmonic_lines(z, df, np.array([found]), k))
    if not standing[: min(2, n_harm)].any():
        standing = np.zeros_like(standing)
    n_standing = int(standing.sum())
    tail = stats.binom.sf(n_standing - 1, n_harm, _SHAFT_LINE_P) if n_standing else 1.0
    return ShaftLines(
        given_hz=shaft_hz,
        found_hz=found,
        n_harmonics=n_harm,
        n_standing=n_standing,
        strength=float(np.log1p(at_found[standing]).sum()),
        p_value=float(min(1.0, grid.size * tail)),
        tolerance=tolerance,
    )


def _harmonic_values(
    z: np.ndarray, df: float, fundamentals: np.ndarray, k: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``(lo, values)`` of harmonics ``k`` of each fundamental: the lower of the two bins
    around each line, and the larger of their values (the line falls between them)."""
    lo = np.clip(np.floor(np.outer(fundamentals, k) / df).astype(int), 0, z.size - 2)
    return lo, np.maximum(z[lo], z[lo + 1])


def _harmonic_lines(
    z: np.ndarray, df: float, fundamentals: np.ndarray, k: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """``(values, stands)`` of harmonics ``k`` of each fundamental: the larger of the two bins
    around each, and whether it stands out (reached by noise with probability
    _SHAFT_LINE_P at most, and the peak of its neighbourhood: the skirt of a strong line a
    few bins away is no line here)."""
    lo, values = _harmonic_values(z, df, fundamentals, k)
    around = np.clip(lo[:, :, None] + np.arange(-2, 4), 0, z.size - 1)
    stands = (values >= _SHAFT_LINE_Z) & (values >= z[around].max(axis=2))
    return values, stands


def _fit_fundamental(power: np.ndarray, df: float, f0: float, k: np.ndarray) -> float:
    """Fundamental fitted to the peaks of harmonics ``k`` of ``f0``.

    Each peak's frequency comes from a parabola through the log power of its top bin (within
    two bins of :math:`k f_0`) and their neighbours. The median of :math:`f_k / k` gives a first
    rate; peaks more than half a bin from its multiples (a noise peak that stood out, one in
    a hundred of the harmonics sought) are left out, and the rest fitted by least squares of
    :math:`f_k = k f`, where a high harmonic weighs most."""
    centre = np.rint(k * f0 / df).astype(int)
    window = np.clip(centre[:, None] + np.arange(-2, 3)[None, :], 1, power.size - 2)
    top = window[np.arange(k.size), np.argmax(power[window], axis=1)]
    tiny = np.finfo(float).tiny
    left, mid, right = (np.log(np.maximum(power[top + d], tiny)) for d in (-1, 0, 1))
    curve = left - 2.0 * mid + right
    shift = np.where(curve < 0.0, 0.5 * (left - right) / np.where(curve < 0.0, curve, -1.0), 0.0)
    f_k = (top + np.clip(shift, -0.5, 0.5)) * df
    first = float(np.median(f_k / k))
    keep = np.abs(f_k - k * first) <= 0.5 * df
    if not keep.any():
        return first
    return float((k[keep] * f_k[keep]).sum() / (k[keep] ** 2).sum())
