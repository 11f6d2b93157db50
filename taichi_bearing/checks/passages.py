"""Spall passages in a run's histories: when each roller enters and leaves the spall, on
the outer raceway or on the inner one (which turns with the shaft), and the force and
acceleration around each passage (numpy and pandas, no Taichi). The run's checks
(:mod:`taichi_bearing.checks`) judge what these find.

Each roller's passage is found from its own contact force and its own position relative
to the spall, so rollers inside the spall at the same time (an extended spall, longer
than the roller spacing) are found each on its own."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from taichi_bearing.analytic.bearing import wrap_angle
from taichi_bearing.output.layout import TIME_COLUMN, roller_force_column, roller_motion_column

__all__ = [
    "EXIT_BURST_S",
    "PASSAGE_QUANTITIES",
    "RESTRESS_MEAN_S",
    "UNLOADED_SHARE",
    "SpallEvent",
    "detect_spall_events",
    "spall_passages",
    "passage_signature",
    "passage_statistics",
]

RESTRESS_MEAN_S = 1e-4  # averaging time of the re-stressing force, s
EXIT_BURST_S = 1e-3  # shortest exit window: the re-stressing burst rings for ~1 ms
# An inner-race spall also passes rollers outside the load zone; a roller carrying less
# than this share of the most loaded roller's force has nothing to lose: no event.
UNLOADED_SHARE = 0.1


class SpallEvent(dict):
    """``roller``; ``entry_time_s`` (de-stressing: the force falls through half its
    value before the spall), ``floor_window_s`` (start, end of the traverse),
    ``first_impact_time_s`` (first touch of the exit edge) and ``exit_time_s``
    (re-stressing: the mean force regains half its value); ``force_before_N``. On the
    inner raceway also ``spall_angle_deg``, where the turning spall was at entry (fixed
    frame, from 12 o'clock)."""


def _spall_geometry(info: Mapping, race: str = "outer") -> dict | None:
    spall = info.get("spall")
    if not spall or spall.get("race") != race:
        return None
    return spall


def _mean_force(fn: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The force averaged over the last :data:`RESTRESS_MEAN_S` at each sample."""
    n_mean = max(1, round(RESTRESS_MEAN_S / max(float(np.median(np.diff(t))), 1e-12)))
    return np.convolve(fn, np.ones(n_mean) / n_mean)[: len(fn)]


def _passage(
    t: np.ndarray, rel: np.ndarray, fn: np.ndarray, span: float, lead: float, meet: float
) -> dict | None:
    """One roller's entry and exit over a record in which it passes the spall once
    (``rel``: travel past the entry edge, rad; see :func:`detect_spall_events`)."""
    before = rel < -lead
    ref = before & (rel > -2 * span - lead)
    if ref.sum() < 3:
        return None
    first_after = np.flatnonzero(~before & (rel < span + lead))
    f0 = float(np.median(fn[ref]))
    if not f0 > 0 or first_after.size == 0:
        return None
    k0 = int(first_after[0])
    low = k0 + np.flatnonzero(fn[k0:] < 0.5 * f0)
    if low.size == 0:
        return None
    i_entry = int(low[0])
    meets = np.flatnonzero((np.arange(len(t)) > i_entry) & (rel >= span - meet))
    if meets.size == 0:
        return None
    i_meet = int(meets[0])
    # the re-stressing is a burst of impulses: its time is when the force averaged over
    # the last RESTRESS_MEAN_S regains half of F0 (a single impulse crossing that level
    # jitters with the phase of the roller's bounce)
    mean = _mean_force(fn, t)
    up = i_meet + np.flatnonzero(mean[i_meet:] > 0.5 * f0)
    hit = i_meet + np.flatnonzero(fn[i_meet:] > 0.1 * f0)
    if up.size == 0 or hit.size == 0:
        return None
    return {
        "entry_time_s": float(t[i_entry]),
        "first_impact_time_s": float(t[hit[0]]),
        "exit_time_s": float(t[up[0]]),
        "floor_window_s": (float(t[min(i_entry + 1, i_meet)]), float(t[i_meet])),
        "force_before_N": f0,
    }


def _reach(spall: Mapping, contact_radius: float) -> tuple[float, float, float]:
    r"""Span of the spall, the lead before its entry edge and the distance before its exit
    edge at which the roller meets it, rad of the raceway.

    A roller of curvature radius :math:`\rho` relative to the raceway over a notch of
    half-length :math:`a` dips :math:`\rho - \sqrt{\rho^2 - a^2}` into it; it meets the exit
    edge about :math:`\sqrt{2 \rho d}` + 0.5 mm before it (:math:`d`: the depth, or the dip
    if smaller).
    """
    radius = float(spall["raceway_radius"])
    half = 0.5 * float(spall["length"])
    dip = contact_radius - math.sqrt(max(contact_radius**2 - half**2, 0.0))
    d = min(float(spall["depth"]), dip)
    meet = (math.sqrt(2.0 * contact_radius * d) + 0.5e-3) / radius
    return float(spall["length"]) / radius, 1e-3 / radius, meet


def detect_spall_events(
    hist: pd.DataFrame,
    n_rollers: int,
    info: Mapping,
    roller_radius: float,
    shaft_speed: float = 0.0,
) -> list[SpallEvent]:
    r"""Entry and exit of every roller that passes the spall.

    Outer raceway: the roller's outer contact point lies on the radial line through its
    centre, so its position relative to the spall is the centre angle minus the spall's
    start angle, ``rel`` (0 at the entry edge, ``span`` at the exit edge). :math:`F_0`: the
    median normal force on the outer raceway while the contact is more than 1 mm before
    the edge. Entry: the first time after ``rel = -1 mm`` that the force is below
    :math:`F_0 / 2`. Once the roller is within the distance at which it meets the exit edge,
    :math:`\sqrt{2 r d}` + 0.5 mm before it (:math:`d`: the spall depth, or the roller's dip into
    the notch if smaller; an impact on the floor earlier in the traverse is not taken for
    the exit): first impact, the first force above :math:`F_0 / 10`; exit (re-stressing),
    the first time the force averaged over the last 0.1 ms exceeds :math:`F_0 / 2`.

    Inner raceway: the spall turns with the shaft (``shaft_speed``, rad/s), so its entry
    edge, the one at the larger angle, is at :math:`\theta_e(t) = \theta_{e0} + \omega_s t`
    and ``rel`` :math:`= \theta_e(t) - \theta_\mathrm{roller}(t)` grows as it overtakes the
    roller; the same rules on the inner-raceway force, with the inner contact's curvature
    (:math:`1/r + 1/R_i`) for the dip. Passages of rollers carrying less than
    :data:`UNLOADED_SHARE` of the most loaded roller's force (outside the load zone) are
    not events; :func:`spall_passages` lists every passage with its load.

    On either raceway each crossing of a roller with the spall is one passage, found in
    the samples within half a turn of it (``_turns``), so a long record holds several
    passages of one roller, and rollers inside an extended spall at the same time are
    each found from their own force. A passage counts when the record holds its
    approach and its exit edge.
    """
    race = "inner" if _spall_geometry(info, "inner") is not None else "outer"
    spall = _spall_geometry(info, race)
    if spall is None:
        return []
    if race == "inner" and not shaft_speed > 0:
        raise ValueError("an inner-race spall turns with the shaft: give shaft_speed > 0")
    radius = float(spall["raceway_radius"])
    # the dip into the notch: relative curvature of roller and raceway (concave outer,
    # convex inner)
    contact = roller_radius if race == "outer" else 1.0 / (1.0 / roller_radius + 1.0 / radius)
    span, lead, meet = _reach(spall, contact)
    t = hist[TIME_COLUMN].to_numpy()
    # an inner-race spall also passes the unloaded rollers outside the load zone
    loaded = UNLOADED_SHARE * _loaded_force(hist, n_rollers, "inner") if race == "inner" else 0.0
    events = []
    for j, rel, w, fn in _turns(hist, n_rollers, spall, race, shaft_speed):
        # the roller must come from before the spall and get past its exit edge
        if not (rel[0] < -lead and rel[-1] >= span):
            continue
        found = _passage(t[w], rel, fn[w], span, lead, meet)
        if found is None or found["force_before_N"] < loaded:
            continue
        if race == "inner":
            at = float(spall["centre_angle_from_top"]) + shaft_speed * found["entry_time_s"]
            found["spall_angle_deg"] = math.degrees(float(wrap_angle(at)))
        events.append(SpallEvent(roller=j, **found))
    events.sort(key=lambda e: e["entry_time_s"])
    return events


def _travel(
    hist: pd.DataFrame, j: int, spall: Mapping, race: str, shaft_speed: float
) -> np.ndarray | None:
    r"""Unwrapped travel of roller ``j`` past the spall's entry edge, rad (:math:`2 \pi k` at
    its :math:`k`-th crossing), or None without the roller's angle. Outer raceway: the roller's
    angle minus the fixed entry edge's; inner: the turning entry edge's angle minus the
    roller's."""
    a_col = roller_motion_column(j, "angle_rad")
    if a_col not in hist:
        return None
    angle = hist[a_col].to_numpy()
    half = 0.5 * float(spall["length"]) / float(spall["raceway_radius"])
    centre = float(spall["centre_angle_from_top"])
    if race == "outer":
        return angle - (centre - half)
    t = hist[TIME_COLUMN].to_numpy()
    return centre + half + shaft_speed * t - angle


def _turns(hist: pd.DataFrame, n_rollers: int, spall: Mapping, race: str, shaft_speed: float):
    """Each crossing of the spall with each roller in the record: ``(j, rel, window,
    fn)``, the samples whose travel lies within half a turn of the crossing
    (``window``), the travel past the entry edge there (``rel``, rad) and roller ``j``'s
    whole force on the spall's raceway."""
    for j in range(n_rollers):
        travel = _travel(hist, j, spall, race, shaft_speed)
        if travel is None:
            continue
        fn = hist[roller_force_column(j, race, "fn")].to_numpy()
        lo = math.ceil((travel.min() - math.pi) / (2 * math.pi))
        hi = math.floor((travel.max() + math.pi) / (2 * math.pi))
        for k in range(lo, hi + 1):
            rel = travel - 2 * math.pi * k
            window = np.flatnonzero((rel >= -math.pi) & (rel < math.pi))
            if window.size:
                yield j, rel[window], window, fn


def _loaded_force(hist: pd.DataFrame, n_rollers: int, race: str) -> float:
    """The most loaded roller's force on a raceway, N: the median over the record of the
    largest roller force at each instant."""
    cols = [roller_force_column(j, race, "fn") for j in range(n_rollers)]
    cols = [c for c in cols if c in hist]
    return float(np.median(hist[cols].to_numpy().max(axis=1))) if cols else 0.0


def spall_passages(
    hist: pd.DataFrame, n_rollers: int, info: Mapping, shaft_speed: float
) -> list[dict]:
    """Every passage of the inner-race spall over a roller in the record, loaded or not.

    Each: ``roller``; ``time_s``, when the spall's centre is on the roller; the spall's
    angle then (``spall_angle_deg``, fixed frame, from 12 o'clock); and the roller's
    inner-raceway force before the spall reaches it (``force_before_N``: the median over
    the events' reference window, from two spall lengths to 1 mm before the entry edge;
    NaN if the record starts later).
    Along the load zone these forces are its profile: the events fade outside it.
    """
    spall = _spall_geometry(info, "inner")
    if spall is None or not shaft_speed > 0:
        return []
    radius = float(spall["raceway_radius"])
    span = float(spall["length"]) / radius
    lead = 1e-3 / radius
    t = hist[TIME_COLUMN].to_numpy()
    out = []
    for j, rel, w, fn in _turns(hist, n_rollers, spall, "inner", shaft_speed):
        rel = rel - 0.5 * span  # 0 with the centre on the roller
        if not (rel[0] < 0.0 <= rel[-1]):
            continue
        i = int(np.searchsorted(rel, 0.0))
        # the reference window of the events: 1 mm to two spall lengths before entry
        ref = (rel < -0.5 * span - lead) & (rel > -2.5 * span - lead)
        at = float(spall["centre_angle_from_top"]) + shaft_speed * float(t[w][i])
        out.append(
            {
                "roller": j,
                "time_s": float(t[w][i]),
                "spall_angle_deg": math.degrees(float(wrap_angle(at))),
                "force_before_N": float(np.median(fn[w][ref])) if ref.any() else math.nan,
            }
        )
    out.sort(key=lambda p: p["time_s"])
    return out


def _windows(
    t: np.ndarray, te: float, tx: float, window_s: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A passage's entry, traverse and exit windows (see :func:`passage_signature`),
    from its entry ``te`` and first touch of the exit edge ``tx``, s."""
    entry = (t >= te - window_s) & (t <= te + 0.5 * window_s)
    floor = (t > te + 0.5 * window_s) & (t < tx)
    leave = (t >= tx) & (t <= tx + max(window_s, EXIT_BURST_S))
    return entry, floor, leave


def passage_signature(
    hist: pd.DataFrame,
    event: Mapping,
    signal: str,
    window_s: float = 3e-4,
    race: str = "outer",
    others: Sequence[Mapping] = (),
) -> dict[str, float]:
    r"""Force and acceleration around one passage: what the reference study says the physics shows.

    Windows: entry ``[entry - window, entry + window / 2]``; traverse (with any floor
    impact) from half a window after entry to the first impact on the exit edge; exit
    (the re-stressing burst) from the first impact for ``window`` or :data:`EXIT_BURST_S`,
    whichever is longer: the roller bounces between the exit edge and the inner raceway
    (a ~15 kHz radial mode) for about a millisecond whatever the speed.

    ``race``: the raceway with the spall, whose force the timings and impulses are read
    from (the text below says outer for it). ``others``: the other rollers' passages;
    their entry and exit windows are left out of this one's traverse window (inside an
    extended spall one sensor records the other roller's entry and exit bursts while
    this one crosses the floor; separate passages do not overlap and leave it whole).

    Returns the largest force on the roller in the entry and exit windows over :math:`F_0`
    (outer or inner raceway, whichever is larger: the re-stressing squeezes the roller
    between both; about 1 or less at entry: no impulse), the number of separate impulses
    of the outer-raceway force at exit (peaks standing at least :math:`F_0 / 4` above the
    troughs either side: on a fine mesh the later impulses ride on the returning load,
    0.25-0.45 :math:`F_0` above their troughs on the default case), and the largest
    :math:`|a - \mathrm{median}|` of ``signal`` in each window; and, for the study of how
    these converge (:data:`PASSAGE_QUANTITIES`):

    - ``entry_destress_time_s``: the outer-raceway force falling from 90 % to 10 % of
      :math:`F_0` around the entry (the last sample at or above :math:`0.9 F_0` before the
      entry, the first at or below :math:`0.1 F_0` after it);
    - ``exit_impulse_width_s``: the median width of the exit impulses at half their
      prominence (NaN without impulses);
    - ``exit_reload_time_s``: from the first touch of the exit edge until the force
      averaged over :data:`RESTRESS_MEAN_S` regains :math:`0.9 F_0` (NaN if it does not within
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
    fn = hist[roller_force_column(j, race, "fn")].to_numpy()
    other = hist.get(roller_force_column(j, "inner" if race == "outer" else "outer", "fn"))
    both = fn if other is None else np.maximum(fn, other.to_numpy())
    acc = hist[signal].to_numpy()
    acc = np.abs(acc - np.median(acc))
    f0 = float(event["force_before_N"])
    te = float(event["entry_time_s"])
    tx = float(event.get("first_impact_time_s", event["exit_time_s"]))
    entry, floor, leave = _windows(t, te, tx, window_s)
    for o in others:
        o_entry, _, o_leave = _windows(
            t,
            float(o["entry_time_s"]),
            float(o.get("first_impact_time_s", o["exit_time_s"])),
            window_s,
        )
        floor &= ~(o_entry | o_leave)
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
    mean = _mean_force(fn, t)
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
