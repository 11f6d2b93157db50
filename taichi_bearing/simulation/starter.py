"""The starter: a case and its mesh turned into the plain set-up data of the model.

Like an explicit code's starter/engine split, nothing here steps in time or touches Taichi
fields: :func:`build_setup` returns a :class:`Setup` of materials, thickness, constraints,
loads, initial rigid velocities, contact pairs and parameters, damping and the rates of
ideal rolling. The engine (:mod:`taichi_bearing.simulation.simulate`) builds the model from it.

Conventions: bearing centre at the origin, +y up; the shaft turns counter-clockwise;
angles in the case are from 12 o'clock, in the mesh from +x.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from taichi_bearing.analytic.bearing import cage_speed
from taichi_bearing.analytic.penalty import pressure_penalty
from taichi_bearing.case import Case
from taichi_bearing.case.material import Material
from taichi_bearing.mesh.supports import outer_surface_nodes, support_plate_nodes
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.solver.contact_setup import ContactPair, ContactParameters
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.loads import (
    NodalForces,
    PrescribedRotation,
    RigidPlate,
    RigidVelocity,
    line_load,
    uniform_load,
)

__all__ = [
    "RACES",
    "Setup",
    "align_rollers",
    "build_setup",
    "outer_surface_nodes",
    "roller_names",
    "support_plate_nodes",
    "rolling_rates",
]

RACES = ("outer", "inner")


@dataclass
class RollingRates:
    """Angular speeds of ideal rolling, rad/s, counter-clockwise positive.

    ``shaft``: inner ring; ``cage``: roller centres about the bearing centre; ``roller``:
    each roller's absolute spin (negative: it turns clockwise while the cage turns
    counter-clockwise); ``roller_relative``: spin relative to the cage (2 pi BSF).
    """

    shaft: float
    cage: float
    roller: float

    @property
    def roller_relative(self) -> float:
        return self.roller - self.cage


@dataclass
class Setup:
    """Everything the model needs, as plain data (SI units)."""

    material: Material
    thickness: float
    constraints: list
    loads: list[NodalForces]
    initial_velocities: list[RigidVelocity]
    damping: StiffnessDamping | None
    contact_params: ContactParameters
    contact_pairs: list[ContactPair]
    # pair_table[j, r]: index in contact_pairs of roller j on race RACES[r]
    pair_table: np.ndarray
    rates: RollingRates
    n_rollers: int
    notes: dict[str, str] = field(default_factory=dict)


def roller_names(n_rollers: int) -> list[str]:
    """Part and surface names of the rollers, ``roller0`` ... (as the mesher names them)."""
    return [f"roller{j}" for j in range(n_rollers)]


def rolling_rates(case: Case) -> RollingRates:
    r"""Shaft, cage and roller spin speeds of ideal rolling (outer ring at rest).

    A roller's centre moves at :math:`\omega_c R_p`; for its outer contact point to be at
    rest its spin :math:`\omega_r` satisfies :math:`\omega_c R_p + \omega_r r = 0`.
    """
    b = case.bearing
    shaft = case.operating.speed
    cage = cage_speed(b, shaft)
    return RollingRates(shaft, cage, -cage * b.pitch_radius / b.roller_radius)


def align_rollers(mesh: Mesh, n_rollers: int) -> Mesh:
    r"""The mesh with every roller turned about its centre so that one of its surface
    nodes points straight at the outer raceway (radially outwards).

    A roller's surface is a polygon whose radius along a given direction varies between
    :math:`r \cos(\pi / N)` (mid-facet) and :math:`r` (at a node): 2.6 um for 150 facets on a 12 mm
    radius, comparable with the ~7 um Hertz deflection of a loaded contact. Meshed alike
    in global axes, rollers at different angles would meet the raceways with different
    effective radii and share the load unevenly. Turned alike relative to their radial
    line (an even facet count also puts a node towards the inner raceway), they start
    identical, as the analytical model assumes. Rigid turns: element quality unchanged.
    """
    nodes = np.array(mesh.nodes, dtype=float)
    centres = np.asarray(mesh.info["roller_centres"], dtype=float)
    for j in range(n_rollers):
        ids = np.unique(mesh.elements[mesh.element_part == mesh.part_id(f"roller{j}")])
        surf = np.unique(mesh.surfaces[f"roller{j}"])
        c = centres[j]
        radial = math.atan2(c[1], c[0])
        d = nodes[surf] - c
        off = (np.arctan2(d[:, 1], d[:, 0]) - radial + math.pi) % (2 * math.pi) - math.pi
        turn = -off[np.argmin(np.abs(off))]
        cs, sn = math.cos(turn), math.sin(turn)
        r = nodes[ids] - c
        nodes[ids] = c + np.stack([cs * r[:, 0] - sn * r[:, 1], sn * r[:, 0] + cs * r[:, 1]], 1)
    return dataclasses.replace(mesh, nodes=nodes)


def build_setup(case: Case, mesh: Mesh) -> Setup:
    """The model's set-up data for ``case`` meshed as ``mesh``.

    Parameters
    ----------
    case : Case
    mesh : Mesh
        From :func:`taichi_bearing.mesh.build_bearing_mesh` of the same case: parts
        ``outer_ring``, ``inner_ring``, ``roller<j>``; node sets ``inner_bore`` and
        ``adapter_top``; surfaces ``outer_raceway``, ``inner_raceway``, ``roller<j>``;
        ``info["roller_centres"]``.

    Returns
    -------
    Setup
    """
    mat = case.material
    n = case.bearing.n_rollers
    rates = rolling_rates(case)
    bore = mesh.node_sets["inner_bore"]

    held = support_plate_nodes(case, mesh)
    plate = RigidPlate(held, (0.0, 1.0))
    if case.bearing.outer_support == "housing":
        load = uniform_load(held, (0.0, -case.operating.load))
        support_note = "rigid housing over the outer ring's outside: one vertical motion"
    else:
        load = line_load(mesh.nodes, held, (0.0, -case.operating.load))
        support_note = "rigid loading plate: one shared vertical motion, x held"
    # The bore turns rigidly at the shaft speed from t = 0 (the bodies start with the
    # velocities of ideal rolling, so no ramp); during the preload it is held at angle 0.
    shaft = PrescribedRotation(bore, (0.0, 0.0), rates.shaft, omega_start=rates.shaft)

    centres = np.asarray(mesh.info["roller_centres"], dtype=float)
    velocities = [RigidVelocity("inner_ring", omega=rates.shaft)]
    for j, name in enumerate(roller_names(n)):
        cx, cy = centres[j]
        v_centre = (-rates.cage * cy, rates.cage * cx)  # omega_c x c
        velocities.append(RigidVelocity(name, rates.roller, (cx, cy), v_centre))

    d = case.damping
    damping = StiffnessDamping(d.ratio, d.frequency, d.max_element_ratio) if d.ratio > 0 else None
    pairs = []
    table = np.zeros((n, len(RACES)), dtype=np.int64)
    for j, name in enumerate(roller_names(n)):
        for r, race in enumerate(RACES):
            table[j, r] = len(pairs)
            pairs.append(ContactPair(f"{name}_{race}", name, f"{race}_raceway", two_pass=True))
    return Setup(
        material=mat,
        thickness=case.bearing.roller_length,
        constraints=[plate, shaft],
        loads=[load],
        initial_velocities=velocities,
        damping=damping,
        contact_params=ContactParameters.from_case(
            case.contact,
            pressure_penalty(case) if case.contact.penalty_method == "pressure" else 0.0,
        ),
        contact_pairs=pairs,
        pair_table=table,
        rates=rates,
        n_rollers=n,
        notes={
            "outer_support": f"{case.bearing.outer_support}: {support_note}",
            "inner_bore": "rigid rotation about the centre at the shaft speed",
            "damping": (
                f"stiffness-proportional {d.ratio:g} at {d.frequency:g} Hz, "
                f"element ratio capped at {d.max_element_ratio:g}"
            ),
        },
    )


def roller_kinematics_matrix(mesh: Mesh, n_rollers: int) -> tuple[np.ndarray, np.ndarray]:
    """Node indices of every roller and the roller each belongs to (for centroid and
    spin read-outs)."""
    ids, owner = [], []
    for j in range(n_rollers):
        nodes = np.unique(mesh.elements[mesh.element_part == mesh.part_id(f"roller{j}")])
        ids.append(nodes)
        owner.append(np.full(len(nodes), j))
    return np.concatenate(ids), np.concatenate(owner)


def polar_angle_from_top(x: float, y: float) -> float:
    """Angle of a point from 12 o'clock, counter-clockwise, rad."""
    return math.atan2(-x, y)
