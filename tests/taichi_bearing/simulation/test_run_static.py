"""Static roller forces at the end of the preload against the rigid-ring (Harris)
load distribution, with the outer ring held all round by a rigid housing
(cases/validation/rigid_housing.yaml, ``bearing.outer_support: housing``).

With both rings rigidly supported the analytical model's assumptions hold: the FE
preload meets its Q_max check (5 %) and, on the 0.5 mm mesh, the 10 % check for every
roller carrying at least half of Q_max (the zone-edge rollers fall short, see the slow
test). The fast test uses 1 mm surface elements, where the rollers' 10 um facets
(h^2 / 8r) are as large as the ~7 um Hertz deflection: only the load zone's extent, the
symmetry, the load balance and Q_max are asserted there.
"""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.analytic.quasistatic import analytical_roller_forces
from taichi_bearing.case import load_case
from taichi_bearing.checks import flexible_reference_checks, static_force_checks
from taichi_bearing.simulation.starter import build_setup, outer_surface_nodes

HOUSING = "cases/validation/rigid_housing.yaml"
THREADS = 1  # the same histories as on any thread count; no spinning team on a shared VM


def _preload(case):
    from taichi_bearing.simulation.simulate import build_model, preload, stage_mesh

    mesh, _ = stage_mesh(case)
    return preload(build_model(case, mesh, "cpu", THREADS))


def test_housing_holds_the_whole_outside_of_the_outer_ring():
    from taichi_bearing.mesh import build_bearing_mesh, spec_from_case

    case = load_case(HOUSING, ["mesh.surface_size_mm=2", "mesh.max_size_mm=4"])
    mesh = build_bearing_mesh(spec_from_case(case))
    radius = case.bearing.outer_ring_outer_radius
    held = outer_surface_nodes(mesh, radius)
    xy = mesh.nodes[held]
    assert np.allclose(np.hypot(xy[:, 0], xy[:, 1]), radius, rtol=1e-9)
    # all the way round: no angular gap larger than a few maximum element sizes
    ang = np.sort(np.arctan2(xy[:, 1], xy[:, 0]))
    gaps = np.diff(np.concatenate([ang, ang[:1] + 2 * np.pi]))
    assert gaps.max() * radius < 2.0 * case.mesh.max_size
    setup = build_setup(case, mesh)
    plate = setup.constraints[0]
    assert set(plate.nodes.tolist()) == set(held.tolist())
    assert setup.loads[0].total == pytest.approx([0.0, -case.operating.load])
    # the adapter option keeps the loading plate on the adapter top
    adapter = build_setup(load_case(HOUSING, ["bearing.outer_support=adapter"]), mesh)
    assert set(adapter.constraints[0].nodes.tolist()) == set(mesh.node_sets["adapter_top"])


def test_coarse_housing_carries_the_load_over_the_analytical_zone():
    case = load_case(HOUSING)  # 1 mm surface elements
    pre = _preload(case)
    fe = np.asarray(pre["outer_force_N"])
    an = analytical_roller_forces(case)
    # equilibrium: the rollers push the housing up with W
    assert sum(pre["outer_fy_N"]) == pytest.approx(case.operating.load, rel=0.01)
    # roller 0 at 12 o'clock: the load zone is symmetric about it
    n = case.bearing.n_rollers
    mirror = (-np.arange(n)) % n
    assert np.allclose(fe, fe[mirror], rtol=0.01, atol=0.01 * fe.max())
    # every analytically loaded roller out to +-72 deg carries load (the adapter-only
    # support leaves the rollers beyond ~+-50 deg unloaded), nothing beyond +-90 deg
    loaded = an > 0.05 * an.max()
    assert np.all(fe[loaded] > 0.5 * an[loaded])
    assert np.all(fe[an == 0] < 0.01 * fe.max())
    # the most loaded roller meets the run's Q_max check already on this mesh
    assert static_force_checks(fe, an)["static_q_max"]["passed"]


@pytest.mark.slow
def test_rigid_housing_preload_matches_harris():
    """0.5 mm surface elements (about 70 s): the load balances W, Q_max meets the 5 %
    check and every roller carrying at least half of Q_max the 10 % check.

    Measured (KE ratio 1e-7): rollers at 0, +-18, +-36, +-54, +-72 deg +1.8, +3.4,
    +1.4, -9.1, -17.8 %. The zone-edge rollers (2.3-5 kN) fall short of the 10 % check:
    the FE contact's load-deflection law there is steeper than Palmgren's 10/9 (the
    measured distribution is Harris's with an exponent of about 1.3), a contact
    discretisation effect that the flexible-ring reference (same law as Harris) shows
    is not ring flexibility (it moves those rollers by under 3 %).
    """
    case = load_case(HOUSING, ["mesh.surface_size_mm=0.5", "mesh.max_size_mm=3.0"])
    pre = _preload(case)
    fe = np.asarray(pre["outer_force_N"])
    an = analytical_roller_forces(case)
    assert sum(pre["outer_fy_N"]) == pytest.approx(case.operating.load, rel=0.01)
    assert static_force_checks(fe, an)["static_q_max"]["passed"]
    heavy = an >= 0.5 * an.max()
    assert np.allclose(fe[heavy], an[heavy], rtol=0.10)


# ------------------------------------------------------------------ flexible-ring reference


def _rings(overrides):
    from taichi_bearing.mesh import build_bearing_mesh, spec_from_case
    from taichi_bearing.simulation.static_reference import ring_compliance

    case = load_case(HOUSING, overrides)
    return case, ring_compliance(case, build_bearing_mesh(spec_from_case(case)))


@pytest.fixture(scope="module")
def housing_rings():
    return _rings([])


@pytest.fixture(scope="module")
def adapter_rings():
    return _rings(["bearing.outer_support=adapter"])


@pytest.mark.parametrize("clearance_mm", [0.0, 0.02, -0.005])
def test_reference_with_rigid_rings_is_harris(housing_rings, clearance_mm):
    """With no ring compliance the spring model is the analytical load distribution."""
    from taichi_bearing.simulation.static_reference import RingCompliance, solve_springs

    case, rings = housing_rings
    case = load_case(HOUSING, [f"bearing.radial_clearance_mm={clearance_mm}"])
    rigid = RingCompliance(np.zeros_like(rings.compliance), rings.angles, rings.gaps)
    ref = solve_springs(case, rigid)
    an = analytical_roller_forces(case)
    assert ref.residual < 1e-9
    assert np.allclose(ref.forces, an, rtol=1e-8, atol=1e-8 * an.max())


def test_ring_compliance_is_reciprocal_and_follows_the_support(housing_rings, adapter_rings):
    case, housing = housing_rings
    _, adapter = adapter_rings
    for rings in (housing, adapter):
        c = rings.compliance
        # Maxwell-Betti: the opening at j per unit pair at k equals that at k per pair at j
        assert np.allclose(c, c.T, rtol=0, atol=1e-6 * np.abs(c).max())
        assert np.all(np.diag(c) > 0)
        assert np.abs(rings.gaps).max() < 1e-9  # healthy raceways: no extra gap
    # held all round, the ring is about equally stiff under every roller; hung from the
    # adapter, it is as stiff under the adapter but far softer at the sides (it ovalises)
    ang = np.abs(np.degrees(housing.angles))
    d_h, d_a = np.diag(housing.compliance), np.diag(adapter.compliance)
    assert d_h.max() < 1.5 * d_h.min()
    top = ang < 20
    assert np.allclose(d_a[top], d_h[top], rtol=0.5)
    side = np.isclose(ang, 90.0)
    assert np.all(d_a[side] > 50 * d_h[side])


def test_reference_with_housing_is_close_to_harris_and_with_adapter_is_not(
    housing_rings, adapter_rings
):
    from taichi_bearing.simulation.static_reference import solve_springs

    case, housing = housing_rings
    an = analytical_roller_forces(case)
    cos = np.cos(housing.angles)
    ref = solve_springs(case, housing)
    assert ref.forces @ cos == pytest.approx(case.operating.load, rel=1e-9)
    loaded = an > 0.05 * an.max()
    assert np.allclose(ref.forces[loaded], an[loaded], rtol=0.05)
    checks = static_force_checks(ref.forces, an)
    assert checks["static_roller_forces"]["passed"] and checks["static_q_max"]["passed"]
    # hung from the adapter: the zone ends near +-45 deg and Q_max is ~40 % above Harris
    adapter_case = load_case(HOUSING, ["bearing.outer_support=adapter"])
    ref_a = solve_springs(adapter_case, adapter_rings[1])
    assert ref_a.forces @ cos == pytest.approx(case.operating.load, rel=1e-9)
    ang = np.abs(np.degrees(housing.angles))
    assert np.all(ref_a.forces[(ang > 50) & (ang < 90)] == 0)
    assert ref_a.forces.max() > 1.3 * an.max()


def test_reference_roller_over_the_spall_carries_nothing():
    from taichi_bearing.simulation.static_reference import reference_roller_forces

    case = load_case("cases/validation/coarse_spall.yaml", ["run.first_roller_angle_deg=0"])
    ref = reference_roller_forces(case)
    an = analytical_roller_forces(case)
    # roller 0's foot is over the 0.3 mm deep floor, deeper than any approach: unloaded
    # in both models, its neighbours share its load symmetrically
    assert ref[0] == 0 and an[0] == 0
    assert ref[1] == pytest.approx(ref[-1], rel=1e-3)
    assert ref @ np.cos(2 * np.pi * np.arange(len(ref)) / len(ref)) == pytest.approx(
        case.operating.load, rel=1e-6
    )


def test_coarse_adapter_preload_follows_the_flexible_reference_not_harris():
    """Hung from the 120 mm adapter (the default support), the FE preload's load zone is
    the flexible-ring reference's: measured on 1 mm elements, FE vs reference +0.1 % at
    +-18 deg, +9.6 % at +-36 deg, -6.2 % at 0 deg; against Harris +40 % to +45 %, and
    nothing beyond +-36 deg where Harris loads rollers out to +-72 deg."""
    from taichi_bearing.simulation.static_reference import reference_roller_forces

    # the adapter-hung ring creeps at KE ratios below ~1e-6; 1e-5 balances W within 0.1 %
    case = load_case(HOUSING, ["bearing.outer_support=adapter", "preload.ke_ratio_tol=1e-5"])
    pre = _preload(case)
    fe = np.asarray(pre["outer_force_N"])
    an = analytical_roller_forces(case)
    ref = reference_roller_forces(case)
    assert sum(pre["outer_fy_N"]) == pytest.approx(case.operating.load, rel=0.01)
    # the same rollers are loaded (5 % of Q_max) in the FE and the reference, fewer
    # than in Harris's rigid-ring model
    assert np.array_equal(fe > 0.05 * fe.max(), ref > 0.05 * ref.max())
    assert (ref > 0.05 * ref.max()).sum() < (an > 0.05 * an.max()).sum()
    assert flexible_reference_checks(fe, ref)["static_roller_forces_flexible"]["passed"]
    # Q_max: within the per-roller 10 % of the reference (the 5 % check is missed on
    # this mesh, -6.2 %), more than 30 % above Harris
    assert fe.max() == pytest.approx(ref.max(), rel=0.10)
    assert fe.max() > 1.3 * an.max()
