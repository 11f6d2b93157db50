"""The load x speed sweep: process pool and Dask cluster agree, reruns skip finished cases,
a failing case is reported while the others finish, bad arguments exit 2.

Cells: the coarse validation case, 0.1 ms of transient (the preload dominates) with a
loose preload tolerance and no frames or per-run report; 2 loads x 2 speeds.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from diagnostics.envelope import envelope_spectrum
from taichi_bearing.__main__ import main as cli
from taichi_bearing.sweep import cell_dir_name, local_threads, make_cells, parse_values, run_sweep
from taichi_bearing.sweep_metrics import envelope_level_at, summary_rows

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "cases" / "validation" / "coarse_spall.yaml"
LOADS, SPEEDS = "20,40", "900,1000"
SETS = (
    "run.duration_ms=0.1",
    "run.frame_interval_ms=0.1",
    "run.checkpoint_interval_ms=0.1",
    "output.frames=false",
    "preload.ke_ratio_tol=1e-2",
)
# Runs are bit-reproducible (fixed-point contact sums, element forces gathered in a fixed
# order), so the two engines' cells must agree exactly.
METRICS = ("max_outer_fn_N", "max_inner_fn_N", "accel_peak")


def _sweep_argv(out: Path, *extra: str) -> list[str]:
    argv = ["sweep", str(CASE), "--load-kN", LOADS, "--speed-rpm", SPEEDS, "--out", str(out)]
    for s in SETS:
        argv += ["--set", s]
    return [*argv, "--no-post", "--quiet", *extra]


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


def test_dask_cluster_matches_pool_and_reports_a_failed_cell(pool_sweep, tmp_path):
    distributed = pytest.importorskip("distributed")
    out_pool, _ = pool_sweep
    out = tmp_path / "dask"
    out.mkdir()
    # an injected failure: a plain file where one cell's run folder must go
    blocked = cell_dir_name(40.0, 900.0)
    (out / blocked).write_text("not a run folder\n")
    cells = make_cells(CASE, parse_values(LOADS, "l"), parse_values(SPEEDS, "s"), out, SETS,
                       post=False)  # fmt: skip
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
