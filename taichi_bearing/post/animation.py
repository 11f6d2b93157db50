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

The frames, the view window, the cells in view, the colour range and the displacement
scale are plain-array functions in :mod:`taichi_bearing.post.animation_view`; here they
are drawn (matplotlib is imported only to draw) and written. Never imports Taichi.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from taichi_bearing.output.layout import ANIMATION_FILES
from taichi_bearing.post.animation_view import (
    Frame,
    FrameInView,
    View,
    auto_scale,
    colour_range,
    contact_closing,
    custom_view,
    follow_nodes,
    frame_in_view,
    nearest_nodes,
    node_parts,
    read_frame,
    ring_points,
    select_frames,
    spall_view,
)

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
FORMATS = tuple(ANIMATION_FILES)
#: Frame interval (``run.frame_interval_ms``) that shows a smooth spall passage.
SMOOTH_FRAME_INTERVAL_MS = 0.02
CMAP = "turbo"
#: Colour bands: a GIF holds 256 colours a frame, so a smooth map would band unevenly.
COLOUR_LEVELS = 16


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
        A run folder with frames (:data:`taichi_bearing.output.layout.FRAMES_DIR`).
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
    from bearing_io.files import atomic_path
    from taichi_bearing.case import parse_case
    from taichi_bearing.output.layout import FRAMES_DIR, MESH_STATISTICS_FILE, PVD_FILE
    from taichi_bearing.output.run_folder import load_run, read_json
    from taichi_bearing.output.vtk import read_pvd

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
