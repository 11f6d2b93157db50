"""An ensemble run end to end: two cases of the coarse case (rollers at another start
angle and another load) run as one model write the run folders their runs alone write,
histories identical column by column; a study groups its cells into ensembles and refuses
cells that cannot share a model."""

from __future__ import annotations

import dataclasses
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from taichi_bearing.case import load_case
from taichi_bearing.output.histories import read_histories

COARSE = "cases/validation/coarse_spall.yaml"
DURATION = 3e-4  # s: 30 samples, past the preload and the start of rolling


def cases():
    base = load_case(COARSE)

    def vary(angle_deg: float = 0.0, load: float = 1.0):
        run = dataclasses.replace(
            base.run,
            first_roller_angle=base.run.first_roller_angle + math.radians(angle_deg),
            duration=DURATION,
        )
        op = dataclasses.replace(base.operating, load=base.operating.load * load)
        # a short preload: what is compared is the arithmetic, not the rest reached
        pre = dataclasses.replace(base.preload, ke_ratio_tol=0.02)
        return dataclasses.replace(base, run=run, operating=op, preload=pre)

    return [vary(), vary(angle_deg=0.7, load=1.3)]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    from taichi_bearing.pipeline import run_case, run_ensemble

    root = tmp_path_factory.mktemp("ensemble_run")
    members = cases()
    singles = [root / f"single{k}" for k in range(len(members))]
    for case, out in zip(members, singles, strict=True):
        run_case(case, out, threads=1, quiet=True, post=False)
    ensemble = [root / f"member{k}" for k in range(len(members))]
    summaries = run_ensemble(members, ensemble, threads=1, quiet=True, post=False)
    return singles, ensemble, summaries


def test_members_write_the_histories_of_their_runs_alone(runs):
    singles, ensemble, summaries = runs
    for k, (single, member) in enumerate(zip(singles, ensemble, strict=True)):
        a, b = read_histories(single), read_histories(member)
        assert list(a.columns) == list(b.columns)
        assert len(a) == round(DURATION * 1e5)
        for column in a.columns:
            np.testing.assert_array_equal(b[column].to_numpy(), a[column].to_numpy(), column)
        alone = json.loads((single / "summary.json").read_text())
        assert summaries[k]["status"] == "finished"
        assert summaries[k]["ensemble"] == {"members": 2, "member": k}
        assert summaries[k]["preload"]["outer_force_N"] == alone["preload"]["outer_force_N"]
        assert summaries[k]["dt_s"] == alone["dt_s"]
        assert summaries[k]["checks"].keys() == alone["checks"].keys()
    # the two cases differ: their histories do too
    a, b = read_histories(ensemble[0]), read_histories(ensemble[1])
    assert not np.array_equal(a["roller0_outer_fn"], b["roller0_outer_fn"])


def test_a_study_refuses_cells_that_cannot_share_a_model(tmp_path):
    out = tmp_path / "sweep"
    proc = subprocess.run(
        [sys.executable, "-m", "taichi_bearing", "sweep", COARSE, "--vary",
         "mesh.surface_size_mm=3,4", "--ensemble", "2", "--out", str(out)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "mesh.surface_size_mm" in lines[0] and "ensemble" in lines[0]
    assert not out.exists()
