"""Every command that writes refuses an unusable output folder in one line naming the
argument (``--out``, ``output.dir``, ``RUN_DIR``), with exit status 2, no traceback and
nothing created: a path under ``/proc``, an existing file, a path through a file, an empty
path (which would be the current folder). Also: argparse's own errors are one line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from synthetic_run import make_synthetic_run

from bearing_io.files import ensure_writable, output_folder

ROOT = Path(__file__).resolve().parents[3]
COARSE = str(ROOT / "cases/validation/coarse_spall.yaml")
BEARING = "n=9,d=7.94mm,D=39.04mm"


def _run(cwd: Path, module: str, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    return subprocess.run(
        [sys.executable, "-m", module, *args],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
        cwd=cwd,
    )


def _run_here(cwd: Path, module: str, *args: str, monkeypatch) -> subprocess.CompletedProcess:
    """As :func:`_run`, but calling the command's ``main`` in this process (no interpreter
    start-up and imports per case); an exception escaping ``main`` fails the test as a
    traceback would."""
    import contextlib
    import importlib
    import io

    main = importlib.import_module(f"{module}.__main__").main
    monkeypatch.chdir(cwd)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            code = main(list(args))
        except SystemExit as exc:  # argparse's errors
            code = exc.code
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


def _tree(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


@pytest.fixture(scope="module")
def inputs(tmp_path_factory) -> dict[str, Path]:
    """A run folder and a measured record for the commands that read them."""
    base = tmp_path_factory.mktemp("inputs")
    run_dir = base / "run"
    make_synthetic_run(run_dir, frames=False)
    fs = 20e3
    t = np.arange(int(1.0 * fs)) / fs
    x = np.random.default_rng(1).standard_normal(t.size)
    record = base / "rig.csv"
    np.savetxt(record, np.column_stack([t, x]), delimiter=",", header="time,accel", comments="")
    return {"run": run_dir, "record": record}


# (module, arguments before the output folder, the option the message names)
COMMANDS = {
    "run": ("taichi_bearing", ["run", COARSE, "--threads", "1", "--out"], "--out"),
    "mesh": ("taichi_bearing", ["mesh", COARSE, "--out"], "--out"),
    "analytic": ("taichi_bearing", ["analytic", COARSE, "--out"], "--out"),
    "sweep": ("taichi_bearing",
              ["sweep", COARSE, "--load-kN", "50", "--speed-rpm", "500", "--out"], "--out"),
    "compare": ("taichi_bearing",
                ["compare", "{run}", "{record}", "--fs", "20000", "--rpm", "1200", "--out"],
                "--out"),
    "post": ("taichi_bearing", ["post"], "RUN_DIR"),
    "diagnostics analyze": ("diagnostics",
                            ["analyze", "{record}", "--fs", "20000", "--rpm", "1200",
                             "--bearing", BEARING, "--channel", "accel", "--out"], "--out"),
}  # fmt: skip

# (folder as given, what the one line says besides the option)
BAD_FOLDERS = {
    "proc": ("/proc/x", "cannot create /proc/x"),
    "file": ("afile", "afile exists and is not a folder"),
    "through_file": ("afile/sub", "afile is a file, not a folder"),
    "empty": ("", "empty path"),
}


@pytest.mark.parametrize("folder", list(BAD_FOLDERS))
@pytest.mark.parametrize("command", list(COMMANDS))
def test_bad_output_folder_is_one_line_exit_2_and_nothing_written(
    command, folder, inputs, tmp_path, monkeypatch
):
    """A path under /proc is tried through ``python -m`` (the real process: exit status,
    stderr); the other folders call each command's ``main`` in this process."""
    module, args, option = COMMANDS[command]
    value, says = BAD_FOLDERS[folder]
    if command == "post" and folder in ("proc", "file", "through_file"):
        pytest.skip("post reads RUN_DIR first: 'not a folder' (tested in test_run_cli)")
    if folder == "proc" and not Path("/proc").is_dir():
        pytest.skip("no /proc")
    (tmp_path / "afile").write_text("not a folder\n")
    before, run_before = _tree(tmp_path), _tree(inputs["run"])
    args = [a.format(**inputs) for a in args]
    if folder == "proc" or (command == "post" and folder == "empty"):
        proc = _run(tmp_path, module, *args, value)
    else:
        proc = _run_here(tmp_path, module, *args, value, monkeypatch=monkeypatch)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"error: {option}: ") and says in lines[0], lines[0]
    # nothing written: not in the current folder (an empty --out is that), not beside
    assert _tree(tmp_path) == before
    assert (tmp_path / "afile").read_text() == "not a folder\n"
    assert not Path("/proc/x").exists()
    assert _tree(inputs["run"]) == run_before


def test_output_dir_key_is_named_when_it_is_the_folder(tmp_path):
    (tmp_path / "afile").write_text("")
    proc = _run(tmp_path, "taichi_bearing", "mesh", COARSE, "--set", "output.dir=afile/sub")
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr
    assert lines[0] == "error: output.dir: afile/sub: afile is a file, not a folder"
    assert _tree(tmp_path) == {"afile"}


@pytest.mark.parametrize(
    ("args", "names"),
    [
        (["run"], "case"),
        (["run", COARSE, "--arch", "tpu"], "--arch"),
        (["run", COARSE, "--progress-interval", "soon"], "--progress-interval"),
        (["run", COARSE, "--progress-interval", "0"], "--progress-interval"),
        (["compare", "somewhere"], "MEASURED_FILE"),
        (["post"], "run_dir"),
        (["--no-such-option"], "--no-such-option"),
    ],
)
def test_argument_errors_are_one_line(args, names, tmp_path):
    proc = _run(tmp_path, "taichi_bearing", *args)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and names in lines[0], proc.stderr
    assert "usage:" not in proc.stderr and "Traceback" not in proc.stderr
    assert _tree(tmp_path) == set()


def test_output_folder_makes_the_missing_folders_and_returns_the_path(tmp_path):
    out = output_folder(tmp_path / "a" / "b", "--out")
    assert out == tmp_path / "a" / "b" and out.is_dir()
    assert output_folder(out, "--out") == out  # an existing folder is fine
    assert _tree(out) == set()  # the write probe leaves nothing
    with pytest.raises(ValueError, match=r"^--out: empty path"):
        output_folder(" ", "--out")


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="no /proc")
def test_a_folder_nothing_can_be_written_in_is_refused():
    with pytest.raises(ValueError, match=r"^--out: cannot write in /proc: "):
        ensure_writable(Path("/proc"), "--out")
