"""Operating points no bearing has, refused (or warned) before any work: the surface speed
against the shear wave speed, the Hertz pressure of the most loaded roller against what an
elastic solid carries and the static capacity, the spall's depth against what a roller
reaches. Every shipped case passes them without a warning (``test_case.py``:
``test_every_shipped_case_loads``). Case loading only: no mesh, no run."""

from __future__ import annotations

import math
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from taichi_bearing.__main__ import main
from taichi_bearing.case import (
    CaseError,
    ContactPressureWarning,
    SpallReachWarning,
    load_case,
    load_case_for_cli,
)
from taichi_bearing.case.validate import (
    DEPTH_REACH_FACTOR,
    MAX_PRESSURE_RATIO,
    MAX_SURFACE_SPEED_RATIO,
    STATIC_CAPACITY_PRESSURE,
    peak_contact_pressure,
    spall_reach,
)
from taichi_bearing.geometry.spall_profile import SpallProfile

ROOT = Path(__file__).resolve().parents[3]


def no_case_warning(path: Path, sets: list[str]):
    """The case, loaded with any case warning raised as an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", Warning)
        return load_case(path, sets)


# --------------------------------------------------------------------------------------
# Speed
# --------------------------------------------------------------------------------------


def test_speed_beyond_the_wave_speed_exits_2_at_once(tmp_path, default_case_path):
    """The issue's case: ``speed_rpm: 1e9`` ran 30 s and died of NaN; now one line, exit 2,
    nothing written."""
    text = default_case_path.read_text(encoding="utf-8")
    path = tmp_path / "fast.yaml"
    path.write_text(text.replace("speed_rpm: 500.0 ", "speed_rpm: 1.0e+9"), encoding="utf-8")
    out = tmp_path / "out"
    proc = subprocess.run(
        [sys.executable, "-m", "taichi_bearing", str(path), "--out", str(out)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=60,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"error: {path}: operating.speed_rpm: 1e+09 rpm ")
    assert "shear wave speed (3208 m/s)" in lines[0]
    assert not out.exists()


def test_speed_limit_is_a_fraction_of_the_shear_wave_speed(default_case_path):
    case = load_case(default_case_path)
    limit = MAX_SURFACE_SPEED_RATIO * case.material.shear_wave_speed  # m/s
    rpm = limit / case.bearing.inner_raceway_radius * 60.0 / (2.0 * math.pi)
    assert 3e4 < rpm < 4e4  # steel, 176 mm raceway: far above any such bearing's speed
    assert no_case_warning(default_case_path, [f"operating.speed_rpm={0.99 * rpm}"])
    with pytest.raises(CaseError) as info:
        load_case(default_case_path, [f"operating.speed_rpm={1.01 * rpm}"])
    assert info.value.key == "operating.speed_rpm"
    assert f"at most {rpm:.4g} rpm here" in info.value.message


# --------------------------------------------------------------------------------------
# Contact pressure
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("clearance_mm", "load_kN"), [(0.0, 50.0), (0.0, 5.0), (0.5, 50.0), (-0.1, 50.0)]
)
def test_peak_pressure_is_the_quasi_static_models_or_below(
    default_case_path, clearance_mm, load_kN
):
    """Stribeck's load on the inner contact: the quasi-static model's pressure at zero
    clearance, a lower bound with clearance or preload (so the model refuses what the
    bound does). Default case: 0.843 GPa; 0.5 mm clearance 0.843 of the model's 1.33 GPa,
    0.1 mm preload 0.742 of its 1.84 GPa."""
    from taichi_bearing.analytic.quasistatic import static_contact_table

    sets = [f"bearing.radial_clearance_mm={clearance_mm}", f"operating.load_kN={load_kN}"]
    case = load_case(default_case_path, sets)
    model = float(static_contact_table(case)["inner_pmax_Pa"].max())
    p0 = peak_contact_pressure(case)
    if clearance_mm == 0.0:
        assert p0 == pytest.approx(model, rel=1e-9)
    else:
        assert p0 < model
    if (clearance_mm, load_kN) == (0.0, 50.0):
        assert p0 == pytest.approx(0.843e9, rel=1e-3)


def test_pressure_no_solid_carries_is_refused(tmp_path, default_case_path, capsys):
    # p0 grows as sqrt(load): 50 kN gives 0.843 GPa, E / 20 = 10.5 GPa needs ~7760 kN
    out = tmp_path / "out"
    args = ["mesh", str(default_case_path), "--out", str(out), "--no-pictures"]
    assert main([*args, "--set", "operating.load_kN=1e5"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and not out.exists()
    assert lines[0].startswith("error: --set operating.load_kN=1e5: operating.load_kN: 1e+05 kN")
    assert "37.7 GPa" in lines[0] and "E/20 (10.5 GPa" in lines[0]
    assert no_case_warning(default_case_path, ["operating.load_kN=1000"])  # 3.77 GPa


def test_pressure_limit_scales_with_the_modulus(default_case_path):
    """The refusal is a strain (b / R), not a steel's number: a soft material at E / 100
    is refused at a load its p0 ~ sqrt(E) would not reach in steel."""
    soft = ["material.youngs_modulus_GPa=2.1"]
    case = load_case(default_case_path, soft)  # 50 kN: 84 MPa < 105 MPa
    assert peak_contact_pressure(case) < MAX_PRESSURE_RATIO * case.material.youngs_modulus
    with pytest.raises(CaseError) as info:
        load_case(default_case_path, [*soft, "operating.load_kN=80"])
    assert info.value.key == "operating.load_kN" and "E/20 (0.105 GPa" in info.value.message


def test_overload_beyond_the_static_capacity_warns_one_line(default_case_path, capsys):
    with pytest.warns(ContactPressureWarning, match="operating.load_kN: 2000 kN") as caught:
        case = load_case(default_case_path, ["operating.load_kN=2000"])
    assert peak_contact_pressure(case) > STATIC_CAPACITY_PRESSURE
    assert "5.33 GPa" in str(caught[0].message)
    load_case_for_cli(default_case_path, ["operating.load_kN=2000"])
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("warning: --set operating.load_kN=2000: ")


# --------------------------------------------------------------------------------------
# Spall depth
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize("length", [1e-3, 10e-3])
def test_reach_is_a_roller_bridging_both_edges(length):
    """A sharp spall on the outer raceway (R = 112 mm), roller r = 12 mm: the centre on the
    middle ray meets both corners, R cos(a) - sqrt(r^2 - R^2 sin^2 a) - (R - r), a the
    half-span; within 15 % of the flat raceway's r - sqrt(r^2 - (L/2)^2)."""
    big_r, r = 0.112, 0.012
    profile = SpallProfile(big_r, 0.0, length / big_r, 5e-3, True)
    a = 0.5 * length / big_r
    exact = big_r * math.cos(a) - math.sqrt(r**2 - (big_r * math.sin(a)) ** 2) - (big_r - r)
    assert spall_reach(profile, r) == pytest.approx(exact, rel=1e-9)
    assert exact == pytest.approx(r - math.sqrt(r**2 - (0.5 * length) ** 2), rel=0.15)
    # a floor the roller reaches caps its drop
    assert spall_reach(SpallProfile(big_r, 0.0, length / big_r, 0.2 * exact, True), r) == (
        pytest.approx(0.2 * exact)
    )


@pytest.mark.parametrize("race", ["outer", "inner"])
def test_spall_far_deeper_than_the_reach_warns(default_case_path, race):
    # 1 mm long: a 24 mm roller drops ~10 um into it (less in the concave outer raceway)
    base = ["defect.length_mm=1", f"defect.race={race}"]
    with pytest.warns(SpallReachWarning, match="defect.depth_mm: 0.2 mm is") as caught:
        load_case(default_case_path, [*base, "defect.depth_mm=0.2"])
    assert "floor is never touched" in str(caught[0].message)
    shallow = f"defect.depth_mm={0.5 * DEPTH_REACH_FACTOR * 0.01}"  # ~5 x the reach
    assert no_case_warning(default_case_path, [*base, shallow]).defect.present


def test_spall_through_the_ring_is_still_an_error(default_case_path):
    """Deeper than the ring allows is the half-ring check's, before the reach's warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", SpallReachWarning)
        with pytest.raises(CaseError, match="defect.depth_mm: .*half the outer ring"):
            load_case(default_case_path, ["defect.length_mm=1", "defect.depth_mm=7"])
