"""Single-part meshes and the quad-grid building blocks behind them."""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.mesh.grid import (
    boundary_segments,
    coons_patch,
    orient_ccw,
    quad_grid,
    signed_areas,
)
from taichi_bearing.mesh.ogrid import o_grid_disk
from taichi_bearing.mesh.primitives import annulus_mesh, disk_mesh, rectangle_mesh
from taichi_bearing.mesh.quality import jacobian_determinants, mesh_statistics, wave_speed
from taichi_bearing.mesh.strip import between_levels, build_strip, plan_arc, plan_row


def polygon_area(n: int, r: float) -> float:
    """Area of the regular n-gon inscribed in a circle of radius r."""
    return 0.5 * n * r * r * np.sin(2 * np.pi / n)


def assert_valid(mesh):
    """Positive Jacobians at the Gauss points, no duplicate nodes, no unused nodes."""
    det = jacobian_determinants(mesh.nodes, mesh.elements)
    assert det.min() > 0
    rounded = np.round(mesh.nodes / 1e-12)
    assert len(np.unique(rounded, axis=0)) == mesh.n_nodes
    assert len(np.unique(mesh.elements)) == mesh.n_nodes


def assert_closed_loop(seg):
    assert np.array_equal(seg[1:, 0], seg[:-1, 1])
    assert seg[-1, 1] == seg[0, 0]


def test_rectangle_area_surfaces_and_normals():
    m = rectangle_mesh(0.3, 0.1, 6, 4, origin=(1.0, -2.0))
    assert_valid(m)
    assert m.n_elements == 24 and m.n_nodes == 35
    assert signed_areas(m.nodes, m.elements).sum() == pytest.approx(0.03, rel=1e-12)
    expected = {"bottom": (0, -1), "right": (1, 0), "top": (0, 1), "left": (-1, 0)}
    for name, normal in expected.items():
        seg = m.surfaces[name]
        assert len(seg) == (6 if name in ("bottom", "top") else 4)
        assert np.allclose(m.segment_normals(name), normal)
        assert np.array_equal(seg[1:, 0], seg[:-1, 1])  # ordered head to tail
        assert set(m.node_sets[name]) == set(seg.ravel())
    # The four sides close the boundary counter-clockwise.
    loop = np.concatenate([m.surfaces[k] for k in ("bottom", "right", "top", "left")])
    assert_closed_loop(loop)
    assert np.allclose(m.nodes[m.node_sets["left"], 0], 1.0)


def test_annulus_area_normals_and_closure():
    n, r0, r1 = 48, 0.05, 0.08
    m = annulus_mesh(r0, r1, n, 5)
    assert_valid(m)
    area = signed_areas(m.nodes, m.elements).sum()
    assert area == pytest.approx(polygon_area(n, r1) - polygon_area(n, r0), rel=1e-12)
    assert area == pytest.approx(np.pi * (r1**2 - r0**2), rel=5e-3)
    for name, sign in (("outer", 1), ("inner", -1)):
        seg = m.surfaces[name]
        assert len(seg) == n
        assert_closed_loop(seg)
        mid = 0.5 * (m.nodes[seg[:, 0]] + m.nodes[seg[:, 1]])
        radial = mid / np.linalg.norm(mid, axis=1, keepdims=True)
        assert np.all(sign * np.sum(m.segment_normals(name) * radial, axis=1) > 0.99)


@pytest.mark.parametrize("n_surface", [40, 42, 150])
def test_disk_area_normals_and_no_degenerate_centre(n_surface):
    r = 0.012
    m = disk_mesh(r, n_surface)
    assert_valid(m)
    seg = m.surfaces["outer"]
    assert len(seg) == n_surface
    assert_closed_loop(seg)
    area = signed_areas(m.nodes, m.elements).sum()
    assert area == pytest.approx(polygon_area(n_surface, r), rel=1e-12)
    assert area == pytest.approx(np.pi * r * r, rel=5e-3)
    mid = 0.5 * (m.nodes[seg[:, 0]] + m.nodes[seg[:, 1]])
    assert np.all(np.sum(m.segment_normals("outer") * mid, axis=1) > 0)
    # O-grid: no node at the centre is shared by more than four elements.
    counts = np.bincount(m.elements.ravel(), minlength=m.n_nodes)
    assert counts.max() <= 4
    det = jacobian_determinants(m.nodes, m.elements)
    assert (det.min(axis=1) / det.max(axis=1)).min() > 0.2


def test_quad_grid_and_coons_patch_reproduce_a_plane_grid():
    xs = np.array([0.0, 0.1, 0.3, 0.6])
    ys = np.array([0.0, 0.2, 0.5])
    bottom = np.stack([xs, np.zeros(4)], 1)
    top = np.stack([xs, np.full(4, 0.5)], 1)
    left = np.stack([np.zeros(3), ys], 1)
    right = np.stack([np.full(3, 0.6), ys], 1)
    pts = coons_patch(bottom, right, top, left)
    gx, gy = np.meshgrid(xs, ys)
    assert np.allclose(pts, np.stack([gx.ravel(), gy.ravel()], 1), atol=1e-15)
    el = quad_grid(3, 2)
    assert signed_areas(pts, el).sum() == pytest.approx(0.3)
    assert len(boundary_segments(el)) == 10


@pytest.mark.parametrize(("n_fine", "n_coarse"), [(8, 4), (12, 4), (10, 8), (9, 3), (14, 6)])
def test_coarsening_plans_conserve_cells(n_fine, n_coarse):
    plan = plan_arc(n_fine, n_coarse)
    span = {1: (1, 1), 2: (4, 2), 3: (3, 1)}
    assert sum(span[k][0] for k in plan) == n_fine
    assert sum(span[k][1] for k in plan) == n_coarse


def test_coarsening_rejects_odd_difference():
    with pytest.raises(ValueError):
        plan_arc(9, 4)


@pytest.mark.parametrize("ratio", [2, 3])
def test_graded_annulus_rows_are_conforming(ratio):
    """A ring coarsened twice has no hanging node: its only free edges are the two circles."""
    n0, r0 = 72, 1.0
    radii = [1.0, 1.1, 1.25, 1.45, 1.7]
    ratios = [1, ratio, 1, ratio]
    plans, arcs = [], [n0]
    for q in ratios:
        plan, arcs = plan_row(arcs, q)
        plans.append(plan if q > 1 else None)

    def level_point(k, u):
        th = 2 * np.pi * u / n0
        return radii[k] * np.stack([np.cos(th), np.sin(th)], axis=1)

    s = build_strip(np.arange(n0, dtype=float), plans, between_levels(level_point), True)
    assert jacobian_determinants(s.nodes, s.elements).min() > 0
    n_outer = len(s.levels[-1])
    assert n_outer == n0 // ratio**2
    assert len(boundary_segments(s.elements)) == n0 + n_outer
    area = signed_areas(s.nodes, s.elements).sum()
    assert area == pytest.approx(polygon_area(n_outer, 1.7) - polygon_area(n0, r0))


def test_graded_o_grid_disk_coarsens_inward():
    r = 0.012
    nodes, el, surf = o_grid_disk(
        r, 60, [r, 0.011, 0.0095, 0.008, 0.008], [0, 0, 0, 0, 1], 0.004, coarsen=[1, 2, 1, 1]
    )
    assert len(surf) == 60
    assert jacobian_determinants(nodes, el).min() > 0
    assert signed_areas(nodes, el).sum() == pytest.approx(polygon_area(60, r), rel=1e-12)
    assert len(boundary_segments(el)) == 60


def test_statistics_of_a_uniform_grid():
    m = rectangle_mesh(0.004, 0.002, 8, 2)  # 0.5 mm x 1 mm cells
    st = mesh_statistics(m)
    c = wave_speed(210e9, 0.3, 7850.0)
    assert c == pytest.approx(np.sqrt(210e9 * 0.7 / (1.3 * 0.4) / 7850.0))
    assert st.min_size == pytest.approx(0.5e-3) and st.max_size == pytest.approx(1e-3)
    assert st.worst_aspect == pytest.approx(2.0)
    assert st.worst_jacobian_ratio == pytest.approx(1.0)
    lc = 0.5e-3 * 1e-3 / np.hypot(0.5e-3, 1e-3)
    assert st.critical_dt == pytest.approx(lc / c)
    assert st.part_elements == {"rectangle": 16}
    assert "16 elements" in st.summary()


def test_orientation_is_fixed_per_block_and_tangles_are_refused():
    m = rectangle_mesh(1.0, 1.0, 2, 1)
    flipped = m.elements[:, ::-1]
    assert np.array_equal(orient_ccw(m.nodes, flipped), m.elements)
    mixed = m.elements.copy()
    mixed[0] = mixed[0, ::-1]
    with pytest.raises(ValueError, match="inverted"):
        orient_ccw(m.nodes, mixed)
