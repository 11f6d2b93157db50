"""An ensemble run end to end: two cases of the coarse case (rollers at another start
angle and another load) run as one model write the run folders their runs alone write,
histories identical column by column; a study groups into ensembles the cells that can
share a model, and refuses an ensemble size that would group no two."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys

import numpy as np
import pytest
from ensemble_cases import base_case, vary

from taichi_bearing.output.histories import read_histories

COARSE = "cases/validation/coarse_spall.yaml"
DURATION = 3e-4  # s: 30 samples, past the preload and the start of rolling


def cases():
    base = base_case()
    # a short preload: what is compared is the arithmetic, not the rest reached
    base = dataclasses.replace(base, preload=dataclasses.replace(base.preload, ke_ratio_tol=0.02))
    return [vary(base, duration=DURATION), vary(base, angle_deg=0.7, load=1.3, duration=DURATION)]


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


def test_cells_group_by_what_they_share_in_the_order_they_come():
    """A convergence-like study: three passages on 1 mm, two on 2 mm, interleaved, in
    ensembles of two: each ensemble holds one mesh's cells only, in order, the last of a
    kind smaller, the ensembles in the order of their first cells; cells differing only in
    start angle or load may share."""
    from taichi_bearing.studies.cells import SweepCell
    from taichi_bearing.studies.ensemble_task import group_cells

    def cell(name: str, *overrides: str) -> SweepCell:
        return SweepCell(COARSE, {}, name, overrides=overrides)

    cells = [
        cell("a0", "mesh.surface_size_mm=1"),
        cell("b0", "mesh.surface_size_mm=2", "run.first_roller_angle_deg=1"),
        cell("a1", "mesh.surface_size_mm=1", "operating.load_kN=40"),
        cell("b1", "mesh.surface_size_mm=2"),
        cell("a2", "mesh.surface_size_mm=1", "run.first_roller_angle_deg=2"),
    ]
    groups = group_cells(cells, 2)
    assert [[c.out_dir for c in g] for g in groups] == [["a0", "a1"], ["b0", "b1"], ["a2"]]
    assert [[c.out_dir for c in g] for g in group_cells(cells, 1)] == [[c.out_dir] for c in cells]
    assert sum(group_cells(cells, 8), []) == [cells[k] for k in (0, 2, 4, 1, 3)]
    # automatic: on the CPU each cell alone, on a GPU every cell of a kind in one model
    assert group_cells(cells, "auto") == [[c] for c in cells]
    on_gpu = [cell(c.out_dir, *c.overrides, "run.arch=cuda") for c in cells]
    assert [[c.out_dir for c in g] for g in group_cells(on_gpu, "auto")] == [
        ["a0", "a1", "a2"], ["b0", "b1"]
    ]  # fmt: skip


@pytest.mark.parametrize("text", ["0", "-2", "x", "1.5"])
def test_ensemble_sizes_other_than_a_count_or_auto_are_refused(text):
    from taichi_bearing.errors import InputError
    from taichi_bearing.studies.ensemble_task import parse_ensemble

    with pytest.raises(InputError, match="^--ensemble: "):
        parse_ensemble(text)
    assert parse_ensemble("AUTO") == "auto" and parse_ensemble("3") == 3
