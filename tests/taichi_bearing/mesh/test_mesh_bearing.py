"""The bearing mesh: geometry against exact values, validity, surfaces and the spall."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
from taichi_bearing.mesh.grid import boundary_segments, signed_areas
from taichi_bearing.mesh.quality import element_geometry, jacobian_determinants, mesh_statistics
from taichi_bearing.mesh.rollers import roller_surface_cells
from taichi_bearing.mesh.spec import BearingMeshSpec, spec_from_case

SENSORS = {"adapter_top": (0.0, 0.156), "outer_ring_top": (0.0, 0.126)}


def coarse(**kw) -> BearingMeshSpec:
    """The default bearing at a coarse element size (fast)."""
    base = dict(surface_size=0.001, max_size=0.004, sensors=SENSORS)
    base.update(kw)
    return BearingMeshSpec(**base)


@pytest.fixture(scope="module")
def coarse_mesh():
    spec = coarse()
    return spec, build_bearing_mesh(spec)


def part_area(mesh, name):
    sel = mesh.element_part == mesh.part_id(name)
    return signed_areas(mesh.nodes, mesh.elements[sel]).sum()


def adapter_area(spec):
    """Area of the block between the ring's outside circle and the flat top."""
    r, a = spec.outer_ring_outer_radius, 0.5 * spec.adapter_width
    under = a * math.sqrt(r * r - a * a) + r * r * math.asin(a / r)
    return spec.adapter_width * spec.adapter_top - under


def notch_area(spec):
    r = spec.outer_raceway_radius
    return 0.5 * (spec.defect_length / r) * ((r + spec.defect_depth) ** 2 - r * r)


def test_part_areas_match_exact_geometry(coarse_mesh):
    spec, m = coarse_mesh
    ro, ri = spec.outer_raceway_radius, spec.inner_raceway_radius
    exact_outer = (
        math.pi * (spec.outer_ring_outer_radius**2 - ro**2) + adapter_area(spec) - notch_area(spec)
    )
    assert part_area(m, "outer_ring") == pytest.approx(exact_outer, rel=5e-3)
    exact_inner = math.pi * (ri**2 - spec.inner_ring_bore_radius**2)
    assert part_area(m, "inner_ring") == pytest.approx(exact_inner, rel=5e-3)
    disk = math.pi * spec.roller_radius**2
    for j in range(spec.n_rollers):
        assert part_area(m, f"roller{j}") == pytest.approx(disk, rel=5e-3)


def test_notch_removes_exactly_its_area():
    """The mesh with the spall lacks the notch's area compared with a healthy ring."""
    spec = coarse(n_rollers=8)
    healthy = build_bearing_mesh(coarse(n_rollers=8, defect_race="none"))
    removed = part_area(healthy, "outer_ring") - part_area(build_bearing_mesh(spec), "outer_ring")
    assert removed == pytest.approx(notch_area(spec), rel=2e-3)


def test_spall_edges_depth_and_corners_are_exact(coarse_mesh):
    spec, m = coarse_mesh
    s = m.info["spall"]
    r = spec.outer_raceway_radius
    half = 0.5 * spec.defect_length / r
    assert s["start_angle"] == pytest.approx(math.pi / 2 - half, abs=1e-15)
    assert s["end_angle"] == pytest.approx(math.pi / 2 + half, abs=1e-15)
    expected = [
        (r, s["start_angle"]),
        (r + spec.defect_depth, s["start_angle"]),
        (r + spec.defect_depth, s["end_angle"]),
        (r, s["end_angle"]),
    ]
    for node, (radius, angle) in zip(s["corner_nodes"], expected, strict=True):
        xy = m.nodes[node]
        assert np.hypot(*(xy - radius * np.array([math.cos(angle), math.sin(angle)]))) < 1e-9
    # The corners lie on the raceway surface, joined by the two walls.
    seg = {tuple(x) for x in m.surfaces["outer_raceway"]}
    c = s["corner_nodes"]
    assert (c[1], c[0]) in seg or (c[0], c[1]) in seg
    assert (c[2], c[3]) in seg or (c[3], c[2]) in seg
    # Nothing of the ring is left inside the notch.
    ring_nodes = np.unique(m.elements[m.element_part == 0])
    xy = m.nodes[ring_nodes]
    rr, th = np.hypot(*xy.T), np.arctan2(xy[:, 1], xy[:, 0])
    inside = (rr < r + spec.defect_depth - 1e-9) & (th > s["start_angle"] + 1e-9)
    inside &= th < s["end_angle"] - 1e-9
    assert not inside.any()
    # The floor is whole element layers deep: its nodes are all at the floor radius.
    floor = [n for a, b in m.surfaces["outer_raceway"] for n in (a, b)]
    fr = np.hypot(*m.nodes[floor].T)
    fth = np.arctan2(m.nodes[floor, 1], m.nodes[floor, 0])
    on_floor = (fth > s["start_angle"] + 1e-9) & (fth < s["end_angle"] - 1e-9)
    assert np.allclose(fr[on_floor], r + spec.defect_depth, atol=1e-12)
    assert on_floor.sum() >= 2 * (round(spec.defect_length / spec.surface_size) - 1)


def test_elements_valid_and_bodies_separate(coarse_mesh):
    spec, m = coarse_mesh
    det = jacobian_determinants(m.nodes, m.elements)
    assert det.min() > 0
    owners = []
    for p, name in enumerate(m.part_names):
        ids = np.unique(m.elements[m.element_part == p])
        owners.append(ids)
        rounded = np.round(m.nodes[ids] / 1e-10)
        assert len(np.unique(rounded, axis=0)) == len(ids), f"duplicate nodes in {name}"
    allids = np.concatenate(owners)
    assert len(allids) == len(np.unique(allids)) == m.n_nodes  # no shared or unused nodes
    assert m.part_names[:2] == ["outer_ring", "inner_ring"]
    assert m.part_names[2:] == [f"roller{j}" for j in range(spec.n_rollers)]


def test_no_hanging_nodes_free_edges_only_on_the_real_boundary(coarse_mesh):
    spec, m = coarse_mesh
    tol = 1e-9
    r = np.hypot(*m.nodes.T)
    # Outer ring: raceway (with the notch), outside circle, adapter sides and top.
    seg = boundary_segments(m.elements[m.element_part == 0])
    on = (
        (r <= spec.outer_raceway_radius + spec.defect_depth + tol)
        | (np.abs(r - spec.outer_ring_outer_radius) < tol)
        | (np.abs(np.abs(m.nodes[:, 0]) - 0.5 * spec.adapter_width) < tol)
        | (np.abs(m.nodes[:, 1] - spec.adapter_top) < tol)
    )
    assert on[seg].all()
    n_race = len(m.surfaces["outer_raceway"])
    # Inner ring: the raceway and the bore close the boundary exactly.
    seg = boundary_segments(m.elements[m.element_part == 1])
    assert len(seg) == len(m.surfaces["inner_raceway"]) + len(m.node_sets["inner_bore"])
    assert np.allclose(r[m.node_sets["inner_bore"]], spec.inner_ring_bore_radius)
    for j in range(spec.n_rollers):
        seg = boundary_segments(m.elements[m.element_part == 2 + j])
        assert len(seg) == len(m.surfaces[f"roller{j}"])
    assert n_race > 0


def _segment_elements(m, name, part):
    """For each segment of a surface, the element of ``part`` that owns it."""
    sel = np.flatnonzero(m.element_part == part)
    owner = {}
    for e in sel:
        q = m.elements[e]
        for a, b in zip(q, np.roll(q, -1), strict=True):
            owner[(int(a), int(b))] = e
    return np.array([owner[(int(a), int(b))] for a, b in m.surfaces[name]])


@pytest.mark.parametrize(
    ("name", "part"), [("outer_raceway", 0), ("inner_raceway", 1), ("roller0", 2), ("roller7", 9)]
)
def test_surfaces_are_closed_loops_with_outward_normals(coarse_mesh, name, part):
    _, m = coarse_mesh
    seg = m.surfaces[name]
    assert np.array_equal(seg[1:, 0], seg[:-1, 1]) and seg[-1, 1] == seg[0, 0]
    owner = _segment_elements(m, name, part)  # raises if a segment runs against its element
    mid = 0.5 * (m.nodes[seg[:, 0]] + m.nodes[seg[:, 1]])
    centroid = m.nodes[m.elements[owner]].mean(axis=1)
    n = m.segment_normals(name)
    assert np.all(np.sum((centroid - mid) * n, axis=1) < 0)


def test_raceway_and_roller_normals_point_across_the_gap(coarse_mesh):
    spec, m = coarse_mesh
    for name, sign in (("outer_raceway", -1), ("inner_raceway", 1)):
        seg = m.surfaces[name]
        mid = 0.5 * (m.nodes[seg[:, 0]] + m.nodes[seg[:, 1]])
        radial = mid / np.hypot(*mid.T)[:, None]
        dot = sign * np.sum(m.segment_normals(name) * radial, axis=1)
        # Everywhere except on the spall walls the normal faces the rolling gap.
        assert np.sum(dot > 0.99) == len(seg) - (2 if name == "outer_raceway" else 0)
    for j, c in enumerate(m.info["roller_centres"]):
        seg = m.surfaces[f"roller{j}"]
        mid = 0.5 * (m.nodes[seg[:, 0]] + m.nodes[seg[:, 1]]) - c
        assert np.all(np.sum(m.segment_normals(f"roller{j}") * mid, axis=1) > 0)


@pytest.mark.parametrize("size", [0.0005, 0.0008, 0.0012, 0.002])
def test_roller_segment_count_is_circumference_over_size(size):
    spec = coarse(n_rollers=6, surface_size=size, max_size=max(0.003, 2 * size))
    m = build_bearing_mesh(spec)
    expected = 2 * round(math.pi * spec.roller_diameter / (2 * size))  # even: all-quad mesh
    assert roller_surface_cells(spec.roller_diameter, size) == expected
    for j in range(spec.n_rollers):
        seg = m.surfaces[f"roller{j}"]
        assert len(seg) == expected == m.info["polygon_edges"][f"roller{j}"]
        lengths = np.hypot(*(m.nodes[seg[:, 1]] - m.nodes[seg[:, 0]]).T)
        assert np.allclose(lengths, lengths.mean(), rtol=1e-9)  # a regular polygon
        assert abs(lengths.mean() / size - 1) < 0.03
    race = m.surfaces["inner_raceway"]
    lengths = np.hypot(*(m.nodes[race[:, 1]] - m.nodes[race[:, 0]]).T)
    assert np.all(np.abs(lengths / size - 1) < 0.1)


@pytest.mark.parametrize("n_rollers", [8, 14])
def test_roller_count_and_positions(n_rollers):
    spec = coarse(n_rollers=n_rollers, first_roller_angle=math.radians(10))
    m = build_bearing_mesh(spec)
    assert len(m.part_names) == 2 + n_rollers
    for j in range(n_rollers):
        ids = np.unique(m.elements[m.element_part == 2 + j])
        centre = m.nodes[ids].mean(axis=0)
        angle = math.pi / 2 + math.radians(10) + 2 * math.pi * j / n_rollers
        expected = spec.pitch_radius * np.array([math.cos(angle), math.sin(angle)])
        assert np.hypot(*(centre - expected)) < 1e-3 * spec.roller_radius
        r = np.hypot(*(m.nodes[m.surfaces[f"roller{j}"][:, 0]] - expected).T)
        assert np.allclose(r, spec.roller_radius, rtol=1e-12)
    cage = m.info["cage"]
    assert np.allclose(np.diff(cage["pocket_angles"]), 2 * math.pi / n_rollers)


@pytest.mark.parametrize(("roller_d", "pitch_d"), [(0.020, 0.180), (0.030, 0.240)])
def test_diameters_change_the_geometry(roller_d, pitch_d):
    spec = coarse(roller_diameter=roller_d, pitch_diameter=pitch_d, n_rollers=12)
    m = build_bearing_mesh(spec)
    r_out = np.hypot(*m.nodes[m.surfaces["outer_raceway"][:, 0]].T)
    assert r_out.min() == pytest.approx(0.5 * pitch_d + 0.5 * roller_d, rel=1e-12)
    r_in = np.hypot(*m.nodes[m.surfaces["inner_raceway"][:, 0]].T)
    assert np.allclose(r_in, 0.5 * pitch_d - 0.5 * roller_d, rtol=1e-12)
    assert part_area(m, "roller3") == pytest.approx(math.pi * roller_d**2 / 4, rel=5e-3)
    n_race = m.info["polygon_edges"]["inner_raceway"]
    assert n_race == pytest.approx(math.pi * (pitch_d - roller_d) / spec.surface_size, rel=0.01)


@pytest.mark.parametrize("length", [0.004, 0.010, 0.016])
def test_defect_length_and_position(length):
    spec = coarse(n_rollers=8, defect_length=length, defect_angle=math.radians(30))
    m = build_bearing_mesh(spec)
    s = m.info["spall"]
    r = spec.outer_raceway_radius
    assert (s["end_angle"] - s["start_angle"]) * r == pytest.approx(length, rel=1e-12)
    assert s["centre_angle"] == pytest.approx(math.pi / 2 + math.radians(30), abs=1e-15)
    floor_segments = [
        (a, b)
        for a, b in m.surfaces["outer_raceway"]
        if np.isclose(np.hypot(*m.nodes[a]), s["floor_radius"], atol=1e-12)
        and np.isclose(np.hypot(*m.nodes[b]), s["floor_radius"], atol=1e-12)
    ]
    assert len(floor_segments) == round(length / spec.surface_size)


def test_deep_spall_spans_several_layers_and_inner_race_spall():
    spec = coarse(n_rollers=8, defect_depth=0.0025)  # 2.5 whole-layer depths at 1 mm
    m = build_bearing_mesh(spec)
    s = m.info["spall"]
    assert s["wall_layers"] >= 2
    c = s["corner_nodes"]
    assert np.hypot(*m.nodes[c[1]]) - np.hypot(*m.nodes[c[0]]) == pytest.approx(0.0025, abs=1e-9)
    # Every wall node lies on the radial line through its edge.
    seg = m.surfaces["outer_raceway"]
    nodes = np.unique(seg)
    xy = m.nodes[nodes]
    th = np.arctan2(xy[:, 1], xy[:, 0])
    rr = np.hypot(*xy.T)
    r = spec.outer_raceway_radius
    for edge in (s["start_angle"], s["end_angle"]):
        wall = np.abs(th - edge) < 1e-12
        assert wall.sum() == s["wall_layers"] + 1
        assert rr[wall].min() == pytest.approx(r) and rr[wall].max() == pytest.approx(r + 0.0025)
    assert len(seg) == m.info["polygon_edges"]["outer_raceway"] + 2 * s["wall_layers"]
    assert jacobian_determinants(m.nodes, m.elements).min() > 0
    spec = coarse(n_rollers=8, defect_race="inner", defect_angle=math.radians(90))
    m = build_bearing_mesh(spec)
    s = m.info["spall"]
    assert s["race"] == "inner"
    r = spec.inner_raceway_radius
    assert np.hypot(*m.nodes[s["corner_nodes"][1]]) == pytest.approx(r - 0.0002, abs=1e-9)
    exact = math.pi * (r**2 - spec.inner_ring_bore_radius**2) - 0.5 * (spec.defect_length / r) * (
        r**2 - (r - 0.0002) ** 2
    )
    assert part_area(m, "inner_ring") == pytest.approx(exact, rel=5e-3)
    assert m.info["polygon_edges"]["outer_raceway"] == len(m.surfaces["outer_raceway"])


def test_node_sets_and_sensors(coarse_mesh):
    spec, m = coarse_mesh
    top = m.node_sets["adapter_top"]
    assert np.allclose(m.nodes[top, 1], spec.adapter_top)
    assert m.nodes[top, 0].min() == pytest.approx(-0.5 * spec.adapter_width)
    assert m.nodes[top, 0].max() == pytest.approx(0.5 * spec.adapter_width)
    assert np.all(m.element_part[np.isin(m.elements, top).any(axis=1)] == 0)
    for name, xy in SENSORS.items():
        node = m.sensor_nodes[name]
        d = np.hypot(*(m.nodes - xy).T)
        assert d[node] == d.min()
        assert d[node] < 1e-9  # both points are nodes of this mesh (top centre line)
    assert m.sensor_nodes["adapter_top"] in set(top)


def test_thin_elements_stay_at_the_spall(coarse_mesh):
    spec, m = coarse_mesh
    g = element_geometry(m.nodes, m.elements)
    rings = m.element_part <= 1  # rollers shrink inward by design; rings must not
    thin = np.flatnonzero(rings & (g["min_edge"] < 0.75 * spec.surface_size))
    centroid = m.nodes[m.elements[thin]].mean(axis=1)
    angle = np.arctan2(centroid[:, 1], centroid[:, 0])
    s = m.info["spall"]
    near_wall = np.minimum(abs(angle - s["start_angle"]), abs(angle - s["end_angle"]))
    assert len(thin) > 0
    assert np.all(near_wall * spec.outer_raceway_radius < 2 * spec.surface_size)


def test_spec_from_default_case(default_case_path):
    from taichi_bearing.case import load_case

    case = load_case(default_case_path)
    spec = spec_from_case(case)
    assert spec.n_rollers == case.bearing.n_rollers
    assert spec.outer_raceway_radius == pytest.approx(case.bearing.outer_raceway_radius)
    assert spec.inner_ring_bore_radius == pytest.approx(case.bearing.inner_ring_bore_radius)
    assert spec.defect_depth == pytest.approx(case.defect.depth)
    assert spec.first_roller_angle == pytest.approx(case.run.first_roller_angle)
    assert spec.sensors["adapter_top"] == pytest.approx((case.sensors["adapter_top"].x, 0.156))
    assert spec.surface_size == pytest.approx(case.mesh.surface_size)


def test_default_mesh_meets_the_budget(default_case_path):
    from taichi_bearing.case import load_case

    spec = spec_from_case(load_case(default_case_path))
    t0 = time.perf_counter()
    m = build_bearing_mesh(spec)
    seconds = time.perf_counter() - t0
    st = mesh_statistics(m)
    print(f"\ndefault mesh built in {seconds:.2f} s\n{st.summary()}")
    assert m.n_elements <= 40_000
    assert jacobian_determinants(m.nodes, m.elements).min() > 0
    assert st.worst_jacobian_ratio > 0.2
    assert st.worst_aspect < 4
    # The only layers thinner than the surface size are the spall's: the time step is
    # set by the wall elements, not by a thin layer around the whole raceway.
    assert st.min_size == pytest.approx(spec.defect_depth, rel=1e-6)
    assert st.min_char_length > 0.45 * spec.surface_size
    roller = m.info["polygon_edges"]["roller0"]
    assert roller == 2 * round(math.pi * spec.roller_diameter / (2 * spec.surface_size))
    assert set(m.sensor_nodes) == {"adapter_top", "outer_ring_top"}


def test_clearance_opens_a_gap_on_both_raceways():
    c = 0.0004
    spec = coarse(n_rollers=8, clearance=c)
    m = build_bearing_mesh(spec)
    r_out = np.hypot(*m.nodes[m.surfaces["inner_raceway"][:, 0]].T)
    assert np.allclose(r_out, spec.pitch_radius - spec.roller_radius - c / 4, rtol=1e-12)
    centre = m.info["roller_centres"][0]
    r_roller = np.hypot(*(m.nodes[m.surfaces["roller0"][:, 0]] - centre).T)
    assert np.allclose(r_roller, spec.roller_radius, rtol=1e-12)
    assert np.hypot(*centre) == pytest.approx(spec.pitch_radius, rel=1e-12)


@pytest.mark.parametrize("side", [-1, 1])
def test_spall_edge_next_to_an_adapter_corner_makes_no_sliver(side):
    """A spall edge 0.2 mm from the angle of an adapter corner: the corner moves onto the
    edge instead of leaving a sliver element that would shrink the time step."""
    spec0 = coarse(n_rollers=8)
    corner_from_top = math.acos(0.5 * spec0.adapter_width / spec0.outer_ring_outer_radius)
    corner_from_top = math.pi / 2 - corner_from_top  # 28.4 deg
    r = spec0.outer_raceway_radius
    centre = side * (corner_from_top + (0.5 * spec0.defect_length + 0.0002) / r)
    spec = coarse(n_rollers=8, defect_angle=centre)
    m = build_bearing_mesh(spec)
    st = mesh_statistics(m)
    assert st.min_char_length > 0.2 * spec.surface_size
    assert jacobian_determinants(m.nodes, m.elements).min() > 0
    width = m.info["adapter"]["width"]
    assert width != pytest.approx(spec.adapter_width, abs=1e-9)
    assert abs(width - spec.adapter_width) < spec.surface_size
