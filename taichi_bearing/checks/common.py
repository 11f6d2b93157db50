"""One entry of ``summary["checks"]`` and the limits of the run's own checks."""

from __future__ import annotations

import math

# Limits of the run's own checks
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
EXIT_BURST_LIMIT = 2.0
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
