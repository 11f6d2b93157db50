"""What the bearing mesher needs from a case, in SI units.

Angles in this spec follow the case file: measured from 12 o'clock, positive
counter-clockwise (``defect_angle``, ``first_roller_angle``). The mesh itself uses angles
from +x (see ``taichi_bearing.mesh.types``); :func:`polar_from_top` converts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from taichi_bearing.case import Bearing
from taichi_bearing.geometry.spall_profile import SpallProfile


def polar_from_top(angle_from_top: float) -> float:
    """Angle from +x (counter-clockwise) of a direction given from 12 o'clock."""
    return math.pi / 2 + angle_from_top


@dataclass(frozen=True)
class BearingMeshSpec:
    """Geometry and mesh controls of the bearing, SI units.

    Parameters
    ----------
    n_rollers : int
    roller_diameter, pitch_diameter : float
        m.
    clearance : float
        Radial internal clearance (total radial play), m; shared equally by both raceways
        as in ``taichi_bearing.case.Bearing``.
    roller_length : float
        Effective roller length, m: the plane-strain thickness (not used by the mesher).
    outer_ring_thickness, inner_ring_thickness : float
        m.
    adapter_width, adapter_height : float
        The adapter block on top of the outer ring: width, and height above the ring's top.
    defect_race : str
        ``"outer"``, ``"inner"`` or ``"none"``.
    defect_angle : float
        Centre of the spall, rad from 12 o'clock, counter-clockwise.
    defect_length, defect_depth : float
        Arc length along the raceway (between the sharp edges at the surface) and radial
        depth of the notch, m.
    defect_entry_slope, defect_exit_slope : float
        Angle of each wall from the raceway's tangent at its edge, rad (pi/2: radial, the
        rectangular notch); entry is the edge the rollers reach first.
    defect_edge_radius : float
        Radius rounding both edges at the raceway, m (0: sharp).
    surface_size, max_size, growth : float
        Element size along contact surfaces, largest element size, m, and the thickness
        ratio between neighbouring element layers.
    spall_size, spall_zone : float
        Element size along the raceway round the spall, and the arc length beyond each of
        its edges meshed at that size, m (see :mod:`taichi_bearing.mesh.zone`); a
        ``spall_size`` of 0, or not below ``surface_size``, leaves the raceway uniform.
    roller_surface_size : float
        Element size along the fine rollers' surfaces, m; 0 (or not below
        ``surface_size``) is ``surface_size``.
    fine_rollers : int
        How many rollers are fine, in the order they leave the spall
        (:meth:`passage_order`); 0 is all.
    elements_per_wavelength : float
        The resolution criterion the mesh is judged by (recorded in ``mesh.info``; see
        :mod:`taichi_bearing.mesh.quality`); it does not change the mesh.
    first_roller_angle : float
        Position of roller 0, rad from 12 o'clock; rollers are numbered counter-clockwise.
    cage_pocket_clearance : float
        Gap between a roller and its cage pocket, m (cage geometry only).
    sensors : dict of str to (float, float)
        Named points, m; the nearest node becomes the sensor node.
    """

    n_rollers: int = 20
    roller_diameter: float = 0.024
    pitch_diameter: float = 0.200
    clearance: float = 0.0
    roller_length: float = 0.050
    outer_ring_thickness: float = 0.014
    inner_ring_thickness: float = 0.012
    adapter_width: float = 0.120
    adapter_height: float = 0.030
    defect_race: str = "outer"
    defect_angle: float = 0.0
    defect_length: float = 0.010
    defect_depth: float = 0.0002
    defect_entry_slope: float = 0.5 * math.pi
    defect_exit_slope: float = 0.5 * math.pi
    defect_edge_radius: float = 0.0
    surface_size: float = 0.0005
    max_size: float = 0.003
    growth: float = 1.3
    spall_size: float = 0.0
    spall_zone: float = 0.002
    roller_surface_size: float = 0.0
    fine_rollers: int = 0
    elements_per_wavelength: float = 10.0
    first_roller_angle: float = math.radians(-5.0)
    cage_pocket_clearance: float = 0.0005
    sensors: dict[str, tuple[float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        positive = (
            "roller_diameter",
            "pitch_diameter",
            "outer_ring_thickness",
            "inner_ring_thickness",
            "surface_size",
            "max_size",
        )
        for name in positive:
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")
        if self.n_rollers < 2:
            raise ValueError(f"n_rollers must be at least 2, got {self.n_rollers}")
        if self.growth < 1:
            raise ValueError(f"growth must be >= 1, got {self.growth}")
        if self.max_size < self.surface_size:
            raise ValueError("max_size must not be smaller than surface_size")
        for name in ("spall_size", "spall_zone", "roller_surface_size", "fine_rollers"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if self.refined_spall and not self.has_defect:
            raise ValueError("spall_size needs a spall to refine round")
        if self.clearance < 0:
            raise ValueError(f"clearance must be >= 0, got {self.clearance}")
        if self.inner_ring_bore_radius <= 0:
            raise ValueError("inner_ring_thickness leaves no bore")
        if self.defect_race not in ("outer", "inner", "none"):
            raise ValueError(f"defect_race must be outer, inner or none, not {self.defect_race!r}")
        if self.has_defect:
            race_r = (
                self.outer_raceway_radius
                if self.defect_race == "outer"
                else (self.inner_raceway_radius)
            )
            if not 0 < self.defect_length < math.pi * race_r:
                raise ValueError("defect_length must be positive and shorter than half a raceway")
            ring = (
                self.outer_ring_thickness
                if self.defect_race == "outer"
                else self.inner_ring_thickness
            )
            if not self.defect_depth < 0.5 * ring:
                raise ValueError("defect_depth must be less than half the ring thickness")
            self.spall_profile()  # raises ValueError when the slopes or radius do not fit
        if self.adapter_width > 0:
            if not self.adapter_width < 2 * self.outer_ring_outer_radius:
                raise ValueError("adapter_width must be less than the outer ring's diameter")
            if not self.adapter_height > 0:
                raise ValueError("adapter_height must be positive when there is an adapter")
        gap = math.pi * self.pitch_diameter / self.n_rollers
        if self.roller_diameter >= gap:
            raise ValueError(
                f"{self.n_rollers} rollers of {self.roller_diameter} m overlap on the pitch circle"
            )

    @property
    def has_defect(self) -> bool:
        return self.defect_race != "none" and self.defect_length > 0 and self.defect_depth > 0

    @property
    def refined_spall(self) -> bool:
        """Whether the raceway round the spall is meshed finer than ``surface_size``."""
        return 0.0 < self.spall_size < self.surface_size

    def roller_sizes(self) -> list[float]:
        """Element size along each roller's surface, m, roller 0 first."""
        fine = self.roller_surface_size
        if not 0.0 < fine < self.surface_size:
            return [self.surface_size] * self.n_rollers
        count = self.fine_rollers if 0 < self.fine_rollers < self.n_rollers else self.n_rollers
        chosen = set(self.passage_order()[:count])
        return [fine if j in chosen else self.surface_size for j in range(self.n_rollers)]

    def passage_order(self) -> list[int]:
        """The rollers in the order they leave the spall (roller 0 first when it starts
        before the spall, as in the default case). On the outer raceway the rollers move
        counter-clockwise and leave over the edge at the larger angle; on the inner one,
        in the inner ring's frame, clockwise over the edge at the smaller angle. Without
        a defect, the order they reach 12 o'clock."""
        angles = np.asarray(self.roller_angles())
        profile = self.spall_profile()
        if profile is None:
            ahead = np.mod(polar_from_top(0.0) - angles, 2 * math.pi)
        elif self.defect_race == "outer":
            ahead = np.mod(profile.end - angles, 2 * math.pi)
        else:
            ahead = np.mod(angles - profile.start, 2 * math.pi)
        return [int(j) for j in np.argsort(ahead, kind="stable")]

    @property
    def bearing(self) -> Bearing:
        """The same geometry as the case's :class:`~taichi_bearing.case.Bearing`, whose
        radii (raceways, ring faces) the mesh uses so the two can never disagree."""
        return Bearing(
            n_rollers=self.n_rollers,
            roller_diameter=self.roller_diameter,
            pitch_diameter=self.pitch_diameter,
            roller_length=self.roller_length,
            radial_clearance=self.clearance,
            outer_ring_thickness=self.outer_ring_thickness,
            inner_ring_thickness=self.inner_ring_thickness,
            adapter_width=self.adapter_width,
            adapter_height=self.adapter_height,
        )

    @property
    def roller_radius(self) -> float:
        return self.bearing.roller_radius

    @property
    def pitch_radius(self) -> float:
        return self.bearing.pitch_radius

    @property
    def outer_raceway_radius(self) -> float:
        return self.bearing.outer_raceway_radius

    @property
    def inner_raceway_radius(self) -> float:
        return self.bearing.inner_raceway_radius

    @property
    def outer_ring_outer_radius(self) -> float:
        return self.bearing.outer_ring_outer_radius

    @property
    def inner_ring_bore_radius(self) -> float:
        return self.bearing.inner_ring_bore_radius

    @property
    def adapter_top(self) -> float:
        """Height of the adapter's top face above the bearing centre, m."""
        return self.outer_ring_outer_radius + self.adapter_height

    def spall_profile(self) -> SpallProfile | None:
        """The spall's cross-section (angles from +x), None without a defect. On the
        outer raceway the rollers move counter-clockwise, so they meet the edge at the
        smaller angle first; on the inner raceway (in the inner ring's frame, which turns
        faster than the cage) the one at the larger angle."""
        if not self.has_defect:
            return None
        outer = self.defect_race == "outer"
        radius = self.outer_raceway_radius if outer else self.inner_raceway_radius
        span = self.defect_length / radius
        start = polar_from_top(self.defect_angle) - 0.5 * span
        entry, exit_ = self.defect_entry_slope, self.defect_exit_slope
        return SpallProfile(
            radius,
            start,
            start + span,
            self.defect_depth,
            outward=outer,
            start_slope=entry if outer else exit_,
            end_slope=exit_ if outer else entry,
            edge_radius=self.defect_edge_radius,
            side_names=("entry", "exit") if outer else ("exit", "entry"),
        )

    def roller_angles(self) -> list[float]:
        """Angle of every roller centre from +x, rad, roller 0 first, counter-clockwise."""
        step = 2 * math.pi / self.n_rollers
        return [polar_from_top(self.first_roller_angle + j * step) for j in range(self.n_rollers)]


def spec_from_case(case) -> BearingMeshSpec:
    """The mesh spec of a loaded case (``taichi_bearing.case.Case``, SI units)."""
    b, d, m = case.bearing, case.defect, case.mesh
    return BearingMeshSpec(
        n_rollers=int(b.n_rollers),
        roller_diameter=b.roller_diameter,
        pitch_diameter=b.pitch_diameter,
        clearance=b.radial_clearance,
        roller_length=b.roller_length,
        outer_ring_thickness=b.outer_ring_thickness,
        inner_ring_thickness=b.inner_ring_thickness,
        adapter_width=b.adapter_width,
        adapter_height=b.adapter_height,
        defect_race=d.race,
        defect_angle=d.angle,
        defect_length=d.length,
        defect_depth=d.depth,
        defect_entry_slope=d.entry_slope,
        defect_exit_slope=d.exit_slope,
        defect_edge_radius=d.edge_radius,
        surface_size=m.surface_size,
        max_size=m.max_size,
        growth=m.growth,
        spall_size=m.spall_size,
        spall_zone=m.spall_zone,
        roller_surface_size=m.roller_surface_size,
        fine_rollers=int(m.fine_rollers),
        elements_per_wavelength=m.elements_per_wavelength,
        first_roller_angle=case.run.first_roller_angle,
        cage_pocket_clearance=case.cage.pocket_clearance,
        sensors={name: (s.x, s.y) for name, s in case.sensors.items()},
    )
