"""bearing_io.files: atomic writes keep the target intact on failure."""

import json
import os
import stat

import numpy as np
import pytest

from bearing_io.files import atomic_path, write_json


def test_failed_write_leaves_previous_file_and_no_temp(tmp_path):
    target = tmp_path / "a.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]


def test_written_file_has_umask_permissions(tmp_path):
    with atomic_path(tmp_path / "b.txt") as tmp:
        tmp.write_text("x")
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE((tmp_path / "b.txt").stat().st_mode) == 0o666 & ~mask


def test_write_json_converts_numpy_and_nan(tmp_path):
    path = write_json(tmp_path / "s.json", {"a": np.float64(1.5), "b": np.arange(3), "c": np.nan})
    assert json.loads(path.read_text()) == {"a": 1.5, "b": [0, 1, 2], "c": None}
