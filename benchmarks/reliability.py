"""Every bad input and fault the project knows of, tried as a user meets it: one row each,
what went in, what came out, pass or fail; the exit status is 1 when any row fails.

    python benchmarks/reliability.py                # every row: a few minutes on 2 cores
    python benchmarks/reliability.py --only sweep   # the rows whose kind or input holds it

What each kind must give (the tests these rows come from in brackets):

- case files, values and command-line arguments: exit status 2 and one line naming the
  file, key or argument, before anything is written (``commands/test_run_cli.py``,
  ``case/test_operating_limits.py``, ``studies/test_sweep.py``, ``test_cli_out.py``);
- diagnostics on a record that is constant, non-finite or in a unit from 1e-300 to 1e300:
  one line and exit status 2, or the record's own verdict with no warning
  (``diagnostics/test_diag_bad_inputs.py``, ``test_diag_scale.py``);
- a run interrupted by Ctrl-C (SIGINT) or killed (SIGKILL) during its transient: a folder
  ``post`` checks, saying partial where the run did not finish (``test_run_cli.py``);
- a study whose cell's process is killed, whose own process is killed, or whose Dask
  worker is: the other cells finish, the lost cell is reported and its folder says why;
  the same command again runs only what did not finish, the finished folders untouched
  and every history that of a sweep never interrupted (``studies/test_sweep.py``).

Runs use the coarse case (``cases/validation/coarse_spall.yaml``) on a 3 mm mesh, one
thread each, at most two at a time; they find the process to kill by its ``--out`` in
``/proc`` (Linux).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.io import savemat

ROOT = Path(__file__).resolve().parents[1]
COARSE = str(ROOT / "cases" / "validation" / "coarse_spall.yaml")


def _sets(*settings: str) -> list[str]:
    return [arg for setting in settings for arg in ("--set", setting)]


# The coarse case on a 3 mm mesh (~4,000 elements): no frames, figures or report.
SMALL = [
    *_sets("mesh.surface_size_mm=3", "mesh.max_size_mm=6", "output.frames=false"),
    "--threads",
    "1",
    "--no-post",
    "--quiet",
]
# Long enough to be caught in its transient: 2 ms, a checkpoint every 0.2 ms.
INTERRUPTIBLE = _sets("run.duration_ms=2", "run.checkpoint_interval_ms=0.2")
# A study: two speeds of the small run, 1 ms each (--workers or --scheduler added).
SWEEP = [
    "--speed-rpm",
    "900,1000",
    *_sets("run.duration_ms=1", "run.checkpoint_interval_ms=0.2"),
    *SMALL,
]
CELLS = ("speed_900rpm", "speed_1000rpm")
BEARING = "n=9,d=7.94mm,D=39.04mm"
FS = 12000.0
LIMIT_S = 15.0  # a refused case value: before any meshing (the interpreter's start included)


@dataclass
class Row:
    """One input or fault: its kind, what went in, what came out, whether that is right."""

    kind: str
    went_in: str
    came_out: str
    passed: bool | None  # None: not tried here (a missing optional package)
    seconds: float


def _env() -> dict[str, str]:
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    return env


def _cmd(module: str, *args: str) -> list[str]:
    return [sys.executable, "-m", module, *map(str, args)]


def _call(module: str, *args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    return subprocess.run(
        _cmd(module, *args),
        capture_output=True,
        text=True,
        cwd=ROOT,
        env=_env(),
        timeout=timeout,
        check=False,
    )


def _first_line(text: str) -> str:
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[0] if lines else ""


def _said(proc: subprocess.CompletedProcess) -> str:
    """Its exit status and what it said: the error line, or the result line."""
    if proc.returncode == 0:
        lines = [ln for ln in proc.stdout.splitlines() if ln.strip()]
        return f"exit 0: {lines[-1].strip() if lines else ''}"
    errors = [ln for ln in proc.stderr.splitlines() if ln.startswith(("error:", "failed:"))]
    return f"exit {proc.returncode}: {errors[0] if errors else _first_line(proc.stderr)}"


def _status(run_dir: Path) -> str | None:
    try:
        return json.loads((run_dir / "summary.json").read_text()).get("status")
    except (OSError, ValueError):
        return None


def _writers(run_dir: Path) -> list[tuple[int, int]]:
    """(pid, parent pid) of the live processes running with ``--out run_dir``."""
    out = []
    for proc in Path("/proc").glob("[0-9]*"):
        try:
            argv = (proc / "cmdline").read_bytes().decode(errors="replace").split("\0")
            state, ppid = (proc / "stat").read_text().rpartition(")")[2].split()[:2]
        except OSError:
            continue
        pairs = zip(argv, argv[1:], strict=False)
        if state not in "ZX" and ("--out", str(run_dir.resolve())) in pairs:
            out.append((int(proc.name), int(ppid)))
    return out


def _in_transient(run_dir: Path) -> bool:
    """The run has written a checkpoint: it is in its transient, with history parts."""
    return any((run_dir / "checkpoints").glob("checkpoint_*.npz"))


# ------------------------------------------------------------------ bad input: exit 2


def refused(
    kind: str,
    went_in: str,
    module: str,
    args: list,
    names: list[str],
    out: Path,
    limit_s: float | None = None,
) -> Row:
    """``python -m module args`` exits 2 with one line holding ``names``, no traceback,
    ``out`` not made; within ``limit_s`` if given."""
    t0 = time.perf_counter()
    proc = _call(module, *args)
    dt = time.perf_counter() - t0
    lines = proc.stderr.strip().splitlines()
    ok = (
        proc.returncode == 2
        and len(lines) == 1
        and all(n in lines[0] for n in names)
        and "Traceback" not in proc.stderr
        and not out.exists()
        and (limit_s is None or dt < limit_s)
    )
    return Row(kind, went_in, _said(proc), ok, dt)


def bad_inputs(tmp: Path) -> Iterator[Row]:
    """Case files and values, and command-line arguments, that must be refused."""
    out = tmp / "never"
    files = {"not_yaml.yaml": "name: [unclosed\n", "a_list.yaml": "- 1\n- 2\n", "empty.yaml": ""}
    for name, text in files.items():
        (tmp / name).write_text(text)
    run = ["run", COARSE, "--out", out]
    yield refused(
        "case file",
        "missing case file",
        "taichi_bearing",
        ["run", "no_such_case.yaml", "--out", out],
        ["no_such_case.yaml"],
        out,
    )
    for name in files:
        yield refused(
            "case file", name, "taichi_bearing", ["run", tmp / name, "--out", out], [name], out
        )
    values = [
        ("nosuchsection.x=1", "nosuchsection"),
        ("operating.nonsense=1", "operating.nonsense"),
        ("operating.load_kN=-5", "operating.load_kN"),
        ("operating.load_kN=.nan", "operating.load_kN"),
        ("run.duration_ms=fast", "run.duration_ms"),
        ("run.duration_ms=.inf", "run.duration_ms"),
        ("run.duration_ms=1e9", "run.max_steps"),  # the step budget
        ("mesh.surface_size_mm=0", "mesh.surface_size_mm"),
        ("operating.load_kN=1e5", "operating.load_kN"),  # a pressure no solid carries
        ("defect.depth_mm=7", "defect.depth_mm"),  # through the ring
        ("operating.speed_rpm=1e9", "operating.speed_rpm"),  # far past the wave speed
    ]
    for setting, name in values:
        yield refused(
            "case value",
            f"--set {setting}",
            "taichi_bearing",
            [*run, "--set", setting],
            [name],
            out,
            limit_s=LIMIT_S,
        )
    a_file = tmp / "a_file"
    a_file.write_text("not a folder\n")
    (tmp / "not_a_run").mkdir()
    record = tmp / "record.csv"
    record.write_text("0.0\n1.0\n")
    sweep = ["sweep", COARSE, "--out", out]
    folders = [
        ("run --out A_FILE", a_file, "exists and is not a folder"),
        ("run --out A_FILE/sub", a_file / "sub", "is a file, not a folder"),
        ("run --out ''", "", "empty path"),
        ("run --out /proc/x", "/proc/x", "/proc/x"),
    ]
    for went_in, folder, says in folders:
        yield refused(
            "output",
            went_in,
            "taichi_bearing",
            ["run", COARSE, "--out", folder],
            ["--out", says],
            out,
        )
    yield refused(
        "output",
        "--set output.dir=A_FILE/sub",
        "taichi_bearing",
        ["mesh", COARSE, "--set", f"output.dir={a_file}/sub"],
        ["output.dir"],
        out,
    )
    arguments = [
        ("run (no case)", ["run"], "case"),
        ("run --threads -1", [*run, "--threads", "-1"], "--threads"),
        ("run --arch tpu", [*run, "--arch", "tpu"], "--arch"),
        (
            "run --progress-interval soon",
            [*run, "--progress-interval", "soon"],
            "--progress-interval",
        ),
        ("run --progress-interval 0", [*run, "--progress-interval", "0"], "--progress-interval"),
        ("run --bogus", [*run, "--bogus"], "--bogus"),
        ("post NOT_A_RUN", ["post", tmp / "not_a_run"], "not_a_run"),
        (
            "compare NOWHERE RECORD",
            ["compare", tmp / "nowhere", record, "--rpm", "1200", "--out", out],
            "not a folder",
        ),
        (
            "compare NOT_A_RUN RECORD",
            ["compare", tmp / "not_a_run", record, "--rpm", "1200", "--out", out],
            "summary.json",
        ),
        ("compare NOT_A_RUN (no record)", ["compare", tmp / "not_a_run"], "MEASURED_FILE"),
        ("analytic --angles 3", ["analytic", COARSE, "--angles", "3", "--out", out], "--angles"),
        (
            "analytic --spall-angles 10 (outer race)",
            ["analytic", COARSE, "--spall-angles", "10", "--out", out],
            "--spall-angles",
        ),
        (
            "mesh --set mesh.max_size_mm=-1",
            ["mesh", COARSE, "--set", "mesh.max_size_mm=-1", "--out", out],
            "mesh.max_size_mm",
        ),
        ("sweep --load-kN 20,x", [*sweep, "--load-kN", "20,x"], "--load-kN"),
        (
            "sweep --load-kN 20 --workers 0",
            [*sweep, "--load-kN", "20", "--workers", "0"],
            "--workers",
        ),
        (
            "sweep --load-kN 20 --ensemble 0",
            [*sweep, "--load-kN", "20", "--ensemble", "0"],
            "--ensemble",
        ),
        ("sweep (nothing varied)", sweep, "--vary"),
        (
            "sweep --vary operating.nonsense=1,2",
            [*sweep, "--vary", "operating.nonsense=1,2"],
            "operating.nonsense",
        ),
    ]
    for went_in, args, name in arguments:
        yield refused("argument", went_in, "taichi_bearing", args, [name], out)


# ------------------------------------------------------------------ diagnostics records


def _fault_record(seconds: float = 2.0) -> np.ndarray:
    """An outer-race fault of the CWRU drive-end bearing at 1797 rpm: a 3 kHz resonance
    struck at BPFO (107.4 Hz, a little jitter), in white noise."""
    rng = np.random.default_rng(1)
    n = int(seconds * FS)
    x = rng.standard_normal(n)
    k = np.arange(200)
    ring = 3.0 * np.exp(-k / 30.0) * np.sin(2 * np.pi * 3000.0 * k / FS)
    t = 0.01
    while (i := int(t * FS)) < n - ring.size:
        x[i : i + ring.size] += ring
        t += (1 + 0.005 * rng.standard_normal()) / 107.36
    return x


def records(tmp: Path) -> Iterator[Row]:
    """Records a diagnosis must refuse in one line, or diagnose as in their own unit."""
    x = _fault_record()
    out = tmp / "never"
    analyze = ["analyze", "--fs", "12000", "--rpm", "1797", "--out", out]
    bad = {
        "constant.csv": (np.zeros_like(x), "constant"),
        "with_nan.csv": (np.where(np.arange(x.size) == 500, np.nan, x), "with_nan.csv"),
        "with_inf.csv": (np.where(np.arange(x.size) == 500, np.inf, x), "with_inf.csv"),
    }
    for name, (values, says) in bad.items():
        np.savetxt(tmp / name, values)
        yield refused(
            "record", name, "diagnostics", [*analyze, tmp / name, "--bearing", BEARING], [says], out
        )
    savemat(tmp / "names.mat", {"operator": "abc", "note": "no signal here"})
    fault = tmp / "fault.csv"
    np.savetxt(fault, x)
    arguments = [
        ("analyze --fs 1e30", ["--bearing", BEARING, "--fs", "1e30"], "--fs"),
        ("analyze --bearing in metres", ["--bearing", "n=9,d=7.94m,D=39.04m"], "--bearing"),
        (
            "analyze --notch 7000 (above Nyquist)",
            ["--bearing", BEARING, "--notch", "7000"],
            "--notch",
        ),
        ("analyze --channel 2 (no such)", ["--bearing", BEARING, "--channel", "2"], "no channel"),
    ]
    for went_in, extra, name in arguments:
        yield refused("argument", went_in, "diagnostics", [*analyze, fault, *extra], [name], out)
    for went_in, path, name in (
        ("analyze FOLDER", tmp, "is a folder"),
        ("names.mat (no signal)", tmp / "names.mat", "no numeric signal"),
    ):
        yield refused(
            "record", went_in, "diagnostics", [*analyze, path, "--bearing", BEARING], [name], out
        )
    reference = None
    for scale in (1.0, 1e-300, 1e-6, 1e6, 1e300):
        t0 = time.perf_counter()
        path, folder = tmp / f"scaled_{scale:g}.csv", tmp / f"scaled_{scale:g}"
        np.savetxt(path, scale * x)
        proc = _call("diagnostics", *analyze[:-1], folder, path, "--bearing", BEARING)
        said = json.loads((folder / "summary.json").read_text()) if proc.returncode == 0 else {}
        got = (said.get("verdict"), said.get("band_hz"))
        reference = reference or got
        quiet = not proc.stderr.strip()
        ok = proc.returncode == 0 and quiet and got == reference and got[0] == "outer"
        came = f"exit {proc.returncode}: verdict {got[0]}, band {got[1]} Hz" + (
            "" if quiet else f"; stderr: {_first_line(proc.stderr)}"
        )
        yield Row(
            "record", f"outer-race fault record x {scale:g}", came, ok, time.perf_counter() - t0
        )


# ------------------------------------------------------------------ interrupted runs


def _default_sigint() -> None:
    """In the child: Ctrl-C as a terminal delivers it (a background job ignores SIGINT,
    and a child inherits that)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _signalled(
    cmd: list,
    ready: Callable[[], bool],
    pick: Callable[[int], int],
    sig: int = signal.SIGKILL,
    tick: Callable[[], None] | None = None,
) -> tuple[subprocess.CompletedProcess, int | None]:
    """Run ``cmd`` (in a process group of its own); once ``ready()``, send ``sig`` to the
    pid ``pick(cmd's pid)`` names (negative: a process group, as a terminal's Ctrl-C);
    call ``tick()`` every 20 ms until ``cmd`` ends. Returns what it gave and the pid
    signalled (None: it ended first)."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(
            cmd,
            cwd=ROOT,
            env=_env(),
            stdout=out,
            stderr=err,
            text=True,
            preexec_fn=_default_sigint,
            start_new_session=True,
        )
        victim, deadline = None, time.monotonic() + 600
        try:
            while proc.poll() is None:
                if tick is not None:
                    tick()
                if victim is None and ready():
                    victim = pick(proc.pid)
                    os.kill(victim, sig)
                if time.monotonic() > deadline:
                    raise TimeoutError(f"still running after 600 s: {cmd[2:5]}")
                time.sleep(0.02)
        finally:
            if proc.poll() is None:
                proc.kill()
            proc.wait()
        out.seek(0)
        err.seek(0)
        return subprocess.CompletedProcess(cmd, proc.returncode, out.read(), err.read()), victim


def interruptions(tmp: Path) -> Iterator[Row]:
    """A run stopped by Ctrl-C and one killed: each leaves a folder ``post`` checks."""
    for sig, want_rc, want_status in (
        (signal.SIGINT, 130, "interrupted"),
        (signal.SIGKILL, -signal.SIGKILL, "running"),
    ):
        t0 = time.perf_counter()
        out = tmp / f"run_{sig.name}"
        cmd = _cmd("taichi_bearing", "run", COARSE, *SMALL, *INTERRUPTIBLE, "--out", out)
        proc, victim = _signalled(cmd, lambda out=out: _in_transient(out), lambda pid: pid, sig)
        status = _status(out)
        post = _call("taichi_bearing", "post", out, "--no-report")
        partial = "partial" in post.stdout
        ok = (
            victim is not None
            and proc.returncode == want_rc
            and status == want_status
            and post.returncode == 0
            and partial
        )
        came = (
            f"exit {proc.returncode}, status {status}; post: exit {post.returncode}"
            f"{', partial' if partial else ''}"
        )
        yield Row(
            "interruption", f"run, {sig.name} in its transient", came, ok, time.perf_counter() - t0
        )


# ------------------------------------------------------------------ studies


def _files(folder: Path) -> dict[str, tuple[int, bytes]]:
    """Every file of a folder: modification time (ns) and bytes."""
    return {
        str(p.relative_to(folder)): (p.stat().st_mtime_ns, p.read_bytes())
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def _ran(out: Path) -> dict[str, tuple[str, bool]]:
    """``sweep_summary.csv``: each cell's status and whether it ran this time."""
    path = out / "sweep_summary.csv"
    if not path.is_file():
        return {}
    with path.open() as f:
        return {r["run_dir"]: (r["status"], r["ran"] == "True") for r in csv.DictReader(f)}


def _sweep_cmd(out: Path) -> list:
    return _cmd("taichi_bearing", "sweep", COARSE, *SWEEP, "--workers", "2", "--out", out)


def _finish_again(out: Path, kept: dict[str, dict], reference: Path) -> Row:
    """The same sweep command again: only the unfinished cells run, the ``kept`` folders
    (cell name: :func:`_files`) untouched, every cell finished with the reference's
    histories."""
    t0 = time.perf_counter()
    proc = _call(*_sweep_cmd(out)[2:])
    cells = _ran(out)
    ran = sorted(c for c, (_, r) in cells.items() if r)
    untouched = all(_files(out / c) == files for c, files in kept.items())
    same = all(_histories(out / c) == _histories(reference / c) for c in CELLS)
    ok = (
        proc.returncode == 0
        and untouched
        and same
        and set(cells) == set(CELLS)
        and all(s == "finished" for s, _ in cells.values())
        and ran == sorted(set(CELLS) - set(kept))
    )
    came = (
        f"exit {proc.returncode}; ran {', '.join(ran) or 'none'}; "
        f"{'others untouched' if untouched else 'a finished one REWRITTEN'}; "
        f"histories {'=' if same else '!='} reference"
    )
    return Row("study", "  the same sweep command again", came, ok, time.perf_counter() - t0)


def _histories(folder: Path) -> bytes | None:
    path = folder / "histories.parquet"
    return path.read_bytes() if path.is_file() else None


def studies(tmp: Path) -> Iterator[Row]:
    """A sweep never interrupted (the reference); one whose cell's process is killed, one
    whose own process is, each then finished by the same command; one on a Dask cluster
    whose worker is killed."""
    t0 = time.perf_counter()
    reference = tmp / "reference"
    proc = _call(*_sweep_cmd(reference)[2:])
    ok = proc.returncode == 0 and all(_status(reference / c) == "finished" for c in CELLS)
    yield Row(
        "study", "sweep of 2 cells (the reference)", _said(proc), ok, time.perf_counter() - t0
    )

    t0 = time.perf_counter()
    out = tmp / "cell_killed"
    lost, kept = out / CELLS[0], out / CELLS[1]
    proc, victim = _signalled(
        _sweep_cmd(out), lambda: _in_transient(lost), lambda _: _writers(lost)[0][0]
    )
    failed = [ln for ln in proc.stderr.splitlines() if ln.startswith("failed:")]
    ok = (
        victim is not None
        and proc.returncode == 1
        and len(failed) == 1
        and "killed by SIGKILL" in failed[0]
        and _status(lost) == "failed"
        and _status(kept) == "finished"
        and not _writers(lost)
    )
    said = failed[0].removeprefix("failed: ").split(" (")[0] if failed else proc.stderr
    came = f"exit {proc.returncode}; {said}; folders {_status(lost)}, {_status(kept)}"
    yield Row("study", "sweep, kill -9 of one cell's process", came, ok, time.perf_counter() - t0)
    yield _finish_again(out, {kept.name: _files(kept)}, reference)

    t0 = time.perf_counter()
    out = tmp / "sweep_killed"
    proc, victim = _signalled(
        _sweep_cmd(out), lambda: _in_transient(out / CELLS[0]), lambda pid: pid
    )
    time.sleep(0.5)  # the kernel's SIGKILL of the cells' processes
    left = [pid for c in CELLS for pid, _ in _writers(out / c)]
    for pid in left:
        os.kill(pid, signal.SIGKILL)
    ok = victim is not None and proc.returncode == -signal.SIGKILL and not left
    came = (
        f"exit {proc.returncode}; {len(left)} cell processes left; folders "
        f"{', '.join(str(_status(out / c)) for c in CELLS)}"
    )
    yield Row("study", "sweep, kill -9 of the sweep itself", came, ok, time.perf_counter() - t0)
    yield _finish_again(out, {}, reference)
    yield _sweep_ctrl_c(tmp / "ctrl_c")
    yield _blocked_cell(tmp / "blocked")
    yield _dask_worker_killed(tmp / "dask", reference)


def _sweep_ctrl_c(out: Path) -> Row:
    """Ctrl-C (SIGINT to the whole process group) while a sweep of three cells runs two
    in their transients: exit 130, the two interrupted, the third never started, no
    process left."""
    t0 = time.perf_counter()
    cells = [*CELLS, "speed_1100rpm"]
    cmd = _cmd(
        "taichi_bearing",
        "sweep",
        COARSE,
        "--speed-rpm",
        "900,1000,1100",
        *SWEEP[2:],
        "--workers",
        "2",
        "--out",
        out,
    )
    proc, victim = _signalled(
        cmd, lambda: all(_in_transient(out / c) for c in CELLS), lambda pid: -pid, signal.SIGINT
    )
    states = [_status(out / c) for c in cells]
    left = [p for c in cells for p in _writers(out / c)]
    ok = (
        victim is not None
        and proc.returncode == 130
        and states == ["interrupted", "interrupted", None]
        and not left
    )
    came = f"exit {proc.returncode}; folders {', '.join(map(str, states))}; {len(left)} left"
    return Row("study", "sweep, Ctrl-C", came, ok, time.perf_counter() - t0)


def _blocked_cell(out: Path) -> Row:
    """A cell whose run folder is taken by a plain file: reported with the run's own
    reason, the file left as it was."""
    t0 = time.perf_counter()
    out.mkdir()
    blocked = out / CELLS[0]
    blocked.write_text("not a run folder\n")
    args = ["sweep", COARSE, "--speed-rpm", "900", *SWEEP[2:], "--workers", "1", "--out", out]
    proc = _call("taichi_bearing", *args)
    failed = [ln for ln in proc.stderr.splitlines() if ln.startswith("failed:")]
    ok = (
        proc.returncode == 1
        and len(failed) == 1
        and f"{CELLS[0]}: exit status 2: error: --out:" in failed[0]
        and blocked.read_text() == "not a run folder\n"
        and _ran(out).get(CELLS[0], ("", False))[0] == "failed"
    )
    return Row(
        "study", "sweep, a cell's folder is a plain file", _said(proc), ok, time.perf_counter() - t0
    )


def _dask_worker_killed(out: Path, reference: Path) -> Row:
    """A LocalCluster of two workers, the one running the first cell killed in its
    transient: its cell's process dies with it and Dask runs the task again on a live
    worker, so that one process at a time writes the folder."""
    t0 = time.perf_counter()
    try:
        import distributed  # noqa: F401
    except ImportError:
        return Row("study", "Dask worker killed", "not tried: no dask.distributed", None, 0.0)
    argv = ["sweep", COARSE, *SWEEP, "--out", str(out)]
    script = (
        "import sys\n"
        "from distributed import LocalCluster\n"
        "from taichi_bearing.__main__ import main\n"
        "with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as c:\n"
        f"    sys.exit(main({argv!r} + ['--scheduler', c.scheduler_address]))\n"
    )
    lost = out / CELLS[0]
    most = [0]

    def tick() -> None:
        most[0] = max(most[0], len(_writers(lost)))

    proc, victim = _signalled(
        [sys.executable, "-c", script],
        lambda: _in_transient(lost),
        lambda _: _writers(lost)[0][1],
        tick=tick,
    )  # the worker
    same = all(_histories(out / c) == _histories(reference / c) for c in CELLS)
    ok = victim is not None and proc.returncode == 0 and same and most[0] == 1
    came = (
        f"exit {proc.returncode}; at most {most[0]} process at a time on the lost cell; "
        f"histories {'=' if same else '!='} reference"
    )
    return Row(
        "study", "Dask sweep, kill -9 of a cell's worker", came, ok, time.perf_counter() - t0
    )


# ------------------------------------------------------------------ table

GROUPS = {"input": bad_inputs, "record": records, "interruption": interruptions, "study": studies}


def _print(row: Row, width: int, tmp: str) -> None:
    mark = {True: "pass", False: "FAIL", None: "n/a"}[row.passed]
    came = row.came_out.replace(tmp, "TMP").replace(str(ROOT) + os.sep, "")
    came = came if len(came) <= width else came[: width - 3] + "..."
    print(
        f"{row.kind:12s} {row.went_in[:40]:40s} {came:{width}s} {mark:4s} {row.seconds:5.1f}",
        flush=True,
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--only",
        choices=sorted(GROUPS),
        action="append",
        help="these groups of rows only (repeatable; default: all)",
    )
    parser.add_argument("--width", type=int, default=76, help="characters of 'came out'")
    args = parser.parse_args(argv)
    print(f"{'kind':12s} {'what went in':40s} {'what came out':{args.width}s} {'':4s} {'s':>5s}")
    rows: list[Row] = []
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="reliability_") as tmp_name:
        for name in args.only or list(GROUPS):
            folder = Path(tmp_name) / name
            folder.mkdir()
            try:
                for row in GROUPS[name](folder):
                    rows.append(row)
                    _print(row, args.width, tmp_name)
            except Exception as exc:  # noqa: BLE001 - a group that breaks is a failed row
                rows.append(
                    Row(name, "(the group broke)", f"{type(exc).__name__}: {exc}", False, 0.0)
                )
                _print(rows[-1], args.width, tmp_name)
    failed = sum(r.passed is False for r in rows)
    print(
        f"{len(rows)} rows: {sum(r.passed is True for r in rows)} passed, {failed} failed, "
        f"{sum(r.passed is None for r in rows)} not tried ({time.perf_counter() - t0:.0f} s)"
    )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
