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


def test_a_patch_the_nodes_do_not_resolve_has_no_width():
    """With the nodal kernel's spread taken off, a patch whose forces spread no more than
    the kernel does (one loaded node; two equal nodes h apart against a spread of h^2 / 4)
    has no measured width (NaN, left out of passage statistics), never a width of 0; one
    just wider has its width."""
    h, t = 5e-4, 0.05
    one = nodal_patch(np.array([0.0, h]), np.array([1e4, 0.0]), np.full(2, h), t, h**2 / 6)
    assert math.isnan(one["half_width_m"]) and one["nodal_half_width_m"] == 0.0
    two = nodal_patch(np.array([0.0, h]), np.array([1e4, 1e4]), np.full(2, h), t, h**2 / 4)
    assert math.isnan(two["half_width_m"])  # variance h^2 / 4 exactly: nothing left
    wider = nodal_patch(np.array([0.0, h]), np.array([1e4, 1e4]), np.full(2, h), t, h**2 / 6)
    assert wider["half_width_m"] == pytest.approx(2 * math.sqrt(h**2 / 4 - h**2 / 6))


def hat_forces(b, p0, t, h, offset):
    """Nodal forces of the Hertz pressure carried to nodes ``h`` apart by the linear
    shape functions (hats), the nodes shifted by ``offset`` from the patch's centre."""
    s = np.arange(-2 * b - 2 * h, 2 * b + 2 * h, h) + offset
    fine = np.linspace(-b, b, 100_001)
    p = p0 * np.sqrt(np.clip(1 - (fine / b) ** 2, 0, None))
    hats = np.clip(1 - np.abs(fine[None, :] - s[:, None]) / h, 0, None)
    return s, hats @ p * (fine[1] - fine[0]) * t


def test_spread_of_coarse_nodes_is_the_hats_variance():
    """The issue's figure: an exact Hertz pressure 0.43 mm wide read from 0.5 mm nodes
    spreads to about 0.46 mm; the hats' variance h^2 / 6 taken off gives it back (averaged
    over where the patch lies between nodes, as a rolling contact does)."""
    from taichi_bearing.analytic.contact_pressure import contact_spread

    b, p0, t, h = 0.215e-3, 0.9e9, 0.05, 0.5e-3
    var_raw, var_fixed = [], []
    for offset in np.linspace(0, h, 21)[:-1]:
        s, f = hat_forces(b, p0, t, h, offset)
        patch = nodal_patch(s, f, np.full(len(s), h), t, float(contact_spread(h)))
        var_raw.append((patch["nodal_half_width_m"] / 2) ** 2)
        var_fixed.append((patch["half_width_m"] / 2) ** 2 if patch["half_width_m"] > 0 else 0)
    raw = 2 * np.sqrt(np.mean(var_raw))
    assert raw == pytest.approx(0.46e-3, abs=0.01e-3)
    # means of variances: the correction is exact on average (no clipping at this size)
    fixed = 2 * np.sqrt(np.mean(var_raw) - h**2 / 6)
    assert fixed == pytest.approx(b, rel=1e-3)
    assert 2 * np.sqrt(np.mean(var_fixed)) == pytest.approx(b, rel=1e-3)


@pytest.mark.parametrize("offset", [0.0, 0.3, 0.5])
def test_spread_correction_on_a_resolved_patch(offset):
    """Four elements across b: the corrected half-width is within 0.5 % wherever the
    nodes lie; the raw one is 2 % wide."""
    from taichi_bearing.analytic.contact_pressure import contact_spread

    b, p0, t = 2e-4, 1.5e9, 0.05
    h = b / 4
    s, f = hat_forces(b, p0, t, h, offset * h)
    patch = nodal_patch(s, f, np.full(len(s), h), t, float(contact_spread(h)))
    assert patch["half_width_m"] == pytest.approx(b, rel=0.005)
    assert patch["nodal_half_width_m"] > 1.015 * b
    # the peak is low by the kernel's spread / (2 b^2) = 0.5 % and, with no node at the
    # centre, by the sampling's (h / 2)^2 / (2 b^2) = 0.8 %; the force is exact
    assert p0 * (1 - 0.0135) < patch["peak_pressure_Pa"] < p0
    assert patch["force_N"] == pytest.approx(math.pi * b * p0 * t / 2, rel=1e-3)
