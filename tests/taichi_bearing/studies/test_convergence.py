"""The numerics of a convergence study against sequences whose answer is known: the
observed order and Richardson's estimate of f0 + C h^p, with constant and unequal
refinement ratios, refining by size or by penalty; what happens where the order means
nothing (oscillating, diverging, too steep, no value); the verdicts' limits."""

from __future__ import annotations

import math

import pytest

from taichi_bearing.studies.convergence import (
    DYNAMIC_LIMIT,
    ORDER_RANGE,
    STATIC_LIMIT,
    assess,
    judge,
    observed_order,
    relative_changes,
    spacings,
)


def test_second_order_sequence_gives_order_two_and_f0_exactly():
    f0, c, h = 1.25, 3.0, 0.4
    hs = [h, h / 2, h / 4]
    e = observed_order(hs, [f0 + c * x**2 for x in hs])
    assert e.meaningful and e.reason == "monotone convergence"
    assert e.order == pytest.approx(2.0, abs=1e-12)
    assert e.extrapolated == pytest.approx(f0, abs=1e-13)


def test_unequal_ratios_solve_the_same_model():
    # h = 0.4, 0.2, 0.05: ratios 2 and 4; the closed form ln(e32/e21)/ln(r) is wrong here
    f0, c, p = -2.0, 0.7, 1.5
    hs = [0.4, 0.2, 0.05]
    f = [f0 + c * x**p for x in hs]
    e = observed_order(hs, f)
    assert e.order == pytest.approx(p, rel=1e-9)
    assert e.extrapolated == pytest.approx(f0, abs=1e-12)
    naive = math.log((f[0] - f[1]) / (f[1] - f[2])) / math.log(2.0)
    assert abs(naive - p) > 0.3


def test_penalty_levels_refine_upwards_with_spacing_one_over_scale():
    scales = [0.03, 0.1, 0.3, 1.0]
    h = spacings(scales)
    assert h == pytest.approx([1 / s for s in scales])
    # a penalty contact's error goes as 1 / k: first order in the spacing
    a = assess(scales, [5.0 - 0.02 / s for s in scales], STATIC_LIMIT)
    assert len(a.orders) == 2
    assert all(o.meaningful for o in a.orders)
    assert a.orders[-1].order == pytest.approx(1.0, rel=1e-9)
    assert a.orders[-1].extrapolated == pytest.approx(5.0, abs=1e-12)
    # the last change: (4.98 - 4.9333) / 4.98 = +0.94 %: within 2 %
    assert a.verdict.status == "converged"
    assert a.verdict.change == pytest.approx(a.changes[-1])
    assert a.changes[-1] == pytest.approx((4.98 - (5.0 - 0.02 / 0.3)) / 4.98)


@pytest.mark.parametrize(
    "f, reason",
    [
        ([1.0, 2.0, 1.5], "oscillating"),
        ([1.0, 1.1, 1.3], "diverging"),
        ([1.0, 1.0, 1.0], "three levels agree"),
        ([1.0, 1.5, 1.5], "two finest levels agree"),
        ([1.0, 1.5, 1.5 * (1 + 1e-15)], "two finest levels agree (to rounding)"),
        ([1.0, math.nan, 1.5], "no value"),
    ],
)
def test_no_estimate_where_the_order_means_nothing(f, reason):
    e = observed_order([1.0, 0.5, 0.25], f)
    assert not e.meaningful and reason in e.reason
    assert math.isnan(e.extrapolated)


def test_orders_outside_the_sensible_range_give_no_estimate():
    hs = [1.0, 0.5, 0.25]
    steep = observed_order(hs, [2.0 + x**6 for x in hs])  # p = 6 > 4
    assert steep.order == pytest.approx(6.0) and not steep.meaningful
    assert "outside the sensible range" in steep.reason
    shallow = observed_order(hs, [2.0 + x**0.25 for x in hs])  # p = 0.25 < 0.5
    assert shallow.order == pytest.approx(0.25) and not shallow.meaningful
    lo, hi = ORDER_RANGE
    assert observed_order(hs, [2.0 + x**lo for x in hs]).meaningful
    assert observed_order(hs, [2.0 + x**hi for x in hs]).meaningful


def test_levels_must_refine_one_way():
    with pytest.raises(ValueError, match="one way"):
        spacings([1.0, 0.5, 0.7])
    with pytest.raises(ValueError, match="positive"):
        spacings([1.0, 0.0, -1.0])
    with pytest.raises(ValueError, match="shrink"):
        observed_order([0.25, 0.5, 1.0], [1.0, 2.0, 3.0])


def test_relative_change_is_taken_on_the_finer_level():
    assert relative_changes([1.0, 2.0, 2.5]) == pytest.approx([0.5, 0.2])
    assert math.isnan(relative_changes([1.0, 0.0])[0])


def test_verdict_limits():
    assert judge(1.0, 1.019, STATIC_LIMIT).status == "converged"
    assert judge(1.0, 1.03, STATIC_LIMIT).status == "not converged"
    assert judge(1.0, 1.09, DYNAMIC_LIMIT).status == "converged"
    no = judge(1.0, 1.2, DYNAMIC_LIMIT)
    assert no.status == "not converged" and no.change == pytest.approx(0.2 / 1.2)
    assert judge(math.nan, 1.0, DYNAMIC_LIMIT).status == "not judged"
    assert judge(1.0, 0.0, DYNAMIC_LIMIT).status == "not judged"
    assert judge(0.0, 0.0, DYNAMIC_LIMIT).status == "converged"
