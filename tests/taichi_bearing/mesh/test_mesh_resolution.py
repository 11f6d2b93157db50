"""Mesh resolution: the highest frequency each part resolves with N elements per Rayleigh
wavelength, the one-line warning of the run, and the report's mesh and modes sections."""

from __future__ import annotations

import math

import pytest

from taichi_bearing.case import load_case
from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
from taichi_bearing.mesh.primitives import rectangle_mesh
from taichi_bearing.mesh.quality import (
    mesh_statistics,
    rayleigh_wave_speed,
    resolution_warning,
    shear_wave_speed,
)
from taichi_bearing.mesh.spec import spec_from_case

STEEL = (210e9, 0.3, 7850.0)


def test_rayleigh_wave_speed_against_the_exact_root():
    # nu = 1/4 (lambda = mu): c_R / c_s = sqrt(2 - 2 / sqrt(3)), Rayleigh's own example
    e, rho = 210e9, 7850.0
    ratio = rayleigh_wave_speed(e, 0.25, rho) / shear_wave_speed(e, 0.25, rho)
    assert ratio == pytest.approx(math.sqrt(2.0 - 2.0 / math.sqrt(3.0)), rel=1e-12)
    # steel: the slowest wave, 0.927 of the shear wave (Viktorov's fit: 0.926)
    assert rayleigh_wave_speed(*STEEL) == pytest.approx(0.9274 * shear_wave_speed(*STEEL), 1e-4)


@pytest.mark.parametrize("n_per", [10.0, 20.0])
def test_resolved_frequency_is_rayleigh_speed_over_n_elements(n_per):
    mesh = rectangle_mesh(0.02, 0.004, 20, 2)  # 1 x 2 mm elements: longest edge 2 mm
    stats = mesh_statistics(mesh, *STEEL, elements_per_wavelength=n_per)
    assert stats.part_max_size["rectangle"] == pytest.approx(0.002, rel=1e-12)
    expected = rayleigh_wave_speed(*STEEL) / (n_per * 0.002)  # 149 kHz at N = 10
    assert stats.resolved_frequency["rectangle"] == pytest.approx(expected, rel=1e-12)
    assert stats.elements_per_wavelength == n_per


def test_case_key_sets_the_criterion_of_the_mesh_statistics(default_case_path):
    coarse = default_case_path.parent / "validation" / "coarse_spall.yaml"
    ten = mesh_statistics(build_bearing_mesh(spec_from_case(load_case(coarse))), *STEEL)
    case = load_case(coarse, ["mesh.elements_per_wavelength=20"])
    twenty = mesh_statistics(build_bearing_mesh(spec_from_case(case)), *STEEL)
    assert ten.elements_per_wavelength == 10.0 and twenty.elements_per_wavelength == 20.0
    for part, f in ten.resolved_frequency.items():
        assert twenty.resolved_frequency[part] == pytest.approx(0.5 * f, rel=1e-12)
    # the largest elements (the outer ring's back, up to 1.2 x mesh.max_size_mm) set it
    assert min(ten.resolved_frequency, key=ten.resolved_frequency.get) == "outer_ring"
    assert "resolves up to" in ten.summary()


def test_warning_names_the_part_that_does_not_resolve_the_band():
    stats = {
        "resolved_frequency": {"outer_ring": 44e3, "inner_ring": 52e3, "roller0": 76e3},
        "part_max_size": {"outer_ring": 0.00335},
        "elements_per_wavelength": 20.0,
    }
    assert resolution_warning(stats, 43e3, "fs / 2") is None
    line = resolution_warning(stats, 50e3, "run.sample_rate_Hz / 2")
    assert "\n" not in line
    assert "50 kHz (run.sample_rate_Hz / 2)" in line and "outer_ring resolves only 44 kHz" in line
    assert "20 elements per Rayleigh wavelength" in line and "3.35 mm" in line
    assert resolution_warning({}, 1e9, "x") is None  # statistics without resolution


def test_run_warns_in_one_line_right_after_meshing(default_case_path, tmp_path, monkeypatch):
    """The run's first lines: the mesh, then the warning (the model is not built here)."""
    import taichi_bearing.simulation.simulate as simulate

    class Stop(Exception):
        pass

    def stop(*args, **kwargs):
        raise Stop

    monkeypatch.setattr(simulate, "build_model", stop)
    coarse = default_case_path.parent / "validation" / "coarse_spall.yaml"
    # 4 mm elements (the ring's back up to 4.8 mm) resolve 62 kHz at N = 10: at 200 kHz
    # the band reaches 100 kHz
    case = load_case(coarse, ["run.sample_rate_Hz=200000"])
    lines = []
    with pytest.raises(Stop):
        simulate.simulate(case, tmp_path, quiet=True, log=lines.append)
    assert len(lines) == 1 and lines[0].startswith("warning: mesh: the analysed band reaches 100")
    lines.clear()
    with pytest.raises(Stop):
        simulate.simulate(load_case(coarse), tmp_path, quiet=True, log=lines.append)
    assert lines == []  # 50 kHz: resolved


def test_report_warns_and_names_the_modes_in_the_band(tmp_path):
    from synthetic_run import make_synthetic_run

    from taichi_bearing.post.report import write_report

    make_synthetic_run(tmp_path)  # 3 mm surface elements: the ring's back is 7.5 mm
    md = write_report(tmp_path).read_text()
    mesh = md[md.index("## Mesh") : md.index("## Stages")]
    assert "Warning: mesh: the analysed band reaches" in mesh
    assert "outer_ring resolves only" in mesh
    modes = md[md.index("## Modes near") : md.index("## Defect size")]
    assert "modes of the outer ring" in modes and "in-plane bending" in modes
    rows = [line for line in modes.splitlines() if line.startswith("| ") and "Hz" not in line]
    assert any("| inside |" in r for r in rows)
