"""The whole bearing: outer ring with adapter, inner ring and rollers, as one :class:`Mesh`.

Parts (in this order): ``outer_ring`` (the ring and the adapter on top of it, one body with
shared nodes), ``inner_ring``, ``roller0`` ... ``roller{Z-1}`` (roller 0 at the first
roller angle, numbered counter-clockwise). Separable bodies share no nodes. The cage is
rigid: only its geometry is recorded, in ``mesh.info["cage"]``.
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.mesh.adapter import adapter_corner_angles, adapter_mesh
from taichi_bearing.mesh.grid import boundary_segments, chain_segments, merge_nodes, orient_ccw
from taichi_bearing.mesh.profile_ring import ProfileMap, profile_map, profile_ring_mesh
from taichi_bearing.mesh.rings import TWO_PI, Notch, RingMesh, ring_mesh
from taichi_bearing.mesh.rollers import roller_mesh
from taichi_bearing.mesh.spec import BearingMeshSpec, polar_from_top
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.mesh.zone import refined_ring_mesh

TOP = math.pi / 2  # 12 o'clock, from +x


def build_bearing_mesh(spec: BearingMeshSpec) -> Mesh:
    """Mesh the bearing described by ``spec``.

    Returns
    -------
    Mesh
        With surfaces ``outer_raceway`` (including the spall's walls and floor),
        ``inner_raceway`` and ``roller{j}``; node sets ``inner_bore`` and ``adapter_top``;
        the spec's sensor nodes; and ``info`` holding polygon edge counts, roller centres,
        the spall's exact geometry and the cage geometry.
    """
    if not spec.adapter_width > 0:
        raise ValueError("adapter_width must be positive: the load is applied on the adapter")
    notch_outer = _notch(spec, "outer", spec.outer_raceway_radius)
    notch_inner = _notch(spec, "inner", spec.inner_raceway_radius)

    outer, adapter_top = _outer_ring_with_adapter(spec, notch_outer)
    inner = _ring(
        notch_inner,
        spec.inner_raceway_radius,
        spec.inner_ring_thickness,
        False,
        _snap([TOP], notch_inner, spec.inner_raceway_radius, spec.surface_size),
        spec.surface_size,
        spec.max_size,
        spec.growth,
        zone=_zone(spec),
    )
    bodies = [
        ("outer_ring", outer.nodes, outer.elements),
        ("inner_ring", inner.nodes, inner.elements),
    ]
    centres = []
    sizes = spec.roller_sizes()
    for j, angle in enumerate(spec.roller_angles()):
        centre = (spec.pitch_radius * math.cos(angle), spec.pitch_radius * math.sin(angle))
        nodes, elements, _ = roller_mesh(
            spec.roller_radius, sizes[j], spec.max_size, spec.growth, centre
        )
        bodies.append((f"roller{j}", nodes, elements))
        centres.append(centre)

    offsets = np.cumsum([0] + [len(n) for _, n, _ in bodies])
    mesh = Mesh(
        nodes=np.concatenate([n for _, n, _ in bodies]),
        elements=np.concatenate([e + off for (_, _, e), off in zip(bodies, offsets, strict=False)]),
        element_part=np.concatenate(
            [np.full(len(e), p, dtype=np.int64) for p, (_, _, e) in enumerate(bodies)]
        ),
        part_names=[name for name, _, _ in bodies],
    )
    d_out = notch_outer.depth if notch_outer else 0.0
    d_in = notch_inner.depth if notch_inner else 0.0
    r_out, r_in = spec.outer_raceway_radius, spec.inner_raceway_radius
    tol = 1e-9 * r_out
    mesh.surfaces["outer_raceway"] = _body_surface(mesh, 0, lambda r: r <= r_out + d_out + tol)
    mesh.surfaces["inner_raceway"] = _body_surface(mesh, 1, lambda r: r >= r_in - d_in - tol)
    for j in range(spec.n_rollers):
        mesh.surfaces[f"roller{j}"] = _body_surface(mesh, 2 + j, None)
    mesh.node_sets["inner_bore"] = inner.back_ids + offsets[1]
    mesh.node_sets["adapter_top"] = adapter_top
    mesh.sensor_nodes = {
        name: int(np.argmin(np.hypot(*(mesh.nodes - np.asarray(xy, dtype=float)).T)))
        for name, xy in spec.sensors.items()
    }
    mesh.info = _info(spec, mesh, centres, outer, inner, notch_outer, notch_inner, offsets)
    return mesh


def _notch(spec: BearingMeshSpec, race: str, radius: float) -> Notch | ProfileMap | None:
    """The rectangular notch (sharp radial walls), or the raceway level that follows a
    profile with sloped or rounded edges."""
    if not spec.has_defect or spec.defect_race != race:
        return None
    profile = spec.spall_profile()
    if not profile.rectangular:
        thickness = spec.outer_ring_thickness if race == "outer" else spec.inner_ring_thickness
        return profile_map(profile, thickness, spec.surface_size, spec.growth, spec.max_size)
    span = spec.defect_length / radius
    start = polar_from_top(spec.defect_angle) - 0.5 * span
    return Notch(start=start, span=span, depth=spec.defect_depth)


def _zone(spec: BearingMeshSpec) -> tuple[float, float] | None:
    """The fine size and zone of the raceway round the spall, None when uniform."""
    return (spec.spall_size, spec.spall_zone) if spec.refined_spall else None


def _ring(
    notch: Notch | ProfileMap | None, *args, zone: tuple[float, float] | None = None
) -> RingMesh:
    """:func:`ring_mesh`, or :func:`profile_ring_mesh` for a profiled spall; with a
    ``zone`` (fine size, arc beyond the spall's edges) and a spall,
    :func:`~taichi_bearing.mesh.zone.refined_ring_mesh`."""
    if zone is not None and notch is not None:
        spall = notch.profile if isinstance(notch, ProfileMap) else notch
        return refined_ring_mesh(*args, spall, *zone)
    if isinstance(notch, ProfileMap):
        return profile_ring_mesh(*args, notch)
    return ring_mesh(*args, notch)


def _snap(
    angles: list[float], notch: Notch | ProfileMap | None, radius: float, size: float
) -> list[float]:
    """Breakpoint angles with any that lies within half a cell of a spall edge moved onto
    that edge (the spall edges themselves are added by the ring mesher; a profiled
    spall's fixed points are its window's ends and the ends of its pieces)."""
    if notch is None:
        return list(angles)
    if isinstance(notch, ProfileMap):
        edges = notch.fixed_u
    else:
        edges = np.array([notch.start, notch.start + notch.span])
    out = []
    for a in angles:
        gap = np.abs(np.mod(a - edges + math.pi, TWO_PI) - math.pi)
        k = int(np.argmin(gap))
        out.append(float(edges[k]) if radius * gap[k] < 0.5 * size else a)
    return out


def _outer_ring_with_adapter(
    spec: BearingMeshSpec, notch: Notch | ProfileMap | None
) -> tuple[RingMesh, np.ndarray]:
    """The outer ring and the adapter merged into one body, and the adapter top's nodes."""
    corners = adapter_corner_angles(spec.outer_ring_outer_radius, spec.adapter_width)
    # A corner closer to a spall edge than half a cell moves onto it (the adapter is then
    # that little narrower or wider): two breakpoints that close would make a sliver.
    corners = _snap(list(corners), notch, spec.outer_raceway_radius, spec.surface_size)
    corners = [float(np.mod(a, TWO_PI)) for a in corners]
    ring = _ring(
        notch,
        spec.outer_raceway_radius,
        spec.outer_ring_thickness,
        True,
        _snap([TOP, *corners], notch, spec.outer_raceway_radius, spec.surface_size),
        spec.surface_size,
        spec.max_size,
        spec.growth,
        zone=_zone(spec),
    )
    theta = np.mod(ring.back_theta, TWO_PI)
    eps = 1e-9
    under = (theta >= corners[0] - eps) & (theta <= corners[1] + eps)
    ids = ring.back_ids[under][np.argsort(-theta[under])]  # left corner to right corner
    a_nodes, a_elements, a_top = adapter_mesh(
        ring.nodes[ids], spec.adapter_top, spec.max_size, spec.surface_size
    )
    n_ring = len(ring.nodes)
    nodes = np.concatenate([ring.nodes, a_nodes])
    elements = np.concatenate([ring.elements, a_elements + n_ring])
    nodes, elements, new_index = merge_nodes(nodes, elements, tol=1e-9 * spec.adapter_top)
    ring.nodes = nodes
    ring.elements = orient_ccw(nodes, elements)
    ring.back_ids = new_index[ring.back_ids]
    return ring, new_index[a_top + n_ring]


def _body_surface(mesh: Mesh, part: int, on_radius) -> np.ndarray:
    """The closed boundary loop of one body, optionally only the segments whose two end
    nodes' radii (about the origin) satisfy ``on_radius``."""
    seg = boundary_segments(mesh.elements[mesh.element_part == part])
    if on_radius is not None:
        r = np.hypot(mesh.nodes[:, 0], mesh.nodes[:, 1])
        seg = seg[on_radius(r[seg[:, 0]]) & on_radius(r[seg[:, 1]])]
    chains = chain_segments(seg)
    if len(chains) != 1 or chains[0][-1, 1] != chains[0][0, 0]:
        raise RuntimeError(f"part {mesh.part_names[part]}: the surface is not one closed loop")
    return chains[0]


def _info(spec, mesh, centres, outer, inner, notch_outer, notch_inner, offsets) -> dict:
    walls = {"outer_raceway": 0, "inner_raceway": 0}
    spall = None
    for race, notch, ring, radius in (
        ("outer", notch_outer, outer, spec.outer_raceway_radius),
        ("inner", notch_inner, inner, spec.inner_raceway_radius),
    ):
        if notch is None:
            continue
        if isinstance(notch, ProfileMap):
            walls[f"{race}_raceway"] = ring.info["wall_segments"]
            spall = _profile_info(race, notch, ring, offsets[0 if race == "outer" else 1])
            continue
        walls[f"{race}_raceway"] = 2 * ring.n_thin
        spall = _spall_info(mesh, race, notch, radius, ring.n_thin)
    polygon = {
        name: int(len(mesh.surfaces[name]) - walls[name])
        for name in ("outer_raceway", "inner_raceway")
    }
    for j in range(spec.n_rollers):
        polygon[f"roller{j}"] = int(len(mesh.surfaces[f"roller{j}"]))
    angles = spec.roller_angles()
    zone = outer.info.get("zone") or inner.info.get("zone")
    return {
        "polygon_edges": polygon,
        "polygon_edges_note": (
            "facets a rolling contact crosses per turn of each surface (raceways: without "
            "the spall walls)"
        ),
        "raceway_radii": {
            "outer": spec.outer_raceway_radius,
            "inner": spec.inner_raceway_radius,
        },
        "inner_bore_radius": spec.inner_ring_bore_radius,
        "outer_ring_outer_radius": spec.outer_ring_outer_radius,
        "roller_radius": spec.roller_radius,
        "roller_centres": np.asarray(centres),
        "roller_angles": np.asarray(angles),
        "pitch_radius": spec.pitch_radius,
        "adapter": {
            # As meshed: differs from the spec only when a corner was moved onto a
            # spall edge less than half a cell away.
            "width": float(np.ptp(mesh.nodes[mesh.node_sets["adapter_top"], 0])),
            "height": spec.adapter_height,
            "top_y": spec.adapter_top,
        },
        "sizes": {
            "surface_size": spec.surface_size,
            "max_size": spec.max_size,
            "growth": spec.growth,
            "elements_per_wavelength": spec.elements_per_wavelength,
            "spall_size": spec.spall_size if spec.refined_spall else spec.surface_size,
            "spall_zone": spec.spall_zone if spec.refined_spall else 0.0,
            "roller_surface_size": np.asarray(spec.roller_sizes()),
        },
        "fine_zone": zone,
        "spall": spall,
        "cage": {
            "model": "rigid",
            "pitch_radius": spec.pitch_radius,
            "pocket_angles": np.asarray(angles),
            "pocket_angles_from_top": np.asarray(angles) - TOP,
            "pocket_clearance": spec.cage_pocket_clearance,
            "pocket_half_width": spec.roller_radius + spec.cage_pocket_clearance,
            # A nominal ring between the rollers' inner and outer thirds.
            "inner_radius": spec.pitch_radius - spec.roller_radius / 1.5,
            "outer_radius": spec.pitch_radius + spec.roller_radius / 1.5,
        },
    }


def _spall_info(mesh: Mesh, race: str, notch: Notch, radius: float, n_thin: int) -> dict:
    """Exact spall geometry and its four corner nodes (edge, floor, floor, edge)."""
    sign = 1.0 if race == "outer" else -1.0
    floor = radius + sign * notch.depth
    end = notch.start + notch.span
    points = [
        (radius, notch.start),
        (floor, notch.start),
        (floor, end),
        (radius, end),
    ]
    corners = []
    for r, a in points:
        xy = np.array([r * math.cos(a), r * math.sin(a)])
        d = np.hypot(*(mesh.nodes - xy).T)
        k = int(np.argmin(d))
        if d[k] > 1e-9:
            raise RuntimeError(f"spall corner at r={r}, angle={a} is not a node")
        corners.append(k)
    centre = notch.start + 0.5 * notch.span
    return {
        "race": race,
        "start_angle": notch.start,
        "end_angle": end,
        "centre_angle": centre,
        "centre_angle_from_top": centre - TOP,
        "length": notch.span * radius,
        "depth": notch.depth,
        "raceway_radius": radius,
        "floor_radius": floor,
        "wall_layers": n_thin,
        "corner_nodes": np.asarray(corners),
    }


def _profile_info(race: str, pmap: ProfileMap, ring: RingMesh, offset: int) -> dict:
    """The spall's geometry as for a rectangular notch, with its slopes and edge
    radius, and the nodes at its corners (the walls' feet, and the edges when sharp) as
    ``corner_nodes``, in order of angle."""
    p = pmap.profile
    centre = 0.5 * (p.start + p.end)
    floor = p.floor_angles
    return {
        "race": race,
        "start_angle": p.start,
        "end_angle": p.end,
        "centre_angle": centre,
        "centre_angle_from_top": centre - TOP,
        "length": p.length,
        "depth": p.depth,
        "raceway_radius": p.raceway_radius,
        "floor_radius": p.floor_radius,
        "floor_start_angle": floor[0],
        "floor_end_angle": floor[1],
        "start_slope": p.start_slope,
        "end_slope": p.end_slope,
        "edge_radius": p.edge_radius,
        "wall_layers": ring.info["profile_levels"],
        "corner_nodes": np.asarray(ring.info["corner_nodes"]) + offset,
    }
