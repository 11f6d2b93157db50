"""`python -m taichi_bearing CASE.yaml`: bad input exits 2 with one line; Ctrl-C keeps
valid histories of everything up to that point."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from taichi_bearing.output.histories import read_histories

ROOT = Path(__file__).resolve().parents[1]
COARSE = str(ROOT / "cases/validation/coarse_spall.yaml")


def _default_sigint() -> None:
    """In the child: Ctrl-C as a terminal delivers it. A shell starts background jobs with
    SIGINT ignored, and a child inherits that; Python then installs no handler."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _run(*args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "taichi_bearing", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        env=_env(),
        cwd=ROOT,
    )


@pytest.mark.parametrize(
    ("args", "names"),
    [
        (["missing_case.yaml"], "missing_case.yaml"),
        ([COARSE, "--set", "operating.load_kN=-5"], "operating.load_kN"),
        ([COARSE, "--set", "run.duration_ms=fast"], "run.duration_ms"),
        ([COARSE, "--set", "nosuchsection.x=1"], "nosuchsection"),
        ([COARSE, "--threads", "-1"], "--threads"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args, names, tmp_path):
    proc = _run(*args, "--out", str(tmp_path / "out"))
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and names in lines[0]
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "out" / "histories.parquet").exists()


def test_unknown_arch_is_rejected_by_the_parser(tmp_path):
    proc = _run(COARSE, "--arch", "tpu", "--out", str(tmp_path))
    assert proc.returncode == 2 and "--arch" in proc.stderr


def test_ctrl_c_leaves_valid_histories(tmp_path):
    out = tmp_path / "run"
    proc = subprocess.Popen(
        [sys.executable, "-m", "taichi_bearing", COARSE, "--out", str(out), "--threads", "1",
         "--quiet", "--no-post"],
        env=_env(), cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=_default_sigint,
    )  # fmt: skip
    try:
        # wait for the first checkpoint (0.5 ms into the transient), then press Ctrl-C
        deadline = time.monotonic() + 240
        while not list((out / "checkpoints").glob("checkpoint_*.npz")):
            assert proc.poll() is None, proc.stderr.read()
            assert time.monotonic() < deadline, "no checkpoint in time"
            time.sleep(0.2)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    assert "interrupted" in err
    hist = read_histories(out)
    t = hist["time_s"].to_numpy()
    # every sample from the first one on, none missing, none from beyond the stop
    assert t[0] == pytest.approx(1e-5)
    assert np.allclose(np.diff(t), 1e-5)
    assert 0.5e-3 - 1e-9 <= t[-1] < 2e-3
    assert np.all(np.isfinite(hist.to_numpy()))
    assert (out / "histories.parquet").is_file()
    assert not (out / "histories.parts").exists()  # merged on the way out
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert summary["n_steps"] > 0
