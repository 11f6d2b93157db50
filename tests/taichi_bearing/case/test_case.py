"""Case files: SI conversion, round trip, every class of error, overrides, CLI exit 2."""

from __future__ import annotations

import dataclasses
import json
import math
import subprocess
import sys
import warnings
from pathlib import Path

import pytest
import yaml

from taichi_bearing.__main__ import main
from taichi_bearing.case import (
    SECTIONS,
    Case,
    CaseError,
    CaseWarning,
    ExtendedDefectWarning,
    Material,
    case_to_dict,
    load_case,
    parse_case,
    schema_attributes,
    stable_step_estimate,
)
from taichi_bearing.case.reference import COMMAND, render_reference
from taichi_bearing.case.sections import SENSOR_KEYS

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture()
def raw(default_case_path) -> dict:
    return yaml.safe_load(default_case_path.read_text())


def write(tmp_path: Path, data: dict, name: str = "case.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def error_of(raw: dict) -> CaseError:
    with pytest.raises(CaseError) as info:
        parse_case(raw, source="x.yaml")
    return info.value


def test_default_case_in_si(default_case_path):
    case = load_case(default_case_path)
    assert isinstance(case, Case)
    assert case.name == "line_spall"
    assert case.source == default_case_path
    b = case.bearing
    assert b.n_rollers == 20
    assert b.pitch_diameter == pytest.approx(0.2)
    assert b.roller_diameter == pytest.approx(0.024)
    # design.md: raceways 224 mm and 176 mm at zero clearance
    assert 2 * b.outer_raceway_radius == pytest.approx(0.224)
    assert 2 * b.inner_raceway_radius == pytest.approx(0.176)
    assert b.outer_ring_outer_radius == pytest.approx(0.126)
    assert b.inner_ring_bore_radius == pytest.approx(0.076)
    assert b.roller_spacing == pytest.approx(math.radians(18.0))
    assert case.material.youngs_modulus == pytest.approx(210e9)
    assert case.operating.load == pytest.approx(50e3)
    assert case.operating.speed == pytest.approx(500 * 2 * math.pi / 60)
    assert case.operating.shaft_hz == pytest.approx(500 / 60)
    assert case.defect.angle == 0.0 and case.defect.race == "outer" and case.defect.present
    assert case.defect.length == pytest.approx(0.01)
    assert case.defect.depth == pytest.approx(2e-4)
    assert case.run.duration == pytest.approx(0.0335)
    assert case.run.first_roller_angle == pytest.approx(math.radians(-4.0))
    assert case.run.sample_rate == pytest.approx(1e5)
    assert case.contact.friction_decay == pytest.approx(1.0)
    assert case.cage.mass == pytest.approx(2.0)
    assert case.damping.max_element_ratio == pytest.approx(0.1)
    assert case.sensors["adapter_top"].y == pytest.approx(0.156)
    assert case.output.dir is None and case.out_dir == Path("runs/line_spall")


def test_exponent_without_a_dot_is_a_number(tmp_path, raw):
    # YAML 1.1 reads 1e-4 as a string; the case takes it as the number it means
    raw["preload"]["ke_ratio_tol"] = "1e-4"
    assert load_case(write(tmp_path, raw)).preload.ke_ratio_tol == 1e-4
    case = load_case(write(tmp_path, raw), ["preload.ke_ratio_tol=2e-6"])
    assert case.preload.ke_ratio_tol == 2e-6
    raw["preload"]["ke_ratio_tol"] = "1e-4x"
    with pytest.raises(CaseError, match="preload.ke_ratio_tol"):
        load_case(write(tmp_path, raw))


def test_damping_element_cap_defaults_and_is_validated(tmp_path, raw):
    raw = dict(raw, damping={k: v for k, v in raw["damping"].items() if k != "max_element_ratio"})
    assert load_case(write(tmp_path, raw)).damping.max_element_ratio == 0.1  # default
    raw["damping"]["max_element_ratio"] = 0.0
    with pytest.raises(CaseError, match="damping.max_element_ratio"):
        load_case(write(tmp_path, raw))


def test_the_pressure_law_is_refused_with_the_element_step(tmp_path, raw):
    """The element estimate ignores the contact's springs, which the pressure law makes
    stiffer than the elements: refused, naming run.time_step; the global one is taken."""
    raw["contact"]["penalty_method"] = "pressure"
    raw["run"]["time_step"] = "element"
    with pytest.raises(CaseError, match="run.time_step"):
        load_case(write(tmp_path, raw))
    raw["run"]["time_step"] = "global"
    assert load_case(write(tmp_path, raw)).contact.penalty_method == "pressure"


def test_preload_mass_scaling_is_refused_where_it_would_lift_nothing_or_move_the_state(
    tmp_path, raw
):
    """The heavier contact nodes lift the step only under the global estimate, and the
    soft penalty's stiffness follows the masses (another static state): both refused,
    naming preload.mass_scaling; the pressure law with the global estimate is taken."""
    assert load_case(write(tmp_path, raw)).preload.mass_scaling is False  # default
    raw["preload"]["mass_scaling"] = True
    raw["run"]["time_step"] = "element"
    with pytest.raises(CaseError, match="preload.mass_scaling.*global"):
        load_case(write(tmp_path, raw))
    raw["run"]["time_step"] = "global"
    raw["contact"]["penalty_method"] = "soft"
    with pytest.raises(CaseError, match="preload.mass_scaling.*soft"):
        load_case(write(tmp_path, raw))
    raw["contact"]["penalty_method"] = "pressure"
    assert load_case(write(tmp_path, raw)).preload.mass_scaling is True


def test_outer_support_defaults_to_the_adapter(tmp_path, raw):
    raw = dict(raw, bearing={k: v for k, v in raw["bearing"].items() if k != "outer_support"})
    assert load_case(write(tmp_path, raw)).bearing.outer_support == "adapter"
    raw["bearing"]["outer_support"] = "housing"
    case = load_case(write(tmp_path, raw))
    assert case.bearing.outer_support == "housing"
    assert case_to_dict(case)["bearing"]["outer_support"] == "housing"


@pytest.mark.parametrize(
    "path", sorted((ROOT / "cases").glob("*.yaml")) + sorted((ROOT / "cases").glob("*/*.yaml"))
)
def test_every_shipped_case_loads(path):
    """Every shipped case loads without a warning, but the extended-spall case, which is
    meant to be one and must say so."""
    from taichi_bearing.case import ExtendedDefectWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        case = load_case(path)
    kinds = [w.category for w in caught]
    assert kinds == ([ExtendedDefectWarning] if path.stem == "extended_spall" else [])
    assert case.name == path.stem


def test_attribute_is_key_without_unit_suffix():
    attrs = schema_attributes()
    assert attrs["bearing"][:3] == ["n_rollers", "roller_diameter", "pitch_diameter"]
    assert attrs["material"] == ["youngs_modulus", "poissons_ratio", "density"]
    assert attrs["defect"][:4] == ["race", "angle", "length", "depth"]
    assert attrs["operating"] == ["load", "speed"]
    assert attrs["contact"][4] == "friction_decay"
    assert attrs["sensors"] == ["x", "y"]


def test_round_trip(tmp_path, raw, default_case_path):
    case = load_case(default_case_path)
    # every key and value of the file comes back, plus the optional keys' defaults
    raw["bearing"].setdefault("outer_support", "adapter")
    assert case_to_dict(case) == raw
    again = load_case(write(tmp_path, case_to_dict(case)))
    assert again.source != case.source
    assert dataclasses.replace(again, source=None) == dataclasses.replace(case, source=None)


def test_clearance_is_shared_by_both_raceways(tmp_path, default_case_path):
    case = load_case(default_case_path, ["bearing.radial_clearance_mm=0.04"])
    b = case.bearing
    # total radial play: (R_o - R_i - d) on each side, twice
    assert 2 * (b.outer_raceway_radius - b.inner_raceway_radius - b.roller_diameter) == (
        pytest.approx(4e-5)
    )
    assert b.outer_raceway_radius + b.inner_raceway_radius == pytest.approx(b.pitch_diameter)


def test_unknown_key_suggests_nearest(raw):
    raw["bearing"]["n_roler"] = 3
    err = error_of(raw)
    assert err.key == "bearing.n_roler"
    assert "did you mean 'bearing.n_rollers'" in str(err)
    assert str(err).startswith("x.yaml: bearing.n_roler:")


def test_unknown_section_suggests_nearest(raw):
    raw["bearng"] = raw.pop("bearing")
    err = error_of(raw)
    assert err.key == "bearng" and "did you mean 'bearing'" in str(err)


def test_unknown_sensor_key(raw):
    raw["sensors"]["adapter_top"]["z_mm"] = 1.0
    assert error_of(raw).key == "sensors.adapter_top.z_mm"


def test_missing_key_and_section(raw):
    del raw["bearing"]["roller_length_mm"]
    err = error_of(raw)
    assert err.key == "bearing.roller_length_mm" and "missing" in str(err)
    raw2 = yaml.safe_load(Path(ROOT / "cases/line_spall.yaml").read_text())
    del raw2["operating"]
    assert error_of(raw2).key == "operating"


def test_output_section_is_optional(raw):
    del raw["output"]
    case = parse_case(raw)
    assert case.output.dir is None and case.output.csv is False and case.output.frames is True


@pytest.mark.parametrize(
    ("section", "key", "value"),
    [
        ("bearing", "n_rollers", 20.5),
        ("bearing", "n_rollers", True),
        ("operating", "load_kN", "fifty"),
        ("operating", "load_kN", [50]),
        ("output", "csv", "yes"),
        ("run", "arch", "tpu"),
        ("defect", "race", "cage"),
        ("bearing", "outer_support", "shaft"),
        ("material", "density_kg_m3", float("nan")),
    ],
)
def test_wrong_type_or_choice(raw, section, key, value):
    raw[section][key] = value
    err = error_of(raw)
    assert err.key == f"{section}.{key}" and "expected" in str(err)


@pytest.mark.parametrize(
    ("section", "key", "value"),
    [
        ("operating", "load_kN", -50.0),
        ("operating", "load_kN", 0.0),
        ("operating", "speed_rpm", -1.0),
        ("material", "poissons_ratio", 0.5),
        ("bearing", "roller_diameter_mm", -24.0),
        ("defect", "angle_deg", 200.0),
        ("mesh", "growth", 0.9),
        ("preload", "max_steps", 0),
    ],
)
def test_out_of_range(raw, section, key, value):
    raw[section][key] = value
    err = error_of(raw)
    assert err.key == f"{section}.{key}" and "out of range" in str(err)


@pytest.mark.parametrize(
    ("overrides", "key", "words"),
    [
        ({"bearing.n_rollers": 30}, "bearing.n_rollers", "overlap"),  # 26 fit at most
        ({"bearing.roller_diameter_mm": 250.0}, "bearing.roller_diameter_mm", "smaller"),
        ({"bearing.radial_clearance_mm": -1.0}, "bearing.radial_clearance_mm", "do not fit"),
        ({"bearing.inner_ring_thickness_mm": 90.0}, "bearing.inner_ring_thickness_mm", "bore"),
        ({"defect.depth_mm": 20.0}, "defect.depth_mm", "half the outer ring"),
        ({"defect.depth_mm": 7.0}, "defect.depth_mm", "half the outer ring"),
        ({"defect.race": "inner", "defect.depth_mm": 6.5}, "defect.depth_mm", "inner ring"),
        ({"defect.length_mm": 400.0}, "defect.length_mm", "half the outer raceway"),
        ({"defect.length_mm": 0.0}, "defect.length_mm", "race: none"),
        ({"contact.friction_dynamic": 0.3}, "contact.friction_dynamic", "exceeds"),
        ({"mesh.surface_size_mm": 4.0}, "mesh.surface_size_mm", "exceeds"),
        ({"bearing.adapter_width_mm": 300.0}, "bearing.adapter_width_mm", "wider"),
    ],
)
def test_physically_impossible(default_case_path, overrides, key, words):
    sets = [f"{k}={v}" for k, v in overrides.items()]
    with pytest.raises(CaseError) as info:
        load_case(default_case_path, sets)
    assert info.value.key == key
    assert words in str(info.value)


def test_rollers_that_just_fit(default_case_path):
    # 26 rollers of 24 mm: chord 200 sin(pi/26) = 24.1 mm > 24 mm, so they fit
    assert load_case(default_case_path, ["bearing.n_rollers=26"]).bearing.n_rollers == 26


def test_extended_defect_warns_but_loads(default_case_path):
    # roller spacing on the outer raceway: 2 pi 112 / 20 = 35.19 mm
    with pytest.warns(ExtendedDefectWarning, match="extended defect"):
        case = load_case(default_case_path, ["defect.length_mm=36"])
    assert case.defect.length == pytest.approx(0.036)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ExtendedDefectWarning)
        load_case(default_case_path, ["defect.length_mm=35"])


def test_healthy_case(default_case_path):
    case = load_case(default_case_path, ["defect.race=none"])
    assert not case.defect.present


def test_overrides(default_case_path):
    case = load_case(
        default_case_path,
        [
            "operating.load_kN=80",
            "run.arch=cuda",
            "output.csv=true",
            "sensors.new_point.x_mm=10",
            "sensors.new_point.y_mm=-120.5",  # in the outer ring (not the unmeshed bore)
            "bearing.n_rollers=18",
        ],
    )
    assert case.operating.load == pytest.approx(80e3)
    assert case.run.arch == "cuda" and case.output.csv is True
    assert case.sensors["new_point"].x == pytest.approx(0.01)
    assert case.sensors["new_point"].y == pytest.approx(-0.1205)
    assert case.bearing.n_rollers == 18


@pytest.mark.parametrize(
    ("override", "key"),
    [
        ("operating.load_kN", "--set"),
        ("operating.lod_kN=3", "operating.lod_kN"),
        ("opperating.load_kN=3", "opperating"),
        ("operating.load_kN=-3", "operating.load_kN"),
        ("sensors.half.x_mm=3", "sensors.half.y_mm"),
    ],
)
def test_bad_overrides(default_case_path, override, key):
    with pytest.raises(CaseError) as info:
        load_case(default_case_path, [override])
    assert info.value.key == key


def test_bad_yaml_names_the_line(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("name: x\nbearing:\n  n_rollers: [1, 2\n")
    with pytest.raises(CaseError) as info:
        load_case(path)
    assert str(path) in str(info.value) and "line" in info.value.key


def _cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "taichi_bearing", *args],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )


@pytest.mark.parametrize("command", [[], ["run"], ["analytic"]])
def test_cli_bad_case_one_line_exit_2(tmp_path, raw, command):
    raw["bearing"]["roller_diameter_mm"] = "big"
    path = write(tmp_path, raw)
    proc = _cli(*command, str(path))
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert "bearing.roller_diameter_mm" in lines[0] and "Traceback" not in proc.stderr


def test_cli_bad_override_exit_2(default_case_path):
    # the error names the --set argument, not the case file it did not come from
    proc = _cli(str(default_case_path), "--set", "bearing.n_roler=3")
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [
        "error: --set bearing.n_roler=3: bearing.n_roler: unknown key; did you mean "
        "'bearing.n_rollers'?"
    ]


def test_cli_missing_file_exit_2(tmp_path):
    proc = _cli(str(tmp_path / "nope.yaml"))
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1


# --------------------------------------------------------------------------------------
# The schema, declared once
# --------------------------------------------------------------------------------------

# float keys without a unit: ratios and coefficients
DIMENSIONLESS = {
    "material.poissons_ratio",
    "mesh.growth",
    "mesh.elements_per_wavelength",
    "contact.penalty_scale",
    "contact.friction_static",
    "contact.friction_dynamic",
    "contact.damping_ratio",
    "damping.ratio",
    "damping.max_element_ratio",
    "preload.ke_ratio_tol",
    "run.max_added_mass",
}


def test_reference_is_current():
    committed = (ROOT / "docs" / "case_reference.md").read_text(encoding="utf-8")
    assert committed == render_reference(), f"out of date: run {COMMAND}"


def test_every_key_has_a_comment_and_its_unit():
    reference = render_reference()
    keys = [(f"{name}.{k.name}", k) for name, sec in SECTIONS.items() for k in sec.keys]
    keys += [(f"sensors.<name>.{k.name}", k) for k in SENSOR_KEYS]
    assert len(keys) == 63
    for path, k in keys:
        assert len(k.doc.split()) >= 2, path
        assert f"| `{k.name}` |" in reference, path
        if k.kind is float:
            assert bool(k.unit) != (path in DIMENSIONLESS), path
            assert k.name == (f"{k.attr}_{k.unit}" if k.unit else k.attr)
    assert {p for p, k in keys if k.kind is float and not k.unit} == DIMENSIONLESS


def test_loaded_values_are_file_values_times_the_unit_factor(default_case_path):
    # the same expressions the results were computed with, bit for bit
    case = load_case(default_case_path)
    assert case.bearing.pitch_diameter == 200.0 * 1e-3
    assert case.run.first_roller_angle == -4.0 * (math.pi / 180.0)
    assert case.operating.speed == 500.0 * (2.0 * math.pi / 60.0)
    assert case.operating.load == 50.0 * 1e3
    assert case.material.youngs_modulus == 210.0 * 1e9
    assert case.run.duration == 33.5 * 1e-3
    assert case.run.max_steps == 100_000_000 and case.preload.max_steps == 200_000


def test_one_material_for_the_case_and_the_solver(default_case_path):
    m = load_case(default_case_path).material
    assert type(m) is Material
    e, nu = 210e9, 0.3
    assert m.lam == e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    assert m.mu == e / (2.0 * (1.0 + nu))
    assert m.wave_speed == pytest.approx(6000.98, abs=0.01)
    with pytest.raises(ValueError, match="poissons_ratio"):
        Material(210e9, 0.5, 7850.0)


def test_count_keys_take_whole_numbers(default_case_path):
    case = load_case(default_case_path, ["preload.max_steps=2.5e5", "run.max_steps=1e9"])
    assert case.preload.max_steps == 250_000 and isinstance(case.preload.max_steps, int)
    assert case.run.max_steps == 10**9 and isinstance(case.run.max_steps, int)
    with pytest.raises(CaseError, match="preload.max_steps: expected an integer"):
        load_case(default_case_path, ["preload.max_steps=2.5"])


# --------------------------------------------------------------------------------------
# Runs that cannot end, or record the wrong point: refused before meshing
# --------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("sets", "key", "words"),
    [
        (["material.youngs_modulus_GPa=1e30"], "material.youngs_modulus_GPa", "below the"),
        (["material.density_kg_m3=1e-20"], "material.density_kg_m3", "faster than in any"),
        (
            ["mesh.surface_size_mm=1e-6", "mesh.max_size_mm=1e-6"],
            "mesh.surface_size_mm",
            "elements are too small",
        ),
        (["run.sample_rate_Hz=1e12"], "run.sample_rate_Hz", "needs a time step below"),
        (["run.sample_rate_Hz=5e9"], "run.sample_rate_Hz", "more than run.max_steps (1e+08)"),
        (["run.duration_ms=1e5"], "run.duration_ms", "more than run.max_steps"),
        (["sensors.adapter_top.y_mm=1e6"], "sensors.adapter_top.y_mm", "outside the outer"),
        (["sensors.adapter_top.x_mm=300"], "sensors.adapter_top.x_mm", "outside the outer"),
        (["sensors.shaft.x_mm=0", "sensors.shaft.y_mm=0"], "sensors.shaft.y_mm", "bore"),
    ],
)
def test_absurd_run_is_refused(default_case_path, sets, key, words):
    with pytest.raises(CaseError) as info:
        load_case(default_case_path, sets)
    assert info.value.key == key
    assert words in info.value.message
    # named by the --set argument it came from (a sensor by the one that created it)
    assert info.value.source in {f"--set {s}" for s in sets}


def test_max_steps_can_be_raised_and_lowered(default_case_path):
    case = load_case(default_case_path, ["run.duration_ms=1e5", "run.max_steps=1e10"])
    assert case.run.duration == pytest.approx(100.0)
    with pytest.raises(CaseError) as info:
        load_case(default_case_path, ["run.max_steps=1000"])
    assert info.value.key == "run.duration_ms"
    assert "more than run.max_steps (1000)" in info.value.message


def test_step_estimate_is_the_step_the_default_run_used(default_case_path):
    case = load_case(default_case_path)
    dt = stable_step_estimate(case)
    assert dt == case.mesh.surface_size / (math.sqrt(2.0) * case.material.wave_speed)
    summary = json.loads((ROOT / "docs/results/line_spall/summary.json").read_text())
    assert 0.8 < dt / summary["dt_s"] < 1.25
    # the default case keeps far from the step limit
    assert summary["n_steps"] < case.run.max_steps / 100


def test_sample_rate_near_the_step_warns(default_case_path):
    with pytest.warns(CaseWarning, match="step will be lowered") as caught:
        load_case(default_case_path, ["run.sample_rate_Hz=2e7"])
    assert str(caught[0].message).startswith("--set run.sample_rate_Hz=2e7: run.sample_rate_Hz:")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_case(default_case_path, ["run.sample_rate_Hz=1e6"])  # 17 steps a sample


def test_sensor_near_the_surface_is_kept(default_case_path):
    # 4 mm above the adapter top and 3 mm off the ring's side: within three elements
    case = load_case(
        default_case_path,
        ["sensors.adapter_top.y_mm=160", "sensors.side.x_mm=-129", "sensors.side.y_mm=0"],
    )
    assert case.sensors["adapter_top"].y == pytest.approx(0.16)
    assert case.sensors["side"].x == pytest.approx(-0.129)


# --------------------------------------------------------------------------------------
# Bad case files, through the command line: one line naming file and key, exit 2
# --------------------------------------------------------------------------------------


def _edit(text: str, old: str, new: str) -> bytes:
    assert text.count(old) == 1
    return text.replace(old, new).encode()


BAD_FILES = {
    # name: (edit of the default case file's text -> bytes, key, words)
    "latin-1": (
        lambda t: b"# r\xe9sum\xe9\n" + t.encode(),
        "line 1",
        "not UTF-8 text (byte 0xe9)",
    ),
    "binary": (lambda t: bytes(range(256)) * 4, "line 1", "binary content"),
    "duplicate": (
        lambda t: _edit(t, "  load_kN: 50.0 ", "  load_kN: 50.0\n  load_kN: 90.0 "),
        "operating.load_kN",
        "given twice (lines 52 and 53)",
    ),
    "duplicate sensor": (
        lambda t: _edit(t, "    y_mm: 156.0 ", "    y_mm: 156.0\n    y_mm: 150.0 "),
        "sensors.adapter_top.y_mm",
        "given twice",
    ),
    "modulus": (
        lambda t: _edit(t, "youngs_modulus_GPa: 210.0", "youngs_modulus_GPa: 1.0e+30"),
        "material.youngs_modulus_GPa",
        "time step would be about",
    ),
    "sample rate": (
        lambda t: _edit(t, "sample_rate_Hz: 100000.0", "sample_rate_Hz: 1.0e+12"),
        "run.sample_rate_Hz",
        "floor",
    ),
    "far sensor": (
        lambda t: _edit(t, "y_mm: 156.0", "y_mm: 1.0e+6"),
        "sensors.adapter_top.y_mm",
        "no mesh node within",
    ),
}


@pytest.mark.parametrize("bad", list(BAD_FILES))
def test_bad_case_file_one_line_exit_2(tmp_path, default_case_path, capsys, bad):
    edit, key, words = BAD_FILES[bad]
    path = tmp_path / "case.yaml"
    path.write_bytes(edit(default_case_path.read_text(encoding="utf-8")))
    out = tmp_path / "out"
    assert main(["mesh", str(path), "--out", str(out), "--no-pictures"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert lines == [lines[0]] and lines[0].startswith(f"error: {path}: {key}: ")
    assert words in lines[0]
    assert not out.exists()  # refused before meshing


def test_bad_set_names_the_argument_not_the_file(tmp_path, default_case_path, capsys):
    out = tmp_path / "out"
    args = ["mesh", str(default_case_path), "--out", str(out), "--no-pictures"]
    assert main([*args, "--set", "operating.load_kN=-3"]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [
        "error: --set operating.load_kN=-3: operating.load_kN: out of range: expected "
        "0 < value, got -3"
    ]
    assert main([*args, "--set", "operating.load_kN=[1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --set operating.load_kN=[1: operating.load_kN: value")
    assert str(default_case_path) not in err and not out.exists()


@pytest.mark.parametrize("bad", ["latin-1", "duplicate"])
def test_bad_case_file_no_traceback(tmp_path, default_case_path, bad):
    edit, key, _ = BAD_FILES[bad]
    path = tmp_path / "case.yaml"
    path.write_bytes(edit(default_case_path.read_text(encoding="utf-8")))
    proc = _cli("mesh", str(path), "--out", str(tmp_path / "out"))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and key in proc.stderr
