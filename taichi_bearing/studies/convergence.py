r"""The numerics of a convergence study: relative changes between levels, the observed
order of convergence, Richardson's extrapolation and the verdicts (pure functions, numpy
only; no run folder, no I/O).

Levels go from coarse to fine. Each level has a spacing :math:`h` that shrinks as it
refines: the element size for a mesh study, and :math:`1 / \mathrm{scale}` for a penalty
study (a stiffer penalty is the finer level: the penetration, the error of a penalty
contact, goes as :math:`1 / k`). Three successive levels, coarsest to finest
:math:`(h_3, h_2, h_1)` with values :math:`(f_3, f_2, f_1)`, fit :math:`f(h) = f_0 + C h^p`
exactly. With a constant refinement ratio :math:`r = h_3 / h_2 = h_2 / h_1` the order is
:math:`p = \ln(|f_3 - f_2| / |f_2 - f_1|) / \ln r`; with unequal ratios :math:`p` solves
:math:`(f_3 - f_2) / (f_2 - f_1) = (h_3^p - h_2^p) / (h_2^p - h_1^p)` (the same model,
bisection on a function that rises with :math:`p`). Richardson's estimate of the converged
value is :math:`f_1 + (f_1 - f_2) / (r_{21}^p - 1)` with :math:`r_{21} = h_2 / h_1`.

The order means something only where the three values converge monotonically (successive
differences of one sign, shrinking) and :math:`p` lies in :data:`ORDER_RANGE`; otherwise no
estimate is given and :attr:`OrderEstimate.reason` says why.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

__all__ = [
    "DYNAMIC_LIMIT",
    "Assessment",
    "ORDER_RANGE",
    "ROUNDING",
    "STATIC_LIMIT",
    "OrderEstimate",
    "Verdict",
    "assess",
    "judge",
    "observed_order",
    "relative_changes",
    "spacings",
]

# The sensible range of an observed order. Below 0.5 the extrapolation multiplies the
# last difference by 1 / (r^p - 1), at least 2.4 for r = 2: it reaches further than the
# levels themselves. Above 4 the differences fall faster than linear elements with penalty
# contact can converge (order 2 for smooth fields, less at the contact's edges): a drop
# that steep is chance (the chaotic exit) or the levels sitting in a pre-asymptotic range.
ORDER_RANGE = (0.5, 4.0)
# Largest relative change between the two finest levels that counts as converged (issue
# 18): a static quantity (the preload's), and the median of a dynamic one over passages.
STATIC_LIMIT = 0.02
DYNAMIC_LIMIT = 0.10
# a difference of two levels below this share of their size is rounding
ROUNDING = 1e-12


@dataclass(frozen=True)
class OrderEstimate:
    """The observed order of three successive levels and Richardson's estimate.

    Attributes
    ----------
    order : float
        :math:`p`; NaN where it cannot be computed (see ``reason``); computed but outside
        :data:`ORDER_RANGE` it is given with ``meaningful`` False.
    extrapolated : float
        Richardson's estimate of the converged value; NaN unless ``meaningful``.
    meaningful : bool
        Monotone convergence with :math:`p` in :data:`ORDER_RANGE`.
    reason : str
        What the three values do, in words (why there is no estimate, where there is none).
    """

    order: float
    extrapolated: float
    meaningful: bool
    reason: str


@dataclass(frozen=True)
class Verdict:
    """Whether a quantity changed by at most ``limit`` between the two finest levels.

    ``status`` is ``"converged"``, ``"not converged"`` or ``"not judged"`` (no value at one
    of the two levels, or a finest value of zero); ``change`` the relative change (NaN
    when not judged); ``reason`` says it in words.
    """

    status: str
    change: float
    limit: float
    reason: str


def spacings(levels: Sequence[float]) -> list[float]:
    """The spacing :math:`h` of each level: the levels themselves when they decrease (element
    sizes), their inverses when they increase (penalty scales).

    Raises
    ------
    ValueError
        Fewer than two levels, a level that is not a positive finite number, or levels
        that do not go one way.
    """
    x = [float(v) for v in levels]
    if len(x) < 2:
        raise ValueError(f"need at least two levels, got {len(x)}")
    if not all(math.isfinite(v) and v > 0 for v in x):
        raise ValueError(f"levels must be positive numbers, got {list(levels)}")
    steps = [b - a for a, b in zip(x[:-1], x[1:], strict=True)]
    if all(s < 0 for s in steps):
        return x
    if all(s > 0 for s in steps):
        return [1.0 / v for v in x]
    raise ValueError(f"levels must go one way (coarse to fine), got {list(levels)}")


def relative_changes(values: Sequence[float]) -> list[float]:
    """:math:`(f_{i+1} - f_i) / |f_{i+1}|` for each pair of successive levels: the change on
    refining, relative to the finer level's value (the better one). NaN where either is
    NaN or the finer value is zero."""
    out = []
    for a, b in zip(values[:-1], values[1:], strict=True):
        a, b = float(a), float(b)
        ok = math.isfinite(a) and math.isfinite(b) and b != 0.0
        out.append((b - a) / abs(b) if ok else math.nan)
    return out


def _ratio_of_differences(p: float, r32: float, r21: float) -> float:
    """:math:`(h_3^p - h_2^p) / (h_2^p - h_1^p)` with :math:`r_{32} = h_3 / h_2`,
    :math:`r_{21} = h_2 / h_1` (both > 1): :math:`(r_{32}^p - 1) / (1 - r_{21}^{-p})`, which
    rises with :math:`p`."""
    return math.expm1(p * math.log(r32)) / -math.expm1(-p * math.log(r21))


def _solve_order(ratio: float, h3: float, h2: float, h1: float) -> float:
    r""":math:`p` with :math:`(h_3^p - h_2^p) / (h_2^p - h_1^p) = \mathrm{ratio}`; NaN if
    :math:`p \le 0`, inf if above 64."""
    r32, r21 = h3 / h2, h2 / h1
    if abs(math.log(r32) - math.log(r21)) <= 1e-12 * math.log(r21):
        p = math.log(ratio) / math.log(r21)  # constant ratio: the closed form
        return p if p > 0 else math.nan
    # as p -> 0 the ratio tends to ln(r32) / ln(r21): below it there is no positive order
    lo, hi = 0.0, 64.0
    if ratio <= math.log(r32) / math.log(r21):
        return math.nan
    if ratio >= _ratio_of_differences(hi, r32, r21):
        return math.inf
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _ratio_of_differences(mid, r32, r21) < ratio:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def observed_order(
    h: Sequence[float], f: Sequence[float], order_range: tuple[float, float] = ORDER_RANGE
) -> OrderEstimate:
    """Observed order and Richardson's estimate from three successive levels.

    Parameters
    ----------
    h : three floats
        Spacings, coarsest to finest (:math:`h_3 > h_2 > h_1 > 0`; :func:`spacings`).
    f : three floats
        The quantity at those levels (:math:`f_3, f_2, f_1`).
    order_range : (float, float)
        Orders outside this range are reported but give no estimate.

    Returns
    -------
    OrderEstimate

    Examples
    --------
    :math:`f(h) = 1 + 3 h^2` at :math:`h = 1, 0.5, 0.25` gives :math:`p = 2` and
    :math:`f_0 = 1`:

    >>> e = observed_order([1, 0.5, 0.25], [4.0, 1.75, 1.1875])
    >>> round(e.order, 12), round(e.extrapolated, 12), e.meaningful
    (2.0, 1.0, True)
    """
    h3, h2, h1 = (float(v) for v in h)
    f3, f2, f1 = (float(v) for v in f)
    if not h3 > h2 > h1 > 0:
        raise ValueError(f"spacings must shrink from coarse to fine, got {list(h)}")
    if not all(math.isfinite(v) for v in (f3, f2, f1)):
        return OrderEstimate(math.nan, math.nan, False, "a level has no value")
    e32, e21 = f3 - f2, f2 - f1
    # differences at the rounding level of the values are no difference
    tiny = ROUNDING * max(abs(f3), abs(f2), abs(f1))
    e32, e21 = (0.0 if abs(e) <= tiny else e for e in (e32, e21))
    if e32 == 0.0 and e21 == 0.0:
        return OrderEstimate(math.nan, math.nan, False, "the three levels agree (to rounding)")
    if e21 == 0.0:
        return OrderEstimate(
            math.inf, math.nan, False, "the two finest levels agree (to rounding): no finite order"
        )
    ratio = e32 / e21
    if ratio < 0:
        return OrderEstimate(
            math.nan, math.nan, False, "oscillating: the successive differences change sign"
        )
    p = _solve_order(ratio, h3, h2, h1)
    if math.isnan(p):
        return OrderEstimate(
            math.nan, math.nan, False, "diverging: the difference does not shrink on refining"
        )
    lo, hi = order_range
    if not lo <= p <= hi:
        return OrderEstimate(
            p, math.nan, False, f"order {p:.3g} outside the sensible range [{lo:g}, {hi:g}]"
        )
    extrapolated = f1 + (f1 - f2) / math.expm1(p * math.log(h2 / h1))
    return OrderEstimate(p, extrapolated, True, "monotone convergence")


def judge(coarse: float, fine: float, limit: float) -> Verdict:
    """The verdict on the change from the second finest level (``coarse``) to the finest
    (``fine``), relative to the finest: converged where ``|change| <= limit``."""
    coarse, fine = float(coarse), float(fine)
    if not (math.isfinite(coarse) and math.isfinite(fine)):
        return Verdict("not judged", math.nan, limit, "no value at one of the two finest levels")
    if fine == 0.0:
        if coarse == 0.0:
            return Verdict("converged", 0.0, limit, "zero at both finest levels")
        return Verdict(
            "not judged", math.nan, limit, "the finest value is zero: no relative change"
        )
    change = (fine - coarse) / abs(fine)
    if abs(change) <= limit:
        return Verdict("converged", change, limit, f"changes {change:+.1%} (limit {limit:.0%})")
    return Verdict("not converged", change, limit, f"changes {change:+.1%}, more than {limit:.0%}")


@dataclass(frozen=True)
class Assessment:
    """One quantity over the levels of a study.

    Attributes
    ----------
    changes : tuple of float
        :func:`relative_changes` between successive levels.
    orders : tuple of OrderEstimate
        :func:`observed_order` of each three successive levels, coarsest first (the last
        is the finest three).
    verdict : Verdict
        :func:`judge` of the two finest levels.
    """

    changes: tuple[float, ...]
    orders: tuple[OrderEstimate, ...]
    verdict: Verdict


def assess(levels: Sequence[float], values: Sequence[float], limit: float) -> Assessment:
    """Changes, observed orders and the verdict of a quantity's ``values`` at ``levels``
    (coarse to fine, at least two; :func:`spacings` says which way they refine).

    Raises
    ------
    ValueError
        As :func:`spacings`, or ``values`` not one per level.
    """
    if len(values) != len(levels):
        raise ValueError(f"{len(values)} values for {len(levels)} levels")
    h = spacings(levels)
    f = [float(v) for v in values]
    orders = tuple(observed_order(h[i : i + 3], f[i : i + 3]) for i in range(len(f) - 2))
    return Assessment(tuple(relative_changes(f)), orders, judge(f[-2], f[-1], limit))
