"""Single-part meshes: rectangle, annulus and disk. Used as solver test bodies and as the
building blocks of the bearing mesh."""

from __future__ import annotations

import numpy as np

from taichi_bearing.mesh.grid import orient_ccw, quad_grid, surface_chain
from taichi_bearing.mesh.ogrid import o_grid_disk
from taichi_bearing.mesh.types import Mesh


def single_part_mesh(
    name: str, nodes: np.ndarray, elements: np.ndarray, surfaces: dict[str, np.ndarray]
) -> Mesh:
    """A one-part :class:`Mesh` whose node sets are the nodes of its surfaces."""
    node_sets = {key: np.unique(seg.ravel()) for key, seg in surfaces.items()}
    return Mesh(
        nodes=np.asarray(nodes, dtype=float),
        elements=np.asarray(elements, dtype=np.int64),
        element_part=np.zeros(len(elements), dtype=np.int64),
        part_names=[name],
        node_sets=node_sets,
        surfaces=surfaces,
    )


def rectangle_mesh(
    width: float,
    height: float,
    nx: int,
    ny: int,
    origin: tuple[float, float] = (0.0, 0.0),
) -> Mesh:
    """A uniform ``nx x ny`` grid on ``[x0, x0 + width] x [y0, y0 + height]``.

    Surfaces and node sets ``bottom``, ``right``, ``top``, ``left``; each surface runs
    counter-clockwise around the rectangle (body on the left).
    """
    if width <= 0 or height <= 0:
        raise ValueError(f"rectangle sides must be positive, got {width} x {height}")
    x0, y0 = origin
    xs = x0 + width * np.arange(nx + 1) / nx
    ys = y0 + height * np.arange(ny + 1) / ny
    gx, gy = np.meshgrid(xs, ys)
    nodes = np.stack([gx.ravel(), gy.ravel()], axis=1)
    elements = quad_grid(nx, ny)
    tol = 1e-9 * max(width, height)
    sides = {
        "bottom": lambda m: np.abs(m[:, 1] - y0) < tol,
        "right": lambda m: np.abs(m[:, 0] - (x0 + width)) < tol,
        "top": lambda m: np.abs(m[:, 1] - (y0 + height)) < tol,
        "left": lambda m: np.abs(m[:, 0] - x0) < tol,
    }
    surfaces = {key: surface_chain(nodes, elements, on) for key, on in sides.items()}
    return single_part_mesh("rectangle", nodes, elements, surfaces)


def annulus_mesh(r_inner: float, r_outer: float, n_theta: int, n_radial: int) -> Mesh:
    """A uniform polar grid of the ring ``r_inner <= r <= r_outer`` centred on the origin.

    Surfaces ``outer`` (counter-clockwise) and ``inner`` (clockwise, a hole); node sets of
    the same names.
    """
    if not 0 < r_inner < r_outer:
        raise ValueError(f"need 0 < r_inner < r_outer, got {r_inner}, {r_outer}")
    theta = 2 * np.pi * np.arange(n_theta) / n_theta
    radii = np.linspace(r_inner, r_outer, n_radial + 1)
    nodes = np.concatenate([r * np.stack([np.cos(theta), np.sin(theta)], axis=1) for r in radii])
    elements = orient_ccw(nodes, quad_grid(n_theta, n_radial, periodic=True))
    surfaces = _circle_surfaces(nodes, elements, {"outer": r_outer, "inner": r_inner})
    return single_part_mesh("annulus", nodes, elements, surfaces)


def disk_mesh(radius: float, n_surface: int, n_layers: int | None = None) -> Mesh:
    """An O-grid disk: ``n_layers`` rings around a square core (no degenerate centre).

    Parameters
    ----------
    radius : float
        Disk radius, centred on the origin.
    n_surface : int
        Segments on the circumference (even: every all-quad mesh has an even boundary).
    n_layers : int, optional
        Rings between the surface and the core square (half side ``radius / 2``); default
        about one surface segment length per ring.

    Surface and node set ``outer`` (counter-clockwise).
    """
    if radius <= 0:
        raise ValueError(f"radius must be positive, got {radius}")
    half = 0.5 * radius
    if n_layers is None:
        n_layers = max(1, round((radius - half) / (2 * np.pi * radius / n_surface)))
    w = np.arange(n_layers + 1) / n_layers
    nodes, elements, _ = o_grid_disk(radius, n_surface, [radius] * (n_layers + 1), w, half)
    surfaces = _circle_surfaces(nodes, elements, {"outer": radius})
    return single_part_mesh("disk", nodes, elements, surfaces)


def _circle_surfaces(
    nodes: np.ndarray, elements: np.ndarray, radii: dict[str, float]
) -> dict[str, np.ndarray]:
    """Boundary chains lying on circles about the origin, by name."""
    out = {}
    for key, r in radii.items():
        out[key] = surface_chain(
            nodes, elements, lambda m, r=r: np.abs(np.hypot(m[:, 0], m[:, 1]) - r) < 1e-6 * r
        )
    return out
