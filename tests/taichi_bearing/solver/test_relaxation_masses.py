"""Dynamic relaxation with the contact nodes made heavier (``relax(scale_masses=True)``):
the static state does not depend on the masses, so a stiff penalty need not set the
relaxation's step. Checked on the pressure-law cylinder of validation (c): the same
patch, far fewer steps, the model's own masses and step afterwards."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np
import pytest

from taichi_bearing.analytic.contact_pressure import contact_spread, nodal_patch
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.contact import ContactParameters
from taichi_bearing.solver.laws import PressurePenalty
from taichi_bearing.validation.hertz_static import (
    B_TARGET,
    E_STAR,
    P,
    pressed_cylinder,
    pressure_profile,
)

FINE = B_TARGET / 2
PRESSURE = 30 * E_STAR / B_TARGET


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu", 1)


def relaxed(scale_masses: bool):
    mesh, model, contact, res = pressed_cylinder(
        FINE,
        ContactParameters(),
        # contact dashpots (as the bearing's 0.2): their bound follows the masses too
        law=PressurePenalty(PRESSURE, damping_ratio=0.2),
        time_step="global",
        tol=1e-7,
        scale_masses=scale_masses,
    )
    x, fy, _, trib = pressure_profile(mesh, contact)
    return model, res, nodal_patch(x, fy, trib, 1.0, float(contact_spread(FINE)))


@pytest.fixture(scope="module")
def both():
    return relaxed(False), relaxed(True)


def test_heavier_nodes_give_the_same_static_patch_in_fewer_steps(both):
    (_, plain, patch), (_, scaled, patch_s) = both
    print(
        f"steps {plain.steps} at {plain.dt:.3g} s, {scaled.steps} at {scaled.dt:.3g} s "
        f"({scaled.scaled_nodes} nodes heavier); half-width {patch['half_width_m']:.6g} / "
        f"{patch_s['half_width_m']:.6g}, peak {patch['peak_pressure_Pa']:.6g} / "
        f"{patch_s['peak_pressure_Pa']:.6g}"
    )
    # Both carry the load (measured: the plain relaxation stops 0.11 % above it, the
    # heavier one 0.001 %: the KE ratio ends each at its own distance from rest) and
    # give one patch (measured 0.04 % and 0.06 % apart)
    for pa in (patch, patch_s):
        assert pa["force_N"] == pytest.approx(P, rel=2e-3)
    for key in ("half_width_m", "peak_pressure_Pa"):
        assert patch_s[key] == pytest.approx(patch[key], rel=2e-3)
    # alpha 30 on b/2 elements: the contact's springs, not the elements, set the step
    # (measured: 48 times longer, 14 times fewer steps)
    assert scaled.dt > 10.0 * plain.dt
    assert scaled.steps * 5 < plain.steps
    assert plain.scaled_nodes == 0 and scaled.scaled_nodes > 0


def test_the_model_steps_with_its_own_masses_and_step_after(both):
    (plain_model, plain, _), (model, scaled, _) = both
    assert model.dt == plain_model.dt == plain.dt
    np.testing.assert_array_equal(model.mass.to_numpy(), model.mass_np)
    # the masses within: the elements' own diagonal frequency at every spring's node
    heavier = model.critical.contributor_mass_scale()
    k = model.critical.node_stiffness
    assert np.all(heavier[k == 0] == model.mass_np[k == 0])
    assert np.all(heavier[k > 0] > model.mass_np[k > 0])
    with model.contributor_masses() as n:
        assert n == scaled.scaled_nodes
        assert model.dt == pytest.approx(scaled.dt, rel=1e-12)
        np.testing.assert_array_equal(model.mass.to_numpy(), heavier)
    assert model.dt == plain.dt


def test_uniformly_heavier_masses_lengthen_the_step_by_their_root(both):
    """The estimate with other masses rescales the assembled matrices and the dashpots'
    bounds: four times the mass everywhere halves every frequency, damping ratios kept."""
    model = both[0][0]
    critical = model.critical
    heavy = critical.with_masses(4.0 * critical.mass)
    step, factor, _ = critical.values()
    step4, factor4, _ = heavy.values()
    assert factor < 0.95  # the dashpots shorten the step
    assert step4 == pytest.approx(2.0 * step, rel=1e-5)
    assert factor4 == pytest.approx(factor, rel=1e-5)
