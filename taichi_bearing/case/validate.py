"""Checks across keys: values each in range must also make a bearing, and a run that ends.

Run before meshing by :func:`~taichi_bearing.case.load.parse_case`: geometry that cannot be
assembled, a defect that is not a line spall, and numbers that would make the run absurd
(a time step far below any real one, more steps than ``run.max_steps``, a sensor far from
the bearing) are refused with a :class:`CaseError` naming the key to change. So are
operating points no bearing has: a surface speed near the material's wave speeds
(:data:`MAX_SURFACE_SPEED_RATIO`), a contact pressure no elastic solid carries
(:data:`MAX_PRESSURE_RATIO`); an overload beyond the static capacity
(:data:`STATIC_CAPACITY_PRESSURE`) and a spall far deeper than a roller can drop into it
(:data:`DEPTH_REACH_FACTOR`) are warned.
"""

from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING

from taichi_bearing.case.operating import (
    MAX_PRESSURE_RATIO,
    MAX_SURFACE_SPEED_RATIO,
    STATIC_CAPACITY_PRESSURE,
    ContactPressureWarning,
    check_operating,
    peak_contact_pressure,
)
from taichi_bearing.case.sections import Bearing, Case
from taichi_bearing.errors import CaseError, CaseWarning

if TYPE_CHECKING:
    from taichi_bearing.geometry.spall_profile import SpallProfile

__all__ = [
    "DEPTH_REACH_FACTOR",
    "MAX_PRESSURE_RATIO",
    "MAX_SURFACE_SPEED_RATIO",
    "MAX_WAVE_SPEED",
    "SENSOR_REACH",
    "STATIC_CAPACITY_PRESSURE",
    "STEP_FLOOR",
    "ContactPressureWarning",
    "ExtendedDefectWarning",
    "SpallReachWarning",
    "check_case",
    "peak_contact_pressure",
    "spall_reach",
    "stable_step_estimate",
]

MM = 1e3  # m -> mm, for messages

STEP_FLOOR = 1e-10
"""Shortest time step a case may need, s: a 0.5 mm steel element steps at ~6e-8 s; a step
below 1e-10 s means a mistyped modulus, density or element size (and a run that never
ends)."""

MAX_WAVE_SPEED = 2.5e4
"""Fastest dilatational wave speed of any solid, m/s, with margin (diamond: ~18 km/s)."""

SENSOR_REACH = 3.0
"""How far, in largest elements (``mesh.max_size_mm``), a sensor may lie outside the
bearing's material before it is refused: the nearest node would be a different point."""


DEPTH_REACH_FACTOR = 10.0
"""How many times deeper than a rigid roller can drop into it (:func:`spall_reach`) a
spall may be before it is warned (:class:`SpallReachWarning`). The roller never touches a
floor deeper than its reach: the contact is that of any spall at least as deep, and the
depth only weakens the ring below it. Real short spalls are often a few times deeper than
their reach; ten times means that nine tenths of the depth are out of the roller's way,
which more often is a unit slip (um for mm) or a spall meant to be longer."""


class ExtendedDefectWarning(CaseWarning):
    """The defect is longer than the spacing between rollers (an extended defect)."""


class SpallReachWarning(CaseWarning):
    """The spall is far deeper than a roller can drop into it
    (:data:`DEPTH_REACH_FACTOR`)."""


def check_case(case: Case, source: str | None = None) -> None:
    """Refuse a case whose keys are each valid but do not fit together.

    Parameters
    ----------
    case : Case
        The loaded case.
    source : str, optional
        Where it came from, for the messages.

    Raises
    ------
    CaseError
        Naming the key to change and why.

    Warns
    -----
    ExtendedDefectWarning
        When the defect is longer than the spacing between rollers.
    ContactPressureWarning
        When the load's contact pressure is beyond the static capacity.
    SpallReachWarning
        When the spall is far deeper than a roller can drop into it.
    CaseWarning
        When the sample rate lowers the time step.
    """
    _check_geometry(case, source)
    check_operating(case, source)
    _check_defect(case, source)
    _check_refinement(case, source)
    _check_time_step(case, source)
    _check_contact(case, source)
    _check_sensors(case, source)


# Palmgren's line-contact exponent, Q ~ delta^(10/9), as in the quasi-static model
# (taichi_bearing.analytic.bearing.LINE_CONTACT_EXPONENT: a later stage, not importable here)


def _check_contact(case: Case, src: str | None) -> None:
    # The element estimate ignores the contact's springs; the pressure law's are stiffer
    # than the elements on any mesh coarser than the Hertz width, so only the global
    # estimate (which counts them) keeps such a run stable.
    if case.contact.penalty_method == "pressure" and case.run.time_step != "global":
        raise CaseError(
            "run.time_step",
            "contact.penalty_method: pressure needs the global step estimate (global): the "
            f"{case.run.time_step!r} estimate ignores the contact's springs, which this law "
            "makes stiffer than the elements, and the run would go unstable",
            src,
        )
    # The masses lift the step only where the estimate counts the contact's springs, and
    # the soft penalty's stiffness follows the masses and the step (another static state).
    if case.preload.mass_scaling and case.run.time_step != "global":
        raise CaseError(
            "preload.mass_scaling",
            "preload.mass_scaling needs run.time_step: global (the "
            f"{case.run.time_step!r} estimate ignores the contact's springs: nothing to lift)",
            src,
        )
    if case.preload.mass_scaling and case.contact.penalty_method == "soft":
        raise CaseError(
            "preload.mass_scaling",
            "preload.mass_scaling does not go with contact.penalty_method: soft (its "
            "stiffness follows the masses and the step, so the static state would change)",
            src,
        )


def _check_geometry(case: Case, src: str | None) -> None:
    b = case.bearing
    if b.roller_diameter >= b.pitch_diameter:
        raise CaseError(
            "bearing.roller_diameter_mm",
            f"roller ({b.roller_diameter * MM:g} mm) must be smaller than the pitch diameter "
            f"({b.pitch_diameter * MM:g} mm)",
            src,
        )
    chord = b.pitch_diameter * math.sin(math.pi / b.n_rollers)
    if chord <= b.roller_diameter:
        raise CaseError(
            "bearing.n_rollers",
            f"{b.n_rollers} rollers of {b.roller_diameter * MM:g} mm overlap on the "
            f"{b.pitch_diameter * MM:g} mm pitch circle (centre spacing {chord * MM:.3g} mm); "
            f"at most {_max_rollers(b)} fit",
            src,
        )
    # A negative clearance is an interference fit (preload); beyond 1 % of the roller
    # diameter the rollers cannot be assembled elastically between the raceways.
    if b.radial_clearance < -0.01 * b.roller_diameter:
        raise CaseError(
            "bearing.radial_clearance_mm",
            f"interference {-b.radial_clearance * MM:g} mm: the rollers do not fit between "
            f"the raceways (at most {0.01 * b.roller_diameter * MM:g} mm of preload)",
            src,
        )
    if b.radial_clearance > 0.1 * b.roller_diameter:
        raise CaseError(
            "bearing.radial_clearance_mm",
            f"clearance {b.radial_clearance * MM:g} mm is larger than 10 % of the roller "
            "diameter: the rollers would not be guided by the raceways",
            src,
        )
    if b.inner_ring_bore_radius <= 0.0:
        raise CaseError(
            "bearing.inner_ring_thickness_mm",
            f"the inner ring ({b.inner_ring_thickness * MM:g} mm) is thicker than the inner "
            f"raceway radius ({b.inner_raceway_radius * MM:g} mm): no room for a bore",
            src,
        )
    if b.adapter_width > 2.0 * b.outer_ring_outer_radius:
        raise CaseError(
            "bearing.adapter_width_mm",
            f"adapter ({b.adapter_width * MM:g} mm) is wider than the outer ring "
            f"({2 * b.outer_ring_outer_radius * MM:g} mm)",
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
            f"surface size ({case.mesh.surface_size * MM:g} mm) exceeds mesh.max_size_mm "
            f"({case.mesh.max_size * MM:g} mm)",
            src,
        )
    if case.mesh.surface_size > 0.25 * b.roller_diameter:
        raise CaseError(
            "mesh.surface_size_mm",
            f"{case.mesh.surface_size * MM:g} mm is too coarse for a "
            f"{b.roller_diameter * MM:g} mm roller (at most a quarter of its diameter)",
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


def _max_rollers(b: Bearing) -> int:
    # largest Z with D sin(pi/Z) > d
    return int(
        math.floor(math.pi / math.asin(min(1.0, b.roller_diameter / b.pitch_diameter)) - 1e-12)
    )


def _check_defect(case: Case, src: str | None) -> None:
    b, d = case.bearing, case.defect
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
            f"defect ({d.depth * MM:g} mm) must be shallower than half the {d.race} ring "
            f"({ring * MM:g} mm thick)",
            src,
        )
    circumference = 2.0 * math.pi * raceway
    if d.length >= 0.5 * circumference:
        raise CaseError(
            "defect.length_mm",
            f"defect ({d.length * MM:g} mm) is longer than half the {d.race} raceway "
            f"({0.5 * circumference * MM:.4g} mm)",
            src,
        )
    profile = _check_profile(case, raceway, src)
    _check_reach(case, profile, src)
    spacing = b.roller_spacing * raceway
    if d.length >= spacing:
        warnings.warn(
            ExtendedDefectWarning(
                "defect.length_mm",
                f"{d.length * MM:g} mm is longer than the roller spacing on the {d.race} "
                f"raceway ({spacing * MM:.4g} mm): an extended defect, two rollers can be "
                "inside it at once. The run follows it: each roller's entry and exit are "
                "found from its own force, the quasi-static model unloads every roller over "
                "it and the others share the load (the report's load-sharing table); the "
                "defect_size check is not applied (the acceleration's entry and exit events "
                "then belong to different rollers)",
                src,
            ),
            stacklevel=4,
        )


def _check_profile(case: Case, raceway: float, src: str | None) -> SpallProfile:
    """The spall's profile: sloped walls must leave a floor, and an edge radius must fit
    its walls."""
    from taichi_bearing.geometry.spall_profile import SpallProfile

    d = case.defect
    outer = d.race == "outer"
    slopes = {"entry_slope_deg": d.entry_slope, "exit_slope_deg": d.exit_slope}
    start, end = (d.entry_slope, d.exit_slope) if outer else (d.exit_slope, d.entry_slope)
    names = ("entry", "exit") if outer else ("exit", "entry")
    span = d.length / raceway
    try:
        SpallProfile(raceway, 0.0, span, d.depth, outer, start, end, 0.0, names)
    except ValueError as exc:
        shallow = min(slopes, key=slopes.get)
        raise CaseError(f"defect.{shallow}", f"{exc}: steepen a wall or lengthen the spall",
                        src) from None  # fmt: skip
    try:
        return SpallProfile(raceway, 0.0, span, d.depth, outer, start, end, d.edge_radius, names)
    except ValueError as exc:
        raise CaseError("defect.edge_radius_mm", str(exc), src) from None


def spall_reach(profile: SpallProfile, roller_radius: float) -> float:
    r"""How far a rigid roller's centre drops into a spall, m: the most over its path.

    About :math:`r - \sqrt{r^2 - (L / 2)^2}` for a short sharp-edged spall (the roller bridging
    both edges); found along the roller's path by
    :func:`~taichi_bearing.geometry.roller_path.centre_drop`, which takes the raceway's
    curvature, the walls' slopes and the edges' radius into account. The profile's depth
    where the roller reaches the floor.

    Parameters
    ----------
    profile : SpallProfile
        The spall's cross-section, on an outer or an inner raceway.
    roller_radius : float
        ``r``, m.

    Returns
    -------
    float
        The largest drop of the roller's centre below the healthy raceway, m.
    """
    import numpy as np

    from taichi_bearing.geometry.roller_path import centre_drop

    phi = np.linspace(profile.start, profile.end, 401)
    return float(np.max(centre_drop(phi, profile, roller_radius)[0]))


def _check_reach(case: Case, profile: SpallProfile, src: str | None) -> None:
    # the half-ring limit (_check_defect) already refuses a spall through the ring; one
    # the roller cannot reach the floor of is a real spall, warned when far deeper
    d = case.defect
    reach = spall_reach(profile, case.bearing.roller_radius)
    if d.depth > DEPTH_REACH_FACTOR * reach:
        ratio = d.depth / reach if reach > 0.0 else math.inf
        warnings.warn(
            SpallReachWarning(
                "defect.depth_mm",
                f"{d.depth * MM:g} mm is {ratio:.3g} x what a rigid roller drops into a "
                f"{d.length * MM:g} mm spall ({reach * MM:.3g} mm): the floor is never "
                "touched and the depth below that only weakens the ring; lengthen the spall "
                "if the roller should reach the floor",
                src,
            ),
            stacklevel=5,
        )


MAX_REFINEMENT = 16.0
"""How many times finer than ``mesh.surface_size_mm`` the zone round the spall may be: the
mesher builds a whole ring at the fine size before it keeps the zone."""


def _check_refinement(case: Case, src: str | None) -> None:
    """The finer sizes round the spall and on the rollers refine, never coarsen; the
    zone needs a spall and must leave most of the raceway to the surface size."""
    m, b, d = case.mesh, case.bearing, case.defect
    for name, value in (("spall_size_mm", m.spall_size), ("roller_surface_size_mm",
                        m.roller_surface_size)):  # fmt: skip
        if value > m.surface_size:
            raise CaseError(
                f"mesh.{name}",
                f"{value * MM:g} mm is coarser than mesh.surface_size_mm "
                f"({m.surface_size * MM:g} mm): it is for finer elements (0 is the surface "
                "size)",
                src,
            )
    if m.fine_rollers > b.n_rollers:
        raise CaseError(
            "mesh.fine_rollers",
            f"{m.fine_rollers} is more than the bearing's {b.n_rollers} rollers (0 is all)",
            src,
        )
    if not 0.0 < m.spall_size < m.surface_size:
        return
    if not d.present:
        raise CaseError(
            "mesh.spall_size_mm", "refines the raceway round a spall, and there is none", src
        )
    if m.spall_size * MAX_REFINEMENT < m.surface_size * (1.0 - 1e-12):
        raise CaseError(
            "mesh.spall_size_mm",
            f"{m.spall_size * MM:g} mm is finer than 1/{MAX_REFINEMENT:g} of "
            f"mesh.surface_size_mm ({m.surface_size * MM:g} mm); refine surface_size_mm too",
            src,
        )
    raceway = b.outer_raceway_radius if d.race == "outer" else b.inner_raceway_radius
    if d.length + 2.0 * m.spall_zone >= math.pi * raceway:
        raise CaseError(
            "mesh.spall_zone_mm",
            f"the spall ({d.length * MM:g} mm) with {m.spall_zone * MM:g} mm either side "
            f"covers half the {d.race} raceway ({math.pi * raceway * MM:.4g} mm) or more",
            src,
        )


def _smallest_size(case: Case) -> tuple[float, str]:
    """The smallest element size along a contact surface, and its key."""
    m = case.mesh
    sizes = [(m.surface_size, "mesh.surface_size_mm")]
    if case.defect.present and m.spall_size > 0.0:
        sizes.append((m.spall_size, "mesh.spall_size_mm"))
    if m.roller_surface_size > 0.0:
        sizes.append((m.roller_surface_size, "mesh.roller_surface_size_mm"))
    return min(sizes)


def stable_step_estimate(case: Case) -> float:
    r"""The explicit time step of a case before meshing, s.

    The critical step :math:`2 / \omega_e` of a square element of the smallest surface size
    (``mesh.surface_size``, or ``spall_size`` or ``roller_surface_size`` when finer):
    :math:`L / (\sqrt{2} c)` with :math:`c` the plane-strain dilatational wave speed
    (:func:`taichi_bearing.solver.element.element_max_frequencies`). The solver's step
    is within a few tens of per cent of it (default case: 5.9e-8 s estimated, 5.4e-8 s
    used: the spall's thinner elements and damping lower it, the global estimate and mass
    scaling raise it), which is all the checks here need.
    """
    return _smallest_size(case)[0] / (math.sqrt(2.0) * case.material.wave_speed)


def _check_time_step(case: Case, src: str | None) -> None:
    m, run = case.material, case.run
    dt = stable_step_estimate(case)
    if dt < STEP_FLOOR:
        c = m.wave_speed
        if c > MAX_WAVE_SPEED:
            # E / rho is beyond any solid: name the one outside a solid's range (no
            # engineering solid is stiffer than diamond, ~1.2e3 GPa)
            key = (
                "material.youngs_modulus_GPa"
                if m.youngs_modulus > 1.2e12
                else "material.density_kg_m3"
            )
            why = (
                f"the dilatational wave speed {c:.3g} m/s (E {m.youngs_modulus / 1e9:.3g} GPa, "
                f"rho {m.density:.4g} kg/m^3) is faster than in any solid"
            )
        else:
            size, key = _smallest_size(case)
            why = f"{size * MM:.3g} mm elements are too small"
        raise CaseError(
            key,
            f"the time step would be about {dt:.2g} s, below the {STEP_FLOOR:g} s floor: {why}",
            src,
        )
    # the solver fits a whole number of steps in each sample interval
    interval = 1.0 / run.sample_rate
    per_sample = max(1, math.ceil(interval / dt * (1 - 1e-12)))
    step = interval / per_sample
    if step < STEP_FLOOR:
        raise CaseError(
            "run.sample_rate_Hz",
            f"a sample every {interval:.3g} s needs a time step below the {STEP_FLOOR:g} s "
            f"floor (the stable step is about {dt:.2g} s)",
            src,
        )
    # within a few steps a sample, rounding to whole steps costs up to half the step
    # (more than the estimate can tell apart)
    few = interval < 3.0 * dt
    n_steps = max(1, round(run.duration * run.sample_rate)) * per_sample
    if n_steps > run.max_steps:
        raise CaseError(
            "run.sample_rate_Hz" if few else "run.duration_ms",
            f"about {n_steps:.3g} time steps ({run.duration * 1e3:g} ms at about {step:.2g} s "
            f"a step), more than run.max_steps ({run.max_steps:g}); raise run.max_steps to "
            "run it anyway",
            src,
        )
    if few:
        warnings.warn(
            CaseWarning(
                "run.sample_rate_Hz",
                f"a sample every {interval:.3g} s is less than three stable time steps (about "
                f"{dt:.2g} s each, estimated): each sample holds a whole number of steps, so "
                f"the step will be lowered to fit (about {step:.2g} s, x{step / dt:.2f}, by "
                f"this estimate), about {n_steps:.3g} steps",
                src,
            ),
            stacklevel=4,
        )


def _check_sensors(case: Case, src: str | None) -> None:
    b = case.bearing
    reach = SENSOR_REACH * case.mesh.max_size
    top = b.outer_ring_outer_radius + b.adapter_height
    half_width = 0.5 * b.adapter_width
    for name, s in case.sensors.items():
        r = math.hypot(s.x, s.y)
        if r < b.inner_ring_bore_radius:
            off = b.inner_ring_bore_radius - r  # in the shaft, which is not meshed
            where = f"inside the inner ring's bore (radius {b.inner_ring_bore_radius * MM:g} mm)"
        else:
            # outside both the outer ring and the adapter block on top of it
            dx = max(abs(s.x) - half_width, 0.0)
            dy = max(s.y - top, -s.y, 0.0)
            off = min(max(r - b.outer_ring_outer_radius, 0.0), math.hypot(dx, dy))
            where = (
                f"outside the outer ring (radius {b.outer_ring_outer_radius * MM:g} mm) and "
                f"the adapter (top at {top * MM:g} mm)"
            )
        if off > reach:
            coord = "x_mm" if abs(s.x) > abs(s.y) else "y_mm"
            raise CaseError(
                f"sensors.{name}.{coord}",
                f"the point ({s.x * MM:g}, {s.y * MM:g}) mm is {off * MM:.4g} mm {where}: "
                f"no mesh node within {SENSOR_REACH:g} elements ({reach * MM:g} mm) of it",
                src,
            )
