"""The case schema: every section of a case file and every key in it, declared once.

Each section is a frozen dataclass; each field declared with :func:`~.schema.key` is a key
of the file (attribute + unit suffix), loaded in SI units. The ``material`` section is
:class:`~taichi_bearing.case.material.Material`. :data:`SECTIONS` and :data:`SENSOR_KEYS`
are read from these classes; the loader, the ``--set`` parser and the case-file reference
(``docs/case_reference.md``) all work from them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from taichi_bearing.case.material import Material
from taichi_bearing.case.schema import Section, key, section_keys, sections_of

if TYPE_CHECKING:
    from diagnostics import BearingGeometry

__all__ = [
    "SECTIONS",
    "SENSOR_KEYS",
    "Bearing",
    "Cage",
    "Case",
    "Contact",
    "Damping",
    "Defect",
    "MeshControls",
    "Operating",
    "Output",
    "Preload",
    "Run",
    "Sensor",
]


@dataclass(frozen=True)
class Bearing:
    """Bearing geometry, m.

    The rollers' centres lie on the pitch circle. The radial internal clearance ``c``
    (ISO 5753: the total radial play of one ring against the other; Harris's diametral
    clearance P_d) is shared equally by both raceways, so each roller on a line through
    the centre has a gap of c/2 when the rings are concentric.
    """

    n_rollers: int = key(ge=3, le=200, doc="number of rollers; they must not overlap")
    roller_diameter: float = key("mm", gt=0.0, doc="roller diameter, less than the pitch")
    pitch_diameter: float = key("mm", gt=0.0, doc="diameter of the circle of roller centres")
    roller_length: float = key(
        "mm", gt=0.0, doc="effective roller length: the plane-strain thickness"
    )
    radial_clearance: float = key(
        "mm",
        doc="radial internal clearance (total play, ISO 5753), shared equally by both "
        "raceways; negative is an interference fit; -1 % to +10 % of the roller diameter",
    )
    outer_ring_thickness: float = key("mm", gt=0.0, doc="outer raceway to ring outside")
    inner_ring_thickness: float = key("mm", gt=0.0, doc="inner ring bore to raceway")
    adapter_width: float = key(
        "mm", gt=0.0, doc="block on top of the outer ring, at most the ring's outside diameter"
    )
    adapter_height: float = key("mm", gt=0.0, doc="adapter height above the outer ring's top")
    outer_support: Literal["adapter", "housing"] = key(
        default="adapter",
        doc="what holds the outer ring: the loading plate on the adapter top only (a "
        "flexible ring), or a rigid housing over the ring's whole outside (Harris's model)",
    )

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
        # imported here: diagnostics pulls in scipy.signal, which the CLI's start-up and
        # the case checks do not need
        from diagnostics import BearingGeometry

        return BearingGeometry(self.n_rollers, self.roller_diameter, self.pitch_diameter)


RIGHT_ANGLE = 90.0 * (math.pi / 180.0)  # as 90 deg in a file loads, to the last bit


@dataclass(frozen=True)
class Defect:
    """Line spall across the raceway: a notch with sharp radial walls by default, or
    with sloped walls and rounded edges.

    ``angle`` is the position of the spall centre (rad, from 12 o'clock, counter-clockwise;
    for the inner race, in the inner ring's own frame at t = 0), ``length`` its arc length
    along the raceway between its edges at the surface and ``depth`` its radial depth (m);
    ``entry_slope`` and ``exit_slope`` (rad) the walls' angles from the raceway, entry
    being the edge the rollers reach first; ``edge_radius`` (m) rounds both edges.
    """

    race: Literal["outer", "inner", "none"] = key(
        doc="raceway with the spall; none is a healthy bearing"
    )
    angle: float = key(
        "deg", ge=-180.0, le=180.0, doc="centre of the spall from 12 o'clock (under the load)"
    )
    length: float = key(
        "mm",
        ge=0.0,
        doc="arc length along the raceway, > 0 with a defect; longer than the roller "
        "spacing is an extended defect (warned)",
    )
    depth: float = key("mm", ge=0.0, doc="radial depth, > 0 with a defect, less than half the ring")
    entry_slope: float = key(
        "deg",
        gt=0.0,
        le=90.0,
        default=RIGHT_ANGLE,
        doc="wall at the edge the rollers reach first, from the raceway's tangent there: "
        "90 is the sharp radial wall; on the curved raceway the wall reaches the floor a "
        "little before depth / tan(slope)",
    )
    exit_slope: float = key(
        "deg",
        gt=0.0,
        le=90.0,
        default=RIGHT_ANGLE,
        doc="wall at the edge the rollers leave over (the re-stressing), as entry_slope_deg",
    )
    edge_radius: float = key(
        "mm",
        ge=0.0,
        default=0.0,
        doc="rounds both edges at the raceway (tangent to the raceway and the wall); 0 is "
        "sharp; at most what fits the walls",
    )

    @property
    def present(self) -> bool:
        return self.race != "none" and self.length > 0.0 and self.depth > 0.0


@dataclass(frozen=True)
class Operating:
    """Operating point: the radial load pushes the adapter down; the shaft turns
    counter-clockwise."""

    load: float = key("kN", gt=0.0, doc="radial load on the adapter top, downwards")
    speed: float = key("rpm", gt=0.0, doc="shaft (inner ring) speed, counter-clockwise")

    @property
    def shaft_hz(self) -> float:
        """Shaft rotation frequency, Hz."""
        return self.speed / (2.0 * math.pi)

    @property
    def shaft_rpm(self) -> float:
        return self.speed * 60.0 / (2.0 * math.pi)


@dataclass(frozen=True)
class MeshControls:
    """Element sizes and the growth ratio between element layers."""

    surface_size: float = key(
        "mm",
        gt=0.0,
        doc="element size along every contact surface, at most a quarter of the roller "
        "diameter and max_size_mm; it sets the time step",
    )
    max_size: float = key("mm", gt=0.0, doc="largest element inside the bodies")
    growth: float = key(ge=1.0, le=3.0, doc="size ratio between neighbouring element layers")
    spall_size: float = key(
        "mm",
        ge=0.0,
        default=0.0,
        doc="finer element size along the raceway with the spall, within spall_zone_mm of "
        "its edges (walls and floor included); beyond, the elements grow to surface_size_mm "
        "by at most growth (at least 1.2) per element and the extra layers merge into the "
        "ring's; 0 is surface_size_mm (no refinement); at most surface_size_mm, at least "
        "1/16 of it; needs a defect",
    )
    spall_zone: float = key(
        "mm",
        ge=0.0,
        default=2e-3,
        doc="arc length of raceway beyond each edge of the spall meshed at spall_size_mm "
        "(widened where the edges' meshing needs it, and past any adapter corner or 12 "
        "o'clock that would fall near its ends or in the transition); the spall with its "
        "zones and "
        "transitions must be shorter than half the raceway",
    )
    roller_surface_size: float = key(
        "mm",
        ge=0.0,
        default=0.0,
        doc="finer element size along the surfaces of the fine rollers (fine_rollers), "
        "graded into each roller's core by growth; 0 is surface_size_mm; at most "
        "surface_size_mm",
    )
    fine_rollers: int = key(
        ge=0,
        default=0,
        doc="how many rollers get roller_surface_size_mm, in the order they leave the "
        "spall (the default case: roller 0, then 19, 18, ...; without a defect, the order "
        "they reach 12 o'clock); 0 is all; at most bearing.n_rollers",
    )
    elements_per_wavelength: float = key(
        ge=2.0,
        le=100.0,
        default=10.0,
        doc="resolution criterion: a part resolves frequencies up to c_R / (N h), with c_R "
        "the Rayleigh (slowest) wave speed and h its longest element; the run warns when "
        "run.sample_rate_Hz / 2 lies above what some part resolves (10: the usual rule for "
        "linear elements, wave speed low by ~1.6 %; 20: ~0.4 %)",
    )


@dataclass(frozen=True)
class Contact:
    """Penalty contact with Coulomb friction and viscous contact damping."""

    penalty_method: Literal["segment", "soft", "pressure"] = key(
        doc="penalty stiffness from the segment's bulk stiffness (K A^2 / V), from the "
        "nodal mass and time step (soft), or a pressure per unit overlap the mesh does not "
        "set (pressure: penalty_pressure_GPa_mm, or penalty_scale E* / b_ref)"
    )
    penalty_scale: float = key(
        gt=0.0,
        doc="scale factor on the penalty stiffness: f_s (segment, soft) or alpha (pressure: "
        "p_s = alpha E* / b_ref, b_ref the smaller Hertz half-width of the most loaded "
        "roller; the penalty's overlap is about 1/alpha of the Hertz gap)",
    )
    friction_static: float = key(ge=0.0, doc="static Coulomb coefficient")
    friction_dynamic: float = key(ge=0.0, doc="dynamic coefficient, at most friction_static")
    friction_decay: float = key(
        "s_m",
        ge=0.0,
        doc="mu = mu_d + (mu_s - mu_d) exp(-decay |v_slip|): how fast friction falls from "
        "static to dynamic with the slip speed",
    )
    damping_ratio: float = key(ge=0.0, le=1.0, doc="viscous contact damping, fraction of critical")
    smoothing: bool = key(
        default=True,
        doc="contact against each surface segment's undeformed arc (true) rather than its "
        "chord (false: LS-DYNA's plain node-to-segment contact)",
    )
    penalty_pressure: float = key(
        "GPa_mm",
        ge=0.0,
        default=0.0,
        doc="pressure law: pressure per unit overlap p_s given directly; 0 = from "
        "penalty_scale (alpha E* / b_ref)",
    )


@dataclass(frozen=True)
class Cage:
    """The cage: a rigid ring with pockets, turning about the centre, driven by the
    rollers."""

    model: Literal["rigid"] = key(doc="cage model")
    pocket_clearance: float = key(
        "mm", ge=0.0, doc="circumferential play of a roller in its pocket"
    )
    mass: float = key("kg", gt=0.0, doc="cage mass")


@dataclass(frozen=True)
class Damping:
    """Stiffness-proportional damping (never brakes rigid rotation): ``ratio`` of critical
    at ``frequency``, with each element's own ratio at its highest frequency capped at
    ``max_element_ratio`` (which bounds how much the damping shortens the time step)."""

    ratio: float = key(ge=0.0, le=1.0, doc="fraction of critical reached at frequency_Hz")
    frequency: float = key("Hz", gt=0.0, doc="frequency at which the law gives ratio")
    max_element_ratio: float = key(
        gt=0.0,
        default=0.1,
        doc="cap on each element's own damping ratio at its highest frequency (lowers "
        "beta in the elements above it, so it also lowers their structural damping)",
    )

    @property
    def beta(self) -> float:
        """Stiffness-proportional coefficient beta = 2 zeta / omega, s."""
        return 2.0 * self.ratio / (2.0 * math.pi * self.frequency)


@dataclass(frozen=True)
class Preload:
    """Dynamic relaxation (damped steps) before the transient, until the bearing is
    statically loaded."""

    ke_ratio_tol: float = key(
        gt=0.0, lt=1.0, doc="ends when the kinetic energy over its peak falls below this"
    )
    max_steps: int = key(ge=1, doc="gives up after this many steps")
    mass_scaling: bool = key(
        default=False,
        doc="relax with the nodes under contact (and the cage's springs) made heavier, so "
        "that a stiff contact (the pressure law) does not set the step: the same static "
        "state in fewer steps, the transient at the real masses; needs run.time_step: "
        "global and a penalty other than soft",
    )


@dataclass(frozen=True)
class Run:
    """The transient: how long, where the rollers start, on what, what is recorded."""

    duration: float = key("ms", gt=0.0, doc="simulated time after the preload")
    first_roller_angle: float = key(
        "deg", ge=-180.0, le=180.0, doc="roller 0's start, from 12 o'clock"
    )
    arch: Literal["cpu", "cuda", "vulkan"] = key(doc="Taichi backend")
    threads: int = key(ge=0, doc="CPU threads; 0 is every core")
    sample_rate: float = key(
        "Hz",
        gt=0.0,
        doc="history output rate; a sample is a whole number of steps, so a rate near "
        "1 / step lowers the step",
    )
    frame_interval: float = key("ms", gt=0.0, doc="field frame (VTU) interval, at most duration_ms")
    checkpoint_interval: float = key("ms", gt=0.0, doc="restart file interval")
    max_added_mass: float = key(
        ge=0.0,
        le=0.01,
        default=0.0,
        doc="selective mass scaling: the smallest elements get the density that lifts "
        "their critical step to the next ones', each part gaining at most this fraction "
        "of its mass; 0 is off",
    )
    time_step: Literal["global", "element"] = key(
        default="global",
        doc="the step from the assembled mesh's highest frequency (with a bound on what "
        "contact adds), or the smallest element's own critical step (always smaller)",
    )
    multirate_levels: int = key(
        ge=0,
        le=4,
        default=0,
        doc="multi-rate stepping: nodes whose elements allow 2, 4, ... 2**levels times the "
        "step change velocity only that often (nodes under contact, loads, constraints or "
        "sensors every step); pays on locally refined meshes "
        "(benchmarks/taichi_bearing/bench_multirate.py); "
        "0 is off",
    )
    max_steps: int = key(
        ge=1,
        default=100_000_000,
        doc="the case is refused when its estimated number of time steps is larger: a "
        "guard against a mistyped value; raise it for a long run",
    )


@dataclass(frozen=True)
class Sensor:
    """A named point (x right, y up, bearing centre at the origin); the nearest mesh node
    is recorded."""

    x: float = key("mm", doc="horizontal position")
    y: float = key("mm", doc="vertical position")


@dataclass(frozen=True)
class Output:
    """What a run writes (the whole section is optional)."""

    dir: str | None = key(default=None, doc="output folder; null is runs/<name>/")
    csv: bool = key(default=False, doc="also write histories.csv beside histories.parquet")
    frames: bool = key(default=True, doc="write field frames (frames/*.vtu and a .pvd)")


@dataclass(frozen=True)
class Case:
    """A validated case, every value in SI units."""

    name: str = key(doc="run name, folder-safe: results go to runs/<name>/ by default")
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


SECTIONS: dict[str, Section] = sections_of(Case)
"""Every section of the file, in the order of :class:`Case` (``name`` and ``sensors`` are
the two top-level keys that are not sections)."""

SENSOR_KEYS = section_keys(Sensor)
