r"""The load zone's modulation of an inner-race spall's events, in the envelope spectrum
(numpy, and :mod:`diagnostics`; no Taichi).

An inner-race spall turns with the shaft, through the load zone and out of it, once per
shaft turn: its impacts are strong under the load and fade outside it. A train of
impulses at BPFI whose strength repeats once per turn has, in its envelope spectrum,
lines at :math:`k \, \mathrm{BPFI} + m f_s`: the shaft-rate sidebands, whose size over the
line at BPFI is the :math:`m`-th Fourier coefficient of the strength over one turn over its
mean (:func:`taichi_bearing.analytic.inner_race.sideband_ratio`). They are resolved only when the
record is long enough that the spectrum's resolution, :math:`1 / T`, separates them from
the line: :math:`T \ge 2 / f_s` here (two shaft turns).
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.analytic.bearing import fault_frequencies
from taichi_bearing.case import Case
from taichi_bearing.checks.common import check

__all__ = [
    "SIDEBAND_DB",
    "analysis_band",
    "flexible_load_zone",
    "load_zone_check",
    "sideband_levels",
]

SIDEBAND_DB = 6.0  # a line this far above the spectrum's median around it stands out


def analysis_band(kg, fs: float) -> tuple[tuple[float, float], str]:
    """The demodulation band of the run's envelope analysis, and how it was chosen: the
    fast kurtogram's best band above fs/16 (the re-stressing bursts ring high; the
    rolling's low-frequency response is left out), else fs/8 to 0.45 fs."""
    from diagnostics import kurtogram_band

    band, how = None, ""
    if kg is not None:
        found = kurtogram_band(kg, min_low_hz=fs / 16.0)
        if found is not None:
            band, how = found[0], "the kurtogram's best band above fs/16"
    if band is None:
        band, how = (fs / 8.0, 0.45 * fs), "fs/8 to 0.45 fs (no kurtogram)"
    return (max(band[0], 1e-3 * fs), min(band[1], 0.499 * fs)), how


def _line(f: np.ndarray, amp: np.ndarray, f0: float) -> float:
    """The largest amplitude within one bin of ``f0`` (a line between two bins)."""
    df = f[1] - f[0]
    sel = np.abs(f - f0) <= df
    return float(amp[sel].max()) if sel.any() else math.nan


def sideband_levels(x: np.ndarray, fs: float, bpfi_hz: float, shaft_hz: float) -> dict:
    """The line at BPFI and its first shaft-rate sidebands in the squared envelope
    spectrum of ``x``, demodulated in :func:`analysis_band`.

    Returns ``band_hz``, ``resolution_hz``, ``resolved`` (the resolution at most half the
    shaft rate), the amplitudes ``line``, ``lower`` and ``upper`` (at BPFI - f_s and
    BPFI + f_s), ``background`` (the median amplitude from 0.5 to 1.5 BPFI),
    ``lower_db``, ``upper_db`` and ``line_db`` (each over the background, dB) and
    ``ratio`` (the mean of the two sidebands over the line).
    """
    from diagnostics import choose_nlevel, envelope_spectrum, kurtogram

    x = np.asarray(x, dtype=float)
    nlevel = choose_nlevel(x.size)
    kg = kurtogram(x, fs, nlevel=nlevel) if nlevel >= 1 else None
    band, _ = analysis_band(kg, fs)
    f, amp = envelope_spectrum(x, fs, band=band)
    df = float(f[1] - f[0])
    near = (f >= 0.5 * bpfi_hz) & (f <= 1.5 * bpfi_hz)
    background = float(np.median(amp[near])) if near.any() else math.nan
    line = _line(f, amp, bpfi_hz)
    lower = _line(f, amp, bpfi_hz - shaft_hz)
    upper = _line(f, amp, bpfi_hz + shaft_hz)

    def db(a: float) -> float:
        return 20.0 * math.log10(a / background) if a > 0 and background > 0 else math.nan

    return {
        "band_hz": [float(band[0]), float(band[1])],
        "resolution_hz": df,
        "resolved": bool(df <= 0.5 * shaft_hz),
        "line": line,
        "lower": lower,
        "upper": upper,
        "background": background,
        "line_db": db(line),
        "lower_db": db(lower),
        "upper_db": db(upper),
        "ratio": 0.5 * (lower + upper) / line if line > 0 else math.nan,
    }


def flexible_load_zone(case: Case, reference: np.ndarray, n_angles: int = 720):
    """The run's own load zone: the flexible-ring reference forces of the preload (one per
    roller, at their start angles), interpolated round the turn (periodic, linear).
    Returns the angles (rad from 12 o'clock) and forces (N)."""
    z = case.bearing.n_rollers
    start = case.run.first_roller_angle + 2.0 * math.pi * np.arange(z) / z
    start = (start + math.pi) % (2.0 * math.pi) - math.pi
    angles = np.linspace(-math.pi, math.pi, n_angles, endpoint=False)
    load = np.interp(angles, start, np.asarray(reference, dtype=float), period=2.0 * math.pi)
    return angles, load


def load_zone_check(
    case: Case,
    signal: np.ndarray,
    fs: float,
    passages: list[dict],
    reference: np.ndarray | None = None,
) -> tuple[dict, dict]:
    r"""Shaft-rate sidebands around BPFI in the squared envelope spectrum: the inner-race
    spall's impacts modulated by the load zone it turns through once per shaft turn.

    Passes when both first sidebands, :math:`\mathrm{BPFI} \pm f_s`, stand
    :data:`SIDEBAND_DB` over the
    spectrum's median around BPFI; the value is their mean over the line at BPFI, beside
    the predictions for impulses growing with the load (squared envelope: the Fourier
    coefficient of :math:`Q^2` over a turn), with the rigid-ring load zone and with the run's own
    (``reference``: the flexible-ring forces of the preload, narrower on an
    adapter-hung ring). ``passed`` is None when the record is shorter than two shaft
    turns: the sidebands are not resolved and the modulation shows only in the passages'
    loads, listed in the note. Returns the check and its numbers.
    """
    from taichi_bearing.analytic.inner_race import sideband_ratio
    from taichi_bearing.analytic.quasistatic import load_zone

    freqs = fault_frequencies(case.bearing, case.operating.shaft_hz)
    angles, load = load_zone(case)
    values: dict = {"predicted_ratio_rigid_ring": sideband_ratio(angles, load**2)}
    predicted = f"{values['predicted_ratio_rigid_ring']:.2f} (rigid-ring load zone)"
    if reference is not None:
        angles, load = flexible_load_zone(case, reference)
        values["predicted_ratio_flexible_ring"] = sideband_ratio(angles, load**2)
        predicted += f", {values['predicted_ratio_flexible_ring']:.2f} (the run's own)"
    loads = ", ".join(
        f"{p['spall_angle_deg']:.0f} deg: {p['force_before_N'] / 1e3:.3g} kN"
        for p in passages
        if math.isfinite(p["force_before_N"])
    )
    why = (
        f"predicted sideband/line for impulses growing with the load {predicted}; roller "
        f"loads at the passages (spall angle: load) {loads or 'none'}"
    )
    if len(signal) * freqs.shaft < 2.0 * fs:
        note = (
            f"the record ({1e3 * len(signal) / fs:.3g} ms) is shorter than two shaft turns "
            f"({2e3 / freqs.shaft:.3g} ms): the shaft-rate sidebands are not resolved; {why}"
        )
        return check(None, None, None, note), values
    lv = sideband_levels(signal, fs, freqs.bpfi, freqs.shaft)
    values.update(lv)
    stand = min(lv["lower_db"], lv["upper_db"])
    return check(
        lv["ratio"],
        None,
        stand >= SIDEBAND_DB,
        f"squared envelope spectrum in {lv['band_hz'][0]:.0f}-{lv['band_hz'][1]:.0f} Hz, "
        f"resolution {lv['resolution_hz']:.3g} Hz: BPFI {freqs.bpfi:.4g} Hz at "
        f"{lv['line_db']:.3g} dB over the median around it, BPFI - f_s {lv['lower_db']:.3g} "
        f"dB, BPFI + f_s {lv['upper_db']:.3g} dB (each must reach {SIDEBAND_DB:g} dB); "
        f"value: sidebands over the line; {why}",
    ), values
