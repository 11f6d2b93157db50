"""Checks on the spall passages: the exit burst against the entry, and the re-stressing
interval against the fault period (outer race) or the passages in the load zone (inner
race)."""

from __future__ import annotations

from math import comb

import numpy as np

from taichi_bearing.checks.common import (
    CHECK_FALSE_FAIL_RATE,
    EXIT_BURST_BELOW_SHARE,
    EXIT_BURST_LIMIT,
    EXIT_BURST_PASSAGES,
    LOAD_ZONE_SHARE,
    RESTRESS_LIMIT,
    check,
)


def median_failure_rate(share_below: float, n: int) -> float:
    """Chance that the median of ``n`` independent passages falls below a limit that each
    passage falls below with probability ``share_below``: more than half of them below
    (for even ``n``, half or more, since the median of an even count is the mean of the
    middle two: counted as below, an upper bound).

    >>> print(f"{median_failure_rate(0.05, 1):.3f} {median_failure_rate(0.05, 3):.4f}")
    0.050 0.0073
    """
    if n < 1:
        return 1.0
    first = n // 2 + 1 if n % 2 else n // 2
    return float(
        sum(comb(n, k) * share_below**k * (1 - share_below) ** (n - k) for k in range(first, n + 1))
    )


def exit_burst_check(signatures: list[dict]) -> dict:
    """Is the exit louder than the entry? The median passage's exit acceleration peak
    against the larger of its entry and traverse (floor impact) peaks.

    One passage is one sample of a chaotic bounce: the size of the burst depends on where
    the roller is in its radial flight across the spall when the exit edge meets it, and
    that phase is set by rounding-level differences after the first floor impact. So the
    check asks only what a run's few passages can decide: that the exit is not quieter
    than the entry, within what a sampled peak can tell
    (:data:`~taichi_bearing.checks.common.EXIT_BURST_LIMIT` = 0.8: a 20 kHz burst sampled
    at 100 kHz reads up to about 20 % low). None of the 57 recorded passages of the
    default model fell below it (the lowest 0.974). It is decided only where a correct
    model would fail it in at most
    :data:`~taichi_bearing.checks.common.CHECK_FALSE_FAIL_RATE` of runs
    (:func:`median_failure_rate` of the 95 % upper bound on a passage's chance to fall
    below: three passages or more); with fewer, ``passed`` is None. How much louder the
    exit is (2.6 times in the median of the 57) is the passage study's number
    (``python -m taichi_bearing passages``), not one run's.
    """
    if not signatures:
        return check(None, EXIT_BURST_LIMIT, None, "no complete passage")
    ratios = [
        s["exit_accel_peak"] / max(s["entry_accel_peak"], s["floor_accel_peak"], 1e-30)
        for s in signatures
    ]
    typical = float(np.median(ratios))
    n = len(ratios)
    n_above = sum(r >= EXIT_BURST_LIMIT for r in ratios)
    rate = median_failure_rate(EXIT_BURST_BELOW_SHARE, n)
    decides = rate <= CHECK_FALSE_FAIL_RATE
    verdict = (
        f"a correct model fails it in at most {rate:.1%} of runs of {n} passages"
        if decides
        else f"{n} passage(s) cannot decide it: a correct model would fail {rate:.1%} of "
        f"such runs (more than {CHECK_FALSE_FAIL_RATE:.0%}), so it is not judged"
    )
    return check(
        typical,
        EXIT_BURST_LIMIT,
        typical >= EXIT_BURST_LIMIT if decides else None,
        "exit not quieter than entry: the median over the passages of the exit "
        "acceleration peak over the larger of the entry and traverse (floor impact) peaks "
        "must be at least the limit (1 less the 20 % a sampled peak can read low); "
        f"{verdict} (a passage of the default model falls below with probability at most "
        f"{EXIT_BURST_BELOW_SHARE:.3f}, 95 % bound from {EXIT_BURST_PASSAGES}); how much "
        "louder is the passage study's number, not one run's; "
        f"{n_above} of {n} passages reach it; per passage: "
        + ", ".join(f"{r:.3g}" for r in ratios),
    )


def restress_check(events: list, bpfo_hz: float) -> dict:
    """Time between consecutive re-stressing events against 1/BPFO."""
    times = np.array([e["exit_time_s"] for e in events])
    if len(times) < 2:
        return check(None, RESTRESS_LIMIT, None, f"{len(times)} re-stressing event(s): needs two")
    gaps = np.diff(times)
    err = float(np.max(np.abs(gaps * bpfo_hz - 1.0)))
    return check(
        err,
        RESTRESS_LIMIT,
        err <= RESTRESS_LIMIT,
        f"intervals {', '.join(f'{g * 1e3:.4g}' for g in gaps)} ms vs 1/BPFO "
        f"{1e3 / bpfo_hz:.4g} ms",
    )


def inner_restress_check(events: list, bpfi_hz: float) -> dict:
    """Time between the re-stressings of consecutive passages in the load zone against
    1/BPFI (inner-race spall).

    Passages in the load zone: the roller carried at least :data:`LOAD_ZONE_SHARE` of
    the most loaded passing roller's force (towards the zone's edges a lightly loaded
    roller's force, a few kN against the facets' rattle, gives no sharp event);
    consecutive: one BPFI period apart (the spall passes unloaded rollers between two
    visits to the load zone without an event). The re-stressing time is the first touch
    of the exit edge: the exit time (the 0.1 ms mean force regaining half of F0) needs
    more of the burst's impulses the larger F0, so it shifts with each passage's load,
    which the spall's turning changes from passage to passage (the exits' intervals are
    in the note).
    """
    loads = np.array([e["force_before_N"] for e in events])
    zone = [e for e in events if e["force_before_N"] >= LOAD_ZONE_SHARE * loads.max()]
    first = np.array([e["first_impact_time_s"] for e in zone])
    exits = np.array([e["exit_time_s"] for e in zone])
    keep = np.round(np.diff(first) * bpfi_hz) == 1
    gaps, exit_gaps = np.diff(first)[keep], np.diff(exits)[keep]
    left = f"{len(events) - len(zone)} passage(s) below {LOAD_ZONE_SHARE:.0%} of the largest load"
    if (~keep).any():
        left += f", {int((~keep).sum())} interval(s) over passages without an event"
    if not len(gaps):
        return check(
            None,
            RESTRESS_LIMIT,
            None,
            f"{len(zone)} re-stressing event(s) in the load zone: needs two one period "
            f"apart; left out: {left}",
        )
    err = float(np.max(np.abs(gaps * bpfi_hz - 1.0)))
    listing = ", ".join(f"{g * 1e3:.4g}" for g in gaps)
    return check(
        err,
        RESTRESS_LIMIT,
        err <= RESTRESS_LIMIT,
        f"first touches of the exit edge: intervals {listing} ms vs 1/BPFI "
        f"{1e3 / bpfi_hz:.4g} ms (exits: {', '.join(f'{g * 1e3:.4g}' for g in exit_gaps)} "
        f"ms); left out: {left}",
    )
