"""Layered quad strips with conforming coarsening rows.

A strip is a stack of node *levels* (curves across the body: circles in a ring, the
raceway and the parallel curves behind it). Every level is a list of positions ``u`` along
the curve; the level curve ``point(k, u)`` places them in the plane. Between two levels lies
a *row* of quads. A plain row joins equal node lists one to one; a coarsening row joins a
fine level to a coarser one with conforming templates (no hanging nodes):

- ``1``: one fine cell to one coarse cell (a plain quad);
- ``2``: four fine cells to two coarse cells (6 quads, 3 interior nodes);
- ``3``: three fine cells to one coarse cell (4 quads, 2 interior nodes).

A quad mesh's boundary always has an even number of edges, so two fine cells cannot
become one coarse cell on their own: the ``2`` template works on pairs. Coarse nodes start
at the positions of the fine nodes they keep; positions that must stay nodes (arc
breakpoints such as the spall edges) survive every coarsening, and the coarse nodes between
them can be re-spaced evenly.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

# (fine cells, coarse cells) of each template.
TEMPLATE_SPAN = {1: (1, 1), 2: (4, 2), 3: (3, 1)}
# Height of a template's interior nodes as a fraction of the row height.
_INTERIOR_HEIGHT = 0.5


@dataclass
class Strip:
    """A meshed strip: nodes, counter-clockwise quads and the node ids of every level."""

    nodes: np.ndarray
    elements: np.ndarray
    levels: list[np.ndarray]
    level_u: list[np.ndarray]
    row_of_element: np.ndarray


def plan_arc(n_fine: int, n_coarse: int) -> list[int]:
    """Templates that turn ``n_fine`` cells of one arc into ``n_coarse`` cells.

    Parameters
    ----------
    n_fine, n_coarse : int
        Cell counts; ``n_fine - n_coarse`` must be even and ``n_fine / 3 <= n_coarse``.

    Returns
    -------
    list of int
        Template kinds (1, 2 or 3) in order along the arc, spread evenly.
    """
    if n_coarse > n_fine or 3 * n_coarse < n_fine or (n_fine - n_coarse) % 2:
        raise ValueError(f"cannot coarsen {n_fine} cells to {n_coarse} with quad templates")
    if 2 * n_coarse >= n_fine:  # ratio up to 2: pairs (2) and plain cells (1)
        counts = {2: (n_fine - n_coarse) // 2, 1: 2 * n_coarse - n_fine, 3: 0}
    else:  # ratio between 2 and 3: pairs (2) and triples (3)
        counts = {3: n_fine - 2 * n_coarse, 2: (3 * n_coarse - n_fine) // 2, 1: 0}
    # Spread each kind evenly: place kind k's i-th template at (i + 1/2) / count_k.
    keyed = []
    for kind, count in counts.items():
        keyed += [((i + 0.5) / count, kind) for i in range(count)]
    return [kind for _, kind in sorted(keyed)]


def coarse_count(n_fine: int, ratio: float) -> int:
    """The coarse cell count nearest ``n_fine / ratio`` that a template row can reach."""
    target = max(1.0, n_fine / ratio)
    lo = max(1, -(-n_fine // 3))
    best = None
    for n in range(lo, n_fine + 1):
        # Ties go to the finer count: plain cells shape better than 3:1 templates.
        if (n_fine - n) % 2 == 0 and (best is None or abs(n - target) <= abs(best - target)):
            best = n
    if best is None:
        raise ValueError(f"no coarser count for {n_fine} cells")
    return best


def plan_row(arc_cells: Sequence[int], ratio: float) -> tuple[list[int], list[int]]:
    """Templates for a whole level split into arcs between breakpoints.

    Returns the template list (all arcs in order) and the coarse cell count of each arc.
    """
    plan: list[int] = []
    coarse = []
    for n in arc_cells:
        nc = coarse_count(n, ratio) if ratio > 1 else n
        plan += plan_arc(n, nc)
        coarse.append(nc)
    return plan, coarse


def build_strip(
    u0: np.ndarray,
    row_plans: Sequence[Sequence[int] | None],
    point: Callable[[float, np.ndarray], np.ndarray],
    periodic: bool,
    breaks: np.ndarray | None = None,
    period: float | None = None,
) -> Strip:
    """Mesh a stack of levels joined by plain or coarsening rows.

    Parameters
    ----------
    u0 : ndarray
        Positions of the first level's nodes along the level curves, increasing.
    row_plans : sequence
        One entry per row: ``None`` for a plain row, else the template kinds covering the
        row's fine level cell by cell (see :func:`plan_row`).
    point : callable
        ``point(v, u) -> (n, 2)`` positions; ``v`` is the level number, fractional inside
        a row (``k + 0.5`` is halfway between levels ``k`` and ``k + 1``).
    periodic : bool
        Whether the levels are closed curves (the last cell joins the last node to the
        first).
    breaks : ndarray, optional
        Positions that are nodes on every level (arc ends). When given, each coarsened
        level is re-spaced evenly between them, so that plain cells left in a coarsening
        row do not stay as narrow columns up the strip.
    period : float, optional
        Length of ``u`` over one turn of a periodic strip (needed with ``breaks``).

    Returns
    -------
    Strip
        Elements counter-clockwise whatever the orientation of ``point``.
    """
    from taichi_bearing.mesh.grid import orient_ccw

    u = np.asarray(u0, dtype=float)
    pts = [point(0.0, u)]
    n_nodes = len(u)
    levels = [np.arange(n_nodes)]
    level_u = [u]
    elements = []
    rows = []
    for k, plan in enumerate(row_plans):
        fine = levels[-1]
        n_cells = len(u) if periodic else len(u) - 1
        if plan is None:
            plan = [1] * n_cells
        kept, quads, interior_u = _row_topology(list(plan), n_cells, periodic)
        u_coarse = u[kept]
        u_interior = u[np.asarray(interior_u, dtype=np.int64)]
        if breaks is not None and len(kept) != len(u):
            u_coarse = respace(u_coarse, breaks, period if periodic else None)
            # Interior nodes sit halfway up the row: move them half as far as the coarse
            # nodes around them moved.
            shift = _interpolate_by_index(kept, u_coarse - u[kept], len(u), periodic)
            u_interior = u_interior + 0.5 * shift[np.asarray(interior_u, dtype=np.int64)]
        coarse = n_nodes + np.arange(len(u_coarse))
        interior = n_nodes + len(u_coarse) + np.arange(len(interior_u))
        pts.append(point(float(k + 1), u_coarse))
        if len(interior_u):
            pts.append(point(k + _INTERIOR_HEIGHT, u_interior))
        n_nodes += len(u_coarse) + len(interior_u)
        # Local ids: ("f", i) fine index, ("c", i) coarse index, ("m", i) interior index.
        lookup = {"f": fine, "c": coarse, "m": interior}
        for quad in quads:
            elements.append([lookup[kind][i] for kind, i in quad])
            rows.append(k)
        levels.append(coarse)
        level_u.append(u_coarse)
        u = u_coarse
    nodes = np.concatenate(pts)
    elements = orient_ccw(nodes, np.asarray(elements, dtype=np.int64))
    return Strip(nodes, elements, levels, level_u, np.asarray(rows, dtype=np.int64))


def _row_topology(plan: list[int], n_cells: int, periodic: bool):
    """Kept fine indices, quads as (kind, index) tuples, and interior nodes' fine indices."""
    covered = sum(TEMPLATE_SPAN[kind][0] for kind in plan)
    if covered != n_cells:
        raise ValueError(f"row plan covers {covered} cells, the level has {n_cells}")
    n_fine_nodes = n_cells if periodic else n_cells + 1
    kept = []
    starts = []
    i = 0
    for kind in plan:
        starts.append(i)
        kept.append(i)
        if kind == 2:
            kept.append(i + 2)
        i += TEMPLATE_SPAN[kind][0]
    if not periodic:
        kept.append(n_cells)
    coarse_of = {f: c for c, f in enumerate(kept)}

    def f(j):
        return ("f", j % n_fine_nodes)

    def c(j):  # coarse node at fine index j
        return ("c", coarse_of[j % n_fine_nodes if periodic else j])

    quads = []
    interior_u = []
    for kind, i in zip(plan, starts, strict=True):
        if kind == 1:
            quads.append((f(i), f(i + 1), c(i + 1), c(i)))
            continue
        m0 = ("m", len(interior_u))
        m1 = ("m", len(interior_u) + 1)
        if kind == 3:
            interior_u += [(i + 1) % n_fine_nodes, (i + 2) % n_fine_nodes]
            quads += [
                (f(i), f(i + 1), m0, c(i)),
                (f(i + 1), f(i + 2), m1, m0),
                (f(i + 2), f(i + 3), c(i + 3), m1),
                (m0, m1, c(i + 3), c(i)),
            ]
        else:
            m2 = ("m", len(interior_u) + 2)
            interior_u += [(i + j) % n_fine_nodes for j in (1, 2, 3)]
            quads += [
                (f(i), f(i + 1), m0, c(i)),
                (f(i + 1), f(i + 2), m1, m0),
                (f(i + 2), f(i + 3), m2, m1),
                (f(i + 3), f(i + 4), c(i + 4), m2),
                (m0, m1, c(i + 2), c(i)),
                (m1, m2, c(i + 4), c(i + 2)),
            ]
    return np.asarray(kept, dtype=np.int64), quads, interior_u


def respace(u: np.ndarray, breaks: np.ndarray, period: float | None) -> np.ndarray:
    """Positions ``u`` moved to even spacing between consecutive ``breaks`` (which are
    themselves among ``u``); the count in every arc is kept."""
    u = np.asarray(u, dtype=float)
    idx = sorted({int(np.argmin(np.abs(_wrap(u - b, period)))) for b in np.atleast_1d(breaks)})
    out = u.copy()
    if period is not None:
        idx.append(idx[0] + len(u))
    for i, j in zip(idx[:-1], idx[1:], strict=True):
        a = u[i]
        b = u[j % len(u)] + (period if (period is not None and j >= len(u)) else 0.0)
        k = np.arange(i, j)
        out[k % len(u)] = a + (b - a) * (k - i) / (j - i)
    return out


def _interpolate_by_index(
    kept: np.ndarray, values: np.ndarray, n: int, periodic: bool
) -> np.ndarray:
    """Values known at fine indices ``kept`` interpolated linearly to every fine index."""
    x = np.asarray(kept, dtype=float)
    if periodic:
        x = np.concatenate([x - n, x, x + n])
        values = np.concatenate([values, values, values])
    return np.interp(np.arange(n, dtype=float), x, values)


def _wrap(d: np.ndarray, period: float | None) -> np.ndarray:
    if period is None:
        return d
    return np.mod(d + 0.5 * period, period) - 0.5 * period


def between_levels(level_point: Callable[[int, np.ndarray], np.ndarray]):
    """A ``point(v, u)`` for :func:`build_strip` that places fractional levels on the
    straight line between the two neighbouring whole levels at the same ``u``."""

    def point(v: float, u: np.ndarray) -> np.ndarray:
        k = int(np.floor(v))
        t = v - k
        p = level_point(k, u)
        return p if t == 0 else (1 - t) * p + t * level_point(k + 1, u)

    return point
