"""Case files: the YAML schema of a simulation, loaded into frozen dataclasses in SI units.

A case file holds one mapping per section (``bearing``, ``material``, ``defect``,
``operating``, ``mesh``, ``contact``, ``cage``, ``damping``, ``preload``, ``run``,
``sensors``, ``output``) plus ``name``. Every dimensional key carries its unit as a suffix;
the loaded attribute is the key without the suffix and holds the SI value:

=========  ==============  ======================================
suffix     attribute unit  example
=========  ==============  ======================================
``_mm``    m               ``pitch_diameter_mm: 200`` -> 0.2
``_kN``    N               ``load_kN: 50`` -> 50000.0
``_GPa``   Pa              ``youngs_modulus_GPa: 210`` -> 2.1e11
``_ms``    s               ``duration_ms: 30`` -> 0.03
``_deg``   rad             ``angle_deg: 90`` -> pi/2
``_rpm``   rad/s           ``speed_rpm: 60`` -> 2 pi
``_Hz``    Hz              unchanged
``_kg``    kg              unchanged
``_kg_m3`` kg/m^3          unchanged
``_s_m``   s/m             unchanged
=========  ==============  ======================================

Angles are measured from 12 o'clock (the load line), positive counter-clockwise seen from
the front; the shaft turns counter-clockwise. The radial load pushes the adapter (on top of
the outer ring) down, so the load zone is at 12 o'clock.

Errors are raised as :class:`CaseError` naming the dotted key path (e.g.
``bearing.roller_diameter_mm``) and what was expected.
"""

from __future__ import annotations

import difflib
import math
import re
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import yaml

from diagnostics.frequencies import BearingGeometry
from taichi_bearing.errors import CaseError, InputError

__all__ = [
    "Bearing",
    "Cage",
    "Case",
    "CaseError",
    "Contact",
    "Damping",
    "Defect",
    "ExtendedDefectWarning",
    "Material",
    "MeshControls",
    "Operating",
    "Output",
    "Preload",
    "Run",
    "Sensor",
    "apply_overrides",
    "case_to_dict",
    "load_case",
    "load_case_for_cli",
    "parse_case",
]


class ExtendedDefectWarning(UserWarning):
    """The defect is longer than the spacing between rollers (an extended defect)."""


# --------------------------------------------------------------------------------------
# Dataclasses (SI units)
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Bearing:
    """Bearing geometry, m.

    The rollers' centres lie on the pitch circle. The radial internal clearance ``c``
    (ISO 5753: the total radial play of one ring against the other; Harris's diametral
    clearance P_d) is shared equally by both raceways, so each roller on a line through
    the centre has a gap of c/2 when the rings are concentric.
    """

    n_rollers: int
    roller_diameter: float
    pitch_diameter: float
    roller_length: float
    radial_clearance: float
    outer_ring_thickness: float
    inner_ring_thickness: float
    adapter_width: float
    adapter_height: float
    # What holds the outer ring: "adapter" (the loading plate on the adapter top only) or
    # "housing" (a rigid housing over the ring's whole outside: Harris's rigid outer ring)
    outer_support: str = "adapter"

    @property
    def roller_radius(self) -> float:
        return 0.5 * self.roller_diameter

    @property
    def pitch_radius(self) -> float:
        return 0.5 * self.pitch_diameter

    @property
    def outer_raceway_radius(self) -> float:
        """Radius of the outer raceway (bore of the outer ring), m."""
        return self.pitch_radius + self.roller_radius + 0.25 * self.radial_clearance

    @property
    def inner_raceway_radius(self) -> float:
        """Radius of the inner raceway (outside of the inner ring), m."""
        return self.pitch_radius - self.roller_radius - 0.25 * self.radial_clearance

    @property
    def outer_ring_outer_radius(self) -> float:
        """Outside radius of the outer ring (where the adapter sits), m."""
        return self.outer_raceway_radius + self.outer_ring_thickness

    @property
    def inner_ring_bore_radius(self) -> float:
        """Bore radius of the inner ring (on the shaft), m."""
        return self.inner_raceway_radius - self.inner_ring_thickness

    @property
    def roller_spacing(self) -> float:
        """Angle between neighbouring rollers, rad."""
        return 2.0 * math.pi / self.n_rollers

    @property
    def geometry(self) -> BearingGeometry:
        """The geometry in the form ``diagnostics`` uses for fault frequencies."""
        return BearingGeometry(self.n_rollers, self.roller_diameter, self.pitch_diameter)


@dataclass(frozen=True)
class Material:
    """Linear elastic steel shared by every part."""

    youngs_modulus: float  # Pa
    poissons_ratio: float
    density: float  # kg/m^3

    @property
    def plane_strain_modulus(self) -> float:
        """E / (1 - nu^2), Pa."""
        return self.youngs_modulus / (1.0 - self.poissons_ratio**2)

    @property
    def dilatational_wave_speed(self) -> float:
        """Plane-strain P-wave speed sqrt((lambda + 2 mu) / rho), m/s."""
        e, nu = self.youngs_modulus, self.poissons_ratio
        return math.sqrt(e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu) * self.density))


@dataclass(frozen=True)
class Defect:
    """Line spall: a rectangular notch across the raceway.

    ``race`` is ``"outer"``, ``"inner"`` or ``"none"`` (a healthy bearing). ``angle`` is
    the angular position of the spall centre (rad, from 12 o'clock, counter-clockwise; for
    the inner race, in the inner ring's own frame at t = 0), ``length`` its arc length along
    the raceway and ``depth`` its radial depth (m).
    """

    race: str
    angle: float
    length: float
    depth: float

    @property
    def present(self) -> bool:
        return self.race != "none" and self.length > 0.0 and self.depth > 0.0


@dataclass(frozen=True)
class Operating:
    """Operating point: radial load (N, pushing the adapter down) and shaft speed."""

    load: float  # N
    speed: float  # rad/s, counter-clockwise

    @property
    def shaft_hz(self) -> float:
        """Shaft rotation frequency, Hz."""
        return self.speed / (2.0 * math.pi)

    @property
    def shaft_rpm(self) -> float:
        return self.speed * 60.0 / (2.0 * math.pi)


@dataclass(frozen=True)
class MeshControls:
    """Element sizes, m, and the growth ratio between element layers."""

    surface_size: float
    max_size: float
    growth: float


@dataclass(frozen=True)
class Contact:
    """Penalty contact with Coulomb friction and viscous contact damping."""

    penalty_method: str  # "segment" or "soft"
    penalty_scale: float
    friction_static: float
    friction_dynamic: float
    friction_decay: float  # s/m
    damping_ratio: float
    smoothing: bool = True  # contact against each segment's reference arc, not its chord


@dataclass(frozen=True)
class Cage:
    model: str  # "rigid"
    pocket_clearance: float  # m
    mass: float  # kg


@dataclass(frozen=True)
class Damping:
    """Stiffness-proportional damping: ``ratio`` of critical at ``frequency`` (Hz), with
    each element's own damping ratio at its highest frequency capped at
    ``max_element_ratio`` (which bounds how much the damping shortens the time step)."""

    ratio: float
    frequency: float  # Hz
    max_element_ratio: float = 0.1

    @property
    def beta(self) -> float:
        """Stiffness-proportional coefficient beta = 2 zeta / omega, s."""
        return 2.0 * self.ratio / (2.0 * math.pi * self.frequency)


@dataclass(frozen=True)
class Preload:
    ke_ratio_tol: float
    max_steps: int


@dataclass(frozen=True)
class Run:
    duration: float  # s
    first_roller_angle: float  # rad
    arch: str  # "cpu", "cuda" or "vulkan"
    threads: int
    sample_rate: float  # Hz
    frame_interval: float  # s
    checkpoint_interval: float  # s
    max_added_mass: float = 0.0  # selective mass scaling budget, fraction of a part's mass
    time_step: str = "global"  # "global" (assembled mesh) or "element" critical step


@dataclass(frozen=True)
class Sensor:
    """A named point, m (bearing centre at the origin, +y up)."""

    x: float
    y: float


@dataclass(frozen=True)
class Output:
    dir: str | None
    csv: bool
    frames: bool


@dataclass(frozen=True)
class Case:
    """A validated case, every value in SI units."""

    name: str
    bearing: Bearing
    material: Material
    defect: Defect
    operating: Operating
    mesh: MeshControls
    contact: Contact
    cage: Cage
    damping: Damping
    preload: Preload
    run: Run
    sensors: dict[str, Sensor]
    output: Output
    source: Path | None = None

    @property
    def out_dir(self) -> Path:
        """``output.dir`` or the default ``runs/<name>``."""
        return Path(self.output.dir) if self.output.dir else Path("runs") / self.name


# --------------------------------------------------------------------------------------
# Schema
# --------------------------------------------------------------------------------------

# unit suffix -> factor to SI; longest suffixes are matched first
UNIT_FACTORS: dict[str, float] = {
    "_kg_m3": 1.0,
    "_s_m": 1.0,
    "_mm": 1e-3,
    "_kN": 1e3,
    "_GPa": 1e9,
    "_ms": 1e-3,
    "_deg": math.pi / 180.0,
    "_rpm": 2.0 * math.pi / 60.0,
    "_Hz": 1.0,
    "_kg": 1.0,
}

_REQUIRED = object()
_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)[eE][-+]?\d+")


@dataclass(frozen=True)
class Key:
    """One key of the schema: type, range and (optional) default."""

    name: str
    kind: type | tuple  # float, int, str, bool, or (str, None) for an optional string
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple[str, ...] | None = None
    default: Any = _REQUIRED

    @property
    def suffix(self) -> str:
        for suffix in UNIT_FACTORS:
            if self.name.endswith(suffix):
                return suffix
        return ""

    @property
    def attr(self) -> str:
        return self.name[: len(self.name) - len(self.suffix)]

    @property
    def factor(self) -> float:
        return UNIT_FACTORS.get(self.suffix, 1.0)

    def range_text(self) -> str:
        lo = "" if self.lo is None else f"{self.lo:g} {'<' if self.lo_open else '<='} "
        hi = "" if self.hi is None else f" {'<' if self.hi_open else '<='} {self.hi:g}"
        return f"{lo}value{hi}"


POS = {"lo": 0.0, "lo_open": True}  # strictly positive
NONNEG = {"lo": 0.0}

SCHEMA: dict[str, tuple[type, tuple[Key, ...]]] = {
    "bearing": (
        Bearing,
        (
            Key("n_rollers", int, lo=3, hi=200),
            Key("roller_diameter_mm", float, **POS),
            Key("pitch_diameter_mm", float, **POS),
            Key("roller_length_mm", float, **POS),
            Key("radial_clearance_mm", float),
            Key("outer_ring_thickness_mm", float, **POS),
            Key("inner_ring_thickness_mm", float, **POS),
            Key("adapter_width_mm", float, **POS),
            Key("adapter_height_mm", float, **POS),
            Key("outer_support", str, choices=("adapter", "housing"), default="adapter"),
        ),
    ),
    "material": (
        Material,
        (
            Key("youngs_modulus_GPa", float, **POS),
            Key("poissons_ratio", float, lo=0.0, hi=0.5, hi_open=True),
            Key("density_kg_m3", float, **POS),
        ),
    ),
    "defect": (
        Defect,
        (
            Key("race", str, choices=("outer", "inner", "none")),
            Key("angle_deg", float, lo=-180.0, hi=180.0),
            Key("length_mm", float, **NONNEG),
            Key("depth_mm", float, **NONNEG),
        ),
    ),
    "operating": (
        Operating,
        (
            Key("load_kN", float, **POS),
            Key("speed_rpm", float, **POS),
        ),
    ),
    "mesh": (
        MeshControls,
        (
            Key("surface_size_mm", float, **POS),
            Key("max_size_mm", float, **POS),
            Key("growth", float, lo=1.0, hi=3.0),
        ),
    ),
    "contact": (
        Contact,
        (
            Key("penalty_method", str, choices=("segment", "soft")),
            Key("penalty_scale", float, **POS),
            Key("friction_static", float, **NONNEG),
            Key("friction_dynamic", float, **NONNEG),
            Key("friction_decay_s_m", float, **NONNEG),
            Key("damping_ratio", float, lo=0.0, hi=1.0),
            Key("smoothing", bool, default=True),
        ),
    ),
    "cage": (
        Cage,
        (
            Key("model", str, choices=("rigid",)),
            Key("pocket_clearance_mm", float, **NONNEG),
            Key("mass_kg", float, **POS),
        ),
    ),
    "damping": (
        Damping,
        (
            Key("ratio", float, lo=0.0, hi=1.0),
            Key("frequency_Hz", float, **POS),
            Key("max_element_ratio", float, **POS, default=0.1),
        ),
    ),
    "preload": (
        Preload,
        (
            Key("ke_ratio_tol", float, lo=0.0, hi=1.0, lo_open=True, hi_open=True),
            Key("max_steps", int, lo=1),
        ),
    ),
    "run": (
        Run,
        (
            Key("duration_ms", float, **POS),
            Key("first_roller_angle_deg", float, lo=-180.0, hi=180.0),
            Key("arch", str, choices=("cpu", "cuda", "vulkan")),
            Key("threads", int, lo=0),
            Key("sample_rate_Hz", float, **POS),
            Key("frame_interval_ms", float, **POS),
            Key("checkpoint_interval_ms", float, **POS),
            Key("max_added_mass", float, lo=0.0, hi=0.01, default=0.0),
            Key("time_step", str, choices=("global", "element"), default="global"),
        ),
    ),
    "output": (
        Output,
        (
            Key("dir", (str, type(None)), default=None),
            Key("csv", bool, default=False),
            Key("frames", bool, default=True),
        ),
    ),
}

SENSOR_KEYS: tuple[Key, ...] = (Key("x_mm", float), Key("y_mm", float))
TOP_KEYS: tuple[str, ...] = ("name", *SCHEMA, "sensors")


# --------------------------------------------------------------------------------------
# Loading
# --------------------------------------------------------------------------------------


def load_case(path: str | Path, overrides: Iterable[str] = ()) -> Case:
    """Read, override and validate a case file.

    Parameters
    ----------
    path : str or Path
        YAML case file.
    overrides : iterable of str
        ``"key.path=value"`` strings (values parsed as YAML), applied before validation,
        e.g. ``"operating.load_kN=80"``.

    Returns
    -------
    Case
        The validated case in SI units.

    Raises
    ------
    CaseError
        On an unreadable file, bad YAML, or any invalid value (the message names the key).

    Warns
    -----
    ExtendedDefectWarning
        When the defect is longer than the spacing between rollers.
    """
    path = Path(path)
    source = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{source}: cannot read the case file ({exc.strerror})") from None
    try:
        raw = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark is not None else "(top)"
        problem = getattr(exc, "problem", None) or "invalid YAML"
        raise CaseError(where, f"not valid YAML ({problem})", source) from None
    if not isinstance(raw, dict):
        raise CaseError("(top)", "expected a mapping of sections at the top level", source)
    raw = apply_overrides(raw, overrides, source)
    return parse_case(raw, source=path)


def load_case_for_cli(path: str | Path, overrides: Iterable[str] = ()) -> Case:
    """:func:`load_case`, with its warnings printed as one line each on stderr."""
    import sys

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ExtendedDefectWarning)
        case = load_case(path, overrides)
    for w in caught:
        if issubclass(w.category, ExtendedDefectWarning):
            print(f"warning: {w.message}", file=sys.stderr)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return case


def apply_overrides(raw: dict, overrides: Iterable[str], source: str | None = None) -> dict:
    """Return a copy of ``raw`` with ``key.path=value`` overrides applied (values as YAML)."""
    import copy

    raw = copy.deepcopy(raw)
    for item in overrides:
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise CaseError("--set", f"expected KEY.PATH=VALUE, got {item!r}", source)
        try:
            value = yaml.safe_load(text)
        except yaml.YAMLError:
            raise CaseError(key, f"--set value {text!r} is not valid YAML", source) from None
        parts = key.split(".")
        node = raw
        for depth, part in enumerate(parts[:-1]):
            child = node.get(part) if isinstance(node, dict) else None
            if child is None:
                if not _is_known_prefix(parts[: depth + 1]):
                    _unknown(".".join(parts[: depth + 1]), _valid_at(parts[:depth]), source)
                child = node[part] = {}
            elif not isinstance(child, dict):
                raise CaseError(".".join(parts[: depth + 1]), "is a value, not a section", source)
            node = child
        node[parts[-1]] = value
    return raw


def _is_known_prefix(parts: list[str]) -> bool:
    # only a new sensor may be created by an override; sections must exist
    return len(parts) == 2 and parts[0] == "sensors" or (len(parts) == 1 and parts[0] in SCHEMA)


def _valid_at(parts: list[str]) -> list[str]:
    if not parts:
        return list(TOP_KEYS)
    if parts[0] in SCHEMA and len(parts) == 1:
        return [f"{parts[0]}.{k.name}" for k in SCHEMA[parts[0]][1]]
    return []


def _unknown(key: str, valid: Iterable[str], source: str | None) -> None:
    valid = list(valid)
    close = difflib.get_close_matches(key, valid, n=1, cutoff=0.6)
    if close:
        hint = f"did you mean '{close[0]}'?"
    else:
        hint = "valid keys here: " + ", ".join(v.rsplit(".", 1)[-1] for v in valid)
    raise CaseError(key, f"unknown key; {hint}", source)


def parse_case(raw: Mapping, source: str | Path | None = None) -> Case:
    """Validate a case given as a nested mapping (the YAML content) and convert it to SI."""
    src = None if source is None else str(source)
    if not isinstance(raw, Mapping):
        raise CaseError("(top)", "expected a mapping of sections at the top level", src)
    for key in raw:
        if key not in TOP_KEYS:
            _unknown(str(key), TOP_KEYS, src)
    for key in TOP_KEYS:
        if key not in raw:
            if key == "output":
                continue  # every output key has a default
            raise CaseError(key, "missing section" if key != "name" else "missing key", src)

    name = raw["name"]
    if not isinstance(name, str) or not name.strip() or any(c in name for c in "/\\"):
        raise CaseError("name", f"expected a non-empty folder-safe string, got {name!r}", src)

    sections = {
        sec: _parse_section(sec, raw.get(sec, {}), cls, keys, src)
        for sec, (cls, keys) in SCHEMA.items()
    }
    sensors = _parse_sensors(raw["sensors"], src)
    case = Case(
        name=name, sensors=sensors, source=None if source is None else Path(source), **sections
    )
    _check_physics(case, src)
    return case


def _parse_section(section: str, raw: Any, cls: type, keys: tuple[Key, ...], src):
    if raw is None and all(k.default is not _REQUIRED for k in keys):
        raw = {}
    if not isinstance(raw, Mapping):
        raise CaseError(section, f"expected a mapping of keys, got {_type_name(raw)}", src)
    names = {k.name for k in keys}
    for key in raw:
        if key not in names:
            _unknown(f"{section}.{key}", [f"{section}.{n}" for n in names], src)
    values = {}
    for k in keys:
        path = f"{section}.{k.name}"
        if k.name not in raw:
            if k.default is _REQUIRED:
                raise CaseError(path, f"missing key (expected {_kind_text(k)})", src)
            values[k.attr] = k.default
            continue
        values[k.attr] = _convert(path, raw[k.name], k, src)
    return cls(**values)


def _parse_sensors(raw: Any, src) -> dict[str, Sensor]:
    if raw is None:
        return {}
    if not isinstance(raw, Mapping):
        raise CaseError("sensors", f"expected a mapping name -> point, got {_type_name(raw)}", src)
    sensors = {}
    for name, point in raw.items():
        path = f"sensors.{name}"
        if not isinstance(name, str) or not name.isidentifier():
            raise CaseError(path, "sensor names must be identifiers (letters, digits, _)", src)
        if not isinstance(point, Mapping):
            raise CaseError(path, "expected a mapping with x_mm and y_mm", src)
        for key in point:
            if key not in ("x_mm", "y_mm"):
                _unknown(f"{path}.{key}", [f"{path}.x_mm", f"{path}.y_mm"], src)
        coords = {}
        for k in SENSOR_KEYS:
            if k.name not in point:
                raise CaseError(f"{path}.{k.name}", "missing key (expected a number)", src)
            coords[k.attr] = _convert(f"{path}.{k.name}", point[k.name], k, src)
        sensors[name] = Sensor(**coords)
    return sensors


def _kind_text(k: Key) -> str:
    if k.choices:
        return "one of " + ", ".join(repr(c) for c in k.choices)
    if k.kind is bool:
        return "true or false"
    if k.kind is int:
        return "an integer"
    if k.kind is float:
        unit = k.suffix.lstrip("_").replace("_", "/") if k.suffix else ""
        return f"a number{' in ' + unit if unit else ''}"
    if k.kind == (str, type(None)):
        return "a string or null"
    return "a string"


def _type_name(value: Any) -> str:
    return {dict: "a mapping", list: "a list", type(None): "null"}.get(
        type(value), f"{type(value).__name__} {value!r}"
    )


def _convert(path: str, value: Any, k: Key, src) -> Any:
    expected = _kind_text(k)
    if k.kind is float:
        if isinstance(value, str) and _NUMBER.fullmatch(value.strip()):
            # YAML 1.1 reads exponents without a dot (1e-5) as strings
            value = float(value)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise CaseError(path, f"expected {expected}, got {_type_name(value)}", src)
        value = float(value)
        if not math.isfinite(value):
            raise CaseError(path, f"expected a finite number, got {value!r}", src)
    elif k.kind is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise CaseError(path, f"expected {expected}, got {_type_name(value)}", src)
    elif k.kind is bool:
        if not isinstance(value, bool):
            raise CaseError(path, f"expected {expected}, got {_type_name(value)}", src)
    elif isinstance(k.kind, tuple):
        if not isinstance(value, k.kind):
            raise CaseError(path, f"expected {expected}, got {_type_name(value)}", src)
    else:
        if not isinstance(value, str):
            raise CaseError(path, f"expected {expected}, got {_type_name(value)}", src)
    if k.choices is not None and value not in k.choices:
        raise CaseError(path, f"expected {expected}, got {value!r}", src)
    if k.kind in (int, float):
        too_low = k.lo is not None and (value <= k.lo if k.lo_open else value < k.lo)
        too_high = k.hi is not None and (value >= k.hi if k.hi_open else value > k.hi)
        if too_low or too_high:
            raise CaseError(path, f"out of range: expected {k.range_text()}, got {value:g}", src)
        return value * k.factor if k.kind is float else value
    return value


def _check_physics(case: Case, src: str | None) -> None:
    """Cross-key checks: the values are individually valid but must also fit together."""
    b, d = case.bearing, case.defect
    mm = 1e3

    if b.roller_diameter >= b.pitch_diameter:
        raise CaseError(
            "bearing.roller_diameter_mm",
            f"roller ({b.roller_diameter * mm:g} mm) must be smaller than the pitch diameter "
            f"({b.pitch_diameter * mm:g} mm)",
            src,
        )
    chord = b.pitch_diameter * math.sin(math.pi / b.n_rollers)
    if chord <= b.roller_diameter:
        raise CaseError(
            "bearing.n_rollers",
            f"{b.n_rollers} rollers of {b.roller_diameter * mm:g} mm overlap on the "
            f"{b.pitch_diameter * mm:g} mm pitch circle (centre spacing {chord * mm:.3g} mm); "
            f"at most {_max_rollers(b)} fit",
            src,
        )
    # A negative clearance is an interference fit (preload); beyond 1 % of the roller
    # diameter the rollers cannot be assembled elastically between the raceways.
    if b.radial_clearance < -0.01 * b.roller_diameter:
        raise CaseError(
            "bearing.radial_clearance_mm",
            f"interference {-b.radial_clearance * mm:g} mm: the rollers do not fit between "
            f"the raceways (at most {0.01 * b.roller_diameter * mm:g} mm of preload)",
            src,
        )
    if b.radial_clearance > 0.1 * b.roller_diameter:
        raise CaseError(
            "bearing.radial_clearance_mm",
            f"clearance {b.radial_clearance * mm:g} mm is larger than 10 % of the roller "
            "diameter: the rollers would not be guided by the raceways",
            src,
        )
    if b.inner_ring_bore_radius <= 0.0:
        raise CaseError(
            "bearing.inner_ring_thickness_mm",
            f"the inner ring ({b.inner_ring_thickness * mm:g} mm) is thicker than the inner "
            f"raceway radius ({b.inner_raceway_radius * mm:g} mm): no room for a bore",
            src,
        )
    if b.adapter_width > 2.0 * b.outer_ring_outer_radius:
        raise CaseError(
            "bearing.adapter_width_mm",
            f"adapter ({b.adapter_width * mm:g} mm) is wider than the outer ring "
            f"({2 * b.outer_ring_outer_radius * mm:g} mm)",
            src,
        )
    if case.contact.friction_dynamic > case.contact.friction_static:
        raise CaseError(
            "contact.friction_dynamic",
            f"dynamic friction ({case.contact.friction_dynamic:g}) exceeds static friction "
            f"({case.contact.friction_static:g})",
            src,
        )
    if case.mesh.surface_size > case.mesh.max_size:
        raise CaseError(
            "mesh.surface_size_mm",
            f"surface size ({case.mesh.surface_size * mm:g} mm) exceeds mesh.max_size_mm "
            f"({case.mesh.max_size * mm:g} mm)",
            src,
        )
    if case.mesh.surface_size > 0.25 * b.roller_diameter:
        raise CaseError(
            "mesh.surface_size_mm",
            f"{case.mesh.surface_size * mm:g} mm is too coarse for a "
            f"{b.roller_diameter * mm:g} mm roller (at most a quarter of its diameter)",
            src,
        )
    if case.run.frame_interval > case.run.duration:
        raise CaseError(
            "run.frame_interval_ms",
            f"{case.run.frame_interval * 1e3:g} ms is longer than run.duration_ms "
            f"({case.run.duration * 1e3:g} ms)",
            src,
        )
    if case.run.sample_rate * case.run.duration < 2.0:
        raise CaseError(
            "run.sample_rate_Hz", "fewer than two samples would be recorded over the run", src
        )

    if d.race == "none":
        return
    ring, raceway = (
        (b.outer_ring_thickness, b.outer_raceway_radius)
        if d.race == "outer"
        else (b.inner_ring_thickness, b.inner_raceway_radius)
    )
    if d.length <= 0.0 or d.depth <= 0.0:
        key = "defect.length_mm" if d.length <= 0.0 else "defect.depth_mm"
        raise CaseError(key, "must be positive for a defect (use race: none for no defect)", src)
    # a spall through half the ring or more is a cracked ring, not a line spall (and the
    # mesher needs solid ring below the notch)
    if d.depth >= 0.5 * ring:
        raise CaseError(
            "defect.depth_mm",
            f"defect ({d.depth * mm:g} mm) must be shallower than half the {d.race} ring "
            f"({ring * mm:g} mm thick)",
            src,
        )
    circumference = 2.0 * math.pi * raceway
    if d.length >= 0.5 * circumference:
        raise CaseError(
            "defect.length_mm",
            f"defect ({d.length * mm:g} mm) is longer than half the {d.race} raceway "
            f"({0.5 * circumference * mm:.4g} mm)",
            src,
        )
    spacing = b.roller_spacing * raceway
    if d.length >= spacing:
        warnings.warn(
            f"{src + ': ' if src else ''}defect.length_mm: {d.length * mm:g} mm is longer than "
            f"the roller spacing on the {d.race} raceway ({spacing * mm:.4g} mm): an extended "
            "defect, more than one roller can be inside it (the models assume a localised one)",
            ExtendedDefectWarning,
            stacklevel=3,
        )


def _max_rollers(b: Bearing) -> int:
    # largest Z with D sin(pi/Z) > d
    return int(
        math.floor(math.pi / math.asin(min(1.0, b.roller_diameter / b.pitch_diameter)) - 1e-12)
    )


# --------------------------------------------------------------------------------------
# Writing back
# --------------------------------------------------------------------------------------


def case_to_dict(case: Case) -> dict:
    """The case as a YAML-ready mapping with unit-suffixed keys (inverse of parse_case)."""
    out: dict[str, Any] = {"name": case.name}
    for section, (_cls, keys) in SCHEMA.items():
        obj = getattr(case, section)
        out[section] = {k.name: _to_units(getattr(obj, k.attr), k) for k in keys}
    out["sensors"] = {
        name: {k.name: _to_units(getattr(s, k.attr), k) for k in SENSOR_KEYS}
        for name, s in case.sensors.items()
    }
    return out


def _to_units(value: Any, k: Key) -> Any:
    if k.kind is float:
        return float(value) / k.factor
    return value


def schema_attributes() -> dict[str, list[str]]:
    """Attribute names per section (for documentation and tests)."""
    attrs = {sec: [f.name for f in fields(cls)] for sec, (cls, _keys) in SCHEMA.items()}
    attrs["sensors"] = [f.name for f in fields(Sensor)]
    return attrs
