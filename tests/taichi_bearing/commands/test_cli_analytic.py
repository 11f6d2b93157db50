"""`python -m taichi_bearing analytic`: files, columns, equilibrium in the written tables."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[3]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _cli(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    # the checkout on the path, whether or not the package is installed
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    }
    return subprocess.run(
        [sys.executable, "-m", "taichi_bearing", "analytic", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=300,
    )


@pytest.fixture(scope="module")
def out_dir(tmp_path_factory, default_case_path) -> Path:
    out = tmp_path_factory.mktemp("analytic")
    proc = _cli(str(default_case_path), "--out", str(out), "--angles", "201")
    assert proc.returncode == 0, proc.stderr
    assert "Q_max Z / W = 4.08" in proc.stdout
    return out


def test_static_contacts_csv(out_dir):
    table = pd.read_csv(out_dir / "static_contacts.csv")
    assert list(table.columns) == [
        "roller",
        "angle_deg",
        "outer_force_N",
        "inner_force_N",
        "outer_half_width_m",
        "inner_half_width_m",
        "outer_pmax_Pa",
        "inner_pmax_Pa",
        "deflection_m",
    ]
    # healthy bearing, roller 0 at 12 o'clock: 9 loaded rollers, symmetric, summing to W
    assert len(table) == 9
    fy = table["outer_force_N"] * np.cos(np.radians(table["angle_deg"]))
    assert fy.sum() == pytest.approx(50e3, rel=1e-8)
    top = table.loc[table["outer_force_N"].idxmax()]
    assert top["angle_deg"] == 0 and top["outer_force_N"] * 20 / 50e3 == pytest.approx(
        4.08, rel=0.01
    )


def test_analytic_forces_csv(out_dir):
    forces = pd.read_csv(out_dir / "analytic_forces.csv")
    assert list(forces.columns) == [
        "cage_angle_deg",
        "roller",
        "outer_fx_N",
        "outer_fy_N",
        "outer_force_N",
        "inner_force_N",
    ]
    assert len(forces) == 201 * 20
    assert forces["cage_angle_deg"].min() == pytest.approx(-9.0)
    assert forces["cage_angle_deg"].max() == pytest.approx(9.0)
    # equilibrium at every cage angle (to the 10 digits written)
    sums = forces.groupby("cage_angle_deg")["outer_fy_N"].sum()
    np.testing.assert_allclose(sums, 50e3, rtol=1e-8)
    np.testing.assert_allclose(
        np.hypot(forces["outer_fx_N"], forces["outer_fy_N"]), forces["outer_force_N"], rtol=1e-8
    )
    # roller 0 inside the spall (5 mm either side of 12 o'clock on a 112 mm raceway)
    r0 = forces[forces["roller"] == 0]
    half = np.degrees(5.0 / 112.0)
    inside = r0[np.abs(r0["cage_angle_deg"]) < half - 0.2]
    assert len(inside) > 0 and np.all(inside["outer_force_N"] == 0.0)
    assert np.all(r0[np.abs(r0["cage_angle_deg"]) > half + 0.2]["outer_force_N"] > 9e3)


def test_figures_and_summary(out_dir):
    for name in ("load_distribution", "defect_passage", "edge_zoom"):
        data = (out_dir / "figures" / f"{name}.png").read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 10_000
    summary = json.loads((out_dir / "analytic_summary.json").read_text())
    assert summary["max_balance_error"] < 1e-9
    assert summary["largest_force_jump_step_N"] > 9e3  # the step model jumps
    assert summary["largest_force_jump_patch_N"] < summary["largest_force_jump_step_N"]
    assert summary["bpfo_hz"] == pytest.approx(73.3333, rel=1e-5)
    # no temporary files left behind
    assert not [p for p in out_dir.rglob("*") if p.name.endswith(".tmp") or ".tmp." in p.name]


def test_default_out_dir_is_runs_case_name(tmp_path, default_case_path):
    proc = _cli(str(default_case_path), "--angles", "21", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "runs" / "line_spall" / "analytic_forces.csv").is_file()


def test_set_override_and_healthy_case(tmp_path, default_case_path):
    proc = _cli(
        str(default_case_path),
        "--out",
        str(tmp_path),
        "--angles",
        "21",
        "--set",
        "defect.race=none",
        "--set",
        "operating.load_kN=80",
    )
    assert proc.returncode == 0, proc.stderr
    table = pd.read_csv(tmp_path / "static_contacts.csv")
    fy = table["outer_force_N"] * np.cos(np.radians(table["angle_deg"]))
    assert fy.sum() == pytest.approx(80e3, rel=1e-8)


@pytest.mark.parametrize(
    "extra",
    [
        ["--set", "operating.load_kN=-5"],
        ["--spall-angles", "10"],  # an outer-race spall does not turn
        ["--set", "defect.race=inner", "--spall-angles=-200"],
        ["--set", "defect.race=inner", "--spall-angles", "ten"],
        ["--angles", "3"],
    ],
)
def test_bad_input_one_line_exit_2(tmp_path, default_case_path, extra):
    proc = _cli(str(default_case_path), "--out", str(tmp_path), *extra)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr
