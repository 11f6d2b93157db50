"""A reference the geometry tests share: how far a roller drops over a spall profile,
found by brute force (bisection on the distance to a fine polyline), with no formula of
:mod:`taichi_bearing.geometry.roller_path`."""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.geometry.spall_profile import SpallProfile

ROLLER_RADIUS = 0.012  # the default bearing's roller radius, m


def brute_force_drop(profile: SpallProfile, phi: float, roller: float = ROLLER_RADIUS) -> float:
    """How far a circle of radius ``roller`` centred on the ray at ``phi`` can move
    towards the profile (out of an outer raceway, in onto an inner one) before it reaches
    it, by bisection on the distance to a fine polyline of the profile with the raceway
    beyond it (no formula of roller_path)."""
    big, s = profile.raceway_radius, profile.sign
    a0 = math.atan2(*profile.pieces[0].p0[::-1])
    a1 = math.atan2(*profile.pieces[-1].p1[::-1])
    before = np.linspace(a0 - 0.2, a0, 4000)[:-1]
    after = np.linspace(a1, a1 + 0.2, 4000)[1:]
    pts = np.concatenate(
        [big * np.stack([np.cos(before), np.sin(before)], 1), profile.polyline(4000),
         big * np.stack([np.cos(after), np.sin(after)], 1)]
    )  # fmt: skip
    seg = np.diff(pts, axis=0)
    keep = np.einsum("ij,ij->i", seg, seg) > 0
    p0, seg = pts[:-1][keep], seg[keep]
    e = np.array([math.cos(phi), math.sin(phi)])

    def clearance(rho_c):
        c = rho_c * e
        t = np.clip(np.einsum("ij,ij->i", c - p0, seg) / np.einsum("ij,ij->i", seg, seg), 0, 1)
        return np.min(np.hypot(*(p0 + t[:, None] * seg - c).T)) - roller

    healthy = big - s * roller
    clear, blocked = healthy - s * 1e-4, healthy + s * (profile.depth + 1e-4)
    for _ in range(80):
        mid = 0.5 * (clear + blocked)
        clear, blocked = (mid, blocked) if clearance(mid) > 0 else (clear, mid)
    return s * (clear - healthy)
