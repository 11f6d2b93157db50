"""Checks on the spall passages: the exit burst against the entry, and the re-stressing
interval against the fault period (outer race) or the passages in the load zone (inner
race)."""

from __future__ import annotations

import numpy as np

from taichi_bearing.checks.common import EXIT_BURST_LIMIT, LOAD_ZONE_SHARE, RESTRESS_LIMIT, check


def exit_burst_check(signatures: list[dict]) -> dict:
    """Exit acceleration burst against entry and floor impact: the median passage.

    Each passage gives the ratio of its exit acceleration peak to the larger of its entry
    and traverse (floor impact) peaks; the check takes the median over the passages. One
    passage is one sample of a chaotic bounce: the size of the burst depends on where the
    roller is in its radial flight across the spall when the exit edge meets it (struck
    with a gap to the inner raceway it rattles between the two; arriving on the inner
    raceway it is squeezed up smoothly), and that phase is set by rounding-level
    differences after the first floor impact. The median states what a typical passage
    does; every passage's ratio is listed in the note.
    """
    if not signatures:
        return check(None, EXIT_BURST_LIMIT, None, "no complete passage")
    ratios = [
        s["exit_accel_peak"] / max(s["entry_accel_peak"], s["floor_accel_peak"], 1e-30)
        for s in signatures
    ]
    typical = float(np.median(ratios))
    n_pass = sum(r >= EXIT_BURST_LIMIT for r in ratios)
    return check(
        typical,
        EXIT_BURST_LIMIT,
        typical >= EXIT_BURST_LIMIT,
        "median over the passages of the ratio of the exit acceleration peak to the larger "
        "of the entry and traverse (floor impact) peaks; must be at least the limit; "
        f"{n_pass} of {len(ratios)} passages reach it; per passage: "
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
