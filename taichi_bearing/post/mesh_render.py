"""Export the mesh to VTU (ParaView) and render it off-screen: the whole bearing with its
parts coloured, and a close-up of the spall showing its edges and the graded elements."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from bearing_io.files import atomic_path
from taichi_bearing.mesh.types import Mesh

# Part colours: outer ring and adapter steel blue, inner ring brass, rollers light grey
# with roller 0 (the reference roller) picked out.
OUTER_RGB = (0.55, 0.66, 0.80)
INNER_RGB = (0.86, 0.74, 0.42)
ROLLER_RGB = (0.72, 0.72, 0.70)
ROLLER0_RGB = (0.85, 0.45, 0.40)
SPALL_RGB = (0.85, 0.10, 0.10)


def write_mesh_vtu(mesh: Mesh, path: str | Path) -> Path:
    """Write ``mesh`` as an unstructured VTK file (quads).

    Cell data ``part_id``; point data ``part_id`` (of the body a node belongs to) and one
    0/1 array per node set and per sensor (``sensor_<name>``). The part names are in the
    field data ``part_names`` order (``part_id`` indexes them).
    """
    import meshio

    path = Path(path)
    points = np.column_stack([mesh.nodes, np.zeros(mesh.n_nodes)])
    node_part = np.full(mesh.n_nodes, -1, dtype=np.int32)
    node_part[mesh.elements.ravel()] = np.repeat(mesh.element_part, 4)
    point_data = {"part_id": node_part}
    for name, ids in mesh.node_sets.items():
        flag = np.zeros(mesh.n_nodes, dtype=np.int8)
        flag[ids] = 1
        point_data[name] = flag
    for name, node in mesh.sensor_nodes.items():
        flag = np.zeros(mesh.n_nodes, dtype=np.int8)
        flag[node] = 1
        point_data[f"sensor_{name}"] = flag
    out = meshio.Mesh(
        points,
        [("quad", mesh.elements.astype(np.int64))],
        point_data=point_data,
        cell_data={"part_id": [mesh.element_part.astype(np.int32)]},
    )
    with atomic_path(path) as tmp:
        out.write(tmp, file_format="vtu")
    return path


def part_colours(mesh: Mesh) -> np.ndarray:
    """RGB (0..1) of every element by part."""
    table = []
    for name in mesh.part_names:
        if name == "outer_ring":
            table.append(OUTER_RGB)
        elif name == "inner_ring":
            table.append(INNER_RGB)
        elif name == "roller0":
            table.append(ROLLER0_RGB)
        else:
            table.append(ROLLER_RGB)
    return np.asarray(table)[mesh.element_part]


def render_mesh_pictures(
    mesh: Mesh, out_dir: str | Path, size: int = 1600, title: str = ""
) -> list[Path]:
    """Render ``mesh_bearing.png`` (whole bearing) and, if there is a spall,
    ``mesh_spall.png`` (close-up) into ``out_dir``.

    Returns
    -------
    list of Path
        The pictures written.
    """
    out_dir = Path(out_dir)
    _quiet_vtk()
    written = []
    lo, hi = mesh.nodes.min(axis=0), mesh.nodes.max(axis=0)
    centre = 0.5 * (lo + hi)
    half_height = 0.5 * max(hi[1] - lo[1], hi[0] - lo[0]) * 1.06
    label = title or f"{mesh.n_elements} elements, {mesh.n_nodes} nodes"
    written.append(
        _render(
            mesh, out_dir / "mesh_bearing.png", centre, half_height, size, label, 0.4, legend=True
        )
    )
    spall = mesh.info.get("spall")
    if spall:
        a = spall["centre_angle"]
        r = 0.5 * (spall["raceway_radius"] + spall["floor_radius"])
        radial = np.array([math.cos(a), math.sin(a)])
        text = (
            f"spall: {1e3 * spall['length']:.3g} mm long, {1e3 * spall['depth']:.3g} mm deep, "
            f"centre {math.degrees(spall['centre_angle_from_top']):.3g} deg from 12 o'clock"
        )
        # Whole notch with some raceway either side, then its first edge close up.
        half_width = 0.5 * spall["length"] + 0.004
        focus = r * radial + 0.25 * half_width * radial * (1 if spall["race"] == "outer" else -1)
        written.append(
            _render(
                mesh,
                out_dir / "mesh_spall.png",
                focus,
                0.5 * half_width,
                size,
                text,
                1.0,
                up=radial,
                spall=spall,
                aspect=2.0,
            )
        )
        edge = spall["start_angle"]
        edge_point = r * np.array([math.cos(edge), math.sin(edge)])
        written.append(
            _render(
                mesh,
                out_dir / "mesh_spall_edge.png",
                edge_point,
                max(4 * spall["depth"], 3 * mesh.info["sizes"]["surface_size"]),
                size,
                text + " - entry edge",
                1.5,
                up=radial,
                spall=spall,
            )
        )
    return written


def _render(
    mesh,
    path,
    focus,
    half_height,
    size,
    text,
    line_width,
    up=(0.0, 1.0),
    spall=None,
    aspect=1.0,
    legend=False,
):
    import pyvista as pv

    grid = _grid(mesh)
    plotter = pv.Plotter(off_screen=True, window_size=(size, int(round(size / aspect))))
    plotter.set_background("white")
    plotter.add_mesh(
        grid,
        scalars=part_colours(mesh),
        rgb=True,
        show_edges=True,
        edge_color=(0.15, 0.15, 0.15),
        line_width=line_width,
        lighting=False,
    )
    if spall is not None:
        outline = _spall_outline(mesh, spall)
        plotter.add_mesh(outline, color=SPALL_RGB, line_width=4 * line_width)
        corners = np.column_stack(
            [mesh.nodes[spall["corner_nodes"]], np.full(len(spall["corner_nodes"]), 1e-6)]
        )
        plotter.add_points(corners, color=SPALL_RGB, point_size=12, render_points_as_spheres=True)
    plotter.add_text(text, position="upper_left", font_size=12, color="black")
    if legend:
        key = "blue: outer ring + adapter\nyellow: inner ring\nred: roller 0\ngrey: rollers"
        plotter.add_text(key, position="upper_right", font_size=12, color="black")
    return frame_and_save(plotter, path, focus, up, half_height)


def frame_and_save(plotter, path, focus, up, half_height: float):
    """Look straight down on the mesh plane at ``focus`` (``up`` upwards on the picture,
    ``half_height`` metres from centre to top edge), save a screenshot atomically, close."""
    plotter.enable_parallel_projection()
    cam = plotter.camera
    cam.focal_point = (float(focus[0]), float(focus[1]), 0.0)
    cam.position = (float(focus[0]), float(focus[1]), 1.0)
    cam.up = (float(up[0]), float(up[1]), 0.0)
    cam.parallel_scale = float(half_height)
    cam.clipping_range = (0.01, 10.0)
    with atomic_path(path) as tmp:
        plotter.screenshot(str(tmp))
    plotter.close()
    return path


def _spall_outline(mesh: Mesh, spall: dict):
    """The notch's walls and floor as lines, lifted slightly above the mesh plane."""
    import pyvista as pv

    surface = mesh.surfaces[f"{spall['race']}_raceway"]
    r = np.hypot(mesh.nodes[:, 0], mesh.nodes[:, 1])
    below = np.abs(r - spall["raceway_radius"]) > 1e-9 * spall["raceway_radius"]
    seg = surface[below[surface[:, 0]] | below[surface[:, 1]]]
    points = np.column_stack([mesh.nodes, np.full(mesh.n_nodes, 1e-6)])
    lines = np.column_stack([np.full(len(seg), 2), seg]).ravel()
    return pv.PolyData(points, lines=lines)


def _grid(mesh: Mesh):
    import pyvista as pv

    points = np.column_stack([mesh.nodes, np.zeros(mesh.n_nodes)])
    cells = np.column_stack([np.full(mesh.n_elements, 4), mesh.elements]).ravel()
    types = np.full(mesh.n_elements, pv.CellType.QUAD, dtype=np.uint8)
    return pv.UnstructuredGrid(cells, types, points)


def _quiet_vtk() -> None:
    """Silence VTK's 'no X server' warning: rendering is off-screen on purpose."""
    from vtkmodules.vtkCommonCore import vtkLogger

    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
