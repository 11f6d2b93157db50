"""Two like cylinders in central impact under the pressure contact law (issue 43,
validation b): peak force and contact duration against the plane-strain Hertz impact.

The roller cap of ``test_contact_impact.py`` strikes a like cap turned over (effective
radius R / 2); the reference is the same line-contact law with its size term calibrated
on the two caps. The levels and why the tolerances are what they are:
docs/results/cylinder_impact/README.md (``python -m taichi_bearing.validation.impact
--target cap --law pressure`` regenerates its table).
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import math

import numpy as np
import pytest

from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.validation.impact import make_reference, run_level, with_penalty
from taichi_bearing.validation.impact_model import ImpactBodies, calibrate_size, impact_mesh

BODIES = ImpactBodies(target="cap")


@pytest.fixture(scope="module")
def reference():
    return make_reference(BODIES)


def test_the_struck_cap_is_the_roller_cap_turned_over():
    """The same body under the same pressure compresses the same, whichever way up; both
    contact faces bulge towards each other and touch at the origin only."""
    _, w_cap, w_struck = calibrate_size(BODIES, BODIES.peak_load, 20e-6)
    assert w_struck == pytest.approx(w_cap, rel=1e-9)
    mesh = impact_mesh(BODIES, 0.2e-3, offset=0.0)
    struck = np.unique(mesh.surfaces["block.top"])
    roller = np.unique(mesh.surfaces["roller.bottom"])
    ys, yr = mesh.nodes[struck, 1], mesh.nodes[roller, 1]
    assert ys.max() == pytest.approx(0.0, abs=1e-15) and yr.min() == pytest.approx(0.0, abs=1e-15)
    # a face at x from the axis stands x^2 / (2 R) off the origin's tangent line, each way
    x = mesh.nodes[struck, 0]
    edge = np.abs(x) <= 1e-3
    np.testing.assert_allclose(-ys[edge], x[edge] ** 2 / (2 * BODIES.radius), rtol=0.02, atol=1e-9)


def test_penalty_compliance_is_a_longer_size_term(reference):
    """The pressure law adds its central overlap 2 P / (pi alpha E*) to the approach:
    at alpha 10 the impact is softer than Hertz by about 1.5 % in peak force."""
    soft = with_penalty(reference, 10.0)
    law = reference.law
    p = reference.impact.peak
    extra = 2.0 * p / (math.pi * 10.0 * BODIES.e_star)
    stretched = law.size * math.exp(0.1)
    assert float(law.approach(p)) + extra == pytest.approx(
        (2 * p / (math.pi * BODIES.e_star)) * math.log(stretched / float(law.half_width(p))),
        rel=1e-12,
    )
    assert -0.02 < soft.peak / reference.impact.peak - 1.0 < -0.01
    assert 0.01 < soft.duration_above / reference.impact.duration_above - 1.0 < 0.02


def test_two_cylinders_impact_against_hertz_with_the_pressure_law(reference):
    """Surface elements of b / 2 (b the Hertz half-width at the peak), alpha 30: peak
    and duration within 1.5 % of the reference with the penalty's compliance; measured
    +0.6 % and -0.2 % (the table's finest level at alpha 100: +0.1 % and +0.3 % against
    Hertz). A penalty a hundred times softer (alpha 0.3) peaks 16 % low and lasts 23 %
    longer than Hertz, the segment law at the bearing's f_s 0.1 on this mesh -9 % and
    +13 %: both fail. A pressure law applied in full on each pass instead of halved over
    the two would be twice as stiff and still pass here (0.3 % of peak); the solver's
    pressure-law tests catch that."""
    init_taichi("cpu", 1)
    fe = run_level(reference, 0.1e-3, 30.0, method="pressure")
    expected = with_penalty(reference, 30.0)
    peak = fe.peak / expected.peak - 1.0
    duration = fe.duration_above / expected.duration_above - 1.0
    print(f"peak {peak:+.4f}, duration {duration:+.4f}, restitution {fe.restitution:.4f}")
    assert abs(peak) < 0.015
    assert abs(duration) < 0.015
    # Frictionless, undamped and quasi-static: the roller leaves as fast as it came.
    assert fe.restitution == pytest.approx(1.0, abs=0.005)
