"""The run's motion: rolling speeds after the start-up against the ideal rolling rates, and
the energy balance."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pandas as pd

from taichi_bearing.case import Case
from taichi_bearing.checks.common import ENERGY_LIMIT, SPEED_LIMIT, check
from taichi_bearing.output.layout import (
    BALANCE_COLUMN,
    CAGE_COLUMNS,
    TIME_COLUMN,
    roller_motion_column,
)


def startup_time(case: Case) -> float:
    """End of the start-up left out of the speed checks: a fifth of the run, s."""
    return 0.2 * case.run.duration


def _slope(t: np.ndarray, y: np.ndarray) -> float:
    if len(t) < 2:
        return math.nan
    return float(np.polyfit(t, y, 1)[0])


def speed_checks(
    case: Case, hist: pd.DataFrame, rates: Mapping[str, float]
) -> tuple[dict[str, dict], dict]:
    """Cage speed and the spin of the loaded rollers (relative to the cage) after the
    start-up, against ideal rolling.

    The cage speed of kinematics is the orbital speed of the roller set: measured as the
    slope of the rollers' mean centre angle (the rigid cage, which only follows them
    through its pockets, is reported beside it). ``rates``: the ideal rolling rates of
    ``preload.json`` (``cage``, ``roller_relative``, rad/s).
    """
    t = hist[TIME_COLUMN].to_numpy()
    after = t >= startup_time(case)
    n = case.bearing.n_rollers
    cage_col = CAGE_COLUMNS[0]
    cols = [roller_motion_column(j, "angle_rad") for j in range(n)]
    if all(c in hist for c in cols):
        orbit = hist[cols].to_numpy().mean(axis=1)
        source = "mean roller orbit"
    else:
        orbit = hist[cage_col].to_numpy()
        source = "cage angle"
    cage = _slope(t[after], orbit[after])
    rigid = _slope(t[after], hist[cage_col].to_numpy()[after])
    ideal_cage, ideal_spin = rates["cage"], rates["roller_relative"]
    cage_err = abs(cage - ideal_cage) / abs(ideal_cage)
    out = {
        "cage_speed": check(
            cage_err,
            SPEED_LIMIT,
            cage_err <= SPEED_LIMIT,
            f"{source} {cage:.5g} rad/s vs kinematics {ideal_cage:.5g} rad/s "
            f"(rigid cage {rigid:.5g} rad/s)",
        )
    }
    # spin relative to the cage, of rollers in the load zone (|angle| < 60 deg)
    spins = []
    for j in range(n):
        a = hist.get(roller_motion_column(j, "angle_rad"))
        s = hist.get(roller_motion_column(j, "spin_rad_s"))
        if a is None or s is None:
            continue
        a = np.asarray(a)
        zone = after & (np.abs((a + math.pi) % (2 * math.pi) - math.pi) < math.radians(60))
        if zone.sum() > 1:
            spins.append(np.asarray(s)[zone] - cage)
    if spins:
        rel_spin = float(np.median(np.concatenate(spins)))
        spin_err = abs(rel_spin - ideal_spin) / abs(ideal_spin)
        out["roller_spin"] = check(
            spin_err,
            SPEED_LIMIT,
            spin_err <= SPEED_LIMIT,
            f"median spin relative to the cage of the loaded rollers {rel_spin:.5g} rad/s "
            f"vs kinematics {ideal_spin:.5g} rad/s",
        )
    return out, {
        "cage_speed_rad_s": cage,
        "rigid_cage_speed_rad_s": rigid,
        "cage_speed_rel_error": cage_err,
    }


def energy_balance_check(hist: pd.DataFrame) -> tuple[dict, float]:
    """Largest |energy balance error| of the run (relative to the largest energy)."""
    err = float(np.max(np.abs(hist[BALANCE_COLUMN].to_numpy())))
    return check(err, ENERGY_LIMIT, err <= ENERGY_LIMIT, "max over the run"), err
