"""Checkpoints: bit-exact round trip, keep-last-K, atomic writes, fingerprint refusal."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from taichi_bearing.errors import InputError
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.output import checkpoint as ck
from taichi_bearing.output.checkpoint import (
    fingerprint,
    latest_checkpoint,
    list_checkpoints,
    load_checkpoint,
    save_checkpoint,
)
from taichi_bearing.output.summary import (
    missing_summary_keys,
    required_summary_keys,
    write_summary,
)


def _state(seed: int = 0) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((50, 2))
    x[0, 0] = np.nextafter(1.0, 2.0)  # a value one ulp away from a round number
    x[1, 1] = -0.0
    x[2, 0] = 1e-310  # subnormal
    return {
        "position": x,
        "velocity": rng.standard_normal((50, 2)),
        "stick": rng.integers(0, 2, 37).astype(np.bool_),
        "gap_node": rng.integers(-1, 50, (20, 3)).astype(np.int32),
        "scalar": np.float64(np.pi),
    }


def _small_mesh() -> Mesh:
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    return Mesh(nodes, np.array([[0, 1, 2, 3]]), np.array([0]), ["block"])


def test_round_trip_is_bit_exact(tmp_path):
    arrays = _state()
    fp = fingerprint({"a": 1}, arrays["position"])
    meta = {"fingerprint": fp, "case": "line_spall", "dt_s": 1.25e-8, "n": np.int64(3)}
    path = save_checkpoint(tmp_path, 1200, 3.0000000000000004e-4, arrays, meta)
    assert path.name == "checkpoint_0000001200.npz"
    step, time, loaded, meta2 = load_checkpoint(path, expected_fingerprint=fp)
    assert step == 1200 and time == 3.0000000000000004e-4
    assert meta2 == {"fingerprint": fp, "case": "line_spall", "dt_s": 1.25e-8, "n": 3}
    assert set(loaded) == set(arrays)
    for name, a in arrays.items():
        b = loaded[name]
        assert b.dtype == np.asarray(a).dtype and b.shape == np.shape(a)
        assert np.asarray(a).tobytes() == b.tobytes(), name


def test_mismatched_fingerprint_is_refused(tmp_path):
    case = {"operating": {"load_kN": 50.0, "speed_rpm": 500.0}}
    mesh = _small_mesh()
    fp = fingerprint(case, mesh)
    path = save_checkpoint(tmp_path, 10, 1e-6, _state(), {"fingerprint": fp})
    other_case = {"operating": {"load_kN": 50.0, "speed_rpm": 501.0}}
    moved = _small_mesh()
    moved.nodes[2, 0] = np.nextafter(1.0, 2.0)
    for wrong in (fingerprint(other_case, mesh), fingerprint(case, moved)):
        with pytest.raises(InputError, match="different case or mesh"):
            load_checkpoint(path, expected_fingerprint=wrong)
    assert load_checkpoint(path, expected_fingerprint=fingerprint(case, _small_mesh()))[0] == 10


def test_fingerprint_sensitivity_and_stability():
    a = np.arange(6, dtype=np.float64)
    base = fingerprint({"x": 1, "y": [1.0, "s"]}, a)
    assert len(base) == 32 and int(base, 16) >= 0
    assert fingerprint({"y": [1.0, "s"], "x": 1}, a.copy()) == base  # key order ignored
    for variant in (
        ({"x": 1.0, "y": [1.0, "s"]}, a),  # int vs float
        ({"x": 1, "y": [1.0, "s"]}, a.astype(np.float32)),  # dtype
        ({"x": 1, "y": [1.0, "s"]}, a.reshape(2, 3)),  # shape
        ({"x": 1, "y": [1.0, "s"]}, a[::-1].copy()),  # values
        ({"x": 1, "y": ["s", 1.0]}, a),  # list order
        ({"x": 1, "y": [1.0, "s"]},),  # argument count
    ):
        assert fingerprint(*variant) != base
    with pytest.raises(TypeError, match="cannot hash"):
        fingerprint(object())


def test_keeps_last_k_and_finds_latest(tmp_path):
    assert latest_checkpoint(tmp_path / "none") is None
    for step in (5, 100, 20, 1000, 300):
        save_checkpoint(tmp_path, step, step * 1e-7, _state(step), {"fingerprint": "f"}, keep=3)
    assert [p.name for p in list_checkpoints(tmp_path)] == [
        "checkpoint_0000000100.npz",
        "checkpoint_0000000300.npz",
        "checkpoint_0000001000.npz",
    ]
    step, time, arrays, _ = load_checkpoint(latest_checkpoint(tmp_path))
    assert step == 1000 and time == 1000 * 1e-7
    np.testing.assert_array_equal(arrays["velocity"], _state(1000)["velocity"])


def test_interrupted_save_leaves_no_partial_file(tmp_path, monkeypatch):
    save_checkpoint(tmp_path, 1, 1e-7, _state(1), {"fingerprint": "f"})
    real_savez = ck.np.savez

    def savez_then_interrupt(f, **arrays):
        real_savez(f, **arrays)
        f.truncate(100)
        raise KeyboardInterrupt

    monkeypatch.setattr(ck.np, "savez", savez_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        save_checkpoint(tmp_path, 2, 2e-7, _state(2), {"fingerprint": "f"})
    monkeypatch.undo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["checkpoint_0000000001.npz"]
    assert load_checkpoint(latest_checkpoint(tmp_path))[0] == 1


def test_bad_input_is_refused(tmp_path):
    with pytest.raises(ValueError, match="fingerprint"):
        save_checkpoint(tmp_path, 1, 0.0, _state(), {})
    with pytest.raises(ValueError, match="__step__"):
        save_checkpoint(tmp_path, 1, 0.0, {"__step__": np.zeros(2)}, {"fingerprint": "f"})
    with pytest.raises(ValueError, match="step"):
        save_checkpoint(tmp_path, -1, 0.0, _state(), {"fingerprint": "f"})
    broken = tmp_path / "checkpoint_0000000009.npz"
    broken.write_bytes(b"PK\x03\x04 not really a zip")
    with pytest.raises(InputError, match="not a readable checkpoint"):
        load_checkpoint(broken)
    with pytest.raises(InputError, match="not a readable checkpoint"):
        load_checkpoint(tmp_path / "missing.npz")
    np.savez(tmp_path / "foreign.npz", x=np.zeros(3))
    with pytest.raises(InputError, match="not a taichi-bearing checkpoint"):
        load_checkpoint(Path(tmp_path / "foreign.npz"))


# summary.json (run metadata written beside the checkpoints) --------------------------


def test_summary_keys_match_design_section_7():
    design_path = Path(__file__).resolve().parents[4] / "shared" / "design.md"
    if not design_path.is_file():
        pytest.skip(f"design contract not available at {design_path}")
    design = design_path.read_text()
    section = design.split("## 7.")[1].split("## 8.")[0]
    block = section.split("`summary.json`, with at least these keys")[1].split("- Column names")[0]
    assert tuple(re.findall(r"`(\w+)`", block)) == required_summary_keys()


def test_write_summary_flags_missing_keys(tmp_path):
    full = {k: 1.0 for k in required_summary_keys()}
    full["static_roller_forces_N"] = np.array([1.5, np.nan])
    path = write_summary(tmp_path, full, strict=True)
    assert path == tmp_path / "summary.json"
    data = json.loads(path.read_text())
    assert "missing_keys" not in data and data["static_roller_forces_N"] == [1.5, None]
    partial = {"n_nodes": np.int64(12), "dt_s": 1e-8}
    with pytest.warns(UserWarning, match="n_elements"):
        write_summary(tmp_path / "summary.json", partial)
    data = json.loads(path.read_text())
    assert data["n_nodes"] == 12
    assert data["missing_keys"] == missing_summary_keys(partial)
    assert len(data["missing_keys"]) == len(required_summary_keys()) - 2
    with pytest.raises(ValueError, match="lacks required keys"):
        write_summary(tmp_path / "other.json", partial, strict=True)
    assert not (tmp_path / "other.json").exists()
