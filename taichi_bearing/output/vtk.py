"""VTU files of the mesh and of field frames, and the ParaView ``.pvd`` series (meshio).

Points are written in 3-D (z = 0) and 2-component point or cell arrays are padded to 3
components, so ParaView treats them as vectors (e.g. "Warp By Vector" on
``displacement``). Each element carries its part id as the cell array ``part``.
Every file is written to a temporary name and renamed, so no reader ever sees half a file.
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path

import meshio
import numpy as np

from bearing_io.files import atomic_path
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.output.layout import FRAMES_DIR, PVD_FILE

__all__ = ["FrameWriter", "mesh_to_meshio", "read_pvd", "write_vtu"]

_FRAME = re.compile(r"^frame_(\d+)\.vtu$")
PVD_NAME = PVD_FILE  # the run folder's name (taichi_bearing.output.run_folder)


def _as_vector3(name: str, a: np.ndarray) -> np.ndarray:
    """Pad an (n, 2) array to (n, 3) with zeros; leave other shapes alone."""
    if a.ndim == 2 and a.shape[1] == 2:
        return np.column_stack([a, np.zeros(a.shape[0], dtype=a.dtype)])
    if a.ndim not in (1, 2):
        raise ValueError(f"{name}: expected a 1-D or 2-D array, got shape {a.shape}")
    return a


def _checked(data: Mapping[str, np.ndarray] | None, n: int, what: str) -> dict[str, np.ndarray]:
    out = {}
    for name, value in (data or {}).items():
        a = np.asarray(value)
        if a.shape[:1] != (n,):
            raise ValueError(f"{what} {name!r}: expected {n} rows, got shape {a.shape}")
        out[name] = _as_vector3(name, a)
    return out


def mesh_to_meshio(
    mesh: Mesh,
    point_data: Mapping[str, np.ndarray] | None = None,
    cell_data: Mapping[str, np.ndarray] | None = None,
) -> meshio.Mesh:
    """A :class:`meshio.Mesh` of quads with the part id of each element as ``part``.

    Parameters
    ----------
    mesh : Mesh
        The mesh (reference coordinates).
    point_data : mapping of str to ndarray, optional
        Arrays with one row per node; (n, 2) arrays become (n, 3) vectors.
    cell_data : mapping of str to ndarray, optional
        Arrays with one row per element; (n, 2) arrays become (n, 3) vectors.

    Returns
    -------
    meshio.Mesh
    """
    points = np.column_stack([mesh.nodes, np.zeros(mesh.n_nodes)]).astype(np.float64)
    cells = [("quad", np.asarray(mesh.elements, dtype=np.int64))]
    pdata = _checked(point_data, mesh.n_nodes, "point data")
    cdata = _checked(cell_data, mesh.n_elements, "cell data")
    if "part" in cdata:
        raise ValueError("cell data 'part' is reserved for the element part ids")
    cdata["part"] = np.asarray(mesh.element_part, dtype=np.int32)
    return meshio.Mesh(
        points, cells, point_data=pdata, cell_data={k: [v] for k, v in cdata.items()}
    )


def _write_meshio(path: Path, m: meshio.Mesh) -> Path:
    with atomic_path(path) as tmp:
        # The temporary name ends in ".tmp.vtu", but name the format anyway.
        meshio.write(tmp, m, file_format="vtu")
    return path


def write_vtu(
    path: str | os.PathLike,
    mesh: Mesh,
    point_data: Mapping[str, np.ndarray] | None = None,
    cell_data: Mapping[str, np.ndarray] | None = None,
) -> Path:
    """Write the mesh (and optional data) as a VTU file, atomically. Returns the path."""
    return _write_meshio(Path(path), mesh_to_meshio(mesh, point_data, cell_data))


def read_pvd(path: str | os.PathLike) -> list[tuple[float, str]]:
    """The ``(time, file)`` entries of a ``.pvd`` collection, file relative to its folder."""
    root = ET.parse(path).getroot()
    return [
        (float(ds.get("timestep")), ds.get("file"))
        for ds in root.iter("DataSet")
        if ds.get("timestep") is not None and ds.get("file") is not None
    ]


def _write_pvd(path: Path, frames: list[tuple[float, str]]) -> None:
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    coll = ET.SubElement(root, "Collection")
    for t, name in frames:
        # repr keeps every bit of the time.
        ET.SubElement(coll, "DataSet", timestep=repr(float(t)), group="", part="0", file=name)
    ET.indent(root)
    with atomic_path(path) as tmp:
        ET.ElementTree(root).write(tmp, encoding="utf-8", xml_declaration=True)


class FrameWriter:
    """Field frames of a run: ``<folder>/frames/frame_00000.vtu`` ... and ``frames.pvd``.

    Parameters
    ----------
    folder : str or path-like
        The run's output folder; frames go into its ``frames`` subfolder.
    mesh : Mesh
        The mesh; points are its reference coordinates (displacement is a point array).
    resume_time : float, optional
        Continue an earlier run: frames up to and including this time are kept, later ones
        (and files the ``.pvd`` does not list) are removed, numbering continues. Without
        it, a previous run's frames in the folder are removed.

    Notes
    -----
    The ``.pvd`` is rewritten (atomically) after every frame, so it always lists exactly
    the complete frames on disk and can be opened in ParaView while the run goes on.
    """

    def __init__(
        self, folder: str | os.PathLike, mesh: Mesh, resume_time: float | None = None
    ) -> None:
        self.folder = Path(folder) / FRAMES_DIR
        self.pvd_path = self.folder / PVD_NAME
        self.mesh = mesh
        self.folder.mkdir(parents=True, exist_ok=True)
        self._frames: list[tuple[float, str]] = []
        if resume_time is not None and self.pvd_path.is_file():
            self._frames = [(t, f) for t, f in read_pvd(self.pvd_path) if t <= resume_time]
        listed = {f for _, f in self._frames}
        for p in self.folder.iterdir():
            if _FRAME.match(p.name) and p.name not in listed:
                p.unlink()
        numbers = [int(_FRAME.match(f).group(1)) for f in listed if _FRAME.match(f)]
        self._next = max(numbers, default=-1) + 1
        _write_pvd(self.pvd_path, self._frames)

    @property
    def frames(self) -> list[tuple[float, str]]:
        """``(time, file name)`` of the frames written so far, in order."""
        return list(self._frames)

    def write(
        self,
        time: float,
        displacement: np.ndarray,
        velocity: np.ndarray,
        von_mises: np.ndarray,
        **extra: np.ndarray,
    ) -> Path:
        """Write the next frame and update the ``.pvd``.

        Parameters
        ----------
        time : float
            Simulated time, s; must exceed the previous frame's.
        displacement, velocity : ndarray, shape (n_nodes, 2)
            Point arrays, m and m/s.
        von_mises : ndarray, shape (n_elements,)
            Cell array, Pa.
        **extra : ndarray
            More arrays, put on points or cells by their length (one row per node or per
            element).

        Returns
        -------
        pathlib.Path
            The ``.vtu`` file written.
        """
        time = float(time)
        if self._frames and not time > self._frames[-1][0]:
            raise ValueError(
                f"frame times must increase: got {time!r} after {self._frames[-1][0]!r}"
            )
        n_nodes, n_elements = self.mesh.n_nodes, self.mesh.n_elements
        point_data = {"displacement": displacement, "velocity": velocity}
        cell_data = {"von_mises": von_mises}
        for name, value in extra.items():
            rows = np.shape(value)[:1]
            if n_nodes == n_elements and rows == (n_nodes,):
                raise ValueError(
                    f"frame array {name!r}: as many nodes as elements, cannot tell "
                    "point from cell data"
                )
            if rows == (n_nodes,):
                point_data[name] = value
            elif rows == (n_elements,):
                cell_data[name] = value
            else:
                raise ValueError(
                    f"frame array {name!r}: expected {n_nodes} (nodes) or {n_elements} "
                    f"(elements) rows, got shape {np.shape(value)}"
                )
        name = f"frame_{self._next:05d}.vtu"
        path = _write_meshio(self.folder / name, mesh_to_meshio(self.mesh, point_data, cell_data))
        self._frames.append((time, name))
        self._next += 1
        _write_pvd(self.pvd_path, self._frames)
        return path
