"""Static roller forces at the end of the preload against the rigid-ring (Harris)
load distribution, with the outer ring held all round by a rigid housing
(cases/validation/rigid_housing.yaml, ``bearing.outer_support: housing``).

With both rings rigidly supported the analytical model's assumptions hold, so the FE
preload must meet the run's own static checks (each loaded roller within 10 %, Q_max
within 5 %). The fast test uses 1 mm surface elements, where the rollers' 10 um facets
(h^2 / 8r) are as large as the ~7 um Hertz deflection: only the load zone's extent, the
symmetry, the load balance and Q_max are asserted there.
"""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.case import load_case
from taichi_bearing.checks import static_force_checks
from taichi_bearing.quasistatic import analytical_roller_forces
from taichi_bearing.starter import build_setup, outer_surface_nodes

HOUSING = "cases/validation/rigid_housing.yaml"
THREADS = 1  # reproducible contact sums (atomics on one thread)


def _preload(case):
    from taichi_bearing.simulate import build_model, preload, stage_mesh

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
    """0.5 mm surface elements (about a minute): the run's 10 % / 5 % static checks pass."""
    case = load_case(HOUSING, ["mesh.surface_size_mm=0.5", "mesh.max_size_mm=3.0"])
    pre = _preload(case)
    fe = np.asarray(pre["outer_force_N"])
    an = analytical_roller_forces(case)
    assert sum(pre["outer_fy_N"]) == pytest.approx(case.operating.load, rel=0.01)
    checks = static_force_checks(fe, an)
    assert checks["static_roller_forces"]["passed"], checks["static_roller_forces"]
    assert checks["static_q_max"]["passed"], checks["static_q_max"]
