"""Off-screen render of a field frame around the spall: deformed mesh, von Mises colours.

Rollers travel tens of millimetres in a run and the inner ring turns, so magnifying the
whole displacement would be meaningless. Each part's displacement is split into its
best-fit rigid motion (2-D Procrustes: translation and rotation) and the elastic rest;
parts are drawn at their rigid position plus the magnified elastic part.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from taichi_bearing.post.mesh_render import _quiet_vtk, frame_and_save

__all__ = ["rigid_and_elastic", "render_spall_frame", "nice_factor"]


def rigid_and_elastic(
    points: np.ndarray, displacement: np.ndarray, node_part: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Split nodal displacements into per-part rigid motion and elastic remainder.

    Parameters
    ----------
    points : ndarray (n, 2)
        Reference coordinates.
    displacement : ndarray (n, 2)
    node_part : ndarray (n,)
        Part id of each node (-1: not in any element; treated as rigid with no motion).

    Returns
    -------
    rigid_position, elastic : ndarray (n, 2)
        ``points + displacement == rigid_position + elastic``.
    """
    current = points + displacement
    rigid = points.copy()
    for p in np.unique(node_part[node_part >= 0]):
        sel = node_part == p
        a, b = points[sel], current[sel]
        ca, cb = a.mean(axis=0), b.mean(axis=0)
        da, db = a - ca, b - cb
        angle = math.atan2(
            float(np.sum(da[:, 0] * db[:, 1] - da[:, 1] * db[:, 0])),
            float(np.sum(da[:, 0] * db[:, 0] + da[:, 1] * db[:, 1])),
        )
        c, s = math.cos(angle), math.sin(angle)
        rigid[sel] = cb + da @ np.array([[c, s], [-s, c]])
    return rigid, current - rigid


def nice_factor(value: float) -> float:
    """Largest 1-2-5 number not above ``value`` (at least 1)."""
    if not (value > 1.0 and math.isfinite(value)):
        return 1.0
    exp = math.floor(math.log10(value))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0**exp <= value:
            return m * 10.0**exp
    return 10.0**exp


def render_spall_frame(
    vtu_path: str | Path,
    out_path: str | Path,
    spall_point: tuple[float, float],
    half_height: float,
    spall_edges: tuple[tuple[float, float], tuple[float, float]] | None = None,
    title: str = "",
    size: int = 1400,
    target_fraction: float = 0.08,
) -> dict:
    """Render the frame in ``vtu_path`` around ``spall_point`` (reference coordinates, m).

    The elastic displacement is magnified so that its largest value in view is about
    ``target_fraction`` of the view's half height (a 1-2-5 factor). ``spall_edges``
    (reference points of the spall's two edges on the raceway) are marked in red.

    Returns
    -------
    dict
        ``magnification``, ``max_elastic_m`` (in view), ``max_von_mises_Pa`` (in view),
        ``file``.
    """
    import pyvista as pv

    _quiet_vtk()
    grid = pv.read(str(vtu_path))
    points = np.asarray(grid.points[:, :2], dtype=float)
    u = np.asarray(grid.point_data["displacement"][:, :2], dtype=float)
    cells = grid.cells.reshape(-1, 5)[:, 1:]
    part = np.asarray(grid.cell_data["part"])
    node_part = np.full(len(points), -1, dtype=int)
    node_part[cells.ravel()] = np.repeat(part, 4)
    rigid, elastic = rigid_and_elastic(points, u, node_part)

    # The spall moves with its ring: follow the nearest node of the same body.
    k = int(np.argmin(np.hypot(*(points - np.asarray(spall_point)).T)))
    focus = rigid[k] + elastic[k]
    near = np.hypot(*(rigid - focus).T) < 1.5 * half_height
    peak = float(np.max(np.hypot(*elastic[near].T))) if near.any() else 0.0
    mag = nice_factor(target_fraction * half_height / peak) if peak > 0 else 1.0
    shown = rigid + mag * elastic
    grid.points = np.column_stack([shown, np.zeros(len(shown))])
    vm = np.asarray(grid.cell_data["von_mises"], dtype=float) / 1e6
    grid.cell_data["von Mises (MPa)"] = vm
    centroids = shown[cells].mean(axis=1)
    in_view = np.hypot(*(centroids - focus).T) < 1.5 * half_height
    vm_max = float(vm[in_view].max()) if in_view.any() else float(vm.max())

    radial = focus / (np.hypot(*focus) or 1.0)
    plotter = pv.Plotter(off_screen=True, window_size=(size, int(size * 0.6)))
    plotter.set_background("white")
    plotter.add_mesh(
        grid,
        scalars="von Mises (MPa)",
        cmap="jet",
        clim=(0.0, max(vm_max, 1e-9)),
        show_edges=True,
        edge_color=(0.25, 0.25, 0.25),
        line_width=0.6,
        lighting=False,
        scalar_bar_args={
            "title": "von Mises (MPa)",
            "color": "black",
            "vertical": True,
            "position_x": 0.90,
            "position_y": 0.08,
            "height": 0.7,
            "width": 0.06,
            "fmt": "%.0f",
        },
    )
    if spall_edges is not None:
        ids = [int(np.argmin(np.hypot(*(points - np.asarray(p)).T))) for p in spall_edges]
        marks = np.column_stack([shown[ids], np.full(len(ids), 1e-6)])
        plotter.add_points(marks, color="red", point_size=18, render_points_as_spheres=True)
        text_marks = "; red dots: spall edges"
    else:
        text_marks = ""
    text = (
        title + f"\nelastic displacement x{mag:g} (rigid motion of each part removed)" + text_marks
    )
    plotter.add_text(text, position=(12, int(size * 0.6) - 60), font_size=10, color="black")
    out_path = frame_and_save(plotter, Path(out_path), focus, radial, half_height)
    return {
        "magnification": mag,
        "max_elastic_m": peak,
        "max_von_mises_Pa": 1e6 * vm_max,
        "file": out_path.name,
    }
