"""python -m diagnostics analyze: verdicts and summary.json on measured records; bad input
gives one line on stderr and exit status 2."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from diagnostics.app.cli import main, parse_bearing

ROOT = Path(__file__).resolve().parents[2]
BEARING = "n=9,d=7.94mm,D=39.04mm,angle=0"
SUMMARY_KEYS = {
    "fault_frequencies_hz",
    "kurtogram",
    "infogram",
    "verdict",
    "confidence",
    "scores",
    "band_hz",
    "families",
    "figures",
}


def _run(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    return subprocess.run(
        [sys.executable, "-m", "diagnostics", *args],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
        timeout=300,
    )


def test_cli_outer_race_record(cwru_dir, tmp_path):
    out = tmp_path / "o"
    res = _run(
        "analyze", str(cwru_dir / "12k_Drive_End_OR007@6_0_130.mat"),
        "--fs", "12000", "--bearing", BEARING, "--out", str(out),
    )  # fmt: skip
    assert res.returncode == 0, res.stderr
    assert "verdict: outer fault" in res.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert SUMMARY_KEYS <= summary.keys()
    assert summary["verdict"] == "outer"
    assert summary["rpm"] == 1796.0  # from the file
    # BPFO = 3.5848 x shaft rate: that of the record's shaft lines, within 0.2 % of 1796 rpm
    shaft = summary["shaft_lines"]["analysed_at"]
    assert shaft == pytest.approx(1796 / 60, 2e-3)
    assert summary["fault_frequencies_hz"]["bpfo_hz"] == pytest.approx(3.5848 * shaft, 1e-4)
    assert summary["scores"]["outer"] > summary["scores"]["inner"]
    for name in summary["figures"]:
        assert (out / name).stat().st_size > 1000
    assert {"kurtogram.png", "infogram.png", "envelope_spectrum.png", "spectrogram.png"} <= set(
        summary["figures"]
    )
    # The band analysed is the infogram's (the record's most repetitive impacts) and lies
    # within the band map's levels; the printed lines name both maps' best bands.
    assert summary["infogram"]["negentropy"] > 0.5
    assert "infogram best band:" in res.stdout and "SES negentropy" in res.stdout
    # The band diagnose took from the infogram is reported, none from the kurtogram (one
    # band is taken from the tree).
    used = summary["infogram"]["diagnosed_band_hz"]
    assert used is not None and summary["kurtogram"]["diagnosed_band_hz"] is None
    # wide enough for two harmonics of the fastest fault frequency (80 % of a band usable)
    assert used[1] - used[0] >= 2 * summary["fault_frequencies_hz"]["bpfi_hz"] / 0.8
    # and the infogram's second band, of the same kind, apart from it
    second = summary["infogram"]["second_band_hz"]
    assert second[1] - second[0] >= 2 * summary["fault_frequencies_hz"]["bpfi_hz"] / 0.8
    assert second[1] <= used[0] or second[0] >= used[1]
    assert f"also in {second[0]:.4g}-{second[1]:.4g} Hz" in res.stdout
    assert "second_band_hz" not in summary["kurtogram"]


@pytest.mark.parametrize(
    "name, fs, verdict",
    [("12k_Drive_End_IR007_0_105.mat", "12000", "inner"), ("normal_0_97.mat", "48000", "none")],
)
def test_cli_verdicts(cwru_dir, tmp_path, capsys, name, fs, verdict):
    out = tmp_path / "r"
    code = main(["analyze", str(cwru_dir / name), "--fs", fs, "--bearing", BEARING,
                 "--out", str(out)])  # fmt: skip
    assert code == 0
    assert json.loads((out / "summary.json").read_text())["verdict"] == verdict
    assert "verdict:" in capsys.readouterr().out


def test_cli_names_the_stronger_series_of_another_component(cwru_dir, tmp_path, capsys):
    """Record 135's fan-end channel with the fan-end bearing: healthy, and the drive-end
    ball-pass series (3.585 orders, 107.4 Hz at 1796 rpm) is reported as what dominated."""
    out = tmp_path / "fe"
    code = main(["analyze", str(cwru_dir / "48k_Drive_End_OR007@6_0_135.mat"), "--fs", "48000",
                 "--channel", "X135_FE_time", "--bearing", "n=8,d=0.2656in,D=1.122in",
                 "--out", str(out)])  # fmt: skip
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["verdict"] == "none"
    assert summary["dominated"] == ["ball"]
    assert summary["other_series"]["fundamental"] == pytest.approx(3.5848 * 1796 / 60, rel=0.01)
    printed = capsys.readouterr().out
    assert "not named: ball (its lines belong to a stronger series at 107" in printed
    from diagnostics import diagnose
    from diagnostics.app.analyze import _markers
    from diagnostics.app.datasets import CWRU_FAN_END, read_labelled_record

    rec = read_labelled_record(cwru_dir / "48k_Drive_End_OR007@6_0_135.mat", end="fan")
    marks = _markers(diagnose(rec.x, rec.fs, CWRU_FAN_END, rec.shaft_hz))
    assert marks["other series"] == pytest.approx(summary["other_series"]["fundamental"])
    assert "2xBSF (set aside)" in marks and "2xBSF (found)" not in marks


def test_cli_names_a_slower_train(tmp_path, capsys):
    """Impacts at half of BPFI (0.3 % off) on a healthy bearing: the inner-race comb is set
    aside as a slower period, and the line says at what rate the impacts repeat."""
    from synthetic_records import FREQS, fault_signal

    path = tmp_path / "half.npz"
    x = fault_signal(12000.0, 0.5 * 1.003 * FREQS.bpfi, 4500.0, seed=101)
    np.savez(path, x=x, fs=12000.0)
    out = tmp_path / "h"
    args = ["analyze", str(path), "--rpm", "1797", "--bearing", BEARING, "--out", str(out)]
    assert main(args) == 0
    summary = json.loads((out / "summary.json").read_text())
    inner = summary["families"]["inner"]
    assert summary["verdict"] == "none" and inner["slower_period"] == 2
    expected = (
        f"the lines between its BPFI harmonics show impacts at {inner['found_hz'] / 2:.4g} Hz"
    )
    assert f"not named: inner ({expected}" in capsys.readouterr().out


def test_cli_says_a_ball_was_named_by_a_line_and_its_sideband(tmp_path, capsys):
    """One line at 2 x BSF with a weaker one a cage rate below: the verdict is ball, and the
    printed evidence says it rests on the line and its sideband, not a pair of harmonics."""
    from synthetic_records import modulated_noise

    from diagnostics import bearing_frequencies
    from diagnostics.app.datasets import CWRU_DRIVE_END

    f = bearing_frequencies(CWRU_DRIVE_END, 1797.0 / 60.0)
    path = tmp_path / "ball.npz"
    np.savez(path, x=modulated_noise({2 * f.bsf: 0.15, 2 * f.bsf - f.ftf: 0.05}), fs=12000.0)
    out = tmp_path / "b"
    args = ["analyze", str(path), "--rpm", "1797", "--bearing", BEARING, "--out", str(out)]
    assert main(args) == 0
    summary = json.loads((out / "summary.json").read_text())
    ball = summary["families"]["ball"]
    assert summary["verdict"] == "ball" and ball["sideband_pair_p"] < ball["pair_p"]
    printed = capsys.readouterr().out
    assert f"evidence: a 2xBSF line and its cage-rate sideband ({f.ftf:.4g} Hz away" in printed


def test_cli_notch_and_rpm_override(tmp_path, capsys):
    # A CSV without speed: --rpm is required and used; --notch is recorded.
    fs = 12000.0
    x = np.random.default_rng(0).standard_normal(int(2 * fs))
    path = tmp_path / "noise.csv"
    np.savetxt(path, x, header="acc", comments="")
    out = tmp_path / "n"
    argv = ["analyze", str(path), "--fs", "12000", "--bearing", BEARING, "--out", str(out)]
    assert main(argv + ["--rpm", "1800", "--notch", "60", "120"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["notch_hz"] == [60.0, 120.0]
    assert summary["fault_frequencies_hz"]["shaft_hz"] == pytest.approx(30.0)
    assert summary["verdict"] == "none"
    capsys.readouterr()
    assert main(argv) == 2  # no speed anywhere
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--rpm" in err[0]


BAD = {
    "bearing": ["--fs", "12000", "--bearing", "n=9,d=7.94,D=39.04mm"],
    "bearing key": ["--fs", "12000", "--bearing", "n=9,d=7.94mm,D=39.04mm,z=3"],
    "geometry": ["--fs", "12000", "--bearing", "n=9,d=40mm,D=39.04mm"],
    "channel": ["--fs", "12000", "--bearing", BEARING, "--channel", "X999_DE_time"],
    "fs": ["--bearing", BEARING],
    "fs value": ["--fs", "twelve", "--bearing", BEARING],
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_arguments_one_line_exit_2(cwru_dir, tmp_path, capsys, case):
    record = str(cwru_dir / "12k_Drive_End_OR007@6_0_130.mat")
    code = main(["analyze", record, *BAD[case], "--out", str(tmp_path / "x")])
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:")
    assert not (tmp_path / "x" / "summary.json").exists()


def test_missing_file_subprocess(tmp_path):
    res = _run("analyze", str(tmp_path / "absent.mat"), "--fs", "12000", "--bearing", BEARING)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "absent.mat" in lines[0]
    assert "Traceback" not in res.stderr


def test_parse_bearing_units():
    g = parse_bearing("n=9, d=0.3126in, D=1.537in, angle=15")
    assert g.n_rollers == 9
    assert g.roller_diameter == pytest.approx(7.94e-3, rel=1e-3)
    assert g.pitch_diameter == pytest.approx(39.04e-3, rel=1e-3)
    assert g.contact_angle_deg == 15.0


def test_markers_name_the_comb_that_found_the_fault():
    from synthetic_records import gated_ball_impacts

    from diagnostics import BearingGeometry, bearing_frequencies, diagnose
    from diagnostics.app.analyze import _markers

    geometry = BearingGeometry(9, 7.94e-3, 39.04e-3)
    freqs = bearing_frequencies(geometry, 29.95)
    d = diagnose(gated_ball_impacts(12000.0, 5.0, jitter=0.08, seed=3), 12000.0, geometry, 29.95)
    marks = _markers(d)
    assert "other series" not in marks  # nothing was set aside
    assert marks["FTF (found)"] == pytest.approx(freqs.ftf, rel=0.02)
    assert marks["BPFO"] == pytest.approx(freqs.bpfo) and marks["BPFI"] == pytest.approx(freqs.bpfi)
