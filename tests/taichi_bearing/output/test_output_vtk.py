"""VTU frames and the .pvd series: exact read-back with meshio, valid XML, atomic, resume."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

from taichi_bearing.mesh.types import Mesh
from taichi_bearing.output import vtk
from taichi_bearing.output.vtk import FrameWriter, mesh_to_meshio, read_pvd, write_vtu


def _grid_mesh(nx: int = 4, ny: int = 3) -> Mesh:
    """A distorted nx-by-ny quad grid in two parts (left and right halves)."""
    x, y = np.meshgrid(np.linspace(0.0, 0.02, nx + 1), np.linspace(0.0, 0.01, ny + 1))
    nodes = np.column_stack([x.ravel(), y.ravel()])
    nodes += 1e-4 * np.sin(7.0 * nodes[:, ::-1] / 0.01)
    idx = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    quads = np.column_stack(
        [idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()]
    )
    part = (np.tile(np.arange(nx), ny) >= nx // 2).astype(int)
    return Mesh(nodes, quads, part, ["left", "right"])


def _fields(mesh: Mesh, seed: int):
    rng = np.random.default_rng(seed)
    return (
        rng.standard_normal((mesh.n_nodes, 2)) * 1e-6,
        rng.standard_normal((mesh.n_nodes, 2)),
        rng.random(mesh.n_elements) * 1e9,
    )


def test_vtu_reads_back_identical(tmp_path):
    mesh = _grid_mesh()
    disp, vel, vm = _fields(mesh, 0)
    temp = np.linspace(20.0, 30.0, mesh.n_nodes)
    path = write_vtu(
        tmp_path / "mesh.vtu",
        mesh,
        point_data={"displacement": disp, "temp": temp},
        cell_data={"von_mises": vm},
    )
    assert path == tmp_path / "mesh.vtu"
    m = meshio.read(path)
    np.testing.assert_array_equal(m.points[:, :2], mesh.nodes)
    np.testing.assert_array_equal(m.points[:, 2], 0.0)
    assert [c.type for c in m.cells] == ["quad"]
    np.testing.assert_array_equal(m.cells[0].data, mesh.elements)
    np.testing.assert_array_equal(m.point_data["displacement"][:, :2], disp)
    np.testing.assert_array_equal(m.point_data["displacement"][:, 2], 0.0)
    np.testing.assert_array_equal(m.point_data["temp"], temp)
    np.testing.assert_array_equal(m.cell_data["von_mises"][0], vm)
    np.testing.assert_array_equal(m.cell_data["part"][0], mesh.element_part)
    assert m.cell_data["part"][0].sum() == mesh.n_elements // 2  # two parts really present
    assert [p.name for p in tmp_path.iterdir()] == ["mesh.vtu"]  # no temporaries left


def test_mesh_to_meshio_checks_sizes():
    mesh = _grid_mesh()
    m = mesh_to_meshio(mesh)
    assert m.points.shape == (mesh.n_nodes, 3) and set(m.cell_data) == {"part"}
    with pytest.raises(ValueError, match="'u'.*20 rows"):
        mesh_to_meshio(mesh, point_data={"u": np.zeros((3, 2))})
    with pytest.raises(ValueError, match="reserved"):
        mesh_to_meshio(mesh, cell_data={"part": np.zeros(mesh.n_elements)})


def test_frames_and_pvd(tmp_path):
    mesh = _grid_mesh()
    writer = FrameWriter(tmp_path, mesh)
    times = [1e-4, 2.5e-4, 3.0000000000000004e-4]
    fields = [_fields(mesh, k) for k in range(3)]
    for t, (d, v, s) in zip(times, fields, strict=True):
        writer.write(t, d, v, s, pressure=s * 0.5, temperature=np.full(mesh.n_nodes, t))
    frames = tmp_path / "frames"
    assert sorted(p.name for p in frames.iterdir()) == [
        "frame_00000.vtu",
        "frame_00001.vtu",
        "frame_00002.vtu",
        "frames.pvd",
    ]
    root = ET.parse(frames / "frames.pvd").getroot()  # valid XML
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    entries = read_pvd(frames / "frames.pvd")
    assert entries == [(t, f"frame_{k:05d}.vtu") for k, t in enumerate(times)]
    for (_, name), (d, v, s) in zip(entries, fields, strict=True):
        m = meshio.read(frames / name)
        np.testing.assert_array_equal(m.point_data["displacement"][:, :2], d)
        np.testing.assert_array_equal(m.point_data["velocity"][:, :2], v)
        np.testing.assert_array_equal(m.cell_data["von_mises"][0], s)
        np.testing.assert_array_equal(m.cell_data["pressure"][0], s * 0.5)
        assert m.point_data["temperature"].shape == (mesh.n_nodes,)
    # ParaView's own reader (VTK, through pyvista) sees the same series.
    pv = pytest.importorskip("pyvista")
    reader = pv.get_reader(str(frames / "frames.pvd"))
    assert list(reader.time_values) == times
    reader.set_active_time_value(times[1])
    block = reader.read()[0]
    np.testing.assert_array_equal(block.point_data["displacement"][:, :2], fields[1][0])
    np.testing.assert_array_equal(block.cell_data["part"], mesh.element_part)
    with pytest.raises(ValueError, match="increase"):
        writer.write(times[-1], *fields[0])
    with pytest.raises(ValueError, match="'bad'"):
        writer.write(1.0, *fields[0], bad=np.zeros(7))


def test_resume_drops_later_frames_and_orphans(tmp_path):
    mesh = _grid_mesh()
    writer = FrameWriter(tmp_path, mesh)
    for k in range(4):
        writer.write((k + 1) * 1e-4, *_fields(mesh, k))
    frames = tmp_path / "frames"
    # A frame written just before a crash, before the .pvd listed it.
    (frames / "frame_00004.vtu").write_bytes((frames / "frame_00003.vtu").read_bytes())
    resumed = FrameWriter(tmp_path, mesh, resume_time=2e-4)
    assert resumed.frames == [(1e-4, "frame_00000.vtu"), (2e-4, "frame_00001.vtu")]
    assert sorted(p.name for p in frames.glob("*.vtu")) == ["frame_00000.vtu", "frame_00001.vtu"]
    path = resumed.write(2.5e-4, *_fields(mesh, 9))
    assert path.name == "frame_00002.vtu"
    assert read_pvd(frames / "frames.pvd")[-1] == (2.5e-4, "frame_00002.vtu")
    # A fresh run in the same folder starts over.
    FrameWriter(tmp_path, mesh)
    assert sorted(p.name for p in frames.iterdir()) == ["frames.pvd"]
    assert read_pvd(frames / "frames.pvd") == []


def test_interrupted_write_leaves_no_partial_file(tmp_path, monkeypatch):
    mesh = _grid_mesh()
    writer = FrameWriter(tmp_path, mesh)
    writer.write(1e-4, *_fields(mesh, 0))
    real_write = vtk.meshio.write

    def write_half_then_interrupt(path, m, **kw):
        real_write(path, m, **kw)
        Path(path).write_bytes(Path(path).read_bytes()[:200])
        raise KeyboardInterrupt

    monkeypatch.setattr(vtk.meshio, "write", write_half_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        writer.write(2e-4, *_fields(mesh, 1))
    with pytest.raises(KeyboardInterrupt):
        write_vtu(tmp_path / "mesh.vtu", mesh)
    monkeypatch.undo()
    frames = tmp_path / "frames"
    assert sorted(p.name for p in tmp_path.rglob("*")) == [
        "frame_00000.vtu",
        "frames",
        "frames.pvd",
    ]
    assert read_pvd(frames / "frames.pvd") == [(1e-4, "frame_00000.vtu")]
    meshio.read(frames / "frame_00000.vtu")  # the complete frame still reads
