"""Bad input, as a new user gives it: the API raises one ValueError that names the
problem, the command line prints one line naming the argument or file and exits with 2."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.io import savemat

import diagnostics as dg
from diagnostics.app.cli import main

ROOT = Path(__file__).resolve().parents[2]
FS = 12000.0
GEOMETRY = dg.BearingGeometry(9, 7.94e-3, 39.04e-3)
BEARING = "n=9,d=7.94mm,D=39.04mm"
NOISE = np.random.default_rng(0).standard_normal(int(2 * FS))


def _api_cases():
    """(id, call, pattern the message must match)."""
    return [
        ("diagnose dead sensor", lambda: dg.diagnose(np.zeros(24000), FS, GEOMETRY, 29.95),
         r"^x is constant.*dead sensor"),
        ("diagnose constant offset", lambda: dg.diagnose(np.full(24000, 0.3), FS, GEOMETRY, 30.0),
         r"^x is constant, every sample 0.3"),
        ("diagnose too short names duration", lambda: dg.diagnose(NOISE[:3000], FS, GEOMETRY, 30.0),
         r"too short: 3000 samples last 0.25 s .* needs 0.286 s"),
        ("prewhiten dead sensor", lambda: dg.prewhiten(np.zeros(4096), FS), r"constant"),
        ("third octave of 10 samples", lambda: dg.third_octave(NOISE[:10], FS),
         r"too short for one-third-octave bands from 19.95 Hz: 10 samples .* at least 2607"),
        ("geometry in millimetres", lambda: dg.BearingGeometry(9, 7.94, 39.04),
         r"roller_diameter = 7.94 m .* takes metres; 7.94 mm is 0.00794 m"),
        ("pitch diameter in millimetres", lambda: dg.BearingGeometry(20, 0.024, 200.0),
         r"pitch_diameter = 200 m .*takes metres"),
        ("defect depth negative",
         lambda: dg.estimate_defect_size(NOISE, FS, GEOMETRY, 29.95, depth_m=-1.0),
         r"depth_m must be finite and positive in m, got -1"),
    ]  # fmt: skip


@pytest.mark.parametrize(("call", "pattern"), [c[1:] for c in _api_cases()],
                         ids=[c[0] for c in _api_cases()])  # fmt: skip
def test_api_refuses_with_one_clear_value_error(call, pattern):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning on the way to the message
        with pytest.raises(ValueError, match=pattern):
            call()


def test_third_octave_still_works_where_every_band_has_a_bin():
    fc, level = dg.third_octave(NOISE, FS)
    assert np.all(np.isfinite(level)) and fc[0] == pytest.approx(19.95, rel=1e-3)


def test_real_bearings_in_metres_pass():
    # Railway axlebox bearing and a large slewing ring: real sizes, accepted.
    assert dg.BearingGeometry(20, 0.024, 0.2).n_rollers == 20
    assert dg.BearingGeometry(100, 0.1, 4.0).pitch_diameter == 4.0


# ---------------------------------------------------------------------------- read_signal
@pytest.fixture
def files(tmp_path):
    two = tmp_path / "two.csv"
    np.savetxt(two, np.column_stack([NOISE, -NOISE]), delimiter=",")
    zero = tmp_path / "zero.csv"
    np.savetxt(zero, np.zeros(int(2 * FS)))
    text_mat = tmp_path / "names.mat"
    savemat(text_mat, {"operator": "abc", "note": "no signal here"})
    return {"two": two, "zero": zero, "text_mat": text_mat, "dir": tmp_path}


def test_headerless_columns_resolve_by_index_given_as_text_or_int(files):
    by_text = dg.read_signal(files["two"], channel="1", fs=FS)
    by_int = dg.read_signal(files["two"], channel=1, fs=FS)
    np.testing.assert_allclose(by_text.x, -NOISE, rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(by_int.x, by_text.x)
    assert by_text.channel_names == ["0", "1"]


@pytest.mark.parametrize(
    ("key", "channel", "pattern"),
    [
        ("text_mat", None, r"names.mat: holds no numeric signal .*it holds: note, operator"),
        ("dir", None, r"is a folder, not a file"),
        ("two", "7", r"no channel '7'; available: 0, 1 \(or an index 0..1\)"),
    ],
)
def test_read_signal_refuses_plainly(files, key, channel, pattern):
    with pytest.raises(ValueError, match=pattern):
        dg.read_signal(files[key], channel=channel, fs=FS)


# -------------------------------------------------------------------------- command line
CLI = {
    "dead sensor": ("zero", [], r"zero.csv:0 is constant .*dead sensor"),
    "no numeric variable": ("text_mat", [], r"holds no numeric signal"),
    "absurd fs": ("two", ["--fs", "1e30"], r"^error: --fs 1e\+30 Hz is beyond"),
    "fs too high for the record": ("two", ["--fs", "1e6"], r"at --fs = 1e\+06 Hz last 0.024 s"),
    "fs too low": ("two", ["--fs", "600"], r"--fs = 600 Hz is too low .*at least 827 Hz"),
    "folder as FILE": ("dir", [], r"is a folder, not a file"),
    "notch above Nyquist": ("two", ["--notch", "7000"], r"--notch 7000 Hz is outside 0..6000"),
    "bearing in metres by mistake": ("two", ["--bearing", "n=9,d=7.94m,D=39.04m"],
                                     r"--bearing: roller_diameter = 7.94 m"),
    "unknown channel": ("two", ["--channel", "2"], r"no channel '2'; available: 0, 1"),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(CLI))
def test_cli_one_line_naming_the_argument_exit_2(files, tmp_path, capsys, case):
    key, extra, pattern = CLI[case]
    argv = ["analyze", str(files[key]), "--fs", "12000", "--rpm", "1797", "--bearing", BEARING]
    code = main(argv + extra + ["--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1, err
    assert re.search(pattern, err[0]), err[0]
    assert not (tmp_path / "out" / "summary.json").exists()


def test_cli_second_headerless_column_by_index(files, tmp_path, capsys):
    out = tmp_path / "o"
    argv = ["analyze", str(files["two"]), "--channel", "1", "--fs", "12000", "--rpm", "1797"]
    assert main(argv + ["--bearing", BEARING, "--out", str(out)]) == 0
    assert capsys.readouterr().out.startswith("1: 12000 Hz")


def test_cli_dead_sensor_subprocess_has_no_warning_or_traceback(files):
    env = dict(os.environ, PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    res = subprocess.run(
        [sys.executable, "-m", "diagnostics", "analyze", str(files["zero"]), "--fs", "12000",
         "--rpm", "1797", "--bearing", BEARING, "--out", str(files["dir"] / "o")],
        capture_output=True, text=True, env=env, timeout=120,
    )  # fmt: skip
    assert res.returncode == 2
    assert res.stderr.count("\n") == 1 and "Warning" not in res.stderr
    assert "Traceback" not in res.stderr and "NaN" not in res.stderr
