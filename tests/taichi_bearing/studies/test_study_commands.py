"""The passages and convergence studies on synthetic run folders (no simulation): the
study commands make their cells, find every cell's folder already finished, and collect,
summarise and report what the folders hold. Also: what a study reads from one folder,
the run report's passage distributions, and bad arguments (one line, exit 2, nothing
written). A real run of each command on the coarse case is marked slow."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from synthetic_run import make_synthetic_run

from bearing_io.files import write_json
from taichi_bearing.__main__ import main as cli
from taichi_bearing.checks.passages import PASSAGE_QUANTITIES
from taichi_bearing.checks.quantities import QUANTITIES
from taichi_bearing.commands.convergence import level_axis
from taichi_bearing.commands.passages import angle_axis
from taichi_bearing.post.document import Table, fmt
from taichi_bearing.post.report import report_blocks
from taichi_bearing.studies.passage_study import run_values, spread_angles, zone_edge_share
from taichi_bearing.studies.sweep import make_cells

ROOT = Path(__file__).resolve().parents[3]
CASE = str(ROOT / "cases" / "single_passage.yaml")
COARSE = str(ROOT / "cases" / "validation" / "coarse_spall.yaml")
HERTZ_B = 2.1e-4  # m
SIZE_NOTE = "not estimated: x is too short for this request"


def _event(roller: int, **values: float) -> dict:
    e = {"roller": roller, "entry_time_s": 1.3e-3, "first_impact_time_s": 4.6e-3,
         "exit_time_s": 4.8e-3, "floor_window_s": [1.4e-3, 3.9e-3],
         "force_before_N": 15e3}  # fmt: skip
    e.update(dict.fromkeys(PASSAGE_QUANTITIES, 1.0))
    e.update(values)
    return e


def _write_run(run_dir: Path, events: list[dict], forces: list[float], half_width: float) -> None:
    """A finished run folder as far as a study reads it: summary.json and preload.json."""
    patch = {"half_width_m": half_width, "peak_pressure_Pa": 4e8, "nodes": 4,
             "hertz_half_width_m": HERTZ_B, "hertz_peak_pressure_Pa": 9e8}  # fmt: skip
    checks = {"defect_size": {"value": None, "limit": 0.5, "passed": None, "note": SIZE_NOTE}}
    summary = {"status": "finished", "events": events, "defect_size_estimate_m": None,
               "checks": checks}  # fmt: skip
    write_json(run_dir / "summary.json", summary)
    write_json(run_dir / "preload.json", {"outer_force_N": forces, "contact_patch": patch})


def _args(**kw) -> argparse.Namespace:
    return argparse.Namespace(**{"case": CASE, "overrides": [], "spread_deg": 0.5, **kw})


# ------------------------------------------------------------------ what a study reads


def test_quantities_cover_every_passage_quantity():
    per_passage = [q.name for q in QUANTITIES if q.per == "passage"]
    assert per_passage == list(PASSAGE_QUANTITIES)
    static = {q.name for q in QUANTITIES if q.kind == "static"}
    assert static == {"q_max_N", "zone_edge_share", "contact_half_width_m",
                      "contact_peak_pressure_Pa"}  # fmt: skip


def test_spread_angles_are_even_and_centred():
    assert spread_angles(-4.0, 0.5, 1) == [-4.0]
    assert spread_angles(-4.0, 0.5, 5) == [-4.25, -4.125, -4.0, -3.875, -3.75]
    a = spread_angles(-4.0, 0.5, 10)
    assert a[0] == -4.25 and a[-1] == -3.75 and np.allclose(np.diff(a), 0.5 / 9)
    with pytest.raises(ValueError):
        spread_angles(0.0, -1.0, 3)


def test_zone_edge_share_is_the_smallest_loaded_roller_over_q_max():
    # 4 N and 3 N carry less than 5 % of Q_max: not loaded
    share, roller = zone_edge_share([100.0, 80.0, 30.0, 4.0, 0.0, 0.0, 3.0])
    assert share == pytest.approx(0.3) and roller == 2
    assert math.isnan(zone_edge_share([0.0, 0.0])[0])


def test_run_values_read_the_preload_and_the_size_estimate(tmp_path):
    _write_run(tmp_path, [_event(0)], [15e3, 12e3, 3e3, 10.0], 6.3e-4)
    v = run_values(tmp_path)
    assert v["q_max_N"] == 15e3 and v["zone_edge_share"] == pytest.approx(0.2)
    assert v["zone_edge_roller"] == 2
    assert v["contact_half_width_m"] == 6.3e-4 and v["hertz_half_width_m"] == HERTZ_B
    assert math.isnan(v["defect_size_estimate_m"]) and SIZE_NOTE in v["defect_size_note"]


# ------------------------------------------------------------------ passages


def test_passages_collects_every_passage_and_reports_its_distribution(tmp_path, capsys):
    out = tmp_path / "study"
    axis = angle_axis(_args(), 4, "--runs")
    assert axis.values == pytest.approx((-4.25, -4.25 + 0.5 / 3, -4.25 + 1.0 / 3, -3.75))
    ratios = {}
    for i, cell in enumerate(make_cells(CASE, [axis], out)):
        # run i holds i + 1 passages with known exit/entry ratios
        events = [_event(j, exit_entry_accel_ratio=1.0 + 0.5 * i + 0.1 * j) for j in range(i + 1)]
        ratios[cell.name] = [e["exit_entry_accel_ratio"] for e in events]
        _write_run(Path(cell.out_dir), events, [15e3, 12e3, 3e3], 6.3e-4)
    argv = ["passages", CASE, "--runs", "4", "--out", str(out), "--workers", "1", "--quiet"]
    assert cli(argv) == 0
    assert "10 passages" in capsys.readouterr().out
    df = pd.read_csv(out / "passages.csv")
    assert len(df) == 10
    assert list(df.columns[:3]) == ["run", "first_roller_angle_deg", "roller"]
    assert set(PASSAGE_QUANTITIES) <= set(df.columns)
    for name, values in ratios.items():
        assert sorted(df.loc[df["run"] == name, "exit_entry_accel_ratio"]) == values
    every = [r for v in ratios.values() for r in v]
    q25, med, q75 = np.percentile(every, [25, 50, 75])
    report = (out / "passages_report.md").read_text()
    row = f"| exit / entry acceleration peak | - | {med:.4g} | {q25:.4g} to {q75:.4g} | 10 |"
    assert row in report
    # the verdict first: what the rollers did, median and range over every passage
    order = [report.index(h) for h in ("## Verdict", "## Each quantity over the passages",
                                       "## Per passage", "## How it was made")]  # fmt: skip
    assert order == sorted(order)
    verdict = report[: report.index("## Each quantity")]
    assert "10 passages from 4 of 4 runs finished." in verdict
    rng = f"a median {fmt(med, 3)} (range {fmt(min(every), 3)} to {fmt(max(every), 3)})"
    assert f"{rng} times that at entry" in verdict
    assert "data:image/png;base64" in (out / "passages_report.html").read_text()
    assert (out / "figures" / "passages.png").stat().st_size > 0
    assert "python -m taichi_bearing passages" in report


@pytest.mark.parametrize(
    "extra, word",
    [
        (["--runs", "0"], "--runs"),
        (["--runs", "3", "--spread-deg", "-1"], "--spread-deg"),
        (["--runs", "3", "--spread-deg", "nan"], "--spread-deg"),
        (["--runs", "3", "--set", "run.first_roller_angle_deg=500"], "first_roller_angle"),
        (["--runs", "3", "--workers", "0"], "--workers"),
    ],
)
def test_bad_passages_arguments_one_line_exit_2(tmp_path, capsys, extra, word):
    assert cli(["passages", CASE, "--out", str(tmp_path / "p"), *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and word in err[0], err
    assert not (tmp_path / "p").exists()


# ------------------------------------------------------------------ convergence

LEVELS = (1.0, 0.5, 0.25)
F0, C = 15e3, 400.0  # Q_max = F0 + C h^2 (h in mm): order 2, Richardson F0


def _convergence_study(out: Path) -> dict[float, list[float]]:
    """Synthetic levels: Q_max second order in h, the contact half-width far from
    converged, the exit ratio's passages about a median that settles."""
    axis, levels = level_axis("mesh.surface_size_mm=" + ",".join(f"{v:g}" for v in LEVELS))
    angles = angle_axis(_args(), 3, "--passages")
    ratios: dict[float, list[float]] = {lv: [] for lv in levels}
    for k, cell in enumerate(make_cells(CASE, [axis, angles], out)):
        h = float(cell.values[axis.key])
        r = 2.0 + 0.5 * h + 0.2 * (k % 3 - 1)  # medians 2.5, 2.25, 2.125
        ratios[h].append(r)
        event = _event(0, exit_entry_accel_ratio=r, exit_impulses=1 + k % 3)
        forces = [F0 + C * h**2, 12e3, 3e3]
        _write_run(Path(cell.out_dir), [event], forces, HERTZ_B * (1 + 4 * h**2))
    return ratios


def test_convergence_report_leads_with_the_verdict(tmp_path):
    out = tmp_path / "conv"
    ratios = _convergence_study(out)
    argv = ["convergence", CASE, "--vary", "mesh.surface_size_mm=1,0.5,0.25", "--passages",
            "3", "--out", str(out), "--workers", "1", "--quiet"]  # fmt: skip
    assert cli(argv) == 0
    report = (out / "convergence_report.md").read_text()
    order = [report.index(h) for h in ("## Verdict", "## Values per level", "## Figures",
                                       "## How it was made")]  # fmt: skip
    assert order == sorted(order)
    verdict = report[: report.index("## Values per level")]
    not_converged = next(ln for ln in verdict.splitlines() if ln.startswith("Not converged:"))
    assert "contact half-width" in not_converged and "Q_max" not in not_converged
    not_judged = next(ln for ln in verdict.splitlines() if ln.startswith("Not judged:"))
    assert "spall length" in not_judged and SIZE_NOTE in not_judged
    v = pd.read_csv(out / "convergence_verdicts.csv").set_index("quantity")
    assert v.loc["q_max_N", "verdict"] == "converged"
    assert v.loc["q_max_N", "order"] == pytest.approx(2.0, rel=1e-9)
    assert v.loc["q_max_N", "richardson"] == pytest.approx(F0, rel=1e-12)
    # b = b_H (1 + 4 h^2): 2 b_H at 0.5 mm, 1.25 b_H at 0.25 mm: -60 %
    assert v.loc["contact_half_width_m", "verdict"] == "not converged"
    assert v.loc["contact_half_width_m", "change"] == pytest.approx(-0.6)
    # the exit ratio's medians 2.5, 2.25, 2.125: -5.9 % between the finest, within 10 %
    assert v.loc["exit_entry_accel_ratio", "verdict"] == "converged"
    t = pd.read_csv(out / "convergence.csv")
    assert len(t) == len(QUANTITIES) * len(LEVELS)
    ex = t[t["quantity"] == "exit_entry_accel_ratio"].set_index("level")
    for h, values in ratios.items():
        assert ex.loc[h, "median"] == pytest.approx(np.median(values))
        assert ex.loc[h, "q25"] == pytest.approx(np.percentile(values, 25))
        assert ex.loc[h, "n"] == 3
    hw = t[t["quantity"] == "contact_half_width_m"]
    assert np.allclose(hw["reference_median"], HERTZ_B)  # Hertz beside it
    for name in ("convergence_values.png", "convergence_differences.png"):
        assert (out / "figures" / name).stat().st_size > 0
    assert (out / "convergence_report.html").is_file()


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--vary", "mesh.surface_size_mm=1,0.5"], ["needs at least 3"]),
        (["--vary", "mesh.surface_size_mm=0.25,0.5,1"], ["coarse to fine", "decrease"]),
        (["--vary", "contact.penalty_scale=1,0.3,0.1"], ["coarse to fine", "increase"]),
        (
            ["--vary", "mesh.spall_size_mm+mesh.roller_surface_size_mm=0.25,0.5,1"],
            ["coarse to fine", "mesh.spall_size_mm must decrease"],
        ),
        (["--vary", "mesh.surface_size_mm=1,0.25,0.5"], ["one way"]),
        (["--vary", "contact.penalty_method=segment,soft,x"], ["not a number"]),
        (["--vary", "mesh.surface_sze_mm=1,0.5,0.25"], ["--vary mesh.surface_sze_mm", "unknown"]),
        (["--vary", "mesh.surface_size_mm=1,0.5,0.25", "--passages", "0"], ["--passages"]),
    ],
)
def test_bad_convergence_arguments_one_line_exit_2(tmp_path, capsys, extra, words):
    assert cli(["convergence", CASE, "--out", str(tmp_path / "c"), *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and all(w in err[0] for w in words), err
    assert not (tmp_path / "c").exists()


# ------------------------------------------------------------------ the run report


def test_run_report_shows_the_passage_distribution(tmp_path):
    make_synthetic_run(tmp_path, frames=False, duration_ms=10.0)
    summary = json.loads((tmp_path / "summary.json").read_text())
    summary["passage_statistics"] = {
        "exit_impulse_width_s": {"median": 2.5e-5, "q25": 2e-5, "q75": 3e-5, "n": 3},
        "exit_impulses": {"median": 2.0, "q25": 1.0, "q75": 4.0, "n": 3},
    }
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    write_json(tmp_path / "figures" / "figures.json", {"figures": {}})  # no figures needed
    blocks = report_blocks(tmp_path)
    start = next(i for i, b in enumerate(blocks) if getattr(b, "text", "") == "Spall passages")
    tables = [b for b in blocks[start:] if isinstance(b, Table)][:2]
    assert tables[0].header[0] == "roller"  # the per-passage table, then the distribution
    assert tables[1].header == ["quantity", "unit", "median", "interquartile range", "n"]
    assert tables[1].rows == [
        ["exit impulse width at half height", "us", "25", "20 to 30", "3"],
        ["impulses at exit", "count", "2", "1 to 4", "3"],
    ]


# ------------------------------------------------------------------ real runs


@pytest.mark.slow
def test_passages_on_the_coarse_case(tmp_path):
    out = tmp_path / "p"
    argv = ["passages", COARSE, "--runs", "2", "--spread-deg", "0.2", "--out", str(out),
            "--workers", "1", "--threads", "1", "--no-post", "--quiet",
            "--set", "output.frames=false"]  # fmt: skip
    assert cli(argv) == 0
    df = pd.read_csv(out / "passages.csv")
    assert sorted(df["first_roller_angle_deg"]) == [-2.5, -2.3]
    assert (df["roller"] == 0).all() and (df["exit_force_peak_ratio"] > 1).all()
    runs = pd.read_csv(out / "runs.csv")
    # the coarse case's 1 mm surface elements do not resolve a ~0.2 mm patch: where the
    # nodal kernel's spread (h^2 / 6) exceeds the measured variance the width is not
    # measured (NaN, analytic.contact_pressure.nodal_patch), never 0
    width = runs["contact_half_width_m"]
    assert (runs["q_max_N"] > 0).all() and (width.isna() | (width > 0)).all()


@pytest.mark.slow
def test_convergence_on_the_coarse_case(tmp_path):
    out = tmp_path / "c"
    argv = ["convergence", COARSE, "--vary", "contact.penalty_scale=0.1,0.2,0.4", "--out",
            str(out), "--workers", "1", "--threads", "1", "--no-post", "--quiet",
            "--set", "output.frames=false", "--set", "run.duration_ms=0.1",
            "--set", "run.frame_interval_ms=0.1",
            "--set", "run.checkpoint_interval_ms=0.1"]  # fmt: skip
    assert cli(argv) == 0
    t = pd.read_csv(out / "convergence.csv")
    q = t[t["quantity"] == "q_max_N"]["median"].to_numpy()
    assert len(q) == 3 and np.all(q > 0)
    # a stiffer penalty: the patch of the same force no wider (unresolved, NaN, where the
    # nodes cannot tell: a patch the softest penalty leaves unresolved stays so)
    b = t[t["quantity"] == "contact_half_width_m"]["median"].to_numpy()
    assert np.isnan(b[-1]) or b[-1] <= b[0]
    assert not np.isnan(b[0]) or np.isnan(b[-1])
    assert "## Verdict" in (out / "convergence_report.md").read_text()


@pytest.mark.parametrize(
    "argv",
    [
        ["passages", CASE, "--runs", "2"],
        ["convergence", CASE, "--vary", "mesh.surface_size_mm=1,0.5,0.25"],
    ],
)
def test_an_output_folder_that_is_a_file_is_refused(tmp_path, capsys, argv):
    (tmp_path / "afile").write_text("not a folder\n")
    assert cli([*argv, "--out", str(tmp_path / "afile")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: --out: "), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]
