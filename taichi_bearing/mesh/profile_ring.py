r"""A ring whose raceway follows a spall profile with sloped or rounded edges.

The rectangular notch (:mod:`taichi_bearing.mesh.rings`) is cut out of thin layers and
its walls are columns of nodes. A sloped wall is not a column: here the raceway level
itself follows the profile (:class:`~taichi_bearing.geometry.spall_profile.SpallProfile`),
node by node along its arc length, and the levels below it close up onto the ring's
ordinary level :math:`m` (the first one at least half a surface element below the floor).

Every node of the profile has an *anchor*, the angle :math:`u` at which its column meets
level :math:`m`, and level :math:`k \le m` lies at
:math:`P(u) + (Q_m(u) - P(u)) D_k / D_m` (:math:`P`: the profile point, :math:`Q_m`: the
point of level :math:`m`, :math:`D_k`: the ordinary level depths).
Within a window round the spall the anchor lags behind the profile where it goes down a
wall and runs ahead where it comes up the other one: the columns then lean into the
material, so a steep (even radial) wall and the concave corner at its foot make convex
elements, and the anchors stay about one surface element apart. Outside the window the
ring is the ordinary graded ring. No element is removed: the walls and the floor are the
raceway level, so their positions are exact by construction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from taichi_bearing.geometry.spall_profile import SpallProfile, unit
from taichi_bearing.mesh.grid import merge_nodes
from taichi_bearing.mesh.layers import graded_layers
from taichi_bearing.mesh.rings import TWO_PI, RingMesh, _arc_cells, plan_rows, raceway_positions
from taichi_bearing.mesh.strip import between_levels, build_strip

__all__ = ["ProfileMap", "profile_map", "profile_ring_mesh"]

# How far the column at the foot of a radial wall leans (as a share of the layer under
# the floor): 0.8 leans it about 40 degrees, which keeps the wall's elements convex.
LEAN = 0.8


def _polar(point: np.ndarray) -> float:
    return math.atan2(point[1], point[0])


def _near(angle: float, reference: float) -> float:
    """``angle`` moved by whole turns to within half a turn of ``reference``."""
    return reference + (angle - reference + math.pi) % TWO_PI - math.pi


@dataclass(frozen=True)
class ProfileMap:
    """The raceway level of a ring with a profiled spall: arc length ``s`` along the
    profile from the window's start, the surface point at each ``s``, and the anchor
    angle ``u(s)`` (piecewise linear through ``s_key``, ``u_key``).

    ``layers``, ``depths``: the ordinary layers' thicknesses and level depths (level 0 =
    0); ``m``: the level the profile's
    columns close onto; ``s_pieces``: arc length at the start of every piece of the
    profile and at the end of the last; ``window``: anchor angles of the window's ends
    (``s = 0`` and ``s = s_end``); ``size``: the surface element size.
    """

    profile: SpallProfile
    layers: np.ndarray
    depths: np.ndarray
    m: int
    s_key: np.ndarray
    u_key: np.ndarray
    s_pieces: np.ndarray
    window: tuple[float, float]
    size: float

    @property
    def depth(self) -> float:
        return self.profile.depth

    @property
    def s_corners(self) -> np.ndarray:
        """Arc lengths of the profile's corners: the floor's ends and any sharp edge
        (a rounded edge's fillet joins the raceway and the wall smoothly)."""
        f = self.profile.floor_index
        out = [self.s_pieces[f], self.s_pieces[f + 1]]
        if self.profile.edge_radius == 0.0:
            out += [self.s_pieces[0], self.s_pieces[-1]]
        return np.unique(out)

    @property
    def s_fixed(self) -> np.ndarray:
        """Arc lengths that must be nodes: the window's ends and the corners."""
        return np.unique(np.concatenate([[0.0, self.s_key[-1]], self.s_corners]))

    @property
    def fixed_u(self) -> np.ndarray:
        """Anchor angles of the points that must be nodes."""
        return self.u_of(self.s_fixed)

    def u_of(self, s) -> np.ndarray:
        return np.interp(s, self.s_key, self.u_key)

    def s_of(self, u) -> np.ndarray:
        return np.interp(u, self.u_key, self.s_key)

    def surface(self, s) -> np.ndarray:
        """Points of the raceway level at arc lengths ``s``, shape (n, 2)."""
        return _surface(self.profile, self.s_pieces, s)


def _surface(profile: SpallProfile, s_pieces: np.ndarray, s) -> np.ndarray:
    """Points at arc lengths ``s`` along the raceway (a circle of radius ``R`` before
    and after the profile) and the profile's pieces, which begin at ``s_pieces``."""
    s = np.atleast_1d(np.asarray(s, dtype=float))
    r = profile.raceway_radius
    pieces = profile.pieces
    out = np.empty((len(s), 2))
    before, after = s <= s_pieces[0], s >= s_pieces[-1]
    out[before] = r * unit(_polar(pieces[0].p0) - (s_pieces[0] - s[before]) / r)
    out[after] = r * unit(_polar(pieces[-1].p1) + (s[after] - s_pieces[-1]) / r)
    for k, piece in enumerate(pieces):
        on = ~before & ~after & (s >= s_pieces[k]) & (s <= s_pieces[k + 1])
        out[on] = piece.at((s[on] - s_pieces[k]) / piece.length)
    return out


def profile_map(
    profile: SpallProfile,
    thickness: float,
    size: float,
    growth: float,
    max_size: float,
    layers: np.ndarray | None = None,
) -> ProfileMap:
    """The raceway level of a ring of ``thickness`` (graded from ``size`` by ``growth``
    up to ``max_size``, or in the given ``layers``) with the spall ``profile``.

    Raises
    ------
    ValueError
        When the spall reaches too deep into the ring's layers, or its walls are too
        close together for the element size.
    """
    t = graded_layers(thickness, size, growth, max_size) if layers is None else layers
    depths = np.concatenate([[0.0], np.cumsum(t)])
    depths[-1] = thickness
    d, r = profile.depth, profile.raceway_radius
    below = np.flatnonzero(depths >= d + 0.5 * size)
    if not len(below) or below[0] >= len(depths) - 1:
        raise ValueError(
            f"the spall ({1e3 * d:.3g} mm deep) reaches the back of the ring's layers "
            f"({1e3 * thickness:.3g} mm)"
        )
    m = int(below[0])
    pieces, f = profile.pieces, profile.floor_index
    lengths = np.array([p.length for p in pieces])
    a_first = _polar(pieces[0].p0)
    a_last = _near(_polar(pieces[-1].p1), a_first + profile.length / r)
    # Each way down (or up) a wall: its length along the profile and its run along the
    # raceway. At the foot of the wall the column leans LEAN of the layer under the floor
    # (scaled by the slope: a shallow wall needs none); at its top the lag is that plus
    # the anchors' span over the way's run, the span being the way's length in whole
    # surface elements: the anchors go down the wall about one element apart, so a wall
    # shorter than an element still gets a whole element's width below it.
    runs = [r * (_near(_polar(pieces[f].p0), a_first) - a_first),
            r * (a_last - _near(_polar(pieces[f].p1), a_last))]  # fmt: skip
    ways = [lengths[:f].sum(), lengths[f + 1 :].sum()]
    slopes = [profile.start_slope, profile.end_slope]
    foot = [LEAN * (depths[m] - d) * math.sin(a) for a in slopes]
    spans = [size * max(1, round(w / size)) for w in ways]  # whole cells, at least one
    top = [span - run + lean for span, run, lean in zip(spans, runs, foot, strict=True)]
    margin = max(4.0 * size, 3.0 * max(top))
    s_pieces = margin + np.concatenate([[0.0], np.cumsum(lengths)])
    s_end = s_pieces[-1] + margin
    window = (a_first - margin / r, a_last + margin / r)
    s_floor = (s_pieces[f], s_pieces[f + 1])
    reach = min(margin, 0.5 * (s_floor[1] - s_floor[0]))  # where the lag is gone

    def anchor(s: float, lag: float) -> float:
        """The anchor ``lag`` (m, along the raceway) behind the profile point at ``s``."""
        return _near(_polar(_surface(profile, s_pieces, s)[0]), a_first) - lag / r

    keys = [
        (0.0, window[0]),
        (s_pieces[0], a_first - top[0] / r),
        (s_floor[0], anchor(s_floor[0], foot[0])),
        (s_floor[0] + reach, anchor(s_floor[0] + reach, 0.0)),
        (s_floor[1] - reach, anchor(s_floor[1] - reach, 0.0)),
        (s_floor[1], anchor(s_floor[1], -foot[1])),
        (s_pieces[-1], a_last + top[1] / r),
        (s_end, window[1]),
    ]
    s_key, u_key = [], []
    for s, u in keys:
        if s_key and s <= s_key[-1] * (1 + 1e-14):
            continue  # a short floor: the two middle keys coincide
        s_key.append(s)
        u_key.append(u)
    if not np.all(np.diff(u_key) > 0):
        raise ValueError("the spall's walls are too close together for this element size")
    return ProfileMap(profile, t, depths, m, np.array(s_key), np.array(u_key), s_pieces,
                      window, size)  # fmt: skip


def _cells(lengths: np.ndarray, size: float, multiple: int) -> np.ndarray:
    """Cells of about ``size`` in each of consecutive intervals, at least one each, their
    sum a multiple of ``multiple`` (so that an arc coarsens into whole cells rather than
    into one wide one when its count is odd). The count changes in the interval of most
    cells (a floor or a raceway), where each cell changes least."""
    n = np.maximum(1, np.round(lengths / size)).astype(int)
    k = int(np.argmax(n))
    n[k] = max(1, n[k] + max(multiple, multiple * round(n.sum() / multiple)) - n.sum())
    return n


def _window_positions(
    pmap: ProfileMap, breakpoints: list[float], multiple: int
) -> tuple[np.ndarray, list]:
    """Anchor angles of the raceway level's nodes over one turn (increasing, starting at
    the window), and every breakpoint as it lies among them. Each arc of the window
    between breakpoints gets a multiple of ``multiple`` cells."""
    u0, u1 = pmap.window
    span = u1 - u0
    inside, outside = [], []
    for b in breakpoints:
        rel = (b - u0) % TWO_PI
        (inside if 0.0 < rel < span else outside).append(u0 + rel)
    rest = raceway_positions(pmap.profile.raceway_radius, [*outside, u0, u1], pmap.size)
    rest = u0 + (rest - u0) % TWO_PI
    rest = np.sort(rest[(rest >= u1 - 1e-12 * span)])  # the ordinary ring after the window
    # nodes of the window: the fixed points, each inside breakpoint, evenly between
    s_breaks = np.unique(np.concatenate([[0.0, pmap.s_key[-1]], pmap.s_of(np.array(inside))]))
    s_fixed = np.unique(np.concatenate([pmap.s_fixed, s_breaks]))
    s_nodes = []
    for lo, hi in zip(s_breaks[:-1], s_breaks[1:], strict=True):
        ends = s_fixed[(s_fixed >= lo) & (s_fixed <= hi)]
        for a, b, n in zip(ends[:-1], ends[1:], _cells(np.diff(ends), pmap.size, multiple),
                           strict=True):  # fmt: skip
            s_nodes.append(a + (b - a) * np.arange(n) / n)
    u_window = pmap.u_of(np.concatenate(s_nodes))
    u_window[0] = u0
    return np.concatenate([u_window, rest]), [*outside, u0, u1, *inside]


def profile_ring_mesh(
    raceway_radius: float,
    thickness: float,
    outward: bool,
    breakpoints: list[float],
    size: float,
    max_size: float,
    growth: float,
    pmap: ProfileMap,
) -> RingMesh:
    """Mesh a ring graded from its raceway, the raceway following ``pmap``'s spall
    profile (arguments as :func:`taichi_bearing.mesh.rings.ring_mesh`)."""
    sign = 1.0 if outward else -1.0
    depths, m = pmap.depths, pmap.m
    # how much the rows coarsen does not depend on the cell counts: find it first
    ratios, _ = plan_rows([1], pmap.layers, depths, raceway_radius, sign, size, max_size, m + 1)
    multiple = 2 ** ratios.count(2.0)
    theta0, breaks = _window_positions(pmap, list(breakpoints), multiple)
    arcs = _arc_cells(theta0, breaks)
    ratios, plans = plan_rows(arcs, pmap.layers, depths, raceway_radius, sign, size, max_size,
                              m + 1)  # fmt: skip
    u0, u1 = pmap.window

    def level_point(k: int, theta: np.ndarray) -> np.ndarray:
        q = (raceway_radius + sign * depths[k]) * unit(theta)
        if k > m:
            return q
        rel = (theta - u0) % TWO_PI
        inside = rel < u1 - u0
        surface = raceway_radius * unit(theta)
        surface[inside] = pmap.surface(pmap.s_of(u0 + rel[inside]))
        q_m = (raceway_radius + sign * depths[m]) * unit(theta)
        return surface + (q_m - surface) * (depths[k] / depths[m])

    strip = build_strip(
        theta0,
        plans,
        between_levels(level_point),
        periodic=True,
        breaks=np.mod(np.asarray(breaks, dtype=float), TWO_PI),
        period=TWO_PI,
    )
    nodes, elements, new_index = merge_nodes(
        strip.nodes, strip.elements, tol=1e-12 * raceway_radius
    )
    surface_ids = new_index[strip.levels[0]]
    rel = (theta0 - u0) % TWO_PI
    s_nodes = np.where(rel < u1 - u0, pmap.s_of(u0 + rel), -1.0)
    fixed = [int(surface_ids[np.argmin(np.abs(s_nodes - s))]) for s in pmap.s_corners]
    # raceway cells on the walls (not the floor): the facets the polygon count leaves out
    f = pmap.profile.floor_index
    lo, hi = s_nodes[:-1], s_nodes[1:]
    on_profile = (lo >= pmap.s_pieces[0]) & (hi <= pmap.s_pieces[-1]) & (lo >= 0)
    on_floor = (lo >= pmap.s_pieces[f]) & (hi <= pmap.s_pieces[f + 1])
    walls = int(np.count_nonzero(on_profile & ~on_floor))
    return RingMesh(
        nodes=nodes,
        elements=elements,
        back_ids=new_index[strip.levels[-1]],
        back_theta=strip.level_u[-1],
        raceway_cells=len(theta0),
        level_depths=depths,
        n_thin=0,
        info={
            "coarsening_rows": [k for k, r in enumerate(ratios) if r > 1],
            "corner_nodes": fixed,
            "profile_levels": m,
            "wall_segments": walls,
        },
    )
