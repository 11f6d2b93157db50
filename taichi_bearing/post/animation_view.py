"""What an animation of the spall region shows, as plain arrays: the run's field frames
(:func:`read_frame`, :func:`select_frames`), the view window (:class:`View`,
:func:`spall_view`, :func:`custom_view`), the cells in view with each part at its rigid
motion plus ``scale`` times its elastic displacement (:func:`frame_in_view`,
:func:`contact_closing`), the colour range (:func:`colour_range`) and the displacement
scale (:func:`auto_scale`). Drawn by :mod:`taichi_bearing.post.animation`; no matplotlib,
no Taichi.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from taichi_bearing.post.deformed_render import nice_factor, rigid_and_elastic

__all__ = [
    "ASPECT",
    "AUTO_SCALE_FRACTION",
    "Frame",
    "FrameInView",
    "View",
    "auto_scale",
    "colour_range",
    "contact_closing",
    "custom_view",
    "follow_nodes",
    "frame_in_view",
    "nearest_nodes",
    "node_parts",
    "read_frame",
    "ring_points",
    "select_frames",
    "spall_view",
]

#: Height of the default view over its width.
ASPECT = 0.55
#: The auto scale shows the largest elastic displacement in view as this share of the
#: view's height (then rounded down to 1, 2 or 5 times a power of ten).
AUTO_SCALE_FRACTION = 0.04


# --------------------------------------------------------------------------- frames


@dataclass(frozen=True)
class Frame:
    """One field frame as plain arrays (SI units).

    Attributes
    ----------
    time : float
        Simulated time of the transient, s.
    points : ndarray, shape (n_nodes, 2)
        Reference coordinates, m.
    cells : ndarray, shape (n_cells, 4)
        Node indices of each quadrilateral.
    part : ndarray, shape (n_cells,)
        Part id of each cell.
    displacement : ndarray, shape (n_nodes, 2)
        m.
    von_mises : ndarray, shape (n_cells,)
        Pa.
    """

    time: float
    points: np.ndarray
    cells: np.ndarray
    part: np.ndarray
    displacement: np.ndarray
    von_mises: np.ndarray


def read_frame(path: str | os.PathLike, time: float) -> Frame:
    """Read one VTU frame written by the run (:class:`taichi_bearing.output.vtk.FrameWriter`).

    Parameters
    ----------
    path : str or path-like
        The ``.vtu`` file.
    time : float
        Its time in the ``.pvd`` series, s.

    Returns
    -------
    Frame

    Raises
    ------
    ValueError
        If the file is not readable or lacks quads, ``displacement``, ``von_mises`` or
        ``part``.
    """
    import meshio

    try:
        mesh = meshio.read(path)
    except Exception as exc:  # meshio raises many kinds; the message says which file
        raise ValueError(f"{path}: not a readable VTU frame ({exc})") from None
    quads = [c.data for c in mesh.cells if c.type == "quad"]
    missing = [k for k in ("displacement",) if k not in mesh.point_data]
    missing += [k for k in ("von_mises", "part") if k not in mesh.cell_data]
    if len(quads) != 1 or missing:
        what = ", ".join(missing) if missing else "one block of quads"
        raise ValueError(f"{path}: not a field frame (lacks {what})")
    return Frame(
        time=float(time),
        points=np.asarray(mesh.points[:, :2], dtype=float),
        cells=np.asarray(quads[0], dtype=np.int64),
        part=np.asarray(mesh.cell_data["part"][0], dtype=np.int64),
        displacement=np.asarray(mesh.point_data["displacement"][:, :2], dtype=float),
        von_mises=np.asarray(mesh.cell_data["von_mises"][0], dtype=float),
    )


def select_frames(
    entries: Sequence[tuple[float, str]],
    from_s: float | None = None,
    to_s: float | None = None,
    every: int = 1,
) -> list[tuple[float, str]]:
    """The frames of a ``.pvd`` series between two times (both included), every n-th.

    Parameters
    ----------
    entries : sequence of (float, str)
        ``(time, file)`` of each frame, s (:func:`taichi_bearing.output.vtk.read_pvd`).
    from_s, to_s : float, optional
        Times of the first and last frames wanted, s; default the series' ends.
    every : int, optional
        Keep every n-th frame of those in the interval, starting with the first.

    Returns
    -------
    list of (float, str)
        In order of time.

    Raises
    ------
    ValueError
        If ``every`` is below 1 or ``from_s`` exceeds ``to_s``.
    """
    if int(every) != every or every < 1:
        raise ValueError(f"every must be an integer >= 1, got {every!r}")
    if from_s is not None and to_s is not None and from_s > to_s:
        raise ValueError(f"from ({from_s!r} s) is after to ({to_s!r} s)")
    lo = -math.inf if from_s is None else from_s
    hi = math.inf if to_s is None else to_s
    # A relative tolerance so that --to-ms 0.2 takes the frame written at 0.20000000000000004 ms.
    tol = 1e-9 * max((abs(t) for t, _ in entries), default=0.0)
    kept = sorted((e for e in entries if lo - tol <= e[0] <= hi + tol), key=lambda e: e[0])
    return kept[:: int(every)]


def node_parts(n_nodes: int, cells: np.ndarray, part: np.ndarray) -> np.ndarray:
    """Part id of each node from its cells' parts (-1: in no cell).

    Parameters
    ----------
    n_nodes : int
    cells : ndarray, shape (n_cells, 4)
    part : ndarray, shape (n_cells,)

    Returns
    -------
    ndarray, shape (n_nodes,)
    """
    out = np.full(int(n_nodes), -1, dtype=np.int64)
    out[cells.ravel()] = np.repeat(part, cells.shape[1])
    return out


# --------------------------------------------------------------------------- view


@dataclass(frozen=True)
class View:
    """A window on the bearing, in coordinates along and across a raceway.

    Local coordinates: origin at ``origin``; ``y`` along the radial direction at polar
    angle ``up`` (outward from the bearing centre), ``x`` along the raceway, to the right
    looking from the centre. At 12 o'clock (``up = pi/2``) they are the bearing's own.

    Attributes
    ----------
    origin : tuple of float
        Bearing coordinates of the local origin, m (the spall centre on the raceway).
    up : float
        Polar angle of the local ``y`` axis, rad, counter-clockwise from ``+x``.
    x0, x1, y0, y1 : float
        The window in local coordinates, m.
    """

    origin: tuple[float, float]
    up: float
    x0: float
    x1: float
    y0: float
    y1: float

    @property
    def width(self) -> float:
        return self.x1 - self.x0

    @property
    def height(self) -> float:
        return self.y1 - self.y0

    def rotate(self, vectors: np.ndarray) -> np.ndarray:
        """Components of bearing-frame vectors ``(..., 2)`` along local ``x`` and ``y``."""
        c, s = math.cos(self.up), math.sin(self.up)
        v = np.asarray(vectors, dtype=float)
        return np.stack([s * v[..., 0] - c * v[..., 1], c * v[..., 0] + s * v[..., 1]], -1)

    def local(self, points: np.ndarray) -> np.ndarray:
        """Local coordinates of bearing-frame points ``(..., 2)``, m."""
        return self.rotate(np.asarray(points, dtype=float) - np.asarray(self.origin))

    def contains(self, local: np.ndarray) -> np.ndarray:
        """Whether local points ``(..., 2)`` lie in the window (edges included)."""
        x, y = local[..., 0], local[..., 1]
        return (x >= self.x0) & (x <= self.x1) & (y >= self.y0) & (y <= self.y1)

    def moved(self, angle: float, shift: np.ndarray) -> View:
        """The view carried by the rigid motion ``x -> R(angle) x + shift``."""
        c, s = math.cos(angle), math.sin(angle)
        ox, oy = self.origin
        origin = (c * ox - s * oy + float(shift[0]), s * ox + c * oy + float(shift[1]))
        return replace(self, origin=origin, up=self.up + angle)


def _window(width: float, height: float, roller_side: float) -> tuple[float, ...]:
    """``x0, x1, y0, y1`` of a window centred along the raceway, with ``roller_side``
    (-1 or +1) of the raceway taking 65 % of its height (a whole roller in view)."""
    below = 0.65 * height if roller_side < 0 else 0.35 * height
    return -0.5 * width, 0.5 * width, -below, height - below


def spall_view(case, width: float | None = None, height: float | None = None) -> View:
    """The default view: centred on the spall, a few roller diameters wide.

    Parameters
    ----------
    case : taichi_bearing.case.Case
        The run's case (its bearing and defect).
    width, height : float, optional
        Window size, m; default ``max(3 D, spall length + 2 D)`` wide (``D`` the roller
        diameter) and :data:`ASPECT` times the width high. The raceway lies at 35 % of the
        height from the ring's side, so a whole roller is in view.

    Returns
    -------
    View
        At 12 o'clock on the outer raceway for a healthy bearing.
    """
    b, d = case.bearing, case.defect
    present = bool(d.present)
    race = d.race if present else "outer"
    angle = d.angle if present else 0.0
    length = d.length if present else 0.0
    radius = b.outer_raceway_radius if race == "outer" else b.inner_raceway_radius
    width = width or max(3.0 * b.roller_diameter, length + 2.0 * b.roller_diameter)
    height = height or ASPECT * width
    up = 0.5 * math.pi + angle  # case angles are from 12 o'clock
    origin = (radius * math.cos(up), radius * math.sin(up))
    return View(origin, up, *_window(width, height, -1.0 if race == "outer" else 1.0))


def custom_view(centre: tuple[float, float], width: float, height: float | None = None) -> View:
    """A window centred on a point of the bearing, its ``y`` axis radial there.

    Parameters
    ----------
    centre : tuple of float
        Bearing coordinates of the window centre, m.
    width : float
        m.
    height : float, optional
        m; default :data:`ASPECT` times the width.
    """
    height = height or ASPECT * width
    x, y = centre
    up = math.atan2(y, x) if math.hypot(x, y) > 0 else 0.5 * math.pi
    return View((float(x), float(y)), up, -0.5 * width, 0.5 * width, -0.5 * height, 0.5 * height)


def ring_points(case) -> tuple[np.ndarray, np.ndarray | None]:
    """Reference points of the spall's ring: one inside the ring's material beyond the
    spall floor (it picks the ring's nodes, never a roller's) and the spall's two edges
    on the raceway (None for a healthy bearing), bearing coordinates, m.

    Parameters
    ----------
    case : taichi_bearing.case.Case

    Returns
    -------
    in_ring : ndarray, shape (2,)
    edges : ndarray, shape (2, 2) or None
    """
    b, d = case.bearing, case.defect
    race = d.race if d.present else "outer"
    radius = b.outer_raceway_radius if race == "outer" else b.inner_raceway_radius
    up = 0.5 * math.pi + (d.angle if d.present else 0.0)
    # Twice the depth is still in the ring: the case limits the depth to half its thickness.
    depth = 2.0 * (d.depth if d.present else 0.0) + 1e-4
    r_in = radius + depth if race == "outer" else radius - depth
    in_ring = np.array([r_in * math.cos(up), r_in * math.sin(up)])
    if not d.present:
        return in_ring, None
    half = 0.5 * d.length / radius
    edges = np.array([[radius * math.cos(a), radius * math.sin(a)] for a in (up + half, up - half)])
    return in_ring, edges


def nearest_nodes(
    points: np.ndarray, targets: np.ndarray, among: np.ndarray | None = None
) -> np.ndarray:
    """Index of the node nearest each target point.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
    targets : ndarray, shape (k, 2)
    among : ndarray of bool, shape (n,), optional
        Only these nodes.

    Returns
    -------
    ndarray of int, shape (k,)
    """
    ids = np.arange(len(points)) if among is None else np.flatnonzero(among)
    d = np.hypot(*(points[ids][None, :, :] - np.asarray(targets)[:, None, :]).transpose(2, 0, 1))
    return ids[np.argmin(d, axis=1)]


def follow_nodes(points: np.ndarray, node_part: np.ndarray, in_body: np.ndarray) -> tuple[int, int]:
    """Two nodes of the body holding the point ``in_body`` whose motion a view follows:
    the node nearest the point and the node of the same part farthest from it."""
    i = int(nearest_nodes(points, np.asarray(in_body)[None])[0])
    same = np.flatnonzero(node_part == node_part[i])
    j = int(same[np.argmax(np.hypot(*(points[same] - points[i]).T))])
    return i, j


def _motion_of(points: np.ndarray, current: np.ndarray, i: int, j: int) -> tuple[float, np.ndarray]:
    """``(angle, shift)`` of the rigid motion taking ``points[i], points[j]`` to
    ``current[i], current[j]``."""
    a, b = points[j] - points[i], current[j] - current[i]
    angle = math.atan2(b[1], b[0]) - math.atan2(a[1], a[0])
    c, s = math.cos(angle), math.sin(angle)
    return angle, current[i] - np.array([[c, -s], [s, c]]) @ points[i]


# --------------------------------------------------------------------------- cells in view


@dataclass(frozen=True)
class FrameInView:
    """The cells of a frame near the window, in the window's local coordinates (m).

    Attributes
    ----------
    time : float
        s.
    rigid : ndarray, shape (m, 4, 2)
        Corner positions of each cell moved by the rigid motion that best fits its part's
        motion near the window.
    elastic : ndarray, shape (m, 4, 2)
        The rest of each corner's displacement.
    von_mises : ndarray, shape (m,)
        Pa.
    part : ndarray, shape (m,)
    inside : ndarray of bool, shape (m,)
        The cell's centroid in its true deformed position (``rigid + elastic``) is in the
        window: the cells the colour range and the scale are taken over.
    view : View
        The window (it follows the spall's ring when asked to).
    marks : ndarray, shape (k, 2, 2)
        Rigid position and elastic displacement of each marked node near the window.
    """

    time: float
    rigid: np.ndarray
    elastic: np.ndarray
    von_mises: np.ndarray
    part: np.ndarray
    inside: np.ndarray
    view: View
    marks: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 2)))
    close: np.ndarray | None = None

    def shown(self, scale: float) -> np.ndarray:
        """Corner positions drawn with the elastic displacement times ``scale``, m (and
        the rollers moved to keep their contacts closed, :func:`contact_closing`)."""
        shown = self.rigid + scale * self.elastic
        return shown if self.close is None else shown + (scale - 1.0) * self.close

    def shown_marks(self, scale: float) -> np.ndarray:
        """Positions of the marked nodes, drawn as the cells are, m, shape (k, 2)."""
        return self.marks[:, 0] + scale * self.marks[:, 1]

    @property
    def peak_elastic(self) -> float:
        """Largest elastic displacement of a corner of a cell inside, m (0 if none)."""
        e = self.elastic[self.inside]
        return float(np.max(np.hypot(e[..., 0], e[..., 1]))) if e.size else 0.0


def frame_in_view(
    frame: Frame,
    view: View,
    node_part: np.ndarray,
    follow: tuple[int, int] | None = None,
    marks: Sequence[int] = (),
    contact: tuple[int, Sequence[int], float] | None = None,
    margin: float = 0.15,
) -> FrameInView:
    """The cells of ``frame`` near ``view``, split into rigid and elastic motion.

    The rigid motion of each part is fitted to its nodes near the window only
    (:func:`~taichi_bearing.post.deformed_render.rigid_and_elastic` on them): the ring's
    global bending is taken out, its local deformation (contact dents, the spall's edges)
    is left to magnify.

    Parameters
    ----------
    frame : Frame
    view : View
    node_part : ndarray, shape (n_nodes,)
        Part of each node (:func:`node_parts`).
    follow : tuple of int, optional
        Two nodes of one body (:func:`follow_nodes`): the view moves with them (an
        inner-ring spall turns with the shaft). Default: the view stays put.
    marks : sequence of int, optional
        Nodes to mark (the spall's edges); those near the window are returned.
    contact : tuple, optional
        ``(ring_part, roller_parts, side)`` of :func:`contact_closing`: keep the rollers'
        contacts with that ring closed when magnified.
    margin : float, optional
        Cells whose centroid lies within this share of the window's size outside it are
        kept too (drawn, clipped by the window), so no cell is missing at its edges.

    Returns
    -------
    FrameInView
    """
    current = frame.points + frame.displacement
    if follow is not None:
        view = view.moved(*_motion_of(frame.points, current, *follow))
    pad = margin * max(view.width, view.height)
    wide = replace(view, x0=view.x0 - pad, x1=view.x1 + pad, y0=view.y0 - pad, y1=view.y1 + pad)
    near = wide.contains(view.local(current)[frame.cells].mean(axis=1))
    nodes, cells = np.unique(frame.cells[near], return_inverse=True)
    cells = cells.reshape(-1, frame.cells.shape[1])
    rigid, elastic = rigid_and_elastic(
        frame.points[nodes], frame.displacement[nodes], node_part[nodes]
    )
    rigid, elastic = view.local(rigid), view.rotate(elastic)
    inside = view.contains((rigid + elastic)[cells].mean(axis=1))
    k = np.searchsorted(nodes, np.asarray(marks, dtype=np.int64))
    k = k[(k < len(nodes)) & (nodes[np.minimum(k, len(nodes) - 1)] == np.asarray(marks))]
    close = np.zeros_like(rigid)
    if contact is not None:
        close = contact_closing(rigid, elastic, node_part[nodes], *contact, view.local(np.zeros(2)))
    return FrameInView(
        frame.time,
        rigid[cells],
        elastic[cells],
        frame.von_mises[near],
        frame.part[near],
        inside,
        view,
        np.stack([rigid[k], elastic[k]], axis=1),
        close[cells],
    )


def contact_closing(
    rigid: np.ndarray,
    elastic: np.ndarray,
    node_part: np.ndarray,
    ring_part: int,
    roller_parts: Sequence[int],
    side: float,
    centre: np.ndarray,
) -> np.ndarray:
    """Per node, the rigid shift of each roller that keeps its contact with a ring closed
    when elastic displacements are magnified, per unit of ``scale - 1``.

    Drawn at ``rigid + scale * elastic``, a roller and a ring in contact would stand
    ``(scale - 1)`` times their contact approach apart (the rigid positions already hold
    the approach). Each roller is moved along the radial line through its point nearest
    the ring by ``(e_ring - e_roller) . n``: the normal elastic displacements of the ring
    and the roller there. A roller away from the ring moves by the ring's elastic motion
    under it, as if it followed the magnified raceway.

    Parameters
    ----------
    rigid, elastic : ndarray, shape (n, 2)
        Nodes' rigid positions and elastic displacements (any frame), m.
    node_part : ndarray, shape (n,)
    ring_part : int
        The ring whose contacts are kept closed (the spall's).
    roller_parts : sequence of int
    side : float
        +1: the ring is outside the rollers (outer ring), -1: inside (inner ring).
    centre : ndarray, shape (2,)
        Bearing centre in the same coordinates.

    Returns
    -------
    ndarray, shape (n, 2)
        Zero for nodes of parts other than the rollers.
    """
    out = np.zeros_like(rigid)
    ring = np.flatnonzero(node_part == ring_part)
    if ring.size == 0:
        return out
    current = rigid + elastic
    for p in roller_parts:
        ids = np.flatnonzero(node_part == p)
        if ids.size == 0:
            continue
        radius = np.hypot(*(current[ids] - centre).T)
        a = ids[np.argmax(side * radius)]
        g = ring[np.argmin(np.hypot(*(current[ring] - current[a]).T))]
        n = (current[a] - centre) / (np.hypot(*(current[a] - centre)) or 1.0)
        out[ids] = float(np.dot(elastic[g] - elastic[a], n)) * n
    return out


def colour_range(frames: Iterable[FrameInView]) -> tuple[float, float]:
    """Smallest and largest von Mises stress of the cells inside the window over all
    frames, Pa: one fixed colour range for the animation.

    Raises
    ------
    ValueError
        If no frame has a cell inside its window.
    """
    lo, hi = math.inf, -math.inf
    for f in frames:
        values = f.von_mises[f.inside]
        if values.size:
            lo, hi = min(lo, float(values.min())), max(hi, float(values.max()))
    if lo > hi:
        raise ValueError("no cell of any frame lies in the view window")
    return lo, hi


def auto_scale(peak_elastic: float, height: float, fraction: float = AUTO_SCALE_FRACTION) -> float:
    """Displacement scale that shows the largest elastic displacement in view as about
    ``fraction`` of the window's height: a 1-2-5 number, at least 1.

    Parameters
    ----------
    peak_elastic : float
        Largest elastic displacement in view over the frames, m.
    height : float
        Window height, m.
    fraction : float, optional
    """
    if not peak_elastic > 0:
        return 1.0
    return nice_factor(fraction * height / peak_elastic)
