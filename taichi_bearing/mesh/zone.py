"""A ring whose raceway is finer round the spall: local refinement without hanging nodes.

The ring is put together from pieces that meet at one level of the ordinary ring, the
first deep enough (depth ``D``, level ``J`` of the ordinary layers) for the fine elements
to grow back to the surface size and for the spall to fit:

- the *fine zone*: the arc round the spall (the spall, its window and ``zone`` either
  side of its edges) as the ordinary ring mesher makes it at the fine size
  (:func:`~taichi_bearing.mesh.rings.ring_mesh`, or
  :func:`~taichi_bearing.mesh.profile_ring.profile_ring_mesh` for sloped or rounded
  edges) in a ring ``D`` thick: ``S`` layers grown from the fine size, rows coarsening as
  in any ring; only the zone is kept;
- the *band*: the ordinary ring's first ``J`` rows at the surface size, outside;
- two *transitions*, one at each end of the zone: along the raceway their elements grow
  from the fine size to the surface size by a constant ratio (at most ``growth``, at
  least :data:`MIN_RATIO` per element), and across it the zone's ``S`` layers merge into
  the band's ``J``: a strip on its side whose levels are columns, its rows joining a
  column of more cells to one of fewer with the same templates as the rings' coarsening
  rows (four cells to two, three to one);
- the *lower ring* below ``D``: the ordinary ring's remaining layers, each arc
  coarsening on its own, so the zone's narrower cells widen like the band's.

Neighbouring pieces share their border nodes (the zone's and the band's side columns,
the level at ``D``), so the whole is conforming.
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.geometry.spall_profile import SpallProfile, unit
from taichi_bearing.mesh.grid import boundary_segments, merge_nodes, orient_ccw
from taichi_bearing.mesh.layers import coarsening_rows, graded_layers, notch_depths
from taichi_bearing.mesh.profile_ring import profile_map, profile_ring_mesh
from taichi_bearing.mesh.rings import (
    TWO_PI,
    Notch,
    RingMesh,
    _arc_cells,
    plan_rows,
    ring_mesh,
)
from taichi_bearing.mesh.strip import between_levels, build_strip, coarse_count, plan_arc

__all__ = ["MIN_RATIO", "refined_ring_mesh"]

MIN_RATIO = 1.2
"""Smallest size ratio between neighbouring raceway elements in a transition: with a
growth ratio near 1 the transition would otherwise grow without end."""

# A layer of the fine zone split for parity leaves halves at least this many fine sizes
# thick: thinner ones would cut the time step.
_THINNEST = 1.5


def _wrap(angle):
    """Angles moved by whole turns into [-pi, pi)."""
    return np.mod(np.asarray(angle) + math.pi, TWO_PI) - math.pi


def _levels(layers: np.ndarray, thickness: float) -> np.ndarray:
    """Level depths from layer thicknesses, level 0 at 0, the last exactly ``thickness``
    (as the ring meshers compute them, so shared levels coincide to the bit)."""
    depths = np.concatenate([[0.0], np.cumsum(layers)])
    depths[-1] = thickness
    return depths


def _band(
    radius: float,
    sign: float,
    spall: Notch | SpallProfile,
    layers: np.ndarray,
    depths: np.ndarray,
    size: float,
    fine: float,
    growth: float,
    max_size: float,
) -> tuple[int, np.ndarray, float]:
    """The level ``J`` of the ordinary ring where the pieces meet: the shallowest at which
    the fine layers hold the spall and their elements widen (by the rings' rule) to at
    least half the band's width there (the lower ring's first row widens them the rest).
    Returns ``J``, the fine layers (:func:`_fine_layers`) and how many times the band's
    elements have doubled in width by ``J``.

    Raises
    ------
    ValueError
        When no level leaves room for the spall in the fine layers.
    """
    found = None
    for j in range(1, len(layers)):
        band = float(depths[j])
        coarse, _ = plan_rows([1], layers[:j], depths[: j + 1], radius, sign, size, max_size, 1)
        widening = 2.0 ** coarse.count(2.0)
        best = _fine_layers(radius, sign, spall, band, j, fine, growth, max_size)
        if best is None:
            continue  # the spall reaches below these layers
        found = (j, best[1], widening)
        if 2.0 * fine * 2.0 ** best[0] >= size * widening * (1.0 - 1e-9):
            break
    if found is None:
        raise ValueError("the spall is too deep for the ring's layers to refine round it")
    return found


def _fine_layers(
    radius: float,
    sign: float,
    spall: Notch | SpallProfile,
    band: float,
    j: int,
    fine: float,
    growth: float,
    max_size: float,
) -> tuple[int, np.ndarray] | None:
    """The fine zone's layers over ``band`` and how many times its elements double in
    width there; None when the spall does not fit. Their count must have the parity of
    ``j`` (a transition joins a column of ``S`` cells to one of ``J`` with templates that
    each drop an even number) and be at least ``j``: when the graded layers do not, one
    is split in two, the one that keeps the most widening and leaves the thickest layer
    (or layer down a notch's wall: the notch takes equal layers down to the first level
    at or below its floor).
    """
    options = [graded_layers(band, fine, growth, max_size)]
    while options and all(len(t) < j or (len(t) - j) % 2 for t in options):
        # halves much thinner than the fine size would cut the time step
        split = [_split(t, k) for t in options for k in range(len(t)) if t[k] >= _THINNEST * fine]
        options = list({tuple(t): t for t in split}.values())
    best = None
    for t in options:
        if len(t) < j or (len(t) - j) % 2:
            continue
        depths = _levels(t, band)
        thinnest = float(t.min())
        try:
            if isinstance(spall, SpallProfile):
                held = profile_map(spall, band, fine, growth, max_size, t).m + 1
            else:
                walls = notch_depths(depths, spall.depth)[1]
                held, thinnest = walls + 1, min(thinnest, spall.depth / walls)
        except ValueError:
            continue
        ratios, _ = plan_rows([1], t, depths, radius, sign, fine, max_size, held)
        key = (ratios.count(2.0), thinnest)
        if best is None or key > best[0]:
            best = (key, t)
    return None if best is None else (best[0][0], best[1])


def _split(layers: np.ndarray, k: int) -> np.ndarray:
    """The layers with layer ``k`` split into two halves."""
    half = 0.5 * layers[k]
    return np.concatenate([layers[:k], [half, layers[k] - half], layers[k + 1 :]])


def _transition_widths(fine: float, size: float, growth: float) -> np.ndarray:
    """Raceway element widths of a transition, from the first after the fine zone to the
    last (the surface size), growing by a constant ratio of at most ``growth``; an odd
    number of them, so that below the transition they can merge into one."""
    ratio = max(growth, MIN_RATIO)
    n = max(1, math.ceil(math.log(size / fine) / math.log(ratio) - 1e-9))
    n += 1 - n % 2
    return fine * (size / fine) ** (np.arange(1, n + 1) / n)


def _column_counts(n_fine: int, n_coarse: int, rows: int) -> list[int]:
    """Cell counts of the columns of a transition, from ``n_fine`` to ``n_coarse`` over
    ``rows`` rows: the merging is left to the last rows, the widest, each at most 3:1
    (every count has the parity of ``n_fine``)."""
    counts = [n_coarse]
    for _ in range(rows):
        n = min(n_fine, 3 * counts[-1])
        counts.append(n - (n - n_fine) % 2)
    if counts[-1] != n_fine:
        raise ValueError(f"cannot merge {n_fine} layers into {n_coarse} in {rows} columns")
    return counts[::-1]


# Templates of a row as groups of cells: a plain cell, three cells to one, four to two.
_GROUPS = {1: (1,), 3: (3,), 2: (2, 2)}


def _merge_plan(depths: np.ndarray, n_out: int, cost) -> list[int]:
    """The templates (1, 2 or 3) that merge the cells between ``depths`` into ``n_out``
    groups at least cost: ``cost(g, top, bottom)`` of group ``g`` spanning those depths
    (dynamic programming over the cells)."""
    n = len(depths) - 1
    best = {(0, 0): (0.0, [])}
    for i in range(n):
        for g in range(n_out):
            if (i, g) not in best:
                continue
            total, plan = best[(i, g)]
            for kind, sizes in _GROUPS.items():
                k, c, extra = i, g, 0.0
                for size in sizes:
                    if k + size > n or c >= n_out:
                        break
                    extra += cost(c, depths[k], depths[k + size])
                    k, c = k + size, c + 1
                else:
                    if (k, c) not in best or total + extra < best[(k, c)][0]:
                        best[(k, c)] = (total + extra, [*plan, kind])
    if (n, n_out) not in best:
        raise ValueError(f"no template row merges {n} cells into {n_out}")
    return best[(n, n_out)][1]


def _transition(
    radius: float,
    sign: float,
    top: np.ndarray,
    bottom: np.ndarray,
    fine_depths: np.ndarray,
    coarse_depths: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Mesh one transition: a strip whose levels are its columns, from the zone's side
    column to the band's. Column ``k`` runs from the raceway at angle ``top[k]`` to depth
    ``D`` at ``bottom[k]``. The first column holds the zone's level depths, the last the
    band's; in between, the nodes slide from the one to the other in proportion to the
    raceway covered, and the last (widest) rows merge cells with the strip templates,
    chosen so that the cells kept meet the band's levels nearest their own depth.

    Returns
    -------
    nodes, elements
        Counter-clockwise quads.
    """
    n_fine, n_coarse = len(fine_depths) - 1, len(coarse_depths) - 1
    rows = len(top) - 1
    counts = _column_counts(n_fine, n_coarse, rows)
    steps = np.abs(np.diff(top)) * radius
    u0 = np.arange(n_fine + 1, dtype=float)
    kept = u0.astype(int)
    plans: list[list[int] | None] = []
    for r in range(rows):
        if counts[r + 1] == counts[r]:
            plans.append(None)
            continue
        if counts[r + 1] == n_coarse:  # the last merge: meet the band's levels

            def cost(g, d0, d1, t=coarse_depths):
                return ((d1 - t[g + 1]) / (t[g + 1] - t[g])) ** 2
        else:  # before: groups about as tall as the row is wide

            def cost(g, d0, d1, w=steps[r]):
                return math.log((d1 - d0) / w) ** 2

        plans.append(_merge_plan(fine_depths[kept], counts[r + 1], cost))
        kept = kept[_kept_cells(plans[-1])]
    share = np.concatenate([[0.0], np.cumsum(steps)]) / steps.sum()
    columns = np.arange(rows + 1, dtype=float)
    depth = fine_depths[-1]

    def point(v: float, u: np.ndarray) -> np.ndarray:
        lam = np.interp(v, columns, share)
        d_f = np.interp(u, u0, fine_depths)
        d = d_f + lam * (np.interp(u, kept.astype(float), coarse_depths) - d_f)
        phi_top, phi_bottom = np.interp(v, columns, top), np.interp(v, columns, bottom)
        phi = phi_top + (phi_bottom - phi_top) * (d / depth)
        return (radius + sign * d)[:, None] * unit(phi)

    strip = build_strip(u0, plans, point, periodic=False)
    return strip.nodes, strip.elements


def _kept_cells(plan: list[int]) -> np.ndarray:
    """Indices of the nodes a row of ``plan`` keeps on its coarser side (both ends of an
    open column, the middle of each four-to-two template)."""
    kept, i = [0], 0
    for kind in plan:
        if kind == 2:
            kept.append(i + 2)
        i += {1: 1, 2: 4, 3: 3}[kind]
        kept.append(i)
    return np.asarray(kept)


def _zone_ends(
    lo: float,
    hi: float,
    margin: float,
    room: float,
    breakpoints: list[float],
    span: float,
    size: float,
    radius: float,
) -> tuple[float, float]:
    """The zone's ends: ``margin`` (rad) beyond ``lo`` and ``hi``, moved outwards past any
    breakpoint that would fall in a transition (``span`` rad) or within ``room`` (rad)
    of an end, to ``room`` beyond it. Below the band every arc between breakpoints
    coarsens on its own: a breakpoint a few fine elements from an end would leave an arc
    too few cells wide to coarsen, a column of slivers down to the back of the ring
    (aspect 15 at an adapter corner)."""
    a, b = lo - margin, hi + margin
    outside = span + size / radius
    for _ in range(len(breakpoints) + 1):
        moved = False
        for p in breakpoints:
            if -outside < _wrap(p - a) < room:
                a, moved = p - room, True
            if -room < _wrap(p - b) < outside:
                b, moved = p + room, True
        if not moved:
            break
    if b - a + 2 * span >= TWO_PI - 2 * size / radius:
        raise ValueError("the refined zone and its transitions cover the whole raceway")
    return a, b


def refined_ring_mesh(
    raceway_radius: float,
    thickness: float,
    outward: bool,
    breakpoints: list[float],
    size: float,
    max_size: float,
    growth: float,
    spall: Notch | SpallProfile,
    fine: float,
    zone: float,
) -> RingMesh:
    """Mesh a ring graded from its raceway, its raceway at element size ``fine`` round
    the spall (see the module notes).

    Parameters
    ----------
    raceway_radius, thickness, outward, breakpoints, size, max_size, growth
        As :func:`taichi_bearing.mesh.rings.ring_mesh`.
    spall : Notch or SpallProfile
        The rectangular notch, or the profile of a spall with sloped or rounded edges.
    fine : float
        Element size along the raceway in the zone, m (less than ``size``).
    zone : float
        Arc length of raceway beyond each edge of the spall meshed at ``fine``, m.

    Returns
    -------
    RingMesh
        ``info["zone"]``: the zone's ends and the transitions' outer ends (angles from
        +x), the fine size, the level ``J`` and depth ``D`` where the pieces meet.

    Raises
    ------
    ValueError
        When the ring is too thin for the fine layers, or the zone covers the raceway.
    """
    if not 0.0 < fine < size:
        raise ValueError(f"the zone's element size ({fine} m) must lie between 0 and {size} m")
    sign = 1.0 if outward else -1.0
    r = raceway_radius
    layers = graded_layers(thickness, size, growth, max_size)
    depths = _levels(layers, thickness)
    if len(layers) < 2:
        raise ValueError("the ring is too thin to refine: one element layer")
    profile = spall if isinstance(spall, SpallProfile) else None
    j, fine_layers, widening = _band(r, sign, spall, layers, depths, size, fine, growth, max_size)
    band = float(depths[j])
    fine_depths = _levels(fine_layers, band)

    widths = _transition_widths(fine, size, growth)
    span = float(widths.sum()) / r
    # room beyond the spall for two of the band's elements at depth D, so the zone's
    # elements there are as wide as the band's, not a narrow column down the ring
    room = 2.0 * size * widening * (r + sign * band) / r**2
    margin = max(zone / r, room)
    if profile is not None:
        pmap = profile_map(profile, band, fine, growth, max_size, fine_layers)
        # the window where the raceway follows the profile lies inside the zone
        # (differences wrapped: the window's angles are atan2's, in (-pi, pi])
        window = float(
            max(_wrap(profile.start - pmap.window[0]), _wrap(pmap.window[1] - profile.end))
        )
        margin = max(margin, window + fine / r)
        lo, hi = profile.start, profile.end
    else:
        lo, hi = spall.start, spall.start + spall.span
    a, b = _zone_ends(lo, hi, margin, room, breakpoints, span, size, r)
    t1, t2 = a - span, b + span

    # the fine zone: a thin ring at the fine size, of which the zone is kept
    fine_breaks = [*breakpoints, a, b]
    if profile is not None:
        thin = profile_ring_mesh(r, band, outward, fine_breaks, fine, max_size, growth, pmap)
    else:
        thin = ring_mesh(r, band, outward, fine_breaks, fine, max_size, growth, spall, fine_layers)
    # the band outside: the ordinary ring's first J rows
    outer = ring_mesh(
        r, band, outward, [*breakpoints, t1, t2], size, max_size, growth, None, layers[:j]
    )
    in_zone = _inside(thin.nodes, thin.elements, a, b)
    in_hole = _inside(outer.nodes, outer.elements, t1, t2)
    reach = np.concatenate([[0.0], np.cumsum(widths)]) / r
    even = np.linspace(0.0, span, len(widths) + 1)
    left = (a - reach, a - even)
    right = (b + reach, b + even)
    pieces = [
        (thin.nodes, thin.elements[in_zone]),
        (outer.nodes, outer.elements[~in_hole]),
        _transition(r, sign, *left, fine_depths, depths[: j + 1]),
        _transition(r, sign, *right, fine_depths, depths[: j + 1]),
    ]
    # the level at D, all round: the zone's and the band's bottoms and the transitions'
    bottom = np.concatenate(
        [
            _between(thin.back_theta, a, b),
            _between(outer.back_theta, t2, t1 + TWO_PI),
            left[1],
            right[1],
        ]
    )
    breaks = np.mod(np.array([*breakpoints, t1, a, b, t2]), TWO_PI)
    lower = _lower_ring(r, sign, bottom, breaks, layers[j:], depths[j:], max_size)
    pieces.append((lower.nodes, lower.elements))

    offsets = np.cumsum([0] + [len(n) for n, _ in pieces])
    nodes = np.concatenate([n for n, _ in pieces])
    elements = np.concatenate([e + o for (_, e), o in zip(pieces, offsets, strict=False)])
    nodes, elements, new_index = merge_nodes(nodes, elements, tol=1e-12 * r)
    elements = orient_ccw(nodes, elements)
    info = dict(thin.info)
    if "corner_nodes" in info:
        info["corner_nodes"] = [int(new_index[k]) for k in info["corner_nodes"]]
    info["zone"] = {
        "fine_size": fine,
        "zone_angles": (a, b),
        "transition_angles": (t1, t2),
        "band_level": j,
        "band_depth": band,
        "fine_layers": len(fine_layers),
    }
    return RingMesh(
        nodes=nodes,
        elements=elements,
        back_ids=new_index[lower.levels[-1] + offsets[-2]],
        back_theta=lower.level_u[-1],
        raceway_cells=len(boundary_segments(elements)) - len(lower.levels[-1]),
        level_depths=depths,
        n_thin=thin.n_thin,
        info=info,
    )


def _relative(theta: np.ndarray, start: float) -> np.ndarray:
    """Angles ``theta`` counted counter-clockwise from ``start``, in [0, 2 pi)."""
    return np.mod(np.asarray(theta) - start, TWO_PI)


def _inside(nodes: np.ndarray, elements: np.ndarray, start: float, end: float) -> np.ndarray:
    """Whether each element's centroid lies counter-clockwise between ``start`` and
    ``end`` (the ends are node columns, so no element straddles one)."""
    c = nodes[elements].mean(axis=1)
    return _relative(np.arctan2(c[:, 1], c[:, 0]), start) < _relative(end, start)


def _between(theta: np.ndarray, start: float, end: float) -> np.ndarray:
    """The angles of ``theta`` from ``start`` to ``end`` counter-clockwise, ends included
    (to a billionth of a radian)."""
    rel = _relative(theta, start)
    rel = np.where(rel > TWO_PI - 1e-9, 0.0, rel)
    return np.asarray(theta)[rel <= _relative(end, start) + 1e-9]


def _lower_ring(
    radius: float,
    sign: float,
    top: np.ndarray,
    breaks: np.ndarray,
    layers: np.ndarray,
    depths: np.ndarray,
    max_size: float,
):
    """The ring below the pieces: a periodic strip from the nodes at angles ``top`` (at
    depth ``depths[0]``) through ``layers``; each arc between ``breaks`` coarsens by the
    rings' rule from its own element width, so the zone's arcs widen like the rest."""
    u = np.sort(np.mod(top, TWO_PI))
    u = u[np.concatenate([[True], np.diff(u) > 1e-9])]
    if u[-1] - u[0] > TWO_PI - 1e-9:
        u = u[:-1]
    # start at a break, as the arcs' plans do
    first = int(np.argmin(np.abs(_wrap(u - np.min(breaks)))))
    u0 = np.concatenate([u[first:], u[:first] + TWO_PI])
    arcs = _arc_cells(u0, list(breaks))
    ends = np.cumsum([0, *arcs])
    top_radius = radius + sign * depths[0]
    mid = 0.5 * (depths[1:] + depths[:-1])
    scale = (radius + sign * mid) / top_radius
    u_closed = np.append(u0, u0[0] + TWO_PI)
    ratios = [
        coarsening_rows(layers, top_radius * (u_closed[e] - u_closed[s]) / n * scale, max_size, 0)
        for s, e, n in zip(ends[:-1], ends[1:], arcs, strict=True)
    ]
    plans, counts = [], list(arcs)
    for k in range(len(layers)):
        plan, before = [], sum(counts)
        for i, n in enumerate(counts):
            counts[i] = coarse_count(n, ratios[i][k]) if ratios[i][k] > 1 else n
            plan += plan_arc(n, counts[i])
        plans.append(plan if sum(counts) < before else None)

    def level_point(k: int, theta: np.ndarray) -> np.ndarray:
        return (radius + sign * depths[k]) * unit(theta)

    return build_strip(u0, plans, between_levels(level_point), True, breaks, TWO_PI)
