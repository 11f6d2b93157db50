"""The contact patch read from nodal forces: a Hertz pressure sampled at nodes gives back
its half-width and peak as the sampling gets finer."""

import math

import numpy as np
import pytest

from taichi_bearing.analytic.contact_pressure import nodal_patch


@pytest.mark.parametrize(("h_over_b", "tol_b", "tol_p"), [(0.05, 0.01, 0.01), (0.25, 0.05, 0.05)])
def test_hertz_ellipse_sampled_at_nodes(h_over_b, tol_b, tol_p):
    b, p0, t = 2e-4, 1.5e9, 0.05
    h = h_over_b * b
    s = np.arange(-2 * b, 2 * b + h / 2, h) + 0.3 * h  # nodes not centred on the patch
    # lumped nodal forces: the pressure integrated over each node's tributary length
    fine = np.linspace(-b, b, 200_001)
    p = p0 * np.sqrt(np.clip(1 - (fine / b) ** 2, 0, None))
    owner = np.clip(np.round((fine - s[0]) / h).astype(int), 0, len(s) - 1)
    f = np.bincount(owner, p, len(s)) * (fine[1] - fine[0]) * t
    patch = nodal_patch(s, f, np.full(len(s), h), t)
    assert patch["force_N"] == pytest.approx(math.pi * b * p0 * t / 2, rel=1e-3)
    assert patch["half_width_m"] == pytest.approx(b, rel=tol_b)
    assert patch["peak_pressure_Pa"] == pytest.approx(p0, rel=tol_p)


def test_one_loaded_node_has_no_width_and_its_mean_pressure():
    patch = nodal_patch(np.array([0.0, 5e-4]), np.array([1e4, 0.0]), np.full(2, 5e-4), 0.05)
    assert patch["nodes"] == 1
    assert patch["half_width_m"] == 0.0
    assert patch["peak_pressure_Pa"] == pytest.approx(1e4 / (5e-4 * 0.05))
