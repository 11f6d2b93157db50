"""Band selection: the demodulation bands :func:`diagnostics.diagnose` tries beside the whole
prewhitened one (the infogram's best band and its best apart from that one, or the
kurtogram's; the kurtogram's band of the random part after discrete/random separation), and
the best band of a band map under constraints (:func:`kurtogram_band`).
"""

from __future__ import annotations

import math

import numpy as np

from diagnostics._comb import _USABLE_FRACTION
from diagnostics._frequencies import FaultFrequencies
from diagnostics._kurtosis import kurtogram, kurtogram_and_infogram
from diagnostics._separation import discrete_random_separation

__all__ = ["kurtogram_band"]

# How the demodulation band beside the whole prewhitened one is chosen.
_SELECTORS = ("infogram", "kurtogram")


def kurtogram_band(
    kg, min_bandwidth_hz: float = 0.0, min_low_hz: float = 0.0, apart_from=None
) -> tuple[tuple[float, float], float] | None:
    """Best band of a fast kurtogram among the bands that meet two constraints.

    Parameters
    ----------
    kg : diagnostics.Kurtogram
        The kurtogram.
    min_bandwidth_hz : float
        Narrowest band accepted.
    min_low_hz : float
        Lowest lower edge accepted.
    apart_from : tuple of float, optional
        A band ``(f_lo, f_hi)`` in Hz that the band found must not overlap.

    Returns
    -------
    ((f_lo, f_hi), kurtosis) or None
        None when no band qualifies.

    References
    ----------
    Antoni, J. (2007). Fast computation of the kurtogram for the detection of transient
    faults. *Mechanical Systems and Signal Processing* 21(1), 108-124.
    """
    fs = float(kg.fs)
    levels = np.asarray(kg.levels, dtype=float)
    bws = fs / 2.0 / 2.0**levels
    centres = np.asarray(kg.freqs, dtype=float)
    # Bands tile 0..fs/2 at every level; a column belongs to the band holding its centre.
    lows = np.floor(centres[None, :] / bws[:, None]) * bws[:, None]
    tol = 1e-9 * fs
    ok = (bws[:, None] >= min_bandwidth_hz) & (lows >= min_low_hz - tol)
    if apart_from is not None:
        ok &= (lows + bws[:, None] <= apart_from[0] + tol) | (lows >= apart_from[1] - tol)
    if not ok.any():
        return None
    masked = np.where(ok, np.asarray(kg.K, dtype=float), -np.inf)
    r, c = np.unravel_index(int(np.argmax(masked)), masked.shape)
    lo = float(lows[r, c])
    return (lo, float(min(lo + bws[r], fs / 2.0))), float(masked[r, c])


def _demod_band(band: tuple[float, float], fs: float) -> tuple[float, float] | None:
    """A band as envelope_spectrum takes it; None for the whole band."""
    lo, hi = band
    if lo <= 0.0 and hi >= fs / 2.0:
        return None
    # A band from 0 Hz becomes a band-pass from a low edge (the filter needs one).
    return max(lo, 1e-3 * fs), min(hi, fs / 2.0)


def _random_part(x: np.ndarray, fs: float, shaft_hz: float) -> np.ndarray | None:
    """Random part of the record by discrete/random separation, resolving a quarter of the
    shaft rate; None for a record too short for it."""
    nfft = int(2 ** math.ceil(math.log2(4.0 * fs / shaft_hz)))
    if x.size < 9 * nfft:
        return None
    return discrete_random_separation(x, fs, nfft=nfft).random


def _candidate_bands(
    x: np.ndarray,
    white: np.ndarray,
    fs: float,
    freqs: FaultFrequencies,
    f_low: float,
    f_high: float,
    f_max: float,
    n_harmonics: int,
    nlevel: int,
    use_kurtogram: bool,
    band_selector: str,
    use_drs: bool,
) -> tuple[list[tuple[str, tuple[float, float], float, np.ndarray]], object, object]:
    """``(candidates, kurtogram, infogram)``: the demodulation bands tried, each as ``(name,
    band, kurtosis, signal)``: the whole prewhitened band, the infogram's best band and its
    best apart from that one (or the kurtogram's best), the kurtogram's band of the random
    part with ``use_drs``."""
    candidates: list[tuple[str, tuple[float, float], float, np.ndarray]] = [
        ("prewhitened", (0.0, fs / 2.0), 0.0, white)
    ]
    kg_white = info = None
    # The fast kurtogram needs 2**(nlevel + 7) samples; a short record gets fewer levels.
    levels = min(nlevel, int(math.log2(white.size)) - 7)
    bw_min = 2.0 * f_high / _USABLE_FRACTION
    # Demodulate above the fault frequencies' own range: below it the band holds the
    # deterministic low-frequency vibration, whose beats are not impacts.
    f_floor = (n_harmonics + 1) * f_high
    if use_kurtogram and levels >= 1:
        if band_selector == "infogram":
            # The band whose squared envelope holds the most lines over the race and spin
            # combs' range (from half the slowest fault frequency), shaft harmonics aside;
            # the kurtogram, shown beside it, takes the most impulsive band, which a few
            # strong impacts at no period can win. Down to half the cage rate instead:
            # 1 more of 40 sub-multiple scenarios, but CWRU 118's band, and verdict, then
            # differed between time and orders.
            cyclic = (0.5 * f_low, f_max)
            kg_white, info = kurtogram_and_infogram(white, fs, levels, cyclic, freqs.shaft)
            chosen = info
        else:
            chosen = kg_white = kurtogram(white, fs, nlevel=levels)
        found = kurtogram_band(chosen, min_bandwidth_hz=bw_min, min_low_hz=f_floor)
        if found is not None:
            candidates.append((band_selector, found[0], found[1], white))
            if band_selector == "infogram":
                # And its best band apart from that one: where another source's lines take
                # the first, the fault's impacts, ringing another resonance, hold the next.
                second = kurtogram_band(info, bw_min, f_floor, apart_from=found[0])
                if second is not None:
                    candidates.append(("infogram, second", second[0], second[1], white))
    if use_drs and levels >= 1:
        separated = _random_part(x, fs, freqs.shaft)
        if separated is not None:
            kg_random = kurtogram(separated, fs, nlevel=levels)
            found = kurtogram_band(kg_random, min_bandwidth_hz=bw_min, min_low_hz=f_floor)
            if found is not None:
                candidates.append(("drs-kurtogram", found[0], found[1], separated))
    return candidates, kg_white, info
