"""Histories of rollers passing a spall, from the kinematics alone (no simulation).

The rollers turn at the cage speed; the spall sits on the outer raceway, or on the inner
one turning at the shaft speed. A roller carries a load-zone force (15 kN cos^2 of its
angle, none beyond 90 degrees) except while its contact is over the spall, where it
carries nothing; on the inner raceway it returns with a short 30 % burst. Every event
time and passage angle follows from the case, so tests can check what
:mod:`taichi_bearing.checks.passages` finds against them.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from taichi_bearing.analytic.bearing import cage_speed

Q_MAX = 15e3  # N


def rolling_histories(case, duration: float, fs: float = 1e5) -> tuple[pd.DataFrame, dict]:
    """``(histories, mesh info)`` of ``case`` over ``duration`` s, sampled at ``fs``."""
    b, d = case.bearing, case.defect
    outer = d.race == "outer"
    radius = b.outer_raceway_radius if outer else b.inner_raceway_radius
    span = d.length / radius
    shaft, cage = case.operating.speed, cage_speed(b, case.operating.speed)
    t = np.arange(1, int(duration * fs) + 1) / fs
    # the edge a roller meets first: the start (outer) or the end (inner, turning)
    first = d.angle - 0.5 * span if outer else d.angle + 0.5 * span + shaft * t
    data = {"time_s": t}
    for j in range(b.n_rollers):
        angle = case.run.first_roller_angle + 2 * math.pi * j / b.n_rollers + cage * t
        q = Q_MAX * np.clip(np.cos(angle), 0.0, None) ** 2
        rel = (angle - first if outer else first - angle) % (2 * math.pi)
        after = (rel >= span) & (rel < span + 0.02) & (not outer)
        fn = np.where(rel < span, 0.0, q) * np.where(after, 1.3, 1.0)
        data[f"roller{j}_angle_rad"] = angle
        data[f"roller{j}_outer_fn"] = fn
        data[f"roller{j}_inner_fn"] = fn
    info = {
        "spall": {
            "race": d.race,
            "centre_angle_from_top": d.angle,
            "length": d.length,
            "raceway_radius": radius,
            "depth": d.depth,
        }
    }
    return pd.DataFrame(data), info
