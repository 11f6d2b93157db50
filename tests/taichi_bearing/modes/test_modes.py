"""Modal analysis: a free thin ring against the thin-ring formula, rigid-body modes, the
run's supports, the command's files and bad input; and no Taichi anywhere in it."""

from __future__ import annotations

import csv
import math
import subprocess
import sys

import numpy as np
import pytest

from taichi_bearing.case import Material, load_case
from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
from taichi_bearing.mesh.primitives import annulus_mesh
from taichi_bearing.mesh.spec import spec_from_case
from taichi_bearing.modes import bearing_modal_model, modal_model, solve_modes
from taichi_bearing.modes.band import modes_near_band
from taichi_bearing.output.vtk import read_pvd

STEEL = Material(210e9, 0.3, 7850.0)
R, H = 0.1, 0.002  # mid radius and thickness of the thin ring: H / R = 0.02


def thin_ring_hz(n: int, modulus: float) -> float:
    """In-plane bending of a free thin ring: (1/2pi) sqrt(E I / (rho A R^4)) n (n^2-1) /
    sqrt(n^2+1), per unit width (I = H^3 / 12, A = H)."""
    root = math.sqrt(modulus * H**3 / 12.0 / (STEEL.density * H * R**4))
    return root * n * (n * n - 1) / math.sqrt(n * n + 1) / (2.0 * math.pi)


@pytest.fixture(scope="module")
def free_ring():
    # square elements (1 mm: 628 round, 2 through the thickness): the hourglass
    # stiffness is bending-exact for squares
    mesh = annulus_mesh(R - H / 2, R + H / 2, 628, 2)
    return solve_modes(modal_model(mesh, STEEL, 1.0), 6)


def test_free_thin_ring_bending_frequencies(free_ring):
    """n = 2, 3, 4 within 0.3 % of the thin-ring formula with the plane-strain modulus
    E' = E / (1 - nu^2) (E alone would be 4.8 % lower), each as a degenerate pair."""
    elastic = free_ring.elastic
    for k, n in enumerate((2, 3, 4)):
        pair = elastic[2 * k : 2 * k + 2]
        expected = thin_ring_hz(n, STEEL.plane_strain_modulus)
        for mode in pair:
            assert mode.order == n
            assert mode.description == f"n={n} in-plane bending"
            assert mode.frequency == pytest.approx(expected, rel=3e-3)
        assert pair[0].frequency == pytest.approx(pair[1].frequency, rel=1e-6)
        assert abs(pair[0].frequency / thin_ring_hz(n, STEEL.youngs_modulus) - 1) > 0.04


def test_free_ring_has_three_rigid_body_modes_at_zero(free_ring):
    rigid = [m for m in free_ring.modes if m.rigid]
    assert len(rigid) == 3
    assert all(m.frequency < 0.1 for m in rigid)
    assert all(m.description.startswith("rigid-body") for m in rigid)
    assert free_ring.elastic[0].frequency > 100.0  # n = 2 at 134 Hz
    assert [m.number for m in free_ring.modes] == list(range(1, 10))


@pytest.fixture(scope="module")
def coarse(default_case_path):
    case = load_case(default_case_path.parent / "validation" / "coarse_spall.yaml")
    return case, build_bearing_mesh(spec_from_case(case))


def test_outer_ring_on_its_plate_keeps_only_the_vertical_motion(coarse):
    """Held as in the run, the outer ring has one rigid-body mode: the plate's vertical
    motion (x held, one shared y); free, it has three."""
    case, mesh = coarse
    held = solve_modes(bearing_modal_model(case, mesh, "outer_ring", "case"), 3)
    rigid = [m for m in held.modes if m.rigid]
    assert len(rigid) == 1
    assert np.abs(rigid[0].shape[:, 0]).max() < 1e-6  # no horizontal motion
    assert np.allclose(rigid[0].shape[:, 1], 1.0, atol=1e-6)  # all moves down together
    free = solve_modes(bearing_modal_model(case, mesh, "outer_ring", "free"), 3)
    assert sum(m.rigid for m in free.modes) == 3
    # holding can only raise the frequencies, mode by mode (interlacing)
    n = min(len(held.modes), len(free.modes))
    assert np.all(held.frequencies[:n] >= free.frequencies[:n] - 1e-6)
    assert held.frequencies[1] > 100.0


def test_bearing_rollers_keep_their_rolling_freedom(default_case_path):
    """The whole bearing held as in the run: an unloaded roller keeps its three
    rigid-body modes, a loaded one (springs along its radial line at both contacts)
    two: rolling and sliding along the raceways."""
    case = load_case(
        default_case_path.parent / "validation" / "coarse_spall.yaml",
        ["bearing.n_rollers=8", "mesh.max_size_mm=6"],
    )
    mesh = build_bearing_mesh(spec_from_case(case))
    model = bearing_modal_model(case, mesh, "bearing", "case")
    loaded = int(model.notes[-1].split()[0])
    result = solve_modes(model, 2)
    assert 0 < loaded < 8
    assert sum(m.rigid for m in result.modes) == 3 * (8 - loaded) + 2 * loaded
    assert result.elastic[0].body in ("outer_ring", "inner_ring") or "roller" in (
        result.elastic[0].body
    )


def test_modes_near_a_band(coarse):
    case, mesh = coarse
    near = modes_near_band(case, (15e3, 25e3), mesh, count=6)
    f = near.frequencies
    assert len(f) == 6 and np.all(np.diff(f) >= 0)
    lowest = solve_modes(bearing_modal_model(case, mesh, "outer_ring", "case"), 6)
    assert f.min() > lowest.frequencies.max()  # not the lowest modes: those near 19 kHz


def test_no_taichi_in_the_modal_analysis():
    code = (
        "import sys, taichi_bearing.modes.solve, taichi_bearing.modes.output, "
        "taichi_bearing.modes.band, taichi_bearing.commands.modes; "
        "print('taichi' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.stdout.strip() == "False", out.stderr


def run_cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "taichi_bearing", "modes", *map(str, args)],
        capture_output=True,
        text=True,
    )


def test_modes_command_writes_csv_series_and_figure(default_case_path, tmp_path):
    case = default_case_path.parent / "validation" / "coarse_spall.yaml"
    out = run_cli(case, "--part", "inner_ring", "--count", "4", "--out", tmp_path)
    assert out.returncode == 0, out.stderr
    with open(tmp_path / "modes.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["mode", "frequency_Hz", "part", "support", "description"]
    # the bore is held: no rigid-body mode, the four lowest elastic ones
    assert len(rows) == 4
    assert {r["part"] for r in rows} == {"inner_ring"} and {r["support"] for r in rows} == {"case"}
    freqs = [float(r["frequency_Hz"]) for r in rows]
    assert freqs == sorted(freqs) and freqs[0] > 100.0
    series = read_pvd(tmp_path / "modes.pvd")
    assert [t for t, _ in series] == [1.0, 2.0, 3.0, 4.0]
    assert all((tmp_path / name).is_file() for _, name in series)
    assert (tmp_path / "modes.png").stat().st_size > 10_000
    # a second analysis with fewer modes leaves no stale shapes behind
    out = run_cli(case, "--part", "inner_ring", "--count", "2", "--out", tmp_path)
    assert out.returncode == 0, out.stderr
    assert len(list((tmp_path / "modes").glob("mode_*.vtu"))) == 2


@pytest.mark.parametrize(
    "args, words",
    [
        (["--count", "0"], "--count"),
        (["--count", "many"], "--count"),
        (["--part", "cage"], "--part"),
        (["--support", "clamped"], "--support"),
        (["--set", "defect.depth_mm=-1"], "defect.depth_mm"),
    ],
)
def test_bad_input_is_one_line_and_status_2(default_case_path, tmp_path, args, words):
    out = run_cli(default_case_path, *args, "--out", tmp_path)
    assert out.returncode == 2
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], out.stderr
    assert not (tmp_path / "modes.csv").exists()
