"""Sloped and rounded spall edges: the profile's geometry, its conforming mesh, the rigid
roller's path over it in the quasi-static model, the case keys; and the default case's
mesh unchanged bit for bit."""

from __future__ import annotations

import dataclasses
import hashlib
import math

import numpy as np
import pytest
from geometry_reference import brute_force_drop

from taichi_bearing.analytic.quasistatic import (
    contact_model,
    solve_load_distribution,
    spall_from_case,
)
from taichi_bearing.analytic.spall_contact import _profile_supports, spall_supports
from taichi_bearing.case import CaseError, load_case
from taichi_bearing.geometry.roller_path import centre_drop
from taichi_bearing.geometry.spall_profile import SpallProfile
from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
from taichi_bearing.mesh.grid import boundary_segments, chain_segments, signed_areas
from taichi_bearing.mesh.quality import jacobian_determinants, mesh_statistics
from taichi_bearing.mesh.spec import spec_from_case

R, r = 0.112, 0.012  # outer raceway and roller radius of the default bearing, m


def digest(a: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()[:16]


@pytest.mark.parametrize(
    "name, nodes, elements, sizes",
    [
        ("line_spall.yaml", "2578cbbea1a322a2", "be9b59e946b6fe75", (31511, 28401)),
        ("validation/coarse_spall.yaml", "9e7c1c2b1020f3d4", "be1812df55f620c3", (16328, 14748)),
    ],
)
def test_default_meshes_are_unchanged(default_case_path, name, nodes, elements, sizes):
    """The meshes built before the slopes existed (ef5bd43), bit for bit: 90-degree walls
    without an edge radius still take the rectangular notch's path."""
    mesh = build_bearing_mesh(spec_from_case(load_case(default_case_path.parent / name)))
    assert (mesh.n_nodes, mesh.n_elements) == sizes
    assert digest(mesh.elements) == elements
    assert digest(mesh.nodes) == nodes


def test_slopes_and_radius_default_to_the_rectangular_notch(default_case_path):
    case = load_case(default_case_path)
    assert case.defect.entry_slope == case.defect.exit_slope == 90.0 * (math.pi / 180.0)
    assert case.defect.edge_radius == 0.0
    assert spall_from_case(case).rectangular


def test_profile_geometry():
    """A 45-degree wall leaves its edge at 45 degrees to the raceway's tangent and meets
    the floor circle; a fillet touches the raceway circle and the wall."""
    d, rho = 0.002, 0.001
    p = SpallProfile(R, 1.5, 1.5 + 0.01 / R, d, True, math.radians(45), math.radians(45), rho)
    for edge, into in ((p.start_edge, 1.0), (p.end_edge, -1.0)):
        u = edge.corner / R
        t = into * np.array([-u[1], u[0]])
        assert np.hypot(*edge.corner) == pytest.approx(R, rel=1e-15)
        assert edge.wall @ t == pytest.approx(math.cos(math.radians(45)), abs=1e-14)
        assert np.hypot(*edge.floor_corner) == pytest.approx(R + d, rel=1e-14)
        c = edge.fillet_centre
        assert np.hypot(*c) == pytest.approx(R + rho, rel=1e-14)  # tangent to the raceway
        assert (c - edge.corner) @ edge.normal == pytest.approx(rho, rel=1e-9)  # and the wall
        assert np.hypot(*(edge.tangent_end - c)) == pytest.approx(rho, rel=1e-9)
    ends = [(a.p1, b.p0) for a, b in zip(p.pieces[:-1], p.pieces[1:], strict=True)]
    assert all(np.allclose(a, b, atol=1e-15) for a, b in ends)  # one continuous chain


@pytest.mark.parametrize("slope, rho", [(45, 0.0), (20, 0.0), (45, 0.002), (90, 0.0005)])
def test_roller_centre_follows_the_profile(slope, rho):
    """The closed-form path (circle on line, on point, on circle) against the bisection
    on a polyline of the profile, across a deep spall's exit edge."""
    d = 0.003  # deep enough for a 12 mm roller to roll on the walls
    p = SpallProfile(R, 1.5, 1.5 + 0.02 / R, d, True, math.radians(slope), math.radians(slope), rho)
    phis = p.end + np.linspace(-0.0095, 0.002, 24) / R  # from the middle out
    drop, _ = centre_drop(phis, p, r)
    expected = [brute_force_drop(p, phi) for phi in phis]
    assert np.allclose(drop, expected, atol=2e-9)
    assert np.all(np.diff(drop) <= 1e-15)  # climbing out: the drop only falls
    assert drop[0] > 0.9 * d and drop[-1] == 0.0


def test_centre_over_a_45_degree_wall_is_r_from_the_line():
    """Circle on a line: with the roller resting on a 45-degree wall its centre lies r
    from the wall along the wall's normal, and the path finds that very centre (the
    inverse construction of the contact). A 12 mm roller on a 45-degree wall sits
    r (1 - cos 45) = 3.5 mm deeper than its contact point: the wall must be deeper still
    for it to touch the wall before the floor."""
    p = SpallProfile(R, 1.5, 1.5 + 0.04 / R, 0.006, True, math.radians(45), math.radians(45))
    edge = p.end_edge
    middle = edge.corner + 0.2 * (edge.floor_corner - edge.corner)
    centre = middle - r * edge.normal
    assert np.hypot(*centre) - (R - r) < p.depth  # above the floor
    phi = math.atan2(centre[1], centre[0])
    drop, contact = centre_drop(np.array([phi]), p, r)
    assert drop[0] == pytest.approx(np.hypot(*centre) - (R - r), abs=1e-12)
    assert np.allclose(contact[0], middle, atol=1e-12)


@pytest.fixture(scope="module")
def default_case(default_case_path):
    return load_case(default_case_path)


def test_profile_path_reproduces_the_rectangular_model(default_case):
    """The general supports with two sharp radial walls are the rectangular model's."""
    cm = contact_model(default_case.bearing, default_case.material)
    spall = spall_from_case(default_case)
    psi = np.linspace(-0.1, 0.1, 2001)[:, None] + np.array([0.0, 0.31])
    b = np.full(psi.shape, 1.5e-4)
    for mode in ("patch", "step"):
        h0, phi0, u0 = spall_supports(psi, b, cm, spall, mode)
        h1, phi1, u1 = _profile_supports(psi, b, cm, spall, mode)
        finite = np.isfinite(h0)
        assert np.array_equal(finite, np.isfinite(h1))
        assert np.allclose(h0[finite], h1[finite], rtol=0, atol=1e-15)
        assert np.allclose(phi0, phi1, atol=1e-15) and np.allclose(u0, u1, atol=1e-12)


def regain_mm(case, spall, share=0.5):
    """Where roller 0's force regains ``share`` of its value, mm from the exit edge."""
    cm = contact_model(case.bearing, case.material)
    angles = spall.exit + np.linspace(-4e-3, 2e-3, 1201) / R
    dist = solve_load_distribution(cm, 20, case.operating.load, angles, spall)
    f = dist.outer_force[:, 0]
    assert dist.balance_error().max() < 1e-12
    assert np.abs(np.diff(f)).max() < 0.05 * f.max()  # no step: the path is continuous
    return 1e3 * R * (angles[np.argmax(f > share * f[-1])] - spall.exit)


def test_exit_slope_in_the_quasi_static_model(default_case):
    """A rigid roller pivots on a sharp edge for the last r (1 - cos(slope)) of its climb
    (46 um at 5 degrees): the force (7 um approach) comes back in that pivot, at the same
    place for 45, 20 and 5 degrees; only a wall shallower than ~2 degrees lifts it earlier,
    and a rounded edge, taking material away, later."""
    spall = spall_from_case(default_case)

    def with_exit(deg, rho=0.0):
        return dataclasses.replace(spall, exit_slope=math.radians(deg), edge_radius=rho)

    pivot = [regain_mm(default_case, with_exit(a)) for a in (45, 20, 5)]
    assert pivot == pytest.approx([pivot[0]] * 3, abs=1e-9)
    assert -0.6 < pivot[0] < -0.3
    assert regain_mm(default_case, with_exit(1.0)) < pivot[0] - 0.05
    assert regain_mm(default_case, with_exit(90, 1e-4)) > pivot[0] + 0.05


def distance_to_pieces(profile: SpallProfile, xy: np.ndarray) -> np.ndarray:
    """Distance of points to the nearest piece of the profile (lines and arcs)."""
    out = np.full(len(xy), np.inf)
    for piece in profile.pieces:
        if piece.kind == "line":
            seg = piece.p1 - piece.p0
            t = np.clip((xy - piece.p0) @ seg / (seg @ seg), 0.0, 1.0)
            d = np.hypot(*(piece.p0 + t[:, None] * seg - xy).T)
        else:
            rel = xy - piece.centre
            angle = np.arctan2(rel[:, 1], rel[:, 0])
            lo, hi = sorted((piece.a0, piece.a1))
            angle = lo + (angle - lo) % (2 * np.pi)
            d = np.where(angle <= hi, np.abs(np.hypot(*rel.T) - piece.radius), np.inf)
        out = np.minimum(out, d)
    return out


def corner(mesh, point):
    d = np.hypot(*(mesh.nodes - point).T)
    return d.min()


@pytest.mark.parametrize(
    "sets",
    [
        ["defect.exit_slope_deg=20"],
        ["defect.exit_slope_deg=20", "defect.edge_radius_mm=0.1"],
        ["defect.entry_slope_deg=45", "defect.exit_slope_deg=45", "defect.edge_radius_mm=0.3"],
        ["defect.race=inner", "defect.angle_deg=-35", "defect.exit_slope_deg=30"],
    ],
)
def test_sloped_mesh_is_valid_and_its_walls_and_floor_are_exact(default_case_path, sets):
    case = load_case(default_case_path.parent / "validation" / "coarse_spall.yaml", sets)
    spec = spec_from_case(case)
    mesh = build_bearing_mesh(spec)
    profile = spec.spall_profile()
    part = 0 if case.defect.race == "outer" else 1
    # quality: convex elements, no hanging nodes (a ring's boundary is two loops)
    assert jacobian_determinants(mesh.nodes, mesh.elements).min() > 0
    stats = mesh_statistics(mesh)
    assert stats.worst_jacobian_ratio > 0.1 and stats.worst_aspect < 10
    assert stats.min_char_length > 0.25 * case.mesh.surface_size
    # no element coarser than in the rectangular notch's mesh (each arc of the window
    # holds a whole number of coarse cells)
    rect = mesh_statistics(build_bearing_mesh(spec_from_case(load_case(case.source))))
    assert stats.part_max_size["outer_ring"] <= 1.01 * rect.part_max_size["outer_ring"]
    assert stats.part_max_size["inner_ring"] <= 1.01 * rect.part_max_size["inner_ring"]
    loops = chain_segments(boundary_segments(mesh.elements[mesh.element_part == part]))
    assert len(loops) == 2
    # every raceway node lies on the exact profile (or the raceway beyond it)
    surface = np.unique(mesh.surfaces[f"{case.defect.race}_raceway"])
    xy = mesh.nodes[surface]
    gap = distance_to_pieces(profile, xy)
    on_raceway = np.abs(np.hypot(*xy.T) - profile.raceway_radius) < 1e-12
    assert np.all(on_raceway | (gap < 1e-9))
    # the floor: nodes between its corners at the floor radius, the corners themselves nodes
    lo, hi = profile.floor_angles
    theta = np.arctan2(xy[:, 1], xy[:, 0])
    floor = (theta > lo + 1e-9) & (theta < hi - 1e-9)
    assert np.allclose(np.hypot(*xy[floor].T), profile.floor_radius, rtol=0, atol=1e-12)
    assert floor.sum() >= round(profile.floor_radius * (hi - lo) / case.mesh.surface_size) - 1
    for edge in (profile.start_edge, profile.end_edge):
        assert corner(mesh, edge.floor_corner) < 1e-12
        if edge.fillet_centre is None:
            assert corner(mesh, edge.corner) < 1e-12
    info = mesh.info["spall"]
    assert info["floor_radius"] == profile.floor_radius
    corners = [profile.start_edge.floor_corner, profile.end_edge.floor_corner]
    corners += [e.corner for e in (profile.start_edge, profile.end_edge) if e.fillet_centre is None]
    found = mesh.nodes[info["corner_nodes"]]
    assert len(found) == len(corners)
    assert all(np.min(np.hypot(*(found - c).T)) < 1e-12 for c in corners)


def test_sloped_mesh_removes_the_profile_area(default_case_path):
    """The ring lacks the profile's area against the healthy ring (chords aside)."""
    coarse = default_case_path.parent / "validation" / "coarse_spall.yaml"
    sets = ["defect.entry_slope_deg=30", "defect.exit_slope_deg=10"]
    spec = spec_from_case(load_case(coarse, sets))
    healthy = build_bearing_mesh(spec_from_case(load_case(coarse, ["defect.race=none"])))
    sloped = build_bearing_mesh(spec)

    def ring_area(m):
        return signed_areas(m.nodes, m.elements[m.element_part == 0]).sum()

    p = spec.spall_profile()
    pts = p.polyline(2000)
    angles = np.unwrap(np.arctan2(pts[:, 1], pts[:, 0]))
    radii = np.hypot(*pts.T)
    # area between the raceway circle and the profile: sum of 0.5 (r^2 - R^2) d(angle)
    exact = np.sum(0.5 * (0.5 * (radii[1:] ** 2 + radii[:-1] ** 2) - R**2) * np.diff(angles))
    removed = ring_area(healthy) - ring_area(sloped)
    assert removed == pytest.approx(exact, rel=2e-2)


@pytest.mark.parametrize(
    "sets, key",
    [
        (["defect.entry_slope_deg=1", "defect.exit_slope_deg=1"], "defect.entry_slope_deg"),
        (["defect.edge_radius_mm=0.5"], "defect.edge_radius_mm"),
        (["defect.exit_slope_deg=0"], "defect.exit_slope_deg"),
        (["defect.exit_slope_deg=91"], "defect.exit_slope_deg"),
    ],
)
def test_profiles_that_do_not_fit_are_refused_naming_the_key(default_case_path, sets, key):
    with pytest.raises(CaseError) as err:
        load_case(default_case_path, sets)
    assert err.value.key == key
