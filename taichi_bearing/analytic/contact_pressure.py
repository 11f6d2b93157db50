"""The contact patch a finite element contact resolves, against Hertz: half-width and peak
pressure from the nodal contact forces on a raceway (numpy only).

With few nodes in contact the patch is sampled coarsely: the half-width is taken from the
distribution's second moment, which for the Hertz ellipse ``p(s) = p0 sqrt(1 - s^2/b^2)``
is ``b^2 / 4`` (so ``b = 2 sqrt(var)``), and is defined for any number of loaded nodes; the
peak pressure is the largest nodal force over its tributary length. Both approach Hertz
only once several surface elements span ``2 b``: what a mesh convergence study measures.
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.analytic.bearing import (
    contact_radius,
    effective_modulus,
    hertz_half_width,
    hertz_peak_pressure,
)

__all__ = ["nodal_patch", "raceway_patch"]


def nodal_patch(s: np.ndarray, f: np.ndarray, h: np.ndarray, thickness: float) -> dict:
    """Patch of normal nodal forces ``f`` (N, compressive positive) at positions ``s``
    along a surface (m) with tributary lengths ``h`` (m), for a body ``thickness`` thick.

    Returns
    -------
    dict
        ``force_N`` (sum), ``centre_m`` (force centroid), ``half_width_m`` (``2 sqrt`` of
        the force-weighted variance of ``s``), ``peak_pressure_Pa`` (largest
        ``f / (h t)``) and ``nodes`` (nodes carrying force).
    """
    s, f, h = (np.asarray(a, dtype=float) for a in (s, f, h))
    f = np.maximum(f, 0.0)
    total = float(f.sum())
    if not total > 0:
        return {"force_N": 0.0, "centre_m": math.nan, "half_width_m": math.nan,
                "peak_pressure_Pa": 0.0, "nodes": 0}  # fmt: skip
    centre = float(np.sum(f * s) / total)
    var = float(np.sum(f * (s - centre) ** 2) / total)
    return {
        "force_N": total,
        "centre_m": centre,
        "half_width_m": 2.0 * math.sqrt(var),
        "peak_pressure_Pa": float(np.max(f / (h * thickness))),
        "nodes": int(np.count_nonzero(f)),
    }


def raceway_patch(
    xy: np.ndarray,
    forces: np.ndarray,
    chain: np.ndarray,
    angle: float,
    bearing,
    material,
    race: str = "outer",
    reach: float = 3e-3,
) -> dict:
    """The contact patch of the roller at polar ``angle`` (rad, from +x) on a raceway,
    from the contact forces on the raceway's nodes, beside the Hertz patch of the same
    force (:func:`taichi_bearing.analytic.bearing.hertz_half_width`).

    Parameters
    ----------
    xy : ndarray (n_nodes, 2)
        Node positions, m (the bearing centre at the origin).
    forces : ndarray (n_nodes, 2)
        Contact force on every node, N.
    chain : ndarray of int (n_segments, 2)
        The raceway surface's segments (node pairs).
    angle : float
        Polar angle of the roller's centre, rad.
    bearing, material :
        The case's ``bearing`` and ``material`` sections (radii, length, E, nu).
    race : {"outer", "inner"}
    reach : float
        Arc length either side of the roller's line taken as its patch, m.
    """
    nodes = np.unique(chain)
    p = xy[nodes]
    radius = np.hypot(p[:, 0], p[:, 1])
    theta = np.arctan2(p[:, 1], p[:, 0])
    s = radius * ((theta - angle + math.pi) % (2 * math.pi) - math.pi)
    near = np.abs(s) <= reach
    # tributary length: half of each segment at the node
    seg_len = np.linalg.norm(xy[chain[:, 1]] - xy[chain[:, 0]], axis=1)
    trib = np.zeros(len(xy))
    np.add.at(trib, chain[:, 0], 0.5 * seg_len)
    np.add.at(trib, chain[:, 1], 0.5 * seg_len)
    # a roller pushes the outer raceway outward, the inner one inward
    normal = p / radius[:, None] * (1.0 if race == "outer" else -1.0)
    fn = np.sum(forces[nodes] * normal, axis=1)
    patch = nodal_patch(s[near], fn[near], trib[nodes][near], bearing.roller_length)
    e_star = effective_modulus(material.youngs_modulus, material.poissons_ratio)
    r_eff = contact_radius(bearing, race)
    force = patch["force_N"]
    patch["hertz_half_width_m"] = float(
        hertz_half_width(force, bearing.roller_length, r_eff, e_star)
    )
    patch["hertz_peak_pressure_Pa"] = float(
        hertz_peak_pressure(force, bearing.roller_length, r_eff, e_star)
    )
    return patch
