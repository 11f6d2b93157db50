"""diagnostics.app.compare: records (arrays, sampling rates, event times) through one pipeline,
figures side by side; ``python -m diagnostics compare`` points to the simulator's command.

The comparison of a simulated run folder is tested in test_compare_cli.py."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from diagnostics import BearingGeometry, bearing_frequencies
from diagnostics.app.compare import (
    Record,
    analyse,
    compare_figures,
    compare_records,
    measured_record,
    summary_lines,
)

ROOT = Path(__file__).resolve().parents[2]
GEOMETRY = BearingGeometry(9, 7.94e-3, 39.04e-3)
FIGURES = {
    "compare_time.png",
    "compare_spectrogram.png",
    "compare_envelope.png",
    "compare_third_octave.png",
}


def _struck(fs: float, seconds: float, rate_hz: float, first_s: float, seed: int = 3):
    """Noise with a 3 kHz resonance struck every 1/rate_hz from first_s; the strike times."""
    t = np.arange(int(seconds * fs)) / fs
    x = 0.05 * np.random.default_rng(seed).standard_normal(t.size)
    strikes = np.arange(first_s, t[-1] - 0.01, 1.0 / rate_hz)
    for t0 in strikes:
        dt = t[t >= t0] - t0
        x[t >= t0] += np.exp(-dt / 5e-4) * np.sin(2 * np.pi * 3000.0 * dt)
    return x, strikes


@pytest.fixture(scope="module")
def measured_csv(tmp_path_factory):
    """2 s at 20 kHz, 1200 rpm, CWRU bearing: a 3 kHz resonance struck once per BPFO."""
    fs, rpm = 20e3, 1200.0
    bpfo = bearing_frequencies(GEOMETRY, rpm / 60).bpfo
    x, _ = _struck(fs, 2.0, bpfo, 0.01)
    t = np.arange(x.size) / fs
    path = tmp_path_factory.mktemp("meas") / "rig.csv"
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header="time,accel", comments="")
    return path, bpfo


def _record(x, fs, shaft_hz, events=None, label="given events") -> Record:
    freqs = bearing_frequencies(GEOMETRY, shaft_hz)
    return Record(
        label="array record", source="simulated", x=x, fs=fs, shaft_hz=shaft_hz,
        bpfo_hz=freqs.bpfo, unit="m/s^2", frequencies=freqs, events_s=events,
        events_label=label,
    )  # fmt: skip


def test_measured_record_needs_a_speed(measured_csv):
    path, _ = measured_csv
    with pytest.raises(ValueError, match="--rpm"):
        measured_record(path, BearingGeometry(9, 7.94e-3, 39.04e-3))


def test_records_of_arrays_with_and_without_event_times(measured_csv, tmp_path):
    fs, shaft_hz = 50e3, 15.0
    bpfo = bearing_frequencies(GEOMETRY, shaft_hz).bpfo
    x, strikes = _struck(fs, 1.0, bpfo, 0.02, seed=5)
    given = _record(x, fs, shaft_hz, events=strikes, label="strikes (known)")
    meas = measured_record(measured_csv[0], GEOMETRY, rpm=1200.0)
    summary = compare_records([given, meas], tmp_path)
    assert set(summary["figures"]) == FIGURES
    assert json.loads((tmp_path / "summary.json").read_text()) == json.loads(json.dumps(summary))
    first, second = summary["records"]
    # given event times are used as they are; without them the bursts are found
    assert first["n_events"] == strikes.size
    assert "events: envelope bursts (strongest per BPFO period)" in second["notes"]
    assert first["bpfo_hz"] == pytest.approx(bpfo) and first["fs_hz"] == fs
    assert summary["speed_ratio"][1] == pytest.approx(20.0 / shaft_hz)
    assert summary["bpfo_comb_shown"] == [True, True]
    an = analyse(given)
    assert an.events_label == "strikes (known)"
    assert an.events_s == pytest.approx(strikes)
    lines = summary_lines(summary)
    assert lines[0].startswith("array record: 50000 Hz")


def test_no_empty_legend_when_the_first_event_precedes_the_window(tmp_path):
    """The trace window starts a quarter period before the first event that leaves room
    for it; an event earlier than that is not drawn and must not take the legend's label
    with it (matplotlib: 'No artists with labels found to put in legend')."""
    fs, shaft_hz = 50e3, 15.0
    bpfo = bearing_frequencies(GEOMETRY, shaft_hz).bpfo
    x, strikes = _struck(fs, 0.5, bpfo, 0.1 / bpfo, seed=7)
    rec = _record(x, fs, shaft_hz, events=strikes)
    assert strikes[0] < 0.25 / bpfo  # the first event is outside the window
    an = analyse(rec)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        written = compare_figures([rec, rec], [an, an], tmp_path)
    assert "compare_time.png" in written


def test_diagnostics_compare_points_to_the_simulator_command(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    for args in (["runs/x", "rig.csv", "--fs", "12000"], []):
        res = subprocess.run(
            [sys.executable, "-m", "diagnostics", "compare", *args],
            capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120,
        )  # fmt: skip
        assert res.returncode == 2
        lines = res.stderr.strip().splitlines()
        assert len(lines) == 1 and "python -m taichi_bearing compare" in lines[0]
        assert not list(tmp_path.iterdir())  # nothing written
