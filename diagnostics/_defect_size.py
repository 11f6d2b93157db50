"""Size of a line spall from the timing of the entry and exit events of each roller passage:
:func:`estimate_defect_size` and its result :class:`DefectSize`, the speed of the contact
point along a race (:func:`contact_speed`) and the spall length from the roller's travel
between the two events (:func:`spall_length_from_travel`). The events, the geometric model
and how each event is found are described in docs/theory/diagnostics.md (*Spall size from
event timing*); measured and simulated accelerations are treated alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from diagnostics._bands import kurtogram_band
from diagnostics._checks import (
    check_band,
    check_bearing_inputs,
    check_positive,
    check_signal,
    normalise,
)
from diagnostics._envelope import envelope
from diagnostics._filters import lowpass_filter
from diagnostics._frequencies import BearingGeometry, bearing_frequencies
from diagnostics._kurtosis import kurtogram

__all__ = [
    "DefectSize",
    "contact_speed",
    "spall_length_from_travel",
    "estimate_defect_size",
]

RACES = ("outer", "inner")
# An impact's envelope peak must exceed this many times the envelope's median.
_IMPACT_RATIO = 5.0
# Longest re-stressing burst, as a share of the passage period.
BURST_FRACTION = 0.15
# The burst starts where its envelope first reaches this share of its peak (over the floor),
# with gaps between its impulses no longer than BURST_GAP of a period.
BURST_LEVEL = 0.1
BURST_GAP = 0.03


@dataclass(frozen=True)
class DefectSize:
    """Result of :func:`estimate_defect_size`.

    Attributes
    ----------
    length_m : float
        Mean spall length over the retained passages, m.
    std_m : float
        Standard deviation of the per-passage lengths, m.
    events : numpy.ndarray
        Shape (n, 2): entry and exit time (s) of every passage found, in order.
    lengths_m : numpy.ndarray
        Length from each passage (NaN where the passage was rejected as an outlier).
    separation_s : float
        Mean entry-to-exit time over the retained passages.
    contact_speed_m_s : float
        Speed of the contact point along the race.
    exit_band : tuple of float
        Band (Hz) whose envelope located the exits.
    entry_cutoff_hz : float
        Low-pass cut-off used to locate the entries.
    """

    length_m: float
    std_m: float
    events: np.ndarray = field(repr=False)
    lengths_m: np.ndarray = field(repr=False)
    separation_s: float = math.nan
    contact_speed_m_s: float = math.nan
    exit_band: tuple[float, float] = (math.nan, math.nan)
    entry_cutoff_hz: float = math.nan

    @property
    def entry_times_s(self) -> np.ndarray:
        """Entry (de-stressing) time of each passage."""
        return self.events[:, 0]

    @property
    def exit_times_s(self) -> np.ndarray:
        """Exit (re-stressing) time of each passage."""
        return self.events[:, 1]


def contact_speed(geometry: BearingGeometry, shaft_hz: float, race: str = "outer") -> float:
    """Speed (m/s) of a roller's contact point along the race, relative to that race.

    Outer race (stationary): cage angular speed times the outer raceway radius. Inner race
    (turning with the shaft): (shaft - cage) angular speed times the inner raceway radius.

    References
    ----------
    Harris, T. A. and Kotzalas, M. N. (2007). *Essential Concepts of Bearing Technology*
    (Rolling Bearing Analysis, 5th ed., vol. 1). CRC Press, Boca Raton.

    Examples
    --------
    The simulator's default bearing (20 rollers of 24 mm on a 200 mm pitch circle) at
    1000 rpm: a roller crosses a 10 mm spall in about 2 ms.

    >>> geometry = BearingGeometry(20, 24e-3, 200e-3)
    >>> round(contact_speed(geometry, 1000 / 60), 4)              # m/s
    5.1606
    >>> round(10e-3 / contact_speed(geometry, 1000 / 60) * 1e3, 2)  # ms over 10 mm
    1.94
    """
    if race not in RACES:
        raise ValueError(f"race must be one of {RACES}, got {race!r}")
    freqs = bearing_frequencies(geometry, shaft_hz)
    d_eff = geometry.roller_diameter * math.cos(math.radians(geometry.contact_angle_deg))
    if race == "outer":
        return 2.0 * math.pi * freqs.ftf * 0.5 * (geometry.pitch_diameter + d_eff)
    return 2.0 * math.pi * (freqs.shaft - freqs.ftf) * 0.5 * (geometry.pitch_diameter - d_eff)


def spall_length_from_travel(
    travel_m, roller_radius_m: float, depth_m: float | None = None
) -> np.ndarray:
    r"""Spall length from the roller travel between the entry and the exit events.

    Parameters
    ----------
    travel_m : float or array_like
        Travel :math:`s` of the roller centre (along the race) from entry to exit, m.
    roller_radius_m : float
        Roller radius :math:`r`, m.
    depth_m : float, optional
        Spall depth :math:`h`, m. Without it the roller is taken not to reach the floor.

    Returns
    -------
    numpy.ndarray or float
        :math:`2 s` while the roller pivots on the entry edge until it strikes the exit
        edge (:math:`s \le a`, :math:`a = \sqrt{h (2r - h)}`); :math:`s + a` when it rolls
        on the floor in between.

    Examples
    --------
    A 24 mm roller over a deep spall strikes the exit edge halfway (:math:`L = 2 s`); over
    a 0.3 mm deep one it lands on the floor after :math:`a` = 2.7 mm and rolls on:

    >>> float(spall_length_from_travel(4e-3, 12e-3))
    0.008
    >>> np.round(spall_length_from_travel([1e-3, 4e-3], 12e-3, depth_m=0.3e-3) * 1e3, 3)  # mm
    array([2.   , 6.666])
    """
    r = check_positive(roller_radius_m, "roller_radius_m", unit=" in m")
    s = np.asarray(travel_m, dtype=float)
    if np.any(s < 0):
        raise ValueError("travel_m must be non-negative")
    if depth_m is None:
        return 2.0 * s
    h = check_positive(depth_m, "depth_m", unit=" in m")
    a = math.sqrt(h * (2.0 * r - h)) if h < r else r
    return np.where(s <= a, 2.0 * s, s + a)


def _exit_times(env: np.ndarray, fs: float, period_s: float, rise_s: float) -> np.ndarray:
    """Impact time of the strongest envelope burst of each passage, in samples (float).

    Behind a zero-phase band an impact whose response in the band is short gives an envelope
    pulse centred on the impact, and one that rings long gives a smoothed step whose
    steepest point is the impact. The estimate therefore moves from the steepest point of the
    rising edge towards the peak by the square of the ratio of the burst's rise to its fall
    (each measured at half height): 1 for a symmetric pulse, near 0 for a long ring.
    """
    peaks, props = signal.find_peaks(env, distance=max(int(0.6 * period_s * fs), 1), height=0.0)
    if peaks.size == 0:
        return np.empty(0)
    heights = props["peak_heights"]
    # Keep the passages with a real impact: not far below the strong ones (the 90th
    # percentile, so that a short record with one impact and a few noise peaks keeps one),
    # and well above noise: the (Rayleigh) envelope of Gaussian noise exceeds 5 times its
    # median with probability 2**-25 per sample.
    floor = _IMPACT_RATIO * np.median(env)
    peaks = peaks[heights >= max(0.3 * np.percentile(heights, 90), floor)]
    slope = np.gradient(env)
    width = max(int(round(rise_s * fs)), 2)
    gap = int(0.4 * period_s * fs)
    burst = int(BURST_FRACTION * period_s * fs)
    times = []
    for p in peaks:
        # A re-stressing is a burst of impulses that may grow: step back from the
        # strongest through the burst (gaps shorter than BURST_GAP of a period between
        # impulses) to its first impulse above BURST_LEVEL of its height and well above
        # the noise.
        base = float(np.median(env[max(p - gap, 0) : max(p - burst, 0) + 1]))
        p = _burst_start(env, p, base, burst, max(int(BURST_GAP * period_s * fs), 1), width)
        lo = max(p - width, 0)
        steepest = lo + int(np.argmax(slope[lo : p + 1]))
        floor = np.median(env[max(p - gap, 0) : lo + 1])
        half = floor + 0.5 * (env[p] - floor)
        before = np.flatnonzero(env[max(p - gap, 0) : p + 1] < half)
        rise = (p - max(p - gap, 0) - before[-1]) if before.size else gap
        after = np.flatnonzero(env[p : p + gap] < half)
        fall = after[0] if after.size else gap
        weight = min(rise / max(fall, 1), 1.0) ** 2
        times.append(steepest + weight * (p - steepest))
    return np.asarray(times, dtype=float)


def _burst_start(env: np.ndarray, p: int, base: float, burst: int, max_gap: int, width: int) -> int:
    """Envelope peak of the first impulse of the burst whose strongest peak is ``p``."""
    level = max(base + BURST_LEVEL * (env[p] - base), _IMPACT_RATIO * base)
    first, k = p, p
    while k > max(p - burst, 0):
        k -= 1
        if env[k] >= level:
            first = k
        elif first - k > max_gap:
            break
    return first + int(np.argmax(env[first : first + width + 1]))


def _entry_times(
    low: np.ndarray, exits: np.ndarray, fs: float, max_sep_s: float, guard_s: float
) -> np.ndarray:
    """Steepest point of the low-passed signal in the window before each exit (samples)."""
    slope = np.gradient(low)
    lo_off = int(round(max_sep_s * fs))
    hi_off = max(int(round(guard_s * fs)), 1)
    windows = [(int(e) - lo_off, int(e) - hi_off) for e in exits]

    def pick(sign: float) -> np.ndarray:
        out = []
        for a, b in windows:
            if a < 0 or b <= a:
                out.append(np.nan)
                continue
            out.append(a + int(np.argmax(sign * slope[a:b])))
        return np.asarray(out, dtype=float)

    # The de-stressing step has one sign for every passage: take the sign of the majority.
    first = pick(1.0), pick(-1.0)
    strength = [np.nansum([abs(slope[int(i)]) for i in cand if np.isfinite(i)]) for cand in first]
    return first[int(np.argmax(strength))]


def estimate_defect_size(
    x,
    fs: float,
    geometry: BearingGeometry,
    shaft_hz: float,
    race: str = "outer",
    *,
    depth_m: float | None = None,
    exit_band: tuple[float, float] | None = None,
    entry_cutoff_hz: float | None = None,
    entry_cutoff_share: float = 0.5,
    max_separation: float = 0.5,
) -> DefectSize:
    """Estimate the length of a line spall from the entry and exit events of each passage.

    Parameters
    ----------
    x : array_like
        1-D acceleration holding at least one complete passage over the spall (a simulated
        record may hold only a few).
    fs : float
        Sampling rate in Hz.
    geometry : BearingGeometry
        Bearing dimensions (metres).
    shaft_hz : float
        Shaft speed in Hz.
    race : {"outer", "inner"}
        Race that carries the spall (sets the passage rate and the contact speed).
    depth_m : float, optional
        Spall depth; enables the roll-on-the-floor correction of a shallow spall.
    exit_band : tuple of float, optional
        Band (Hz) of the re-stressing impacts; default from the lower edge of the fast
        kurtogram's best band (among the bands above fs/16) up to fs/2.
    entry_cutoff_hz : float, optional
        Low-pass cut-off (Hz) for the de-stressing steps; default ``entry_cutoff_share``
        of the exit band's lower edge.
    entry_cutoff_share : float
        Default cut-off over the exit band's lower edge: 0.5 suits a de-stressing that is a
        step (as measured records often show it); a gradual one, the load leaving over a
        few tenths of a millisecond as in the finite element runs, needs about 0.125, or
        its slope is lost next to that of the roller grazing the exit edge before it
        strikes.
    max_separation : float
        Longest entry-to-exit time sought, as a fraction of the passage period. The shortest
        is one period of ``entry_cutoff_hz``: a smaller spall needs a higher cut-off.

    Returns
    -------
    DefectSize
        Mean length, spread, per-passage events and lengths. Passages whose separation lies
        more than 5 scaled MADs from the median are kept in ``events`` but left out of the
        mean (their ``lengths_m`` is NaN).

    Raises
    ------
    ValueError
        On invalid input, or when no complete passage is found.

    Notes
    -----
    Per passage, the exit is found on the Hilbert envelope of the exit band: the envelope
    peaks once per passage, and the exit is the steepest point of the rising edge before
    the peak (the onset, which the zero-phase filter does not shift). The entry is the
    steepest point of the low-passed signal in a window before the exit that stops one
    period of the cut-off short of it, so that the exit's own low-frequency content is not
    taken for the entry. The time between them, times :func:`contact_speed`, is the travel
    that :func:`spall_length_from_travel` turns into a length.

    References
    ----------
    Sawalhi, N. and Randall, R. B. (2011). Vibration response of spalled rolling element
    bearings: observations, simulations and signal processing techniques to track the spall
    size. *Mechanical Systems and Signal Processing* 25(3), 846-870.
    """
    fs, shaft_hz = check_bearing_inputs(geometry, fs, shaft_hz)
    if race not in RACES:
        raise ValueError(f"race must be one of {RACES}, got {race!r}")
    if depth_m is not None:
        depth_m = check_positive(depth_m, "depth_m", unit=" in m")
    max_separation = check_positive(max_separation, "max_separation")
    if max_separation >= 1.0:
        raise ValueError(f"max_separation must be below 1 (a passage period), got {max_separation}")
    freqs = bearing_frequencies(geometry, shaft_hz)
    period = 1.0 / (freqs.bpfo if race == "outer" else freqs.bpfi)
    x = check_signal(x, fs, min_length=int(math.ceil(period * fs)))
    x, _ = normalise(x)  # event times have no unit

    if exit_band is None:
        # Everything above the lower edge of the kurtogram's best band: the impulsive band
        # sets where the high frequencies start, and the full width above it keeps the
        # envelope's smoothing (about 1 / bandwidth) short, so the onset is not blurred.
        # Bands from fs/16 up: the low bands hold the entry steps, not the impacts.
        kg = kurtogram(x, fs, nlevel=max(1, min(7, int(math.log2(x.size)) - 7)))
        found = kurtogram_band(kg, min_low_hz=fs / 16.0)
        exit_band = (found[0][0] if found is not None else fs / 8.0, fs / 2.0)
    exit_band = check_band(exit_band[0], exit_band[1], fs, "exit_band")
    if entry_cutoff_hz is None:
        entry_cutoff_hz = check_positive(entry_cutoff_share, "entry_cutoff_share") * exit_band[0]
    entry_cutoff_hz = check_positive(entry_cutoff_hz, "entry_cutoff_hz", unit=" in Hz")
    if entry_cutoff_hz >= fs / 2.0:
        raise ValueError(f"entry_cutoff_hz = {entry_cutoff_hz:g} Hz must be below fs/2")

    env = envelope(x, fs, band=exit_band)
    bandwidth = exit_band[1] - exit_band[0]
    exits = _exit_times(env, fs, period, rise_s=min(4.0 / bandwidth, 0.25 * period))
    low = lowpass_filter(x, fs, entry_cutoff_hz)
    # the window before an exit stops a cut-off period, and at least a burst gap, short
    # of it: the roller grazing the exit edge before it strikes belongs to the exit
    guard = max(1.0 / entry_cutoff_hz, BURST_GAP * period)
    entries = _entry_times(low, exits, fs, max_separation * period, guard)
    ok = np.isfinite(entries)
    events = np.column_stack([entries[ok], exits[ok]]) / fs
    if events.shape[0] == 0:
        raise ValueError(
            "found no complete spall passage (record too short, or no impacts at the passage rate)"
        )
    sep = events[:, 1] - events[:, 0]
    med = np.median(sep)
    mad = 1.4826 * np.median(np.abs(sep - med))
    keep = np.abs(sep - med) <= 5.0 * max(mad, 1.0 / fs)
    speed = contact_speed(geometry, shaft_hz, race)
    radius = 0.5 * geometry.roller_diameter
    lengths = np.where(keep, spall_length_from_travel(sep * speed, radius, depth_m), np.nan)
    return DefectSize(
        length_m=float(np.nanmean(lengths)),
        std_m=float(np.nanstd(lengths)),
        events=events,
        lengths_m=lengths,
        separation_s=float(np.mean(sep[keep])),
        contact_speed_m_s=speed,
        exit_band=(float(exit_band[0]), float(exit_band[1])),
        entry_cutoff_hz=float(entry_cutoff_hz),
    )
