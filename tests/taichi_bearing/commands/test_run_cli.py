"""`python -m taichi_bearing CASE.yaml`: bad input exits 2 with one line; Ctrl-C keeps
valid histories of everything up to that point; after kill -9 the run folder is still one
(`post` checks what was recorded and says partial, `--resume` finishes it); piped into a
log, a run prints progress lines of the preload and the transient (none with --quiet)."""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from taichi_bearing.output.histories import read_histories

ROOT = Path(__file__).resolve().parents[3]
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


def _wait_for_checkpoint(proc: subprocess.Popen, out: Path, timeout: float = 240) -> None:
    """Until the run has written its first checkpoint (it is then in the transient)."""
    deadline = time.monotonic() + timeout
    while not list((out / "checkpoints").glob("checkpoint_*.npz")):
        assert proc.poll() is None, proc.stderr.read()
        assert time.monotonic() < deadline, "no checkpoint in time"
        time.sleep(0.05)


def test_unknown_arch_is_rejected_by_the_parser(tmp_path):
    proc = _run(COARSE, "--arch", "tpu", "--out", str(tmp_path))
    assert proc.returncode == 2 and "--arch" in proc.stderr


def test_ctrl_c_leaves_valid_histories(tmp_path):
    out = tmp_path / "run"
    proc = subprocess.Popen(
        [sys.executable, "-m", "taichi_bearing", *TINY, "--out", str(out), "--no-post"],
        env=_env(), cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=_default_sigint,
    )  # fmt: skip
    try:
        # wait for the first checkpoint (0.2 ms into the transient), then press Ctrl-C
        _wait_for_checkpoint(proc, out)
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
    assert 0.2e-3 - 1e-9 <= t[-1] < 2e-3
    assert np.all(np.isfinite(hist.to_numpy()))
    assert (out / "histories.parquet").is_file()
    assert not (out / "histories.parts").exists()  # merged on the way out
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert summary["n_steps"] > 0


# A run small enough to kill, inspect and resume in a test: the coarse case on a 3 mm
# mesh (about 4,000 elements), 2 ms, a checkpoint every 0.2 ms.
TINY = [COARSE, "--set", "mesh.surface_size_mm=3", "--set", "mesh.max_size_mm=6",
        "--set", "run.duration_ms=2", "--set", "run.checkpoint_interval_ms=0.2",
        "--set", "run.frame_interval_ms=1", "--threads", "1", "--quiet"]  # fmt: skip


@pytest.fixture(scope="module")
def killed_run(tmp_path_factory):
    """A tiny run killed with SIGKILL during the transient, after its first checkpoint;
    then ``post`` on what it left, then ``--resume``. Returns what each step left."""
    out = tmp_path_factory.mktemp("killed") / "run"
    proc = subprocess.Popen(
        [sys.executable, "-m", "taichi_bearing", *TINY, "--out", str(out)],
        env=_env(), cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        _wait_for_checkpoint(proc, out)
        proc.kill()  # SIGKILL: nothing runs on the way out
        proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    left = {
        "returncode": proc.returncode,
        "files": sorted(p.name for p in out.iterdir()),
        "summary": json.loads((out / "summary.json").read_text()),
    }
    left["post"] = _run("post", str(out))
    left["post_summary"] = json.loads((out / "summary.json").read_text())
    left["report"] = (out / "report.md").read_text()
    left["parts_after_post"] = (out / "histories.parts").is_dir()
    left["resume"] = _run(*TINY, "--out", str(out), "--resume", "--no-post")
    left["resumed_summary"] = json.loads((out / "summary.json").read_text())
    return out, left


def test_kill_9_leaves_a_run_folder_with_the_histories_in_parts(killed_run):
    _, left = killed_run
    assert left["returncode"] == -signal.SIGKILL
    assert "histories.parquet" not in left["files"]
    assert "histories.parts" in left["files"]
    # written before the transient: what post needs
    for name in ("case.yaml", "mesh_info.json", "preload.json", "summary.json"):
        assert name in left["files"]
    assert left["summary"]["status"] == "running"
    assert "reference_roller_forces_N" in left["summary"]["preload"]


def test_post_checks_a_killed_run_on_what_it_recorded_and_says_partial(killed_run):
    _, left = killed_run
    post = left["post"]
    assert post.returncode == 0, post.stderr
    assert "partial" in post.stdout
    summary = left["post_summary"]
    partial = summary["partial"]
    assert partial["status"] == "running"
    assert partial["histories"] == "histories.parts/ only"
    # killed after the first checkpoint (0.2 ms), before the end (2 ms)
    assert 0.2e-3 - 1e-9 <= partial["recorded_until_s"] < 2e-3
    assert partial["duration_s"] == pytest.approx(2e-3)
    assert summary["status"] == "running"  # post does not pretend the run finished
    assert summary["checks"]["energy_balance"]["value"] is not None
    assert "Partial run (status running)" in left["report"]
    assert left["parts_after_post"]  # post reads the parts, it does not merge them


def test_resume_after_kill_9_and_post_finishes_the_run(killed_run):
    out, left = killed_run
    resume = left["resume"]
    assert resume.returncode == 0, resume.stderr
    summary = left["resumed_summary"]
    assert summary["status"] == "finished" and "partial" not in summary
    assert (out / "histories.parquet").is_file()
    assert not (out / "histories.parts").exists()
    t = read_histories(out)["time_s"].to_numpy()
    assert len(t) == 200 and t[0] == pytest.approx(1e-5)
    assert np.allclose(np.diff(t), 1e-5)


def test_post_of_a_folder_without_the_reference_names_it_and_remesh_restores_it(
    killed_run, tmp_path
):
    """A run folder from before runs recorded mesh_info.json and the flexible-ring
    reference: one line naming what is missing; ``--remesh`` gives the same checks."""
    out, left = killed_run
    old = tmp_path / "old"
    shutil.copytree(out, old)
    (old / "mesh_info.json").unlink()
    pre = json.loads((old / "preload.json").read_text())
    del pre["reference_roller_forces_N"], pre["rolling_rates_rad_s"]
    (old / "preload.json").write_text(json.dumps(pre))
    refused = _run("post", str(old), "--no-report")
    assert refused.returncode == 2
    lines = refused.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in refused.stderr
    for what in ("mesh_info.json", "reference_roller_forces_N", "--remesh"):
        assert what in lines[0]
    redone = _run("post", str(old), "--no-report", "--remesh")
    assert redone.returncode == 0, redone.stderr
    summary = json.loads((old / "summary.json").read_text())
    assert summary["checks"] == left["resumed_summary"]["checks"]
    restored = json.loads((old / "preload.json").read_text())
    assert restored["computed_after_the_run"]["keys"] == [
        "reference_roller_forces_N",
        "rolling_rates_rad_s",
    ]


def _small_run(duration_ms: float) -> list[str]:
    """The tiny case for ``duration_ms``, no checkpoints, frames or post-processing, with
    progress lines every 0.2 s of wall time when stderr is a pipe."""
    return [COARSE, "--set", "mesh.surface_size_mm=3", "--set", "mesh.max_size_mm=6",
            "--set", f"run.duration_ms={duration_ms}", "--set", "output.frames=false",
            "--threads", "1", "--no-post", "--progress-interval", "0.2"]  # fmt: skip


PRELOAD_LINE = re.compile(
    r"^preload: KE ratio \S+ \(stops below 0\.0001\), step [\d,]+ of at most [\d,]+, "
    r"[\d,]+ steps/s, [\d.]+ s (so far|in all)$"
)
TRANSIENT_LINE = re.compile(
    r"^transient: [\d.]+/0\.500 ms simulated \(\d+%\), step [\d,]+, [\d,]+ steps/s, "
    r"[\d.]+ s (so far, about [\d.]+ s left|in all)$"
)


def _progress_lines(stderr: str, pattern: re.Pattern) -> list[str]:
    return [line for line in stderr.splitlines() if pattern.match(line)]


def test_piped_run_logs_the_preload_and_the_transient_periodically(tmp_path):
    proc = _run(*_small_run(0.5), "--out", str(tmp_path / "run"))
    assert proc.returncode == 0, proc.stderr
    for pattern in (PRELOAD_LINE, TRANSIENT_LINE):
        lines = _progress_lines(proc.stderr, pattern)
        periodic = [line for line in lines if "so far" in line]
        assert periodic, proc.stderr
        assert lines[-1].endswith(" in all") and len(lines) == len(periodic) + 1
    last = _progress_lines(proc.stderr, TRANSIENT_LINE)[-1]
    assert last.startswith("transient: 0.500/0.500 ms simulated (100%)")
    assert "\r" not in proc.stderr  # no bar drawn into a log


def test_quiet_run_prints_no_progress(tmp_path):
    # a looser preload and a shorter transient than the piped run: only silence is checked
    proc = _run(*_small_run(0.1), "--set", "preload.ke_ratio_tol=0.01",
                "--set", "run.frame_interval_ms=0.1", "--set", "run.checkpoint_interval_ms=0.1",
                "--quiet", "--out", str(tmp_path / "run"))  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    stages = ("mesh:", "model:", "preload:", "transient:", "checks:", "results in")
    shown = [line for line in proc.stderr.splitlines() if line.startswith(stages)]
    assert shown == [] and proc.stdout.count("results in") == 0, proc.stderr
    assert (tmp_path / "run" / "histories.parquet").is_file()
