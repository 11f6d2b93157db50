r"""The contact patch a finite element contact resolves, against Hertz: half-width and peak
pressure from the nodal contact forces on a raceway (numpy only).

With few nodes in contact the patch is sampled coarsely: the half-width is taken from the
distribution's second moment, which for the Hertz ellipse
:math:`p(s) = p_0 \sqrt{1 - s^2/b^2}` is :math:`b^2 / 4` (so
:math:`b = 2 \sqrt{\mathrm{var}}`), and is defined for any number of loaded nodes; the
peak pressure is the largest nodal force over its tributary length.

A nodal force is the pressure weighted by a kernel (the shape functions that carry it to
the node), and a kernel's own variance adds to the pressure's: nodal forces of an exact
Hertz pressure read at 0.5 mm nodes spread a 0.43 mm wide patch to about 0.46 mm.
:func:`nodal_patch` subtracts what the caller says the kernel adds
(:func:`contact_spread` for the two-pass contact of two like meshes), so the half-width is
the pressure's. The peak pressure keeps a bias of about :math:`\mathrm{spread} / (2 b^2)`
(0.5 % with four elements across :math:`b`).
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

__all__ = ["contact_spread", "nodal_patch", "raceway_patch"]


def contact_spread(h) -> float | np.ndarray:
    """Variance (m^2) that reading a pressure from nodal forces adds, for a two-pass
    penalty contact between two surfaces meshed alike at spacing ``h`` (m): :math:`h^2 / 6`.

    Each pass carries half the pressure. The raceway's own queries gather it over their
    tributary boxes (variance :math:`h^2 / 12`); the roller's gather it over theirs and hand
    it to the raceway's nodes by the segment's linear shape functions
    (:math:`h^2 / 12 + h^2 / 6`); half of each is :math:`h^2 / 6`, the variance of a linear
    shape function's hat.
    Averaged over where the patch lies between nodes; exact once it spans several.
    """
    return np.asarray(h, dtype=float) ** 2 / 6.0


def nodal_patch(
    s: np.ndarray, f: np.ndarray, h: np.ndarray, thickness: float, spread: float = 0.0
) -> dict:
    """Patch of normal nodal forces ``f`` (N, compressive positive) at positions ``s``
    along a surface (m) with tributary lengths ``h`` (m), for a body ``thickness`` thick.

    Parameters
    ----------
    s, f, h : array_like
    thickness : float
    spread : float
        Variance (m^2) the nodal kernel adds to the pressure's (:func:`contact_spread`);
        0 reads the forces' own second moment.

    Returns
    -------
    dict
        ``force_N`` (sum), ``centre_m`` (force centroid), ``half_width_m`` (twice the square
        root of the force-weighted variance of ``s`` less ``spread``; NaN where that variance is
        no more than ``spread`` > 0: the patch is narrower than the nodes resolve, and a
        width of 0 would be a reading, not the absence of one), ``nodal_half_width_m``
        (without the correction), ``peak_pressure_Pa`` (largest :math:`f / (h t)`) and
        ``nodes`` (nodes carrying force).
    """
    s, f, h = (np.asarray(a, dtype=float) for a in (s, f, h))
    f = np.maximum(f, 0.0)
    total = float(f.sum())
    if not total > 0:
        return {"force_N": 0.0, "centre_m": math.nan, "half_width_m": math.nan,
                "nodal_half_width_m": math.nan, "peak_pressure_Pa": 0.0,
                "nodes": 0}  # fmt: skip
    centre = float(np.sum(f * s) / total)
    var = float(np.sum(f * (s - centre) ** 2) / total)
    return {
        "force_N": total,
        "centre_m": centre,
        "half_width_m": 2.0 * math.sqrt(var - spread) if var > spread or spread <= 0 else math.nan,
        "nodal_half_width_m": 2.0 * math.sqrt(var),
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
    h_near = trib[nodes][near]
    # the kernel's variance at the loaded nodes (the roller meshed like the raceway)
    loaded = np.maximum(fn[near], 0.0)
    spread = float(np.sum(loaded * contact_spread(h_near)) / max(loaded.sum(), 1e-300))
    patch = nodal_patch(s[near], fn[near], h_near, bearing.roller_length, spread)
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
