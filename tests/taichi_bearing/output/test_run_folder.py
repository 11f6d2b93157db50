"""taichi_bearing.output.run_folder: the loader reads a finished run, a run killed with its
histories only in parts, and says what a folder lacks for the checks."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pandas as pd
import pytest
from synthetic_run import make_synthetic_run

from taichi_bearing.output.histories import HistoryWriter, read_histories
from taichi_bearing.output.layout import (
    CASE_FILE,
    HISTORIES_FILE,
    HISTORIES_PARTS_DIR,
    MESH_INFO_FILE,
    PRELOAD_FILE,
    REFERENCE_KEY,
    ROLLING_RATES_KEY,
    SUMMARY_FILE,
    history_columns,
)
from taichi_bearing.output.run_folder import (
    acceleration_signal,
    load_run,
    missing_for_checks,
    passage_events,
    sensor_acceleration,
)


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("run")
    make_synthetic_run(d, frames=False, duration_ms=10.0)
    return d


def test_a_finished_run_reads_back_whole(run_dir):
    run = load_run(run_dir)
    summary = json.loads((run_dir / SUMMARY_FILE).read_text())
    hist = pd.read_parquet(run_dir / HISTORIES_FILE)
    assert run.summary == summary and run.merged and not run.partial
    pd.testing.assert_frame_equal(run.histories, hist)
    t = hist["time_s"].to_numpy()
    assert run.fs == (t.size - 1) / (t[-1] - t[0])  # the one definition of the rate
    assert run.t0 == t[0] and run.t_end == t[-1]
    assert run.case["name"] == summary["case_name"] == run.case_name
    assert run.bpfo_hz == summary["bpfo_hz"] and run.rollers == summary["n_rollers"]
    assert [e["roller"] for e in run.events] == [e["roller"] for e in summary["events"]]


def test_the_analysed_signal_is_the_default_and_a_column_is_taken_as_it_is(run_dir):
    run = load_run(run_dir)
    analysed = run.summary["analysed_signal"]
    default = acceleration_signal(run)
    assert default.column == analysed
    np.testing.assert_array_equal(default.x, run.histories[analysed].to_numpy())
    other = f"{run.sensor_names[1]}_ay"
    assert acceleration_signal(run, other).column == other
    # a sensor name: its radial acceleration (a combination of columns)
    radial = acceleration_signal(run, run.sensor_names[0])
    assert radial.column is None and "radial" in radial.label
    x, label = sensor_acceleration(run)
    np.testing.assert_array_equal(x, default.x)
    assert label == default.label
    with pytest.raises(ValueError, match="nowhere"):
        acceleration_signal(run, "nowhere")


def test_a_run_killed_hard_reads_from_its_parts(run_dir, tmp_path):
    """kill -9: no merged file, no summary; the parts are the run's histories."""
    killed = tmp_path / "killed"
    killed.mkdir()
    shutil.copy(run_dir / CASE_FILE, killed / CASE_FILE)
    columns = history_columns(["s"], n_rollers=1)
    rows = np.column_stack([np.arange(1, 301) * 1e-5] + [np.ones(300)] * (len(columns) - 1))
    writer = HistoryWriter(killed, columns, chunk_rows=100)
    writer.append(rows[:250])  # two parts on disk, 50 rows in the buffer: lost
    assert not (killed / HISTORIES_FILE).exists()
    assert len(list((killed / HISTORIES_PARTS_DIR).iterdir())) == 2
    run = load_run(killed)
    assert not run.merged and run.partial and run.status is None and run.summary == {}
    assert len(run.histories) == 200 and run.t_end == pytest.approx(2e-3)
    pd.testing.assert_frame_equal(run.histories, read_histories(killed))
    assert missing_for_checks(run) == [MESH_INFO_FILE, PRELOAD_FILE]


def test_what_the_checks_need_is_named(run_dir, tmp_path):
    folder = tmp_path / "old"
    shutil.copytree(run_dir, folder)
    (folder / MESH_INFO_FILE).write_text(json.dumps({"polygon_edges": {}}))
    (folder / PRELOAD_FILE).write_text(json.dumps({"outer_force_N": [1.0]}))
    run = load_run(folder)
    assert missing_for_checks(run) == [f"{PRELOAD_FILE}:{REFERENCE_KEY}",
                                       f"{PRELOAD_FILE}:{ROLLING_RATES_KEY}"]  # fmt: skip
    (folder / PRELOAD_FILE).write_text(
        json.dumps({"outer_force_N": [1.0], REFERENCE_KEY: [1.0], ROLLING_RATES_KEY: {}})
    )
    assert missing_for_checks(load_run(folder)) == []


def test_not_a_run_folder(tmp_path):
    with pytest.raises(FileNotFoundError, match="not a run folder"):
        load_run(tmp_path)
    (tmp_path / CASE_FILE).write_text("name: x\n")
    with pytest.raises(FileNotFoundError, match="no histories recorded"):
        load_run(tmp_path)
    (tmp_path / SUMMARY_FILE).write_text("[1, 2]")
    with pytest.raises(ValueError, match="JSON object"):
        load_run(tmp_path)


def test_passages_from_the_event_list_or_the_time_lists():
    listed = passage_events({"events": [{"roller": 3, "entry_time_s": 0.1,
                                         "exit_time_s": None, "exit_impulses": 2}]})  # fmt: skip
    assert listed[0]["roller"] == 3 and listed[0]["exit_impulses"] == 2
    assert np.isnan(listed[0]["exit_time_s"])
    paired = passage_events({"entry_times_s": [0.1, 0.2], "restress_times_s": [0.15]})
    assert [e["entry_time_s"] for e in paired] == [0.1, 0.2]
    assert paired[0]["exit_time_s"] == 0.15 and np.isnan(paired[1]["exit_time_s"])
    assert all(e["roller"] is None for e in paired)
