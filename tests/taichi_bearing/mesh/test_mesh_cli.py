"""`python -m taichi_bearing mesh`: files written, read back, and bad input."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from taichi_bearing.__main__ import main
from taichi_bearing.case import load_case
from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
from taichi_bearing.mesh.spec import spec_from_case

COARSE = ["--set", "mesh.surface_size_mm=1.0", "--set", "mesh.max_size_mm=4.0"]


def test_mesh_command_writes_vtu_pictures_and_statistics(default_case_path, tmp_path, capsys):
    import meshio
    from PIL import Image

    out = tmp_path / "out"
    rc = main(["mesh", str(default_case_path), "--out", str(out), *COARSE])
    assert rc == 0
    printed = capsys.readouterr().out
    # The same mesh, built directly from the case with the same overrides.
    case = load_case(default_case_path, ["mesh.surface_size_mm=1.0", "mesh.max_size_mm=4.0"])
    ref = build_bearing_mesh(spec_from_case(case))
    assert f"mesh: {ref.n_elements} elements, {ref.n_nodes} nodes" in printed

    vtu = meshio.read(out / "mesh.vtu")
    assert np.allclose(vtu.points[:, :2], ref.nodes)
    assert np.array_equal(vtu.cells_dict["quad"], ref.elements)
    assert np.array_equal(vtu.cell_data["part_id"][0], ref.element_part)
    top = vtu.point_data["adapter_top"].astype(bool)
    assert np.array_equal(np.flatnonzero(top), np.sort(ref.node_sets["adapter_top"]))
    assert vtu.point_data["sensor_adapter_top"].sum() == 1

    stats = json.loads((out / "mesh_statistics.json").read_text())
    assert stats["statistics"]["n_elements"] == ref.n_elements
    assert stats["spall"]["depth"] == pytest.approx(case.defect.depth)

    for name in ("mesh_bearing.png", "mesh_spall.png", "mesh_spall_edge.png"):
        image = np.asarray(Image.open(out / name).convert("RGB"))
        # Not blank: white background plus the part colours and edges.
        assert image.shape[0] >= 400
        assert len(np.unique(image.reshape(-1, 3), axis=0)) > 20
    assert not list(out.glob(".*tmp*"))  # no temporary files left behind


def test_mesh_command_without_pictures(default_case_path, tmp_path):
    out = tmp_path / "o"
    rc = main(["mesh", str(default_case_path), "--out", str(out), "--no-pictures", *COARSE])
    assert rc == 0
    assert sorted(p.name for p in out.iterdir()) == ["mesh.vtu", "mesh_statistics.json"]


def test_bad_value_is_one_line_and_status_2(default_case_path, tmp_path):
    cmd = [sys.executable, "-m", "taichi_bearing", "mesh", str(default_case_path)]
    cmd += ["--out", str(tmp_path), "--no-pictures", "--set", "mesh.surface_size_mm=-1"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "mesh.surface_size_mm" in lines[0]
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "mesh.vtu").exists()


def test_geometry_the_mesher_rejects_is_an_input_error(
    default_case_path, tmp_path, monkeypatch, capsys
):
    import taichi_bearing.mesh.bearing_mesh as bearing_mesh

    def refuse(spec):
        raise ValueError("the ring is too thin")

    monkeypatch.setattr(bearing_mesh, "build_bearing_mesh", refuse)
    rc = main(["mesh", str(default_case_path), "--out", str(tmp_path), "--no-pictures"])
    assert rc == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and "cannot mesh" in err and "too thin" in err
    assert not (tmp_path / "mesh.vtu").exists()


def test_missing_case_file(tmp_path):
    rc = main(["mesh", str(tmp_path / "nope.yaml"), "--out", str(tmp_path)])
    assert rc == 2
