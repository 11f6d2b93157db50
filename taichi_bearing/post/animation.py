"""Animation of the spall region from a run's field frames (``python -m taichi_bearing
animate RUN_DIR``): the deformed mesh coloured by von Mises stress, the rollers passing
through the spall, the time of each frame.

Rollers travel tens of millimetres in a run and the inner ring turns, so the displacement
is split per part into the rigid motion that best fits it near the window and the elastic
rest (:func:`~taichi_bearing.post.deformed_render.rigid_and_elastic`); each part is drawn
at its rigid position plus ``scale`` times its elastic displacement. ``scale = 1`` is the
true deformed geometry. With ``scale > 1`` the contact approach shows, and each roller is
moved along the radius to keep its contact with the spall's ring closed
(:func:`contact_closing`): otherwise a loaded roller would be drawn ``scale - 1`` times its
approach away from the raceway.

Everything but :func:`draw_animation` works on plain arrays: reading a frame
(:func:`read_frame`), picking frames (:func:`select_frames`), the view window
(:class:`View`, :func:`spall_view`, :func:`custom_view`), the cells in view
(:func:`frame_in_view`), the colour range (:func:`colour_range`) and the displacement
scale (:func:`auto_scale`). Matplotlib is imported only to draw. Never imports Taichi.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from taichi_bearing.post.deformed_render import nice_factor, rigid_and_elastic

__all__ = [
    "ANIMATION_FILES",
    "FORMATS",
    "SMOOTH_FRAME_INTERVAL_MS",
    "Frame",
    "FrameInView",
    "View",
    "animate_run",
    "animation_note",
    "auto_scale",
    "colour_range",
    "contact_closing",
    "custom_view",
    "draw_animation",
    "follow_nodes",
    "frame_in_view",
    "nearest_nodes",
    "node_parts",
    "read_frame",
    "ring_points",
    "select_frames",
    "spall_view",
]

#: Output file of each format, in the run folder by default.
ANIMATION_FILES = {"gif": "animation.gif", "mp4": "animation.mp4"}
FORMATS = tuple(ANIMATION_FILES)
#: Frame interval (``run.frame_interval_ms``) that shows a smooth spall passage.
SMOOTH_FRAME_INTERVAL_MS = 0.02
#: Height of the default view over its width.
ASPECT = 0.55
#: The auto scale shows the largest elastic displacement in view as this share of the
#: view's height (then rounded down to 1, 2 or 5 times a power of ten).
AUTO_SCALE_FRACTION = 0.04
CMAP = "turbo"
#: Colour bands: a GIF holds 256 colours a frame, so a smooth map would band unevenly.
COLOUR_LEVELS = 16


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


# --------------------------------------------------------------------------- drawing


@dataclass(frozen=True)
class Labels:
    """Text drawn on the animation.

    Attributes
    ----------
    title : str
        First title line (case, spall, load, speed).
    part_names : list of str
        Name of each part id (rollers are labelled by name when in view); may be empty.
    notes : callable, optional
        Extra text for a frame's time (e.g. which roller is in the spall), s -> str.
    mark_side : float, optional
        Local ``y`` side (+1 or -1) of the marked nodes (the spall's edges) where their
        red triangles are drawn, pointing at them: the ring's side.
    closing : str
        How the rollers are kept in contact (:func:`contact_closing`), for the subtitle.
    """

    title: str
    part_names: list[str] = field(default_factory=list)
    notes: Callable[[float], str] | None = None
    mark_side: float = 1.0
    closing: str = ""


def draw_animation(
    frames: Iterable[FrameInView],
    out: str | os.PathLike,
    *,
    scale: float,
    vm_range: tuple[float, float],
    labels: Labels,
    fmt: str = "gif",
    fps: float = 10.0,
    width_px: int = 960,
) -> tuple[int, tuple[int, int]]:
    """Draw the frames into a GIF (Pillow) or MP4 (ffmpeg).

    Parameters
    ----------
    frames : iterable of FrameInView
        Drawn one at a time (a generator keeps one frame in memory).
    out : str or path-like
        Output file, written directly (wrap in an atomic rename for safety).
    scale : float
        Elastic displacement scale.
    vm_range : tuple of float
        Colour range, Pa (shown in MPa).
    labels : Labels
    fmt : {'gif', 'mp4'}
    fps : float
    width_px : int
        Width of the picture; its height is 9/16 of it.

    Returns
    -------
    n_frames : int
    size : tuple of int
        ``(width, height)`` in pixels.
    """
    from matplotlib import colormaps, colors, patheffects
    from matplotlib.animation import FFMpegWriter, PillowWriter
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    dpi = 100
    size = (int(width_px), int(round(width_px * 9 / 16)))
    fig = Figure(figsize=(size[0] / dpi, size[1] / dpi), dpi=dpi, facecolor="white")
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.075, 0.11, 0.80, 0.73))
    cax = fig.add_axes((0.895, 0.11, 0.018, 0.73))
    norm = colors.Normalize(vm_range[0] / 1e6, max(vm_range[1], vm_range[0] + 1.0) / 1e6)
    cmap = colormaps[CMAP].resampled(COLOUR_LEVELS)
    bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), cax=cax)
    bar.set_label("von Mises stress (MPa)")
    fig.text(0.075, 0.962, labels.title, fontsize=11, weight="bold", va="center")
    subtitle = (
        "colour: von Mises stress, one range for all frames; red triangles: the spall's edges\n"
        f"elastic displacement x{scale:g} (each part's rigid motion true{labels.closing})"
    )
    fig.text(0.075, 0.9, subtitle, fontsize=8.5, va="center", color="0.25", linespacing=1.4)
    outline = [patheffects.withStroke(linewidth=2.5, foreground="white")]
    writer = (PillowWriter if fmt == "gif" else FFMpegWriter)(fps=fps)
    n = 0
    with writer.saving(fig, str(out), dpi):
        for f in frames:
            ax.clear()
            view = f.view
            ax.set_xlim(1e3 * view.x0, 1e3 * view.x1)
            ax.set_ylim(1e3 * view.y0, 1e3 * view.y1)
            ax.set_aspect("equal", adjustable="box")
            ax.set_facecolor("white")
            ax.set_xlabel("along the raceway from the spall centre (mm)")
            ax.set_ylabel("radial, from the raceway (mm)")
            ax.add_collection(
                PolyCollection(
                    1e3 * f.shown(scale),
                    array=f.von_mises / 1e6,
                    cmap=cmap,
                    norm=norm,
                    edgecolors=(0.0, 0.0, 0.0, 0.18),
                    linewidths=0.25,
                )
            )
            if len(f.marks):
                m = 1e3 * f.shown_marks(scale)
                dy = 0.02e3 * view.height * labels.mark_side
                marker = "v" if labels.mark_side > 0 else "^"
                ax.plot(m[:, 0], m[:, 1] + dy, marker, color="red", ms=8, mec="white", mew=0.8)
            _label_parts(ax, f, scale, labels.part_names, outline)
            note = labels.notes(f.time) if labels.notes else ""
            ax.text(
                0.012,
                0.975,
                f"t = {1e3 * f.time:.3f} ms" + (f"\n{note}" if note else ""),
                transform=ax.transAxes,
                va="top",
                fontsize=12,
                weight="bold",
                path_effects=outline,
            )
            writer.grab_frame()
            n += 1
    return n, size


def _label_parts(ax, f: FrameInView, scale: float, names: list[str], outline) -> None:
    """Write each roller's name at its centroid when the centroid is in view."""
    shown = f.shown(scale)
    for p in np.unique(f.part):
        name = names[p] if 0 <= p < len(names) else ""
        if not name.startswith("roller"):
            continue
        centre = shown[f.part == p].reshape(-1, 2).mean(axis=0)
        if f.view.contains(centre):
            ax.text(
                *(1e3 * centre),
                name.replace("roller", "roller "),
                ha="center",
                va="center",
                fontsize=10,
                weight="bold",
                path_effects=outline,
                clip_on=True,
            )


# --------------------------------------------------------------------------- a run


def animation_note(run_dir: str | os.PathLike) -> str | None:
    """A sentence linking the run's animation (Markdown), None when there is none.

    For the run report: ``[Para(n) for n in [animation_note(run_dir)] if n]``.
    """
    files = [name for name in ANIMATION_FILES.values() if (Path(run_dir) / name).is_file()]
    if not files:
        return None
    links = " and ".join(f"[{name}]({name})" for name in files)
    return (
        f"Animation of the spall region over the run's field frames: {links} "
        "(`python -m taichi_bearing animate RUN_DIR`)."
    )


def _passage_note(events: list[dict]) -> Callable[[float], str]:
    """Time -> 'roller j in the spall' from the run's passage events."""

    def note(t: float) -> str:
        inside = [
            e
            for e in events
            if e.get("roller") is not None
            and e["entry_time_s"] <= t <= e["exit_time_s"]  # NaN compares False
        ]
        return ", ".join(f"roller {e['roller']} in the spall" for e in inside)

    return note


def _title(run, case) -> str:
    d, op = case.defect, case.operating
    spall = (
        f"{d.race} raceway spall {1e3 * d.length:.3g} x {1e3 * d.depth:.3g} mm"
        if d.present
        else "healthy bearing"
    )
    return f"{run.case_name}: {spall}, {op.load / 1e3:.3g} kN, {op.shaft_rpm:.4g} rpm"


def animate_run(
    run_dir: str | os.PathLike,
    out: str | os.PathLike,
    *,
    fmt: str = "gif",
    scale: float | None = None,
    fps: float = 10.0,
    from_s: float | None = None,
    to_s: float | None = None,
    every: int = 1,
    centre: tuple[float, float] | None = None,
    width: float | None = None,
    height: float | None = None,
    width_px: int = 960,
) -> dict:
    """Write the animation of a run folder's frames.

    Parameters
    ----------
    run_dir : str or path-like
        A run folder with frames (:data:`taichi_bearing.run_folder.FRAMES_DIR`).
    out : str or path-like
        Output file (written atomically).
    fmt : {'gif', 'mp4'}
    scale : float, optional
        Elastic displacement scale; default :func:`auto_scale`.
    fps : float
    from_s, to_s : float, optional
        Times of the first and last frames, s.
    every : int
        Every n-th frame.
    centre : tuple of float, optional
        Window centre, m (bearing coordinates); default the spall (:func:`spall_view`),
        and the window follows the spall's ring.
    width, height : float, optional
        Window size, m.
    width_px : int

    Returns
    -------
    dict
        ``file``, ``n_frames``, ``times_s``, ``scale``, ``von_mises_range_Pa``, ``view``
        (:class:`View` of the first frame), ``size_px``.

    Raises
    ------
    FileNotFoundError
        If the folder is not a run folder or has no frames.
    ValueError
        If fewer than 2 frames are selected, or a frame is unreadable.
    """
    from diagnostics.files import atomic_path
    from taichi_bearing.case import parse_case
    from taichi_bearing.output.vtk import read_pvd
    from taichi_bearing.run_folder import (
        FRAMES_DIR,
        MESH_STATISTICS_FILE,
        PVD_FILE,
        load_run,
        read_json,
    )

    run = load_run(run_dir)
    pvd = run.run_dir / FRAMES_DIR / PVD_FILE
    if not pvd.is_file():
        raise FileNotFoundError(
            f"{run.run_dir}: no {FRAMES_DIR}/{PVD_FILE} (the run wrote no frames: output.frames)"
        )
    entries = read_pvd(pvd)
    chosen = select_frames(entries, from_s, to_s, every)
    if len(chosen) < 2:
        raise ValueError(
            f"{pvd}: {len(chosen)} of {len(entries)} frames selected; an animation needs at "
            f"least 2 (widen --from-ms/--to-ms, or run with --set "
            f"run.frame_interval_ms={SMOOTH_FRAME_INTERVAL_MS:g})"
        )
    case = parse_case(run.case)
    if centre is None:
        view = spall_view(case, width, height)
    else:
        view = custom_view(centre, width or spall_view(case).width, height)
    first = read_frame(pvd.parent / chosen[0][1], chosen[0][0])
    node_part = node_parts(len(first.points), first.cells, first.part)
    in_ring, edges = ring_points(case)
    follow = follow_nodes(first.points, node_part, in_ring)
    ring_part = int(node_part[follow[0]])
    marks = () if edges is None else nearest_nodes(first.points, edges, node_part == ring_part)
    follow = follow if centre is None else None
    stats_path = run.run_dir / MESH_STATISTICS_FILE
    names = list(read_json(stats_path).get("part_elements", {})) if stats_path.is_file() else []
    rollers = [p for p, name in enumerate(names) if name.startswith("roller")]
    side = -1.0 if case.defect.present and case.defect.race == "inner" else 1.0
    contact = (ring_part, rollers, side) if rollers else None

    def in_view() -> Iterator[FrameInView]:
        for t, name in chosen:
            frame = read_frame(pvd.parent / name, t)
            yield frame_in_view(frame, view, node_part, follow, marks, contact)

    # Pass 1: the colour range and the scale over every frame; pass 2 draws (one frame in
    # memory at a time: a run may have thousands).
    peaks: list[float] = []

    def tracked() -> Iterator[FrameInView]:
        for f in in_view():
            peaks.append(f.peak_elastic)
            yield f

    lo, hi = colour_range(tracked())
    peak = max(peaks)
    scale = auto_scale(peak, view.height) if scale is None else float(scale)

    race = "outer" if side > 0 else "inner"
    closing = f"; rollers kept on the {race} raceway" if rollers else ""
    labels = Labels(_title(run, case), names, _passage_note(run.events), side, closing)
    with atomic_path(out) as tmp:
        n, size = draw_animation(
            in_view(),
            tmp,
            scale=scale,
            vm_range=(lo, hi),
            labels=labels,
            fmt=fmt,
            fps=fps,
            width_px=width_px,
        )
    return {
        "file": Path(out),
        "n_frames": n,
        "times_s": [t for t, _ in chosen],
        "scale": scale,
        "von_mises_range_Pa": (lo, hi),
        "peak_elastic_m": peak,
        "view": view,
        "size_px": size,
    }
