"""Spall passages in a run's histories: when each roller enters and leaves the outer
raceway's spall, and the force and acceleration around each passage (numpy and pandas, no
Taichi). The run's checks (:mod:`taichi_bearing.checks`) judge what these find."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from taichi_bearing.run_folder import TIME_COLUMN, roller_force_column, roller_motion_column

__all__ = [
    "EXIT_BURST_S",
    "PASSAGE_QUANTITIES",
    "RESTRESS_MEAN_S",
    "SpallEvent",
    "detect_spall_events",
    "passage_signature",
    "passage_statistics",
]

RESTRESS_MEAN_S = 1e-4  # averaging time of the re-stressing force, s
EXIT_BURST_S = 1e-3  # shortest exit window: the re-stressing burst rings for ~1 ms


class SpallEvent(dict):
    """``roller``; ``entry_time_s`` (de-stressing: the force falls through half its
    value before the spall), ``floor_window_s`` (start, end of the traverse),
    ``first_impact_time_s`` (first touch of the exit edge) and ``exit_time_s``
    (re-stressing: the mean force regains half its value); ``force_before_N``."""


def _spall_geometry(info: Mapping) -> dict | None:
    spall = info.get("spall")
    if not spall or spall.get("race") != "outer":
        return None
    return spall


def detect_spall_events(
    hist: pd.DataFrame, n_rollers: int, info: Mapping, roller_radius: float
) -> list[SpallEvent]:
    """Entry and exit of every roller that passes the outer-raceway spall.

    The roller's outer contact point lies on the radial line through its centre, so its
    position relative to the spall is the centre angle minus the spall's start angle,
    ``rel`` (0 at the entry edge, ``span`` at the exit edge). ``F0``: the median normal
    force on the outer raceway while the contact is more than 1 mm before the edge.
    Entry: the first time after ``rel = -1 mm`` that the force is below ``F0 / 2``.
    Once the roller is within the distance at which it meets the exit edge,
    ``sqrt(2 r d) + 0.5 mm`` before it (``d``: the spall depth, or the roller's dip into
    the notch if smaller; an impact on the floor earlier in the traverse is not taken for
    the exit): first impact, the first force above ``F0 / 10``; exit (re-stressing), the
    first time the force averaged over the last 0.1 ms exceeds ``F0 / 2``.
    """
    spall = _spall_geometry(info)
    if spall is None:
        return []
    radius = float(spall["raceway_radius"])
    start = float(spall["centre_angle_from_top"]) - 0.5 * float(spall["length"]) / radius
    span = float(spall["length"]) / radius
    half = 0.5 * float(spall["length"])
    dip = roller_radius - math.sqrt(max(roller_radius**2 - half**2, 0.0))
    d = min(float(spall["depth"]), dip)
    meet = (math.sqrt(2.0 * roller_radius * d) + 0.5e-3) / radius
    lead = 1e-3 / radius
    t = hist[TIME_COLUMN].to_numpy()
    events = []
    for j in range(n_rollers):
        a_col = roller_motion_column(j, "angle_rad")
        if a_col not in hist:
            continue
        rel = (hist[a_col].to_numpy() - start + math.pi) % (2 * math.pi) - math.pi
        fn = hist[roller_force_column(j, "outer", "fn")].to_numpy()
        before = rel < -lead
        # the roller must come from before the spall and get past its exit edge
        ref = before & (rel > -2 * span - lead)
        passes = rel[0] < -lead and rel[-1] >= span and np.all(np.abs(rel) < 1.0)
        if not passes or ref.sum() < 3:
            continue
        first_after = np.flatnonzero(~before & (rel < span + lead))
        f0 = float(np.median(fn[ref]))
        if not f0 > 0 or first_after.size == 0:
            continue
        k0 = int(first_after[0])
        low = k0 + np.flatnonzero(fn[k0:] < 0.5 * f0)
        if low.size == 0:
            continue
        i_entry = int(low[0])
        meets = np.flatnonzero((np.arange(len(t)) > i_entry) & (rel >= span - meet))
        if meets.size == 0:
            continue
        i_meet = int(meets[0])
        # the re-stressing is a burst of impulses: its time is when the force averaged
        # over the last RESTRESS_MEAN_S regains half of F0 (a single impulse crossing
        # that level jitters with the phase of the roller's bounce)
        n_mean = max(1, round(RESTRESS_MEAN_S / max(float(np.median(np.diff(t))), 1e-12)))
        mean = np.convolve(fn, np.ones(n_mean) / n_mean)[: len(fn)]
        up = i_meet + np.flatnonzero(mean[i_meet:] > 0.5 * f0)
        hit = i_meet + np.flatnonzero(fn[i_meet:] > 0.1 * f0)
        if up.size == 0 or hit.size == 0:
            continue
        events.append(
            SpallEvent(
                roller=j,
                entry_time_s=float(t[i_entry]),
                first_impact_time_s=float(t[hit[0]]),
                exit_time_s=float(t[up[0]]),
                floor_window_s=(float(t[min(i_entry + 1, i_meet)]), float(t[i_meet])),
                force_before_N=f0,
            )
        )
    events.sort(key=lambda e: e["entry_time_s"])
    return events


def passage_signature(
    hist: pd.DataFrame, event: Mapping, signal: str, window_s: float = 3e-4
) -> dict[str, float]:
    """Force and acceleration around one passage: what the reference study says the physics shows.

    Windows: entry ``[entry - window, entry + window / 2]``; traverse (with any floor
    impact) from half a window after entry to the first impact on the exit edge; exit
    (the re-stressing burst) from the first impact for ``window`` or :data:`EXIT_BURST_S`,
    whichever is longer: the roller bounces between the exit edge and the inner raceway
    (a ~15 kHz radial mode) for about a millisecond whatever the speed.

    Returns the largest force on the roller in the entry and exit windows over ``F0``
    (outer or inner raceway, whichever is larger: the re-stressing squeezes the roller
    between both; about 1 or less at entry: no impulse), the number of separate impulses
    of the outer-raceway force at exit (peaks standing at least ``F0 / 4`` above the
    troughs either side: on a fine mesh the later impulses ride on the returning load,
    0.25-0.45 F0 above their troughs on the default case), and the largest
    |a - median| of ``signal`` in each window; and, for the study of how these converge
    (:data:`PASSAGE_QUANTITIES`):

    - ``entry_destress_time_s``: the outer-raceway force falling from 90 % to 10 % of
      ``F0`` around the entry (the last sample at or above 0.9 F0 before the entry, the
      first at or below 0.1 F0 after it);
    - ``exit_impulse_width_s``: the median width of the exit impulses at half their
      prominence (NaN without impulses);
    - ``exit_reload_time_s``: from the first touch of the exit edge until the force
      averaged over :data:`RESTRESS_MEAN_S` regains 0.9 ``F0`` (NaN if it does not within
      the record);
    - ``exit_entry_accel_ratio``: the exit acceleration peak over the larger of the
      entry and traverse peaks (the exit-burst check's ratio);
    - ``exit_peak_frequency_hz``: the frequency of the largest component of ``signal``
      in the exit window (Hann window, zero-padded to 16x): the band the re-stressing
      excites.
    """
    from scipy.signal import find_peaks, peak_widths

    t = hist[TIME_COLUMN].to_numpy()
    j = int(event["roller"])
    fn = hist[roller_force_column(j, "outer", "fn")].to_numpy()
    inner = hist.get(roller_force_column(j, "inner", "fn"))
    both = fn if inner is None else np.maximum(fn, inner.to_numpy())
    acc = hist[signal].to_numpy()
    acc = np.abs(acc - np.median(acc))
    f0 = float(event["force_before_N"])
    te = float(event["entry_time_s"])
    tx = float(event.get("first_impact_time_s", event["exit_time_s"]))
    entry = (t >= te - window_s) & (t <= te + 0.5 * window_s)
    floor = (t > te + 0.5 * window_s) & (t < tx)
    leave = (t >= tx) & (t <= tx + max(window_s, EXIT_BURST_S))
    # the roller is unloaded just before its first impact: a zero in front lets an
    # impulse at the window's start count
    peaks, _ = find_peaks(np.concatenate([[0.0], fn[leave]]), prominence=0.25 * f0)

    def peak(a, sel):
        return float(a[sel].max()) if sel.any() else 0.0

    signature = {
        "entry_force_peak_ratio": peak(both, entry) / f0,
        "exit_force_peak_ratio": peak(both, leave) / f0,
        "exit_impulses": int(len(peaks)),
        "entry_accel_peak": peak(acc, entry),
        "floor_accel_peak": peak(acc, floor),
        "exit_accel_peak": peak(acc, leave),
    }
    dt = float(np.median(np.diff(t)))
    i_entry = int(np.searchsorted(t, te))
    high = np.flatnonzero(fn[:i_entry] >= 0.9 * f0)
    low = i_entry + np.flatnonzero(fn[i_entry:] <= 0.1 * f0)
    destress = float(t[low[0]] - t[high[-1]]) if high.size and low.size else math.nan
    widths = (
        peak_widths(np.concatenate([[0.0], fn[leave]]), peaks, rel_height=0.5)[0] * dt
        if len(peaks)
        else []
    )
    n_mean = max(1, round(RESTRESS_MEAN_S / max(dt, 1e-12)))
    mean = np.convolve(fn, np.ones(n_mean) / n_mean)[: len(fn)]
    full = np.flatnonzero((t >= tx) & (mean >= 0.9 * f0))
    x = hist[signal].to_numpy()[leave]
    freq = math.nan
    if x.size >= 4:
        spectrum = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(x.size), 16 * x.size))
        freq = float(np.argmax(spectrum[1:]) + 1) / (16 * x.size * dt)
    signature.update(
        {
            "entry_destress_time_s": destress,
            "exit_impulse_width_s": float(np.median(widths)) if len(widths) else math.nan,
            "exit_reload_time_s": float(t[full[0]] - tx) if full.size else math.nan,
            "exit_entry_accel_ratio": signature["exit_accel_peak"]
            / max(signature["entry_accel_peak"], signature["floor_accel_peak"], 1e-30),
            "exit_peak_frequency_hz": freq,
        }
    )
    return signature


# What a passage's signature measures that a study compares across passages and levels.
PASSAGE_QUANTITIES = (
    "entry_destress_time_s",
    "exit_force_peak_ratio",
    "exit_impulses",
    "exit_impulse_width_s",
    "exit_reload_time_s",
    "exit_entry_accel_ratio",
    "exit_peak_frequency_hz",
)


def passage_statistics(
    signatures: Sequence[Mapping[str, float]], quantities: Sequence[str] = PASSAGE_QUANTITIES
) -> dict[str, dict[str, float | int]]:
    """The distribution over passages of each quantity: ``median``, ``q25``, ``q75``
    (the interquartile range) and ``n``, the passages where it is defined (not NaN).

    One passage is one sample of a chaotic bounce (see
    :func:`taichi_bearing.checks.exit_burst_check`): a finding is a distribution over
    passages, never one passage's value.
    """
    out: dict[str, dict[str, float | int]] = {}
    for q in quantities:
        v = np.array([float(s[q]) for s in signatures if q in s], dtype=float)
        v = v[np.isfinite(v)]
        if v.size:
            q25, med, q75 = (float(a) for a in np.percentile(v, [25, 50, 75]))
        else:
            q25 = med = q75 = math.nan
        out[q] = {"median": med, "q25": q25, "q75": q75, "n": int(v.size)}
    return out
