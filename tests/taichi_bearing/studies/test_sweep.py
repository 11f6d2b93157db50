"""The sweep: process pool and Dask cluster agree, reruns skip finished cases, a failing
case is reported while the others finish, bad arguments exit 2; any case key varies
(``--vary``), ``--load-kN``/``--speed-rpm`` are its shorthands. Faults: a cell killed
mid-run (``kill -9`` of its process, of its Dask worker) fails alone, its folder marked;
the same command again runs only it, and its histories are those of a sweep never
interrupted.

Cells: the coarse validation case, 0.1 ms of transient (the preload dominates) with a
loose preload tolerance and no frames or per-run report; 2 loads x 2 speeds; one thread
per case, two cases at a time (the 2-core CI machine).
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from diagnostics import envelope_spectrum
from taichi_bearing.__main__ import main as cli
from taichi_bearing.case import case_to_dict, load_case
from taichi_bearing.errors import CaseError, InputError
from taichi_bearing.post.document import fmt
from taichi_bearing.studies.metrics import METRICS as CELL_METRICS
from taichi_bearing.studies.metrics import envelope_level_at, summary_rows
from taichi_bearing.studies.sweep import (
    LOAD_KEY,
    SPEED_KEY,
    Axis,
    cell_dir_name,
    column_labels,
    local_threads,
    make_cells,
    mark_failed,
    parse_values,
    parse_vary,
    run_sweep,
)
from taichi_bearing.studies.sweep_figures import write_sweep_outputs

ROOT = Path(__file__).resolve().parents[3]
CASE = ROOT / "cases" / "validation" / "coarse_spall.yaml"
LOADS, SPEEDS = "20,40", "900,1000"
# 3 mm surface elements (4,040 elements, the faults' cells below and test_run_cli's tiny
# runs: the cells' processes share the compiled kernels through the offline cache): the
# static forces still follow the load, and the pool and the cluster must agree whatever
# the mesh.
SETS = (
    "mesh.surface_size_mm=3",
    "mesh.max_size_mm=6",
    "run.duration_ms=0.1",
    "run.frame_interval_ms=0.1",
    "run.checkpoint_interval_ms=0.1",
    "output.frames=false",
    "preload.ke_ratio_tol=1e-2",
)
# Runs are bit-reproducible (fixed-point contact sums, element forces gathered in a fixed
# order), so the two engines' cells must agree exactly.
METRICS = ("max_outer_fn_N", "max_inner_fn_N", "accel_peak")


def _sweep_argv(out: Path, *extra: str, axes=("--load-kN", LOADS, "--speed-rpm", SPEEDS)):
    argv = ["sweep", str(CASE), *axes, "--out", str(out)]
    for s in SETS:
        argv += ["--set", s]
    return [*argv, "--no-post", "--quiet", "--threads", "1", *extra]


def _load_speed_axes() -> list[Axis]:
    return [
        Axis(LOAD_KEY, tuple(parse_values(LOADS, "l")), "--load-kN"),
        Axis(SPEED_KEY, tuple(parse_values(SPEEDS, "s")), "--speed-rpm"),
    ]


def _mtimes(out: Path) -> dict[str, int]:
    return {p.parent.name: p.stat().st_mtime_ns for p in out.glob("*/summary.json")}


@pytest.fixture(scope="module")
def pool_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("pool")
    rc = cli(_sweep_argv(out, "--workers", "2"))
    return out, rc


def test_pool_sweep_finishes_every_cell(pool_sweep):
    out, rc = pool_sweep
    assert rc == 0
    df = pd.read_csv(out / "sweep_summary.csv")
    assert len(df) == 4 and set(df["status"]) == {"finished"}
    assert sorted(zip(df["load_kN"], df["speed_rpm"], strict=True)) == [
        (20.0, 900.0), (20.0, 1000.0), (40.0, 900.0), (40.0, 1000.0)
    ]  # fmt: skip
    for r in df.itertuples():
        case = json.loads((out / r.run_dir / "summary.json").read_text())
        assert case["status"] == "finished"
        # the cell ran its own load and speed: shaft frequency from the overridden speed
        assert case["shaft_hz"] == pytest.approx(r.speed_rpm / 60.0, rel=1e-12)
    # a doubled load: the static roller forces (largest of the record) roughly double
    for speed in (900.0, 1000.0):
        f = df[df["speed_rpm"] == speed].set_index("load_kN")["max_outer_fn_N"]
        assert 1.6 < f[40.0] / f[20.0] < 2.4
    # 0.1 ms records hold a fraction of a BPFO period: the level at BPFO is not resolved
    assert (df["periods"] < 1).all() and df["env_bpfo"].isna().all()
    assert (out / "sweep_report.md").is_file()
    assert (out / "sweep_increase.csv").is_file()
    assert (out / "figures" / "sweep_outer_forces.png").stat().st_size > 0


def test_rerun_skips_finished_cells(pool_sweep):
    out, _ = pool_sweep
    before = _mtimes(out)
    assert len(before) == 4
    assert cli(_sweep_argv(out, "--workers", "2")) == 0
    assert _mtimes(out) == before  # no run folder was written again
    df = pd.read_csv(out / "sweep_summary.csv")
    assert not df["ran"].any()
    assert set(df["status"]) == {"finished"}


# ~45 s; the pool sweep runs the same cell engine in CI (run -m slow when touching Dask)
@pytest.mark.slow
def test_dask_cluster_matches_pool_and_reports_a_failed_cell(pool_sweep, tmp_path):
    distributed = pytest.importorskip("distributed")
    out_pool, _ = pool_sweep
    out = tmp_path / "dask"
    out.mkdir()
    # an injected failure: a plain file where one cell's run folder must go
    blocked = cell_dir_name({LOAD_KEY: 40.0, SPEED_KEY: 900.0})
    (out / blocked).write_text("not a run folder\n")
    cells = make_cells(CASE, _load_speed_axes(), out, SETS, threads=1, post=False)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        results = run_sweep(cells, scheduler=client, progress=False)
    by_name = {r.name: r for r in results}
    assert by_name[blocked].status == "failed"
    assert blocked in by_name[blocked].error
    assert [r.status for r in results].count("finished") == 3
    dask_rows = {r["run_dir"]: r for r in summary_rows(results)}
    # (pandas reads floats back exactly: its default parser round-trips)
    pool_rows = pd.read_csv(out_pool / "sweep_summary.csv").set_index("run_dir")
    for name, row in dask_rows.items():
        if name == blocked:
            continue
        for key in METRICS:
            assert row[key] == pool_rows.loc[name, key], (name, key)
        a = json.loads((out / name / "summary.json").read_text())
        b = json.loads((out_pool / name / "summary.json").read_text())
        assert a["n_steps"] == b["n_steps"]
        assert a["static_roller_forces_N"] == b["static_roller_forces_N"]


@pytest.mark.parametrize(
    "extra, word",
    [
        (["--load-kN", "20,x"], "--load-kN"),
        (["--speed-rpm", "0,100"], "--speed-rpm"),
        (["--load-kN", "20,20"], "--load-kN"),
        (["--workers", "0"], "--workers"),
        (["--set", "operating.nonsense=1"], "operating.nonsense"),
    ],
)
def test_bad_arguments_one_line_exit_2(tmp_path, capsys, extra, word):
    argv = ["sweep", str(CASE), "--load-kN", "20", "--speed-rpm", "900", "--out",
            str(tmp_path / "s"), *extra]  # fmt: skip
    assert cli(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and word in err[0]
    assert not (tmp_path / "s").exists()


def test_envelope_level_is_the_envelope_spectrum_bin_on_whole_periods():
    fs, f0 = 50_000.0, 125.0
    t = np.arange(int(fs * 8 / f0)) / fs  # 8 whole periods of f0
    rng = np.random.default_rng(3)
    x = (1 + 0.5 * np.cos(2 * math.pi * f0 * t)) * np.sin(2 * math.pi * 8000 * t)
    x = x + 0.01 * rng.standard_normal(t.size)
    f, amp = envelope_spectrum(x, fs)
    k = int(round(f0 * t.size / fs))
    assert f[k] == pytest.approx(f0)
    assert envelope_level_at(x, fs, f0) == pytest.approx(amp[k], rel=1e-9)
    # squared envelope (1 + 0.5 cos)^2 holds 1.0 cos at f0
    assert envelope_level_at(x, fs, f0) == pytest.approx(1.0, rel=0.03)


def test_threads_per_worker():
    assert local_threads(2, cores=16) == 8
    assert local_threads(3, cores=16) == 5
    assert local_threads(32, cores=16) == 1


# ------------------------------------------------------------------ any-key sweeps


def test_vary_reads_values_as_yaml():
    assert parse_vary("contact.smoothing=true,false").values == (True, False)
    assert parse_vary("contact.penalty_method=segment,soft").values == ("segment", "soft")
    # YAML 1.1 reads 1e-1 as a string; a study means the number
    assert parse_vary("mesh.surface_size_mm=1, 0.5,1e-1").values == (1, 0.5, 0.1)
    axis = parse_vary("run.first_roller_angle_deg=-4.25,-4")
    assert axis.key == "run.first_roller_angle_deg" and axis.values == (-4.25, -4)


@pytest.mark.parametrize(
    "text, says",
    [
        ("mesh.surface_size_mm", "expected KEY=v1,v2"),
        ("=1,2", "expected KEY=v1,v2"),
        ("mesh.surface_size_mm=1,,2", "comma-separated"),
        ("mesh.surface_size_mm=1,1.0", "given twice"),
        ("mesh.surface_size_mm=[1", "not a YAML value"),
    ],
)
def test_vary_refuses_malformed_values(text, says):
    with pytest.raises(InputError, match=says):
        parse_vary(text)


def test_cells_are_named_from_their_key_value_pairs():
    # today's load x speed names, unchanged, in whichever order the keys are varied
    assert cell_dir_name({LOAD_KEY: 40.0, SPEED_KEY: 900.0}) == "load_40kN_speed_900rpm"
    assert cell_dir_name({SPEED_KEY: 900.0, LOAD_KEY: 40.0}) == "load_40kN_speed_900rpm"
    assert cell_dir_name({"contact.penalty_scale": 0.3}) == "penalty_scale_0p3"
    values = {"mesh.surface_size_mm": 0.125, "run.first_roller_angle_deg": -4.25}
    assert cell_dir_name(values) == "surface_size_0p125mm_first_roller_angle_-4p25deg"
    assert cell_dir_name({"contact.smoothing": False}) == "smoothing_false"
    # two keys of one name keep their sections apart, in names and in columns
    both = {"run.max_steps": 10, "preload.max_steps": 5}
    assert cell_dir_name(both) == "preload_max_steps_5_run_max_steps_10"  # schema order
    assert list(column_labels(both).values()) == ["run_max_steps", "preload_max_steps"]


def test_tied_keys_take_each_value_together(tmp_path):
    tied = "mesh.spall_size_mm+mesh.roller_surface_size_mm"
    axis = parse_vary(f"{tied}=0.5,0.25")
    assert axis.keys == ("mesh.spall_size_mm", "mesh.roller_surface_size_mm")
    cells = make_cells(CASE, [axis], tmp_path, SETS)
    assert [c.name for c in cells] == ["spall_size_0p5mm", "spall_size_0p25mm"]
    assert column_labels([tied]) == {tied: "spall_size_mm"}
    for c, size in zip(cells, (0.5, 0.25), strict=True):
        mesh = case_to_dict(load_case(CASE, c.overrides))["mesh"]
        assert mesh["spall_size_mm"] == mesh["roller_surface_size_mm"] == size
    # a bad value names the argument; a key tied to itself or varied again is refused
    with pytest.raises(CaseError, match=r"--vary mesh\.spall_size_mm\+"):
        make_cells(CASE, [parse_vary(f"{tied}=0.5,9")], tmp_path, SETS)
    with pytest.raises(InputError, match="tied to itself"):
        parse_vary("mesh.spall_size_mm+mesh.spall_size_mm=0.5")
    with pytest.raises(InputError, match="varied twice"):
        make_cells(CASE, [axis, parse_vary("mesh.spall_size_mm=0.5")], tmp_path, SETS)


def test_shorthands_make_the_cells_of_vary(tmp_path):
    vary = [parse_vary(f"{LOAD_KEY}={LOADS}"), parse_vary(f"{SPEED_KEY}={SPEEDS}")]
    a = make_cells(CASE, _load_speed_axes(), tmp_path, SETS)
    b = make_cells(CASE, vary, tmp_path, SETS)
    assert sorted(c.name for c in a) == sorted(c.name for c in b)
    by_name = {c.name: c for c in b}
    for c in a:  # the same case in each cell (20 and 20.0 are one load)
        same = case_to_dict(load_case(CASE, by_name[c.name].overrides))
        assert case_to_dict(load_case(CASE, c.overrides)) == same
    # the duration scales with the speed: the 900 rpm cells run 1000/900 of the case's
    c900 = next(c for c in a if c.values[SPEED_KEY] == 900.0)
    assert "run.duration_ms=0.1111111111111111" in c900.overrides
    fixed = make_cells(CASE, vary, tmp_path, SETS, scale_duration=False)
    assert not any(o.startswith("run.duration_ms=0.11") for c in fixed for o in c.overrides)


def test_load_speed_vary_reuses_the_shorthand_cells(pool_sweep):
    out, _ = pool_sweep
    before = _mtimes(out)
    axes = ("--vary", f"{SPEED_KEY}={SPEEDS}", "--vary", f"{LOAD_KEY}={LOADS}")
    assert cli(_sweep_argv(out, "--workers", "1", axes=axes)) == 0
    assert _mtimes(out) == before  # the same folders: nothing ran again
    df = pd.read_csv(out / "sweep_summary.csv")
    assert {"load_kN", "speed_rpm"} <= set(df.columns) and not df["ran"].any()
    assert (out / "sweep_increase.csv").is_file()  # still the load x speed outputs


def _vary_argv(tmp_path, *vary: str) -> list[str]:
    return ["sweep", str(CASE), *vary, "--out", str(tmp_path / "s")]


@pytest.mark.parametrize(
    "vary, words",
    [
        (["--vary", "operating.nonsense=1,2"], ["--vary operating.nonsense=1,2", "unknown key"]),
        (["--vary", "mesh.surface_size_mm=1,abc"], ["--vary mesh.surface_size_mm=1,abc",
                                                    "mesh.surface_size_mm"]),
        (["--vary", "contact.penalty_scale=0.1,-1"], ["contact.penalty_scale"]),
        (["--vary", "contact.penalty_scale=0.1", "--vary", "contact.penalty_scale=0.2"],
         ["varied twice"]),
        (["--load-kN", "20", "--vary", "operating.load_kN=30"], ["varied twice"]),
        ([], ["--vary", "nothing to vary"]),
    ],
)  # fmt: skip
def test_bad_vary_one_line_exit_2_nothing_written(tmp_path, capsys, vary, words):
    assert cli(_vary_argv(tmp_path, *vary)) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and all(w in err[0] for w in words), err
    assert not (tmp_path / "s").exists()


def test_any_key_sweep_runs_its_own_value(tmp_path):
    out = tmp_path / "penalty"
    argv = _sweep_argv(out, "--workers", "1", axes=("--vary", "contact.penalty_scale=0.2"))
    assert cli(argv) == 0
    run = out / "penalty_scale_0p2"
    case = yaml.safe_load((run / "case.yaml").read_text())
    assert case["contact"]["penalty_scale"] == 0.2
    df = pd.read_csv(out / "sweep_summary.csv")
    assert list(df["penalty_scale"]) == [0.2] and list(df["status"]) == ["finished"]
    assert df.loc[0, "max_outer_fn_N"] > 0
    report = (out / "sweep_report.md").read_text()
    assert report.startswith("# Sweep over penalty_scale")
    assert (out / "figures" / "sweep_outer_forces.png").stat().st_size > 0
    assert not (out / "sweep_increase.csv").exists()  # no load x speed tables


def test_grid_outputs_draw_each_metric_against_the_first_key(tmp_path):
    rows = []
    for method in ("segment", "soft"):
        for scale in (0.1, 0.3, 1.0):
            row = {"penalty_method": method, "penalty_scale": scale, "status": "finished",
                   "run_dir": f"{method}_{scale}", "ran": True, "error": "",
                   "n_passages": 1}  # fmt: skip
            row.update({k: scale * (2.0 if method == "soft" else 1.0) for k in CELL_METRICS})
            rows.append(row)
    paths = write_sweep_outputs(rows, tmp_path, ["penalty_scale", "penalty_method"])
    df = pd.read_csv(paths["summary"])
    assert list(df.columns[:2]) == ["penalty_method", "penalty_scale"]
    assert list(df["penalty_scale"]) == [0.1, 0.1, 0.3, 0.3, 1.0, 1.0]  # sorted by the axes
    report = paths["report"].read_text()
    assert "# Sweep over penalty_scale x penalty_method" in report
    assert "one line per penalty_method" in report
    # the verdict first: each quantity's range over the cells, where it is largest
    order = [report.index(h) for h in ("## Verdict", "## Per-cell values", "## Figures",
                                       "## Definitions")]  # fmt: skip
    assert order == sorted(order)
    verdict = report[: report.index("## Per-cell values")]
    peaks = [r["restress_peak_N"] for r in rows]
    assert (f"{CELL_METRICS['restress_peak_N'][0]}: {fmt(min(peaks))} to {fmt(max(peaks))} N, "
            "largest at penalty_scale 1, penalty_method soft") in verdict  # fmt: skip
    assert "data:image/png;base64" in paths["html"].read_text()
    for stem in ("envelope_bpfo", "outer_forces", "inner_forces"):
        assert (tmp_path / "figures" / f"sweep_{stem}.png").stat().st_size > 0
    assert "increase" not in paths


def test_load_speed_report_leads_with_the_trends_and_names_a_failed_cell(tmp_path):
    """Synthetic load x speed cells (no simulation): every quantity grows with load and
    speed except the re-stressing peak at one cell; one cell failed."""
    rows = []
    for load in (25.0, 50.0):
        for speed in (300.0, 800.0):
            name = f"load_{load:g}kN_speed_{speed:g}rpm"
            row = {"load_kN": load, "speed_rpm": speed, "status": "finished", "run_dir": name,
                   "ran": True, "error": "", "n_passages": 2, "periods": 1.35}  # fmt: skip
            row.update({k: load * speed for k in CELL_METRICS})
            rows.append(row)
    rows[3]["restress_peak_N"] = 1.0  # 50 kN, 800 rpm: below the others
    rows[0].update(status="failed", error="exit status 1: boom")
    paths = write_sweep_outputs(rows, tmp_path)
    report = paths["report"].read_text()
    order = [
        report.index(h)
        for h in (
            "## Verdict",
            "## Trends with load and speed",
            "## Per-cell values",
            "## Figures",
            "## Definitions",
        )
    ]
    assert order == sorted(order)
    verdict = report[: report.index("## Trends")]
    assert (
        "4 cells, 3 finished, 1 failed. Failed: `load_25kN_speed_300rpm`: exit status 1" in verdict
    )
    label = CELL_METRICS["restress_peak_N"][0]
    assert "10 of 12 quantity-axis pairs grow" in verdict
    assert f"Not growing or not judged: {label} grows with load at 1 of 2 speeds" in verdict
    assert f"{label} grows with speed at 1 of 2 loads" in verdict
    assert paths["html"].is_file()


# ------------------------------------------------------------------ faults

needs_proc = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="finds processes in /proc; ties them by prctl"
)
# Two cells on a 3 mm mesh (~4,000 elements), 0.5 ms each, that differ only in an output
# option: the cell not killed is the uninterrupted run the killed one's rerun must equal,
# bit for bit.
FAULT_SETS = ("mesh.surface_size_mm=3", "mesh.max_size_mm=6", "run.duration_ms=0.5",
              "run.checkpoint_interval_ms=0.1", "output.frames=false",
              "preload.ke_ratio_tol=1e-2")  # fmt: skip
FAULT_AXIS = ("--vary", "output.csv=false,true")


def _fault_argv(out: Path) -> list[str]:
    argv = ["sweep", str(CASE), *FAULT_AXIS, "--out", str(out), "--workers", "2"]
    for s in FAULT_SETS:
        argv += ["--set", s]
    return [*argv, "--no-post", "--quiet", "--threads", "1"]


def _summary(run_dir: Path) -> dict:
    return json.loads((run_dir / "summary.json").read_text())


def _status(run_dir: Path) -> str | None:
    try:
        return _summary(run_dir).get("status")
    except (OSError, ValueError):  # not written yet
        return None


def _pids_writing(run_dir: Path) -> list[tuple[int, int]]:
    """(pid, parent pid) of each live process whose command line has ``--out run_dir``."""
    found = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            argv = (proc / "cmdline").read_bytes().decode(errors="replace").split("\0")
            state, ppid = (proc / "stat").read_text().rpartition(")")[2].split()[:2]
        except OSError:  # gone meanwhile
            continue
        out = argv[argv.index("--out") + 1] if "--out" in argv[:-1] else None
        if state not in "ZX" and out == str(run_dir.resolve()):
            found.append((int(proc.name), int(ppid)))
    return found


class _Watch(threading.Thread):
    """Watches the processes writing ``run_dir``: the most at once, and (with ``kill``)
    SIGKILLs, once, the one ``kill(pid, parent_pid)`` names as soon as the run has
    written its first checkpoint (it is then in its transient)."""

    def __init__(self, run_dir: Path, kill=None) -> None:
        super().__init__(daemon=True)
        self.run_dir, self.kill = run_dir, kill
        self.killed: int | None = None
        self.most = 0
        self.stop = threading.Event()

    def run(self) -> None:
        while not self.stop.wait(0.02):
            found = _pids_writing(self.run_dir)
            self.most = max(self.most, len(found))
            started = any((self.run_dir / "checkpoints").glob("checkpoint_*.npz"))
            if self.kill and self.killed is None and found and started:
                self.killed = self.kill(*found[0])
                os.kill(self.killed, signal.SIGKILL)

    def __enter__(self) -> _Watch:
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop.set()
        self.join(timeout=5)


def _files(run_dir: Path) -> dict[str, tuple[int, bytes]]:
    """Every file of a folder: its modification time (ns) and bytes."""
    return {str(p.relative_to(run_dir)): (p.stat().st_mtime_ns, p.read_bytes())
            for p in sorted(run_dir.rglob("*")) if p.is_file()}  # fmt: skip


def _histories(run_dir: Path) -> bytes:
    return (run_dir / "histories.parquet").read_bytes()


def test_mark_failed_says_why_only_where_the_run_did_not(tmp_path):
    running = tmp_path / "running"
    running.mkdir()
    (running / "summary.json").write_text(json.dumps({"status": "running", "n_nodes": 5}))
    assert mark_failed(running, "killed by SIGKILL")
    s = _summary(running)
    assert (s["status"], s["stop_reason"], s["n_nodes"]) == ("failed", "killed by SIGKILL", 5)
    assert "dt_s" in s["missing_keys"]  # a partial summary says what it lacks
    bare = tmp_path / "bare"  # killed while meshing: no summary yet
    bare.mkdir()
    assert mark_failed(bare, "exit status 1: MemoryError")
    assert _summary(bare)["status"] == "failed"
    for status in ("finished", "stopped", "interrupted"):  # the run said itself how it ended
        said = tmp_path / status
        said.mkdir()
        (said / "summary.json").write_text(json.dumps({"status": status}))
        assert not mark_failed(said, "x") and _status(said) == status
    assert not mark_failed(tmp_path / "absent", "x") and not (tmp_path / "absent").exists()


@needs_proc
def test_a_cells_process_dies_with_the_process_that_started_it():
    """A lost worker takes its cell's process along: no orphan writes the folder on."""
    code = (
        "import subprocess, time\n"
        "from taichi_bearing.studies.child import child_command\n"
        "cmd = child_command('timeit', '-n1', '-r1', 'import time; time.sleep(120)')\n"
        "print(subprocess.Popen(cmd).pid, flush=True)\n"
        "time.sleep(120)\n"
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    parent = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True,
                              env=env)  # fmt: skip
    try:
        child = int(parent.stdout.readline())
        time.sleep(0.5)  # the child is running its module (sleeping)
    finally:
        parent.kill()
        parent.communicate()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        try:
            state = Path(f"/proc/{child}/stat").read_text().rpartition(")")[2].split()[0]
        except OSError:
            break  # gone and reaped
        if state in "ZX":
            break  # dead, waiting for its new parent to reap it
        time.sleep(0.05)
    else:
        os.kill(child, signal.SIGKILL)
        pytest.fail("the child outlived its parent")


@needs_proc
def test_a_killed_cell_fails_alone_and_the_same_command_finishes_it(tmp_path, capsys):
    """``kill -9`` of one cell's process in its transient: the other cell finishes, the
    killed one is reported with the signal and its folder says failed; the same command
    again runs only it and leaves the finished folder as it was (every file, bit for bit
    and not even rewritten); its histories are then those of a run never interrupted."""
    out = tmp_path / "faulty"
    lost, kept = out / "csv_false", out / "csv_true"
    with _Watch(lost, kill=lambda pid, ppid: pid) as watch:
        assert cli(_fault_argv(out)) == 1
    assert watch.killed is not None and watch.most == 1
    err = capsys.readouterr().err
    assert f"failed: {lost.name}: killed by SIGKILL (out of memory" in err
    assert "the same command again runs the cells not finished" in err
    said = _summary(lost)
    assert said["status"] == "failed" and said["stop_reason"].startswith("killed by SIGKILL")
    assert (lost / "histories.parts").is_dir()  # what it recorded, for post
    assert _status(kept) == "finished"
    df = pd.read_csv(out / "sweep_summary.csv").set_index("run_dir")
    assert df["status"].to_dict() == {lost.name: "failed", kept.name: "finished"}
    assert df.loc[lost.name, "error"].startswith("killed by SIGKILL")
    assert "2 cells, 1 finished, 1 failed" in (out / "sweep_report.md").read_text()

    before = _files(kept)
    assert cli(_fault_argv(out)) == 0
    assert _files(kept) == before
    df = pd.read_csv(out / "sweep_summary.csv").set_index("run_dir")
    assert df["status"].to_dict() == {lost.name: "finished", kept.name: "finished"}
    assert df["ran"].to_dict() == {lost.name: True, kept.name: False}
    assert df["max_outer_fn_N"].notna().all()  # the summary covers every cell
    assert "stop_reason" not in _summary(lost) and not (lost / "histories.parts").exists()
    assert _histories(lost) == _histories(kept)


# 40 to 90 s each: a LocalCluster, two cells and a rerun (run -m slow when touching Dask)
@needs_proc
@pytest.mark.slow
@pytest.mark.parametrize("allowed_failures", [0, 3])
def test_a_lost_dask_worker_takes_only_its_cell(tmp_path, allowed_failures):
    """The Dask worker running a cell killed in its transient: the cell's process dies
    with it (never two runs writing one folder). Past the scheduler's allowed failures the
    cell is reported failed and its folder says so, and the same sweep again runs only it;
    within them Dask runs the task again on a live worker. Its histories are then those of
    a run never interrupted."""
    distributed = pytest.importorskip("distributed")
    import dask

    out = tmp_path / "dask"
    out.mkdir()
    cells = make_cells(CASE, [parse_vary(FAULT_AXIS[1])], out, FAULT_SETS, threads=1,
                       post=False)  # fmt: skip
    lost, kept = (Path(c.out_dir) for c in cells)
    with (
        dask.config.set({"distributed.scheduler.allowed-failures": allowed_failures}),
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
        _Watch(lost, kill=lambda pid, ppid: ppid) as watch,  # the worker, not the run
    ):
        results = run_sweep(cells, scheduler=client, progress=False)
    assert watch.killed is not None and watch.most == 1
    assert [r.name for r in results] == [lost.name, kept.name]
    assert results[1].status == "finished"
    if allowed_failures == 0:
        assert results[0].status == "failed"
        assert results[0].error.startswith("KilledWorker: its Dask worker died")
        assert _summary(lost)["status"] == "failed"
        before = _files(kept)
        again = run_sweep(cells, workers=2, progress=False)
        assert [(r.status, r.ran) for r in again] == [("finished", True), ("finished", False)]
        assert _files(kept) == before
    else:
        assert results[0].status == "finished"
    assert _histories(lost) == _histories(kept)
