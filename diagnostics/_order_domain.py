"""The order-domain path of :func:`diagnostics.diagnose`: a record at a varying speed checked
for length in shaft revolutions, order-tracked, and band-limited to the orders it holds all
through.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import signal

from diagnostics._checks import check_positive
from diagnostics._frequencies import BearingGeometry, bearing_frequencies
from diagnostics._prewhiten import _TAPER_S
from diagnostics._speed import order_track, shaft_angle


def _angular_sampling(
    geometry: BearingGeometry,
    rate: np.ndarray,
    fs: float,
    samples_per_rev: float | None,
) -> tuple[float, float]:
    """``(samples_per_rev, taper)`` of a record at the speed profile ``rate``: the angular
    sampling (default ``fs / min(rate)``, which keeps the whole band at the slowest speed)
    and the prewhitening taper in revolutions (the time domain's at the mean speed).

    Raises
    ------
    ValueError
        On a bad ``samples_per_rev``, or a record shorter than 20 periods of the slowest
        fault order and the tapers.
    """
    spr = float(math.ceil(fs / float(rate.min()))) if samples_per_rev is None else samples_per_rev
    spr = check_positive(spr, "samples_per_rev")
    orders = bearing_frequencies(geometry, 1.0)
    slowest = min(orders.bpfo, orders.bpfi, 2.0 * orders.bsf)
    revolutions = float(shaft_angle(rate, fs)[-1])
    # The prewhitening's taper covers the same time at the mean speed as in the time domain.
    taper = _TAPER_S * float(rate.mean())
    needed = 20.0 / slowest + 2.0 * taper
    if revolutions < needed:
        raise ValueError(
            f"x is too short: the record covers {revolutions:.3g} shaft revolutions; diagnose "
            f"needs {needed:.3g} (20 periods of the slowest fault order, {slowest:.4g})"
        )
    return spr, taper


def _band_limited_orders(
    x: np.ndarray, fs: float, rate: np.ndarray, spr: float
) -> tuple[np.ndarray, float]:
    """``(y, spr)``: ``x`` order-tracked at ``spr`` samples per revolution and kept to the
    orders held all through the record, and the angular sampling of ``y``."""
    tracked = order_track(x, fs, rate, spr)
    # Only the orders held all through the record are analysed: above them the content comes
    # and goes with the speed (and the prewhitening would raise an empty band to unit level),
    # which the kurtogram reads as impulsiveness. An FFT resampling keeps exactly that band.
    kept = int(round(tracked.x.size * 2.0 * tracked.cutoff_order / spr))
    if kept < tracked.x.size:
        band_limited = signal.resample(tracked.x, kept)
        spr = spr * kept / tracked.x.size
    else:
        band_limited = tracked.x
    return band_limited, spr
