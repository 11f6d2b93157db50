"""Chunked history recording: exact round trip, crash and Ctrl-C survival, resume."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from taichi_bearing.output import histories
from taichi_bearing.output.histories import (
    HistoryWriter,
    energy_columns,
    history_columns,
    read_histories,
    roller_force_columns,
    sensor_columns,
)

ROOT = Path(__file__).resolve().parents[3]


def _default_sigint() -> None:
    """In the child: Ctrl-C as a terminal delivers it. A shell starts background jobs with
    SIGINT ignored, and a child inherits that; Python then installs no handler."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _rows(n: int, ncols: int, seed: int = 0, t0: float = 0.0, dt: float = 1e-5) -> np.ndarray:
    """Rows with increasing times and random full-precision values."""
    rng = np.random.default_rng(seed)
    data = rng.standard_normal((n, ncols)) * 10.0 ** rng.integers(-12, 12, (n, ncols))
    data[:, 0] = t0 + dt * np.arange(1, n + 1)
    return data


COLS = history_columns(["top", "side"], n_rollers=2, energy_kinds=["kinetic", "internal"])


def test_column_names_follow_design():
    assert sensor_columns(["top"]) == [f"top_{q}" for q in ("ux", "uy", "vx", "vy", "ax", "ay")]
    rf = roller_force_columns(2)
    assert len(rf) == 2 * 2 * 4
    assert rf[:5] == [
        "roller0_outer_fx",
        "roller0_outer_fy",
        "roller0_outer_fn",
        "roller0_outer_ft",
        "roller0_inner_fx",
    ]
    assert rf[-1] == "roller1_inner_ft"
    assert energy_columns(["kinetic", "external_work"]) == [
        "energy_kinetic",
        "energy_external_work",
    ]
    assert COLS[0] == "time_s"
    assert len(COLS) == 1 + 2 * 6 + 16 + 2
    with pytest.raises(ValueError, match="n_rollers"):
        roller_force_columns(-1)


def test_bad_columns_and_rows_are_refused(tmp_path):
    with pytest.raises(ValueError, match="time_s"):
        HistoryWriter(tmp_path, ["t", "a"])
    with pytest.raises(ValueError, match="duplicate"):
        HistoryWriter(tmp_path, ["time_s", "a", "a"])
    with HistoryWriter(tmp_path, ["time_s", "a"]) as w:
        with pytest.raises(ValueError, match="2 columns"):
            w.append([1.0, 2.0, 3.0])
        w.append([1.0, 2.0])
        with pytest.raises(ValueError, match="increase"):
            w.append([1.0, 5.0])
        with pytest.raises(ValueError, match="increase"):
            w.append([[2.0, 0.0], [2.0, 1.0]])
    assert read_histories(tmp_path)["a"].tolist() == [2.0]


def test_merge_equals_appended_data_exactly(tmp_path):
    data = _rows(1003, len(COLS))
    with HistoryWriter(tmp_path, COLS, chunk_rows=100, csv=True) as w:
        w.append(data[0])  # one row
        w.append(data[1:250])  # a block spanning several chunks
        for row in data[250:]:
            w.append(row)
        assert len(list((tmp_path / "histories.parts").glob("part-*.parquet"))) == 10
    assert not (tmp_path / "histories.parts").exists()
    df = pd.read_parquet(tmp_path / "histories.parquet")
    assert list(df.columns) == COLS
    np.testing.assert_array_equal(df.to_numpy(), data)
    np.testing.assert_array_equal(read_histories(tmp_path / "histories.parquet").to_numpy(), data)
    # The CSV keeps full precision.
    csv = pd.read_csv(tmp_path / "histories.csv")
    assert list(csv.columns) == COLS
    np.testing.assert_array_equal(csv.to_numpy(), data)


def test_parts_left_without_close_read_back(tmp_path):
    data = _rows(57, 3, seed=1)
    w = HistoryWriter(tmp_path, ["time_s", "a", "b"], chunk_rows=10)
    w.append(data)
    # No close: 5 chunks on disk, 7 rows only in memory (lost, as in a crash).
    assert not (tmp_path / "histories.parquet").exists()
    np.testing.assert_array_equal(read_histories(tmp_path).to_numpy(), data[:50])


def test_flush_writes_the_partial_chunk(tmp_path):
    data = _rows(7, 2, seed=2)
    w = HistoryWriter(tmp_path, ["time_s", "a"], chunk_rows=100)
    w.append(data)
    w.flush()
    np.testing.assert_array_equal(read_histories(tmp_path).to_numpy(), data)


def test_wall_time_flush(tmp_path):
    data = _rows(3, 2, seed=3)
    w = HistoryWriter(tmp_path, ["time_s", "a"], chunk_rows=100, max_wall_s=0.0)
    w.append(data[0])
    w.append(data[1:])
    np.testing.assert_array_equal(read_histories(tmp_path).to_numpy(), data)


def test_missing_histories_raise(tmp_path):
    with pytest.raises(FileNotFoundError, match="histories"):
        read_histories(tmp_path)


_CHILD = """
import sys, time
import numpy as np
sys.path.insert(0, {root!r})
from taichi_bearing.output.histories import HistoryWriter
data = np.load({data!r})
with HistoryWriter({out!r}, ["time_s", "a", "b", "c"], chunk_rows=10) as w:
    w.append(data)
    print("ready", flush=True)
    time.sleep(60)
"""


def _start_child(tmp_path: Path, data: np.ndarray) -> subprocess.Popen:
    np.save(tmp_path / "data.npy", data)
    code = textwrap.dedent(
        _CHILD.format(root=str(ROOT), data=str(tmp_path / "data.npy"), out=str(tmp_path / "run"))
    )
    script = tmp_path / "child.py"
    script.write_text(code)
    proc = subprocess.Popen(
        [sys.executable, str(script)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=_default_sigint,
    )
    line = proc.stdout.readline()
    if line.strip() != "ready":
        proc.kill()
        pytest.fail(f"child did not start: {proc.communicate()[1]}")
    return proc


def test_sigkill_mid_run_keeps_every_flushed_row(tmp_path):
    data = _rows(35, 4, seed=4)
    proc = _start_child(tmp_path, data)
    proc.send_signal(signal.SIGKILL)
    proc.communicate(timeout=30)
    assert proc.returncode == -signal.SIGKILL
    # 3 chunks of 10 were flushed; the 5 buffered rows died with the process.
    np.testing.assert_array_equal(read_histories(tmp_path / "run").to_numpy(), data[:30])


def test_ctrl_c_in_child_leaves_valid_merged_file(tmp_path):
    data = _rows(35, 4, seed=5)
    proc = _start_child(tmp_path, data)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode != 0 and "KeyboardInterrupt" in err
    merged = tmp_path / "run" / "histories.parquet"
    assert merged.is_file() and not (tmp_path / "run" / "histories.parts").exists()
    np.testing.assert_array_equal(pd.read_parquet(merged).to_numpy(), data)


def test_keyboard_interrupt_in_context_manager_merges_everything(tmp_path):
    data = _rows(25, 2, seed=6)
    with pytest.raises(KeyboardInterrupt), HistoryWriter(tmp_path, ["time_s", "a"], 10) as w:
        w.append(data)
        raise KeyboardInterrupt
    np.testing.assert_array_equal(pd.read_parquet(tmp_path / "histories.parquet").to_numpy(), data)


@pytest.mark.parametrize("target", ["part-000003", "histories.parquet"])
def test_interrupted_write_leaves_no_partial_file(tmp_path, monkeypatch, target):
    data = _rows(25, 2, seed=7)
    w = HistoryWriter(tmp_path, ["time_s", "a"], chunk_rows=10)
    w.append(data)
    real_write = histories.pq.write_table

    def write_half_then_interrupt(table, where, **kw):
        real_write(table, where, **kw)
        if Path(where).name.startswith("." + target):
            Path(where).write_bytes(Path(where).read_bytes()[:50])
            raise KeyboardInterrupt

    monkeypatch.setattr(histories.pq, "write_table", write_half_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        w.close()
    monkeypatch.undo()
    # Nothing at the target name, no temporary left over, and every chunk written before
    # the interruption is intact.
    assert not (tmp_path / "histories.parquet").exists()
    assert [p.name for p in tmp_path.rglob(".*")] == []
    n_saved = 20 if target.startswith("part") else 25
    np.testing.assert_array_equal(read_histories(tmp_path).to_numpy(), data[:n_saved])


def test_resume_truncates_after_checkpoint_time_and_continues(tmp_path):
    cols = ["time_s", "a", "b"]
    first = _rows(40, 3, seed=8)  # times 1e-5 .. 4e-4
    with HistoryWriter(tmp_path, cols, chunk_rows=8, csv=True) as w:
        w.append(first)
    t_ck = first[24, 0]
    rest = _rows(30, 3, seed=9, t0=t_ck)
    with HistoryWriter(tmp_path, cols, chunk_rows=8, csv=True, resume_time=t_ck) as w:
        assert w.last_time == t_ck
        with pytest.raises(ValueError, match="increase"):
            w.append(first[20])
        w.append(rest)
    expected = np.vstack([first[:25], rest])
    np.testing.assert_array_equal(read_histories(tmp_path).to_numpy(), expected)
    np.testing.assert_array_equal(pd.read_csv(tmp_path / "histories.csv").to_numpy(), expected)


def test_resume_after_crash_uses_parts_and_merged_file(tmp_path):
    cols = ["time_s", "a"]
    first = _rows(30, 2, seed=10)
    with HistoryWriter(tmp_path, cols, chunk_rows=10) as w:
        w.append(first[:10])
    # Resumed run that crashes (no close) after two chunks.
    w = HistoryWriter(tmp_path, cols, chunk_rows=10, resume_time=first[9, 0])
    w.append(first[10:27])
    np.testing.assert_array_equal(read_histories(tmp_path).to_numpy(), first[:20])
    # Resume again from an earlier checkpoint; the rows after it are dropped.
    t_ck = first[14, 0]
    more = _rows(5, 2, seed=11, t0=t_ck)
    with HistoryWriter(tmp_path, cols, chunk_rows=10, resume_time=t_ck) as w:
        w.append(more)
    np.testing.assert_array_equal(
        read_histories(tmp_path).to_numpy(), np.vstack([first[:15], more])
    )


def test_resume_refuses_other_columns(tmp_path):
    with HistoryWriter(tmp_path, ["time_s", "a"]) as w:
        w.append([1.0, 1.0])
    with pytest.raises(ValueError, match="columns differ"):
        HistoryWriter(tmp_path, ["time_s", "b"], resume_time=1.0)


def test_fresh_run_replaces_previous_histories(tmp_path):
    with HistoryWriter(tmp_path / "h.parquet", ["time_s", "a"], chunk_rows=2) as w:
        w.append(_rows(5, 2))
    w = HistoryWriter(tmp_path / "h.parquet", ["time_s", "a"], chunk_rows=2)
    assert not (tmp_path / "h.parquet").exists() and not (tmp_path / "h.parts").exists()
    w.close()
    assert len(read_histories(tmp_path / "h.parquet")) == 0
    assert os.listdir(tmp_path) == ["h.parquet"]


def test_crash_between_merge_and_cleanup_reads_no_duplicates(tmp_path, monkeypatch):
    data = _rows(25, 2, seed=12)
    w = HistoryWriter(tmp_path, ["time_s", "a"], chunk_rows=10)
    w.append(data)

    def interrupted_rmtree(*args, **kw):
        raise KeyboardInterrupt

    monkeypatch.setattr(histories.shutil, "rmtree", interrupted_rmtree)
    with pytest.raises(KeyboardInterrupt):
        w.close()
    monkeypatch.undo()
    assert (tmp_path / "histories.parquet").is_file()
    assert len(list((tmp_path / "histories.parts").glob("part-*"))) == 3
    np.testing.assert_array_equal(read_histories(tmp_path).to_numpy(), data)


def _oscillators(x: np.ndarray, v: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """One leapfrog step of unit oscillators with frequencies 1..n rad/s (a stand-in engine)."""
    w2 = np.arange(1, x.size + 1, dtype=np.float64) ** 2
    v = v - dt * w2 * x
    return x + dt * v, v


def _engine_run(out: Path, n_steps: int, stop_after: int | None = None) -> None:
    """Record every 7 steps, checkpoint every 40 (flushing histories first), resume if a
    checkpoint exists; ``stop_after`` abandons the run without closing (a crash)."""
    from taichi_bearing.output.checkpoint import latest_checkpoint, load_checkpoint, save_checkpoint

    dt, cols = 1e-3, ["time_s", "x0", "x1", "x2"]
    x, v, step, resume_time = np.array([1.0, 0.5, -0.2]), np.zeros(3), 0, None
    last = latest_checkpoint(out / "checkpoints")
    if last is not None:
        step, resume_time, state, _ = load_checkpoint(last, expected_fingerprint="osc")
        x, v = state["x"], state["v"]
    w = HistoryWriter(out, cols, chunk_rows=5, resume_time=resume_time)
    while step < n_steps:
        x, v = _oscillators(x, v, dt)
        step += 1
        if step % 7 == 0:
            w.append(np.concatenate([[step * dt], x]))
        if step % 40 == 0:
            w.flush()
            save_checkpoint(
                out / "checkpoints", step, step * dt, {"x": x, "v": v}, {"fingerprint": "osc"}
            )
        if step == stop_after:
            return
    w.close()


def test_crash_and_resume_reproduce_an_uninterrupted_run(tmp_path):
    _engine_run(tmp_path / "a", 300)
    _engine_run(
        tmp_path / "b", 300, stop_after=158
    )  # crash: checkpoint at 120, rows to 154 on disk
    _engine_run(tmp_path / "b", 300)
    a = read_histories(tmp_path / "a")
    assert len(a) == 300 // 7
    pd.testing.assert_frame_equal(read_histories(tmp_path / "b"), a)
