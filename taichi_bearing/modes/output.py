"""Files of a modal analysis: ``modes.csv``, a ParaView series of the shapes
(``modes.pvd`` + ``modes/mode_001.vtu`` ...) and a figure of the first shapes. Every file
is written to a temporary name and renamed."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from bearing_io.files import atomic_path
from taichi_bearing.mesh.grid import boundary_segments
from taichi_bearing.modes.solve import ModalResult

__all__ = ["CSV_COLUMNS", "write_modes", "write_modes_csv", "write_modes_figure", "write_modes_pvd"]

CSV_COLUMNS = ("mode", "frequency_Hz", "part", "support", "description")
CSV_FILE = "modes.csv"
PVD_FILE = "modes.pvd"
SHAPES_DIR = "modes"
FIGURE_FILE = "modes.png"
# Shapes in the VTU files: largest displacement 5 % of the model's size, in metres, so
# that ParaView's "Warp By Vector" at scale 1 shows them plainly.
SHAPE_SCALE = 0.05
# Shapes in the figure: at most this many panels (the first elastic modes).
FIGURE_PANELS = 6


def write_modes_csv(result: ModalResult, path: str | Path) -> Path:
    """One row per mode: :data:`CSV_COLUMNS` (frequency to 7 significant figures)."""
    path = Path(path)
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(CSV_COLUMNS)
        for m in result.modes:
            w.writerow(
                [m.number, f"{m.frequency:.7g}", result.model.part, result.model.support,
                 m.description]
            )  # fmt: skip
    return path


def _model_size(result: ModalResult) -> float:
    return float(np.hypot(*np.ptp(result.model.mesh.nodes, axis=0)))


def write_modes_pvd(result: ModalResult, folder: str | Path) -> Path:
    """``modes.pvd`` and one VTU per mode in ``modes/`` (the pvd's time is the mode
    number). Point data ``displacement``: the shape, largest displacement
    :data:`SHAPE_SCALE` of the model's size (m); field ``frequency_Hz`` on every cell.
    Shapes left from an earlier analysis with more modes are removed."""
    from taichi_bearing.output.vtk import _write_pvd, write_vtu

    folder = Path(folder)
    shapes = folder / SHAPES_DIR
    shapes.mkdir(parents=True, exist_ok=True)
    mesh = result.model.mesh
    scale = SHAPE_SCALE * _model_size(result)
    entries = []
    for m in result.modes:
        name = f"mode_{m.number:03d}.vtu"
        u = m.shape / max(float(np.max(np.hypot(*m.shape.T))), 1e-300)
        freq = np.full(mesh.n_elements, m.frequency)
        write_vtu(shapes / name, mesh, {"displacement": scale * u}, {"frequency_Hz": freq})
        entries.append((float(m.number), f"{SHAPES_DIR}/{name}"))
    written = {e[1].split("/")[-1] for e in entries}
    for p in shapes.glob("mode_*.vtu"):
        if p.name not in written:
            p.unlink()
    path = folder / PVD_FILE
    _write_pvd(path, entries)
    return path


def write_modes_figure(result: ModalResult, path: str | Path, title: str = "") -> Path:
    """The first elastic mode shapes as deformed outlines over the undeformed mesh
    outline (grey); each panel names the mode, its frequency and its description."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    mesh = result.model.mesh
    shown = result.elastic[:FIGURE_PANELS] or result.modes[:FIGURE_PANELS]
    seg = boundary_segments(mesh.elements)
    size = _model_size(result)
    cols = min(3, max(1, len(shown)))
    rows = math.ceil(len(shown) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 4.4 * rows), squeeze=False)
    for ax in axes.ravel():
        ax.set_axis_off()
    for ax, m in zip(axes.ravel(), shown, strict=False):
        u = m.shape / max(float(np.max(np.hypot(*m.shape.T))), 1e-300)
        moved = mesh.nodes + 0.06 * size * u
        ax.add_collection(LineCollection(mesh.nodes[seg], colors="0.75", linewidths=0.5))
        ax.add_collection(LineCollection(moved[seg], colors="#1f5fa8", linewidths=0.9))
        ax.autoscale()
        ax.set_aspect("equal")
        ax.set_title(f"mode {m.number}: {m.frequency:.5g} Hz\n{m.description}", fontsize=8)
    fig.suptitle(
        title
        or f"{result.model.part} ({result.model.support}): first mode shapes, "
        "deformed outline (blue) over the undeformed (grey)",
        fontsize=9,
    )
    fig.tight_layout()
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")
    plt.close(fig)
    return path


def write_modes(result: ModalResult, folder: str | Path, title: str = "") -> list[Path]:
    """``modes.csv``, ``modes.pvd`` with ``modes/*.vtu`` and ``modes.png`` in ``folder``."""
    folder = Path(folder)
    return [
        write_modes_csv(result, folder / CSV_FILE),
        write_modes_pvd(result, folder),
        write_modes_figure(result, folder / FIGURE_FILE, title),
    ]
