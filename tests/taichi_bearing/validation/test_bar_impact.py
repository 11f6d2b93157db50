"""Issue 43 item 7a: an elastic bar (Poisson's ratio 0, so plane strain is one-dimensional)
striking a rigid wall at v0 is pressed by rho c v0 for 2 L / c, c = sqrt(E / rho); the
pressure law's spring delays the rise by tau ln 2, tau = rho c / p_s, and leaves the
duration alone. Formulas only: nothing here comes from the solver's stiffness."""

import math

import pytest

from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.validation.bar_impact import RHO, E, bar_impact


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def test_plateau_and_duration_of_the_wave_solution():
    """40 elements along the bar, p_s = 1000 GPa/mm (tau ln 2 is 0.4 % of 2 L / c)."""
    r = bar_impact(40, 1e15)
    print(f"plateau {r.plateau_error:+.4f}, duration {r.duration_error:+.4f}")
    assert abs(r.plateau_error) < 0.02
    assert abs(r.duration_error) < 0.02
    assert r.rebound == pytest.approx(1.0, abs=0.03)  # the bar leaves at v0


def test_a_soft_penalty_delays_the_rise_and_keeps_the_duration():
    """p_s = 100 GPa/mm: tau ln 2 = 0.28 us, 3.6 % of 2 L / c; the force reaches half
    the plateau that late (within 15 %: the bar's end node is half an element's mass,
    not a continuum's end) and lets go as late."""
    r = bar_impact(40, 1e14)
    tau = RHO * math.sqrt(E / RHO) / 1e14
    print(f"onset {r.onset * 1e9:.1f} ns against {tau * math.log(2) * 1e9:.1f} ns")
    assert r.onset == pytest.approx(tau * math.log(2.0), rel=0.15)
    assert abs(r.duration_error) < 0.02
    assert abs(r.plateau_error) < 0.02
