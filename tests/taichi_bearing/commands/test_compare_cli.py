"""python -m taichi_bearing compare RUN_DIR MEASURED...: a run folder against measured
records (figures, summary.json, one-line errors); also a run killed before its checks."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
from synthetic_run import make_synthetic_run

from diagnostics import BearingGeometry, bearing_frequencies
from diagnostics.app.compare import analyse
from taichi_bearing.commands.compare import RESTRESS_LABEL, simulated_record
from taichi_bearing.output.layout import HISTORIES_FILE, HISTORIES_PARTS_DIR, SUMMARY_FILE

ROOT = Path(__file__).resolve().parents[3]
CWRU_BEARING = "n=9,d=7.94mm,D=39.04mm"
FIGURES = {
    "compare_time.png",
    "compare_spectrogram.png",
    "compare_envelope.png",
    "compare_third_octave.png",
}


def _cli(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    return subprocess.run(
        [sys.executable, "-m", "taichi_bearing", "compare", *args],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
        timeout=300,
    )


def _cli_here(*args: str, monkeypatch) -> subprocess.CompletedProcess:
    """As :func:`_cli`, calling ``main`` in this process (no interpreter start-up and
    imports per case); an exception escaping ``main`` fails the test as a traceback
    would."""
    import contextlib
    import io

    from taichi_bearing.__main__ import main

    monkeypatch.chdir(ROOT)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            code = main(["compare", *args])
        except SystemExit as exc:  # argparse's errors
            code = exc.code
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("run")
    make_synthetic_run(d, frames=False)
    return d


@pytest.fixture(scope="module")
def measured_csv(tmp_path_factory):
    """2 s at 20 kHz, 1200 rpm, CWRU bearing: a 3 kHz resonance struck once per BPFO."""
    fs, rpm = 20e3, 1200.0
    bpfo = bearing_frequencies(BearingGeometry(9, 7.94e-3, 39.04e-3), rpm / 60).bpfo
    t = np.arange(int(2.0 * fs)) / fs
    rng = np.random.default_rng(3)
    x = 0.05 * rng.standard_normal(t.size)
    for t0 in np.arange(0.01, t[-1] - 0.01, 1.0 / bpfo):
        dt = t[t >= t0] - t0
        x[t >= t0] += np.exp(-dt / 5e-4) * np.sin(2 * np.pi * 3000.0 * dt)
    path = tmp_path_factory.mktemp("meas") / "rig.csv"
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header="time,accel", comments="")
    return path, bpfo


def test_compare_synthetic_measured_record(run_dir, measured_csv, tmp_path):
    path, bpfo = measured_csv
    out = tmp_path / "cmp"
    res = _cli(str(run_dir), str(path), "--rpm", "1200", "--bearing", CWRU_BEARING,
               "--out", str(out))  # fmt: skip
    assert res.returncode == 0, res.stderr
    # no matplotlib warning (an empty legend) nor any other
    assert "Warning" not in res.stderr, res.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["figures"]) == FIGURES
    for name in FIGURES:
        assert (out / name).read_bytes()[:4] == b"\x89PNG"
    sim, meas = summary["records"]
    run_summary = json.loads((run_dir / "summary.json").read_text())
    assert sim["source"] == "simulated" and meas["source"] == "measured"
    assert sim["bpfo_hz"] == run_summary["bpfo_hz"]
    assert sim["n_events"] == len(run_summary["events"])
    assert meas["bpfo_hz"] == pytest.approx(bpfo, rel=1e-12)
    assert meas["fs_hz"] == pytest.approx(20e3)
    # Speeds differ: the ratio is reported and the measured comb sits at orders 1..5.
    assert summary["speed_ratio"][1] == pytest.approx(20.0 / run_summary["shaft_hz"])
    assert min(meas["bpfo_harmonic_ratios"]) > 3.0
    assert summary["bpfo_comb_shown"][1] is True
    # The kurtogram band holds the 3 kHz resonance.
    assert meas["band_hz"][0] <= 3000.0 <= meas["band_hz"][1]


def test_simulated_record_reads_the_run_folder(run_dir):
    _, case, rec = simulated_record(run_dir)
    run_summary = json.loads((run_dir / "summary.json").read_text())
    assert rec.fs == pytest.approx(100e3)
    assert rec.events_s == pytest.approx([e["exit_time_s"] for e in run_summary["events"]])
    assert rec.events_label == RESTRESS_LABEL
    assert rec.frequencies.bpfo == pytest.approx(run_summary["bpfo_hz"], rel=1e-12)
    # the signal the run's checks analysed, named by its column
    assert rec.meta["column"] == run_summary["analysed_signal"]
    assert rec.label.endswith(f"({run_summary['analysed_signal']})")
    an = analyse(rec)
    assert an.events_s.size == 3
    # Envelope spectrum normalised by its own median between 0.5 and 10.5 BPFO.
    f = an.f_env
    ref = (f >= 0.5 * rec.bpfo_hz) & (f <= 10.5 * rec.bpfo_hz)
    assert np.median(an.env_norm[ref]) == pytest.approx(1.0)


def test_a_run_killed_before_its_checks_is_compared_on_what_it_recorded(
    run_dir, measured_csv, tmp_path
):
    """kill -9: no summary.json, the histories only in parts; BPFO from case.yaml."""
    killed = tmp_path / "killed"
    shutil.copytree(run_dir, killed)
    (killed / SUMMARY_FILE).unlink()
    parts = killed / HISTORIES_PARTS_DIR
    parts.mkdir()
    table = pq.read_table(killed / HISTORIES_FILE)
    pq.write_table(table.slice(0, 2000), parts / "part-000001.parquet")
    (killed / HISTORIES_FILE).unlink()
    _, _, rec = simulated_record(killed)
    run_summary = json.loads((run_dir / "summary.json").read_text())
    assert rec.x.size == 2000
    assert rec.bpfo_hz == pytest.approx(run_summary["bpfo_hz"], rel=1e-12)
    assert rec.shaft_hz == pytest.approx(run_summary["shaft_hz"], rel=1e-12)
    assert rec.events_s.size == 0  # no summary: no known events
    res = _cli(str(killed), str(measured_csv[0]), "--rpm", "1200", "--out", str(tmp_path / "o"))
    assert res.returncode == 0, res.stderr
    assert "did not finish" in res.stderr
    sim = json.loads((tmp_path / "o" / "summary.json").read_text())["records"][0]
    assert sim["n_samples"] == 2000


def test_cwru_outer_race_record(run_dir, cwru_dir, tmp_path):
    mat = cwru_dir / "12k_Drive_End_OR007@6_0_130.mat"
    res = _cli(str(run_dir), str(mat), "--fs", "12000", "--bearing", CWRU_BEARING,
               "--out", str(tmp_path))  # fmt: skip
    assert res.returncode == 0, res.stderr
    meas = json.loads((tmp_path / "summary.json").read_text())["records"][1]
    assert meas["bpfo_hz"] == pytest.approx(3.5848 * 1796 / 60, rel=1e-4)  # README ratio
    assert meas["bpfo_harmonic_ratios"][0] > 10.0  # a clear outer-race comb


@pytest.mark.parametrize(
    "args, words",
    [
        (["{missing}", "{csv}", "--rpm", "1200"], "not a folder"),
        (["{empty}", "{csv}", "--rpm", "1200"], "summary.json"),
        (["{run}", "{csv}", "--rpm", "1200", "--bearing", "n=9,d=7.94"], "--bearing"),
        (["{run}", "{csv}", "--rpm", "-5"], "--rpm"),
        (["{run}", "{csv}", "--rpm", "1200", "--fs", "0"], "--fs"),
        (["{run}", "{missing}", "--rpm", "1200"], "not found"),
        (["{run}", "{csv}"], "--rpm"),
        (["{run}", "{csv}", "--rpm", "1200", "--sensor", "nowhere"], "nowhere"),
        (["{run}"], "MEASURED_FILE"),
    ],
)
def test_bad_input_one_line_exit_2(args, words, run_dir, measured_csv, tmp_path, monkeypatch):
    """The first case through ``python -m`` (the real process), the others in-process."""
    (tmp_path / "empty").mkdir()
    values = {
        "missing": str(tmp_path / "nope"),
        "empty": str(tmp_path / "empty"),
        "run": str(run_dir),
        "csv": str(measured_csv[0]),
    }
    argv = [*[a.format(**values) for a in args], "--out", str(tmp_path / "o")]
    if words == "not a folder":
        res = _cli(*argv)
    else:
        res = _cli_here(*argv, monkeypatch=monkeypatch)
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in res.stderr
    assert words in lines[0]
