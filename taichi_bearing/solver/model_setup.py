"""The plain-numpy set-up of a :class:`~taichi_bearing.solver.model.Model` (no Taichi):
each element's geometry, material constants, hourglass stiffness, tangent and own
frequency; the lumped masses with selective mass scaling; the damping coefficients; the
constraint, load and initial-velocity tables. The model uploads them into its fields."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.element import (
    ElementGeometry,
    element_geometry,
    element_max_frequencies,
    element_stiffness,
    hourglass_stiffness,
    materials_per_element,
    selective_mass_scale,
)
from taichi_bearing.solver.laws.material import ElementLaw
from taichi_bearing.solver.loads import (
    FixedNodes,
    HeldDirection,
    NodalForces,
    PrescribedRotation,
    RigidPlate,
)
from taichi_bearing.solver.step_phases import FIXED, HELD, PLATE, ROTATED

__all__ = [
    "ElementData",
    "constraint_tables",
    "element_data",
    "load_tables",
    "rigid_velocity_field",
]


@dataclass(frozen=True)
class ElementData:
    """What the model's elements and nodes start from (per element unless said)."""

    elements: np.ndarray  # (n, 4) node indices
    geometry: ElementGeometry
    lam: np.ndarray  # Lame constants, Pa
    mu: np.ndarray
    khg: np.ndarray  # hourglass stiffness (times thickness)
    stiffness: np.ndarray  # small-strain stiffness matrices (n, 8, 8)
    omega_e: np.ndarray  # own highest frequency, after mass scaling, rad/s
    beta_e: np.ndarray  # stiffness-damping coefficient, s
    mass: np.ndarray  # lumped nodal masses (n_nodes,), kg
    n_mass_scaled: int
    part_mass: np.ndarray  # each part's mass before scaling, kg
    added_mass: np.ndarray  # the mass scaling added to each part, kg
    adjacency: tuple[np.ndarray, np.ndarray]  # CSR lists of the force slots on each node


def _adjacency(elements: np.ndarray, n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR lists of the element-force slots (4 e + I) that act on each node."""
    slots = np.arange(elements.size, dtype=np.int64)
    node_of_slot = elements.ravel()
    order = np.argsort(node_of_slot, kind="stable")
    ptr = np.zeros(n_nodes + 1, dtype=np.int64)
    np.cumsum(np.bincount(node_of_slot, minlength=n_nodes), out=ptr[1:])
    return ptr.astype(np.int32), slots[order].astype(np.int32)


def element_data(
    mesh: Mesh,
    materials: Material | Mapping[str, Material],
    thickness: float,
    hourglass_scale: float,
    max_added_mass: float,
    damping: StiffnessDamping | None,
    law: ElementLaw,
) -> ElementData:
    """The elements' and nodes' set-up (see :class:`~taichi_bearing.solver.model.Model`'s
    parameters)."""
    nn, ne = mesh.n_nodes, mesh.n_elements
    elements = np.asarray(mesh.elements, dtype=np.int64)
    geo = element_geometry(np.asarray(mesh.nodes, dtype=float), elements)
    lam, mu, rho, eprime = materials_per_element(mesh, materials)
    khg = hourglass_stiffness(geo, eprime, thickness, hourglass_scale)
    k_el = element_stiffness(geo, lam, mu, khg, thickness, law.tangent(lam, mu))
    omega_e = element_max_frequencies(geo, lam, mu, rho, khg, thickness, k_el)
    part = np.asarray(mesh.element_part)
    element_mass = rho * geo.area * thickness
    rho_scale = selective_mass_scale(omega_e, element_mass, part, max_added_mass)
    rho = rho * rho_scale
    omega_e = omega_e / np.sqrt(rho_scale)  # one element alone: omega ~ 1/sqrt(mass)
    beta_e = damping.element_beta(omega_e) if damping is not None else np.zeros(ne)
    mass = np.zeros(nn)
    np.add.at(mass, elements, geo.shape_integrals * (rho * thickness)[:, None])
    if np.any(mass <= 0):
        raise ValueError(f"node {int(np.argmin(mass))} belongs to no element (zero mass)")
    return ElementData(
        elements=elements,
        geometry=geo,
        lam=lam,
        mu=mu,
        khg=khg,
        stiffness=k_el,
        omega_e=omega_e,
        beta_e=beta_e,
        mass=mass,
        n_mass_scaled=int(np.count_nonzero(rho_scale > 1.0)),
        part_mass=np.bincount(part, weights=element_mass),
        added_mass=np.bincount(part, weights=(rho_scale - 1.0) * element_mass),
        adjacency=_adjacency(elements, nn),
    )


def constraint_tables(constraints: Sequence, nn: int):
    """Per node: the constraint flags, the held direction and the rotation set (-1:
    none); the rotations and the rigid plates, from the model's constraints."""
    bc = np.zeros(nn, dtype=np.int32)
    held = np.zeros((nn, 2))
    rgroup = np.full(nn, -1, dtype=np.int32)
    rots: list[PrescribedRotation] = []
    plates = [c for c in constraints if isinstance(c, RigidPlate)]
    for c in constraints:
        ids = np.asarray(c.nodes)
        if ids.min() < 0 or ids.max() >= nn:
            raise ValueError(f"{type(c).__name__}: node index out of range 0..{nn - 1}")
        if isinstance(c, FixedNodes):
            bc[ids] |= FIXED
        elif isinstance(c, HeldDirection):
            if np.any(bc[ids] & HELD):
                raise ValueError("HeldDirection: a node can hold only one direction")
            bc[ids] |= HELD
            held[ids] = c.direction
        elif isinstance(c, PrescribedRotation):
            if np.any(rgroup[ids] >= 0):
                raise ValueError("PrescribedRotation: a node is in two rotation sets")
            bc[ids] |= ROTATED
            rgroup[ids] = len(rots)
            rots.append(c)
        elif isinstance(c, RigidPlate):
            if np.any(bc[ids] & (HELD | ROTATED | PLATE)):
                raise ValueError("RigidPlate: nodes already held, rotated or on a plate")
            bc[ids] |= PLATE
        else:
            raise TypeError(f"unknown constraint {type(c).__name__}")
    return bc, held, rgroup, rots, plates


def load_tables(loads: Sequence[NodalForces], nn: int):
    """The loaded nodes, their forces and ramp times, one list entry per load."""
    nodes, forces, ramps = [], [], []
    for load in loads:
        if len(load.nodes) and (load.nodes.min() < 0 or load.nodes.max() >= nn):
            raise ValueError("NodalForces: node index out of range")
        nodes.append(load.nodes)
        forces.append(load.forces)
        ramps.append(np.full(len(load.nodes), load.ramp_time))
    return nodes, forces, ramps


def rigid_velocity_field(
    nodes: np.ndarray, omega: float, center=(0.0, 0.0), velocity=(0.0, 0.0)
) -> np.ndarray:
    """Velocities ``velocity + omega x (X - center)`` of points ``nodes`` (n, 2)."""
    r = nodes - np.asarray(center, dtype=float)
    return np.asarray(velocity, dtype=float) + omega * np.stack([-r[:, 1], r[:, 0]], axis=1)
