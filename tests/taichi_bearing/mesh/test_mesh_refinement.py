"""Local refinement: a finer raceway round the spall (mesh.spall_size_mm, spall_zone_mm)
and finer rollers (mesh.roller_surface_size_mm, fine_rollers). The refined meshes are
conforming, counter-clockwise and convex, fine where asked and nowhere else, far cheaper
than refining everywhere; the keys off leave the default mesh bit for bit; bad values are
refused naming the key."""

from __future__ import annotations

import hashlib
import json
import math
import subprocess
import sys
from functools import cache

import numpy as np
import pytest

from taichi_bearing.__main__ import main
from taichi_bearing.case import CaseError, load_case
from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
from taichi_bearing.mesh.grid import boundary_segments, chain_segments, signed_areas
from taichi_bearing.mesh.quality import CORNERS, jacobian_determinants, mesh_statistics
from taichi_bearing.mesh.spec import spec_from_case
from taichi_bearing.solver.element import element_geometry

CASES = "cases"
FINE = ["mesh.spall_size_mm=0.125", "mesh.roller_surface_size_mm=0.125", "mesh.fine_rollers=3"]


@cache
def refined(name: str, sets: tuple[str, ...]):
    case = load_case(f"{CASES}/{name}", list(sets))
    return case, build_bearing_mesh(spec_from_case(case))


def digest(a: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()[:16]


# the default case's mesh as pinned in tests/test_spall_profile.py (ef5bd43)
DEFAULT = ("2578cbbea1a322a2", "be9b59e946b6fe75", (31511, 28401))


@pytest.mark.parametrize(
    "sets",
    [
        [],
        # off: 0, or not finer than the surface size, whatever the zone and the count
        ["mesh.spall_size_mm=0", "mesh.roller_surface_size_mm=0", "mesh.fine_rollers=3"],
        ["mesh.spall_size_mm=0.5", "mesh.spall_zone_mm=7", "mesh.roller_surface_size_mm=0.5"],
    ],
)
def test_keys_off_leave_the_default_mesh_bit_for_bit(default_case_path, sets):
    case = load_case(default_case_path, sets)
    assert case.mesh.spall_size in (0.0, case.mesh.surface_size)
    mesh = build_bearing_mesh(spec_from_case(case))
    assert (digest(mesh.nodes), digest(mesh.elements), (mesh.n_nodes, mesh.n_elements)) == DEFAULT
    assert mesh.info["fine_zone"] is None
    assert set(mesh.info["sizes"]["roller_surface_size"]) == {case.mesh.surface_size}


def test_defaults_are_off(default_case_path):
    m = load_case(default_case_path).mesh
    assert (m.spall_size, m.roller_surface_size, m.fine_rollers) == (0.0, 0.0, 0)
    assert m.spall_zone == pytest.approx(2e-3)


VARIANTS = [
    ("line_spall.yaml", tuple(FINE)),
    ("line_spall.yaml", ("mesh.spall_size_mm=0.25", "mesh.roller_surface_size_mm=0.25")),
    ("line_spall.yaml", ("mesh.spall_size_mm=0.0625", "mesh.spall_zone_mm=0")),
    # sloped and rounded edges: the raceway follows the profile inside the zone
    (
        "validation/coarse_spall.yaml",
        ("mesh.spall_size_mm=0.25", "defect.exit_slope_deg=20", "defect.edge_radius_mm=0.1"),
    ),
    # an adapter corner (28.4 deg) where the transition would be: the zone takes it in
    ("validation/coarse_spall.yaml", ("mesh.spall_size_mm=0.25", "defect.angle_deg=24.5")),
    (
        "validation/coarse_spall.yaml",
        ("mesh.spall_size_mm=0.125", "mesh.growth=1.3", "defect.angle_deg=180"),
    ),
    # a profiled spall where atan2's angles wrap (225 deg from +x is -135 deg)
    (
        "validation/coarse_spall.yaml",
        ("mesh.spall_size_mm=0.125", "defect.exit_slope_deg=20", "defect.angle_deg=135"),
    ),
    (
        "validation/coarse_spall.yaml",
        (
            "mesh.spall_size_mm=0.25",
            "defect.race=inner",
            "defect.angle_deg=-35",
            "defect.exit_slope_deg=30",
        ),
    ),
]


@pytest.mark.parametrize("name, sets", VARIANTS)
def test_refined_meshes_are_conforming_counter_clockwise_and_convex(name, sets):
    case, mesh = refined(name, sets)
    e = mesh.elements
    # every node used; every edge in one element (boundary) or two (interior)
    assert np.array_equal(np.unique(e), np.arange(mesh.n_nodes))
    edges = np.sort(np.stack([e, np.roll(e, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
    _, uses = np.unique(edges, axis=0, return_counts=True)
    assert set(uses) == {1, 2}
    # no hanging node: each body's boundary is closed loops only (a ring: raceway and
    # back; a roller: its surface), so no edge of one element ends mid-edge of another
    for p, part in enumerate(mesh.part_names):
        loops = chain_segments(boundary_segments(e[mesh.element_part == p]))
        assert all(c[-1, 1] == c[0, 0] for c in loops)
        assert len(loops) == (2 if part.endswith("ring") else 1)
    # counter-clockwise and convex: positive Jacobians at the corners and Gauss points
    assert signed_areas(mesh.nodes, e).min() > 0
    assert jacobian_determinants(mesh.nodes, e, CORNERS).min() > 0
    assert jacobian_determinants(mesh.nodes, e).min() > 0
    element_geometry(mesh.nodes, e)  # the solver's own check raises otherwise
    stats = mesh_statistics(mesh)
    assert stats.worst_jacobian_ratio > 0.15 and stats.worst_aspect < 10
    # no sliver: the smallest element is about as large as the finest size asked for
    finest = min(case.mesh.spall_size, case.mesh.roller_surface_size or np.inf)
    assert stats.min_char_length > 0.2 * finest
    # local: the zone with its transitions is a small part of the raceway
    t1, t2 = mesh.info["fine_zone"]["transition_angles"]
    assert 0 < t2 - t1 < 0.25 * 2 * math.pi


def test_a_corner_in_the_way_of_a_transition_moves_the_zone_past_it():
    case, mesh = refined(*VARIANTS[4])
    zone = mesh.info["fine_zone"]["zone_angles"]
    spec = spec_from_case(case)
    corner = math.pi / 2 - math.acos(0.5 * spec.adapter_width / spec.outer_ring_outer_radius)
    corner += math.pi / 2  # the corner 28.4 deg from 12 o'clock, on the spall's side
    edge = spec.spall_profile().end + spec.spall_zone / spec.outer_raceway_radius
    assert zone[1] > corner > edge  # asked to end before the corner, it ends past it
    # and the adapter is as wide as asked: its corners are nodes of the ring's outside
    assert mesh.info["adapter"]["width"] == pytest.approx(spec.adapter_width, rel=1e-9)


def raceway_segments(mesh, race: str):
    """Raceway segments on the circle (the spall's walls and floor left out): lengths
    and angles of their midpoints from the spall's centre, rad."""
    seg = mesh.surfaces[f"{race}_raceway"]
    a, b = mesh.nodes[seg[:, 0]], mesh.nodes[seg[:, 1]]
    radius = mesh.info["raceway_radii"][race]
    on = (np.abs(np.hypot(*a.T) - radius) < 1e-9) & (np.abs(np.hypot(*b.T) - radius) < 1e-9)
    mid = 0.5 * (a + b)[on]
    angle = np.arctan2(mid[:, 1], mid[:, 0]) - mesh.info["spall"]["centre_angle"]
    angle = (angle + math.pi) % (2 * math.pi) - math.pi
    return np.linalg.norm(b - a, axis=1)[on], angle


def test_fine_where_asked_graded_between_and_coarse_elsewhere():
    case, mesh = refined("line_spall.yaml", tuple(FINE))
    m, spall = case.mesh, mesh.info["spall"]
    length, angle = raceway_segments(mesh, "outer")
    s = angle * spall["raceway_radius"]  # arc from the spall's centre, m
    half = 0.5 * spall["length"]
    zone = np.abs(s) < half + m.spall_zone
    assert zone.sum() >= 2 * m.spall_zone / m.spall_size  # at least the asked zone
    assert np.allclose(length[zone], m.spall_size, rtol=0.05)
    # beyond the transitions: the surface size
    t1, t2 = mesh.info["fine_zone"]["transition_angles"]
    reach = spall["raceway_radius"] * 0.5 * (t2 - t1)
    far = np.abs(s) > reach + 1e-6
    assert np.allclose(length[far], m.surface_size, rtol=0.05)
    # between: each element at most growth (1.5 here) times its neighbour
    order = np.argsort(s)
    ratio = length[order][1:] / length[order][:-1]
    assert np.all(ratio < 1.5 * 1.01) and np.all(1 / ratio < 1.5 * 1.01)
    assert np.any((np.abs(s) > half + m.spall_zone) & (length < 0.9 * m.surface_size))
    # the notch's floor and walls are fine too
    seg = mesh.surfaces["outer_raceway"]
    lengths = segment_lengths(mesh, "outer_raceway")
    r = np.hypot(*mesh.nodes[seg].transpose(2, 0, 1))
    floor = np.all(np.abs(r - spall["floor_radius"]) < 1e-9, axis=1)
    walls = ~floor & np.any(np.abs(r - spall["raceway_radius"]) > 1e-9, axis=1)
    assert floor.sum() == round(spall["length"] / m.spall_size)
    assert np.allclose(lengths[floor], m.spall_size, rtol=0.05)
    assert walls.sum() == 2 * spall["wall_layers"] and lengths[walls].max() < m.spall_size
    # the inner raceway is untouched
    assert np.allclose(segment_lengths(mesh, "inner_raceway"), m.surface_size, rtol=0.05)


def segment_lengths(mesh, surface: str) -> np.ndarray:
    seg = mesh.surfaces[surface]
    return np.linalg.norm(mesh.nodes[seg[:, 1]] - mesh.nodes[seg[:, 0]], axis=1)


def test_the_rollers_that_leave_the_spall_first_are_fine():
    case, mesh = refined("line_spall.yaml", tuple(FINE))
    # roller 0 starts 4 deg before 12 o'clock, the rollers turn counter-clockwise: it
    # leaves the spall first, then 19 (18 deg behind), then 18
    assert spec_from_case(case).passage_order()[:4] == [0, 19, 18, 17]
    size = mesh.info["sizes"]["roller_surface_size"]
    for j in range(case.bearing.n_rollers):
        fine = j in (0, 18, 19)
        assert size[j] == (case.mesh.roller_surface_size if fine else case.mesh.surface_size)
        assert np.allclose(segment_lengths(mesh, f"roller{j}"), size[j], rtol=0.01)
        # graded into the core: fine rollers have more, and smaller, elements inside too
        n = np.count_nonzero(mesh.element_part == mesh.part_id(f"roller{j}"))
        assert (n > 3000) if fine else (n == 732)


def test_passage_order_follows_the_race_and_the_start():
    spec = spec_from_case(load_case(f"{CASES}/line_spall.yaml", ["run.first_roller_angle_deg=5"]))
    # roller 0 has already left the spall (its exit edge at 2.56 deg): 19 leaves first
    assert spec.passage_order()[:3] == [19, 18, 17]
    # inner race: in the inner ring's frame the rollers move clockwise and leave over
    # the edge at the smaller angle (-38.3 deg for a spall at -35 deg): roller 18 (-40
    # deg) has left it, 19 (-22 deg) leaves first, then 0 (-4 deg)
    inner = ["defect.race=inner", "defect.angle_deg=-35"]
    spec = spec_from_case(load_case(f"{CASES}/line_spall.yaml", inner))
    assert spec.passage_order()[:3] == [19, 0, 1]
    # every roller when fine_rollers is 0
    fine = ["mesh.roller_surface_size_mm=0.25"]
    spec = spec_from_case(load_case(f"{CASES}/line_spall.yaml", fine))
    assert spec.roller_sizes() == pytest.approx([0.25e-3] * 20, rel=1e-12)


def test_refinement_is_local_and_far_cheaper_than_everywhere():
    _, local = refined("line_spall.yaml", tuple(FINE))
    _, default = refined("line_spall.yaml", ())
    everywhere = load_case(f"{CASES}/line_spall.yaml", ["mesh.surface_size_mm=0.125"])
    uniform = mesh_statistics(build_bearing_mesh(spec_from_case(everywhere)))
    stats, base = mesh_statistics(local), mesh_statistics(default)
    # the zone adds a few hundred elements to the outer ring, the inner ring is as it was
    extra = stats.part_elements["outer_ring"] - base.part_elements["outer_ring"]
    assert 100 < extra < 1500
    assert stats.part_elements["inner_ring"] == base.part_elements["inner_ring"]
    assert stats.n_elements < 0.35 * uniform.n_elements
    # the smallest elements are those of the uniform 0.125 mm mesh, not smaller
    assert stats.min_char_length > 0.95 * uniform.min_char_length
    # reported per part
    assert stats.part_min_char_length["outer_ring"] < 0.4 * base.part_min_char_length["outer_ring"]
    roller = stats.part_min_char_length["roller1"]
    assert roller == pytest.approx(base.part_min_char_length["roller1"], rel=1e-9)
    assert "smallest characteristic length per part" in stats.summary()


def test_mesh_command_reports_the_refinement(default_case_path, tmp_path, capsys):
    sets = [a for s in FINE for a in ("--set", s)]
    rc = main(["mesh", str(default_case_path), "--out", str(tmp_path), "--no-pictures", *sets])
    assert rc == 0
    assert "refined: raceway 0.125 mm from -7 to 7 mm" in capsys.readouterr().out
    saved = json.loads((tmp_path / "mesh_statistics.json").read_text())
    refinement = saved["refinement"]
    assert refinement["fine_rollers"] == [0, 18, 19]
    assert refinement["zone"]["from_centre_mm"] == pytest.approx([-7.0, 7.0])
    assert saved["statistics"]["part_elements"]["roller0"] > 3000
    assert saved["statistics"]["part_min_char_length"]["outer_ring"] < 1e-4


@pytest.mark.parametrize(
    "sets, key",
    [
        (["mesh.spall_size_mm=0.6"], "mesh.spall_size_mm"),
        (["mesh.spall_size_mm=0.02"], "mesh.spall_size_mm"),
        (["mesh.spall_size_mm=-0.1"], "mesh.spall_size_mm"),
        (["mesh.spall_size_mm=0.25", "defect.race=none"], "mesh.spall_size_mm"),
        (["mesh.spall_size_mm=0.25", "mesh.spall_zone_mm=180"], "mesh.spall_zone_mm"),
        (["mesh.spall_zone_mm=-1"], "mesh.spall_zone_mm"),
        (["mesh.roller_surface_size_mm=0.75"], "mesh.roller_surface_size_mm"),
        (["mesh.fine_rollers=21"], "mesh.fine_rollers"),
        (["mesh.fine_rollers=2.5"], "mesh.fine_rollers"),
        # the time step floor names the finest size
        (["mesh.roller_surface_size_mm=0.0001"], "mesh.roller_surface_size_mm"),
    ],
)
def test_bad_values_are_refused_naming_the_key(default_case_path, sets, key):
    with pytest.raises(CaseError) as err:
        load_case(default_case_path, sets)
    assert err.value.key == key


def test_bad_value_on_the_command_line_is_one_line_and_status_2(default_case_path, tmp_path):
    cmd = [sys.executable, "-m", "taichi_bearing", "mesh", str(default_case_path), "--out"]
    cmd += [str(tmp_path), "--no-pictures", "--set", "mesh.spall_size_mm=0.75"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "mesh.spall_size_mm" in lines[0]
    assert "Traceback" not in proc.stderr
