"""One entry of ``summary["checks"]`` and the limits of the run's own checks."""

from __future__ import annotations

import math

# Limits of the run's own checks
STATIC_EACH_LIMIT = 0.10
STATIC_QMAX_LIMIT = 0.05
SPEED_LIMIT = 0.02
RESTRESS_LIMIT = 0.02
ENERGY_LIMIT = 0.02
NOISE_LIMIT = 0.05
TONE_DB = 10.0  # a spectral peak this far above its band's median is a tone
DEFECT_SIZE_LIMIT = 0.5
DEFECT_ENTRY_CUTOFF_SHARE = 0.125  # entry low-pass cut-off / exit band's lower edge
# exit_burst: the median passage's exit acceleration peak must not be below its entry's,
# within what a sampled peak can tell (a 20 kHz burst sampled at 100 kHz reads up to about
# 20 % low): at least 0.8 of it. None of the 57 recorded passages of the default model
# fell below 0.8 (docs/results/exit_burst_check/); the one-sided 95 % upper confidence
# bound on a passage's chance to (Clopper-Pearson, 0 of 57) is 0.0512, so three
# passages' median falls below in at most 0.76 % of correct runs.
EXIT_BURST_LIMIT = 0.8
EXIT_BURST_BELOW_SHARE = 1.0 - 0.05 ** (1.0 / 57.0)
EXIT_BURST_PASSAGES = "docs/results/exit_burst_check/recorded_passages.csv"
# a check may fail a correct model at most this often; with fewer passages it informs only
CHECK_FALSE_FAIL_RATE = 0.01
PASSAGE_WINDOW_M = 1.5e-3  # contact travel of the entry and exit windows, m
# A roller counts as loaded when the analytical model gives it this share of Q_max.
LOADED_SHARE = 0.05
# An inner-race passage is in the load zone when its roller carried this share of the
# most loaded passing roller's force.
LOAD_ZONE_SHARE = 0.5
# Floor of each loaded roller's tolerance, as a share of Q_max (the zone-edge rollers).
STATIC_EDGE_SHARE = 0.05


def check(value, limit, passed, note: str = "") -> dict:
    """One entry of ``summary["checks"]`` (NaN values become None)."""

    def clean(v):
        if v is None:
            return None
        v = float(v)
        return v if math.isfinite(v) else None

    return {
        "value": clean(value),
        "limit": clean(limit),
        "passed": None if passed is None else bool(passed),
        "note": note,
    }
