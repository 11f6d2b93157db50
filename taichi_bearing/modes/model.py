r"""The finite element model of the modal analysis: the solver's own lumped masses and
small-strain stiffness, the supports the run uses, and linearised roller contacts.

Everything here is numpy/scipy. The element routines are those of
:mod:`taichi_bearing.solver.element` (the tangent of the explicit element at the
reference state: uniform-strain part plus the Flanagan-Belytschko hourglass stiffness, and
the per-element materials), numpy only: importing them does not start Taichi.

The eigenproblem :math:`K u = \omega^2 M u` is solved in the mass-normalised form
:math:`S y = \omega^2 y` with :math:`S = B^T K B`, where :math:`B` maps the kept
coordinates :math:`y` to nodal displacements :math:`u = B y`: fixed degrees of freedom are
left out and the nodes of a rigid plate share one coordinate, whose mass is the plate's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from taichi_bearing.case import Case, Material
from taichi_bearing.mesh.supports import support_plate_nodes
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.solver import element

__all__ = [
    "PARTS",
    "SUPPORTS",
    "ModalModel",
    "bearing_modal_model",
    "modal_model",
]

PARTS = ("outer_ring", "inner_ring", "bearing")
SUPPORTS = ("free", "case")


@dataclass
class ModalModel:
    """A mass-normalised linear model of some parts of a mesh.

    Attributes
    ----------
    mesh : Mesh
        The parts analysed, nodes renumbered from 0.
    matrix : scipy.sparse.csr_matrix
        :math:`S = B^T K B` over the kept coordinates, 1/s^2.
    basis : scipy.sparse.csr_matrix
        ``B`` (2 n_nodes, n_kept): nodal displacements (x0, y0, x1, ...) of each kept
        coordinate, m per unit of sqrt(kg) m.
    mass : ndarray (n_nodes,)
        Lumped nodal masses, kg (the solver's, without mass scaling).
    part, support : str
        What was analysed and how it is held (``free`` or ``case``).
    notes : list of str
        How it is held, in words.
    shear_wave_speed : float
        sqrt(mu / rho) of the first part's material, m/s (sets the rigid-body threshold).
    """

    mesh: Mesh
    matrix: sp.csr_matrix
    basis: sp.csr_matrix
    mass: np.ndarray
    part: str
    support: str
    notes: list[str] = field(default_factory=list)
    shear_wave_speed: float = 0.0

    @property
    def n_bodies(self) -> int:
        """Separate bodies (parts) of the mesh: each may add rigid-body modes."""
        return len(self.mesh.part_names)


def sub_mesh(mesh: Mesh, parts: list[str]) -> tuple[Mesh, np.ndarray]:
    """The named parts of ``mesh`` alone, and the new index of every old node (-1 if
    dropped). Node sets, surfaces and sensors keep the nodes that stay."""
    ids = [mesh.part_id(p) for p in parts]
    keep = np.isin(mesh.element_part, ids)
    used = np.unique(mesh.elements[keep])
    new = np.full(mesh.n_nodes, -1, dtype=np.int64)
    new[used] = np.arange(len(used))
    renumber = {old: k for k, old in enumerate(ids)}

    def kept(a: np.ndarray) -> np.ndarray:
        a = np.asarray(a)
        m = new[a]
        return m[np.all(m >= 0, axis=-1)] if a.ndim > 1 else m[m >= 0]

    return (
        Mesh(
            nodes=mesh.nodes[used],
            elements=new[mesh.elements[keep]],
            element_part=np.array([renumber[p] for p in mesh.element_part[keep]], np.int64),
            part_names=list(parts),
            node_sets={k: kept(v) for k, v in mesh.node_sets.items()},
            surfaces={k: kept(v) for k, v in mesh.surfaces.items()},
            sensor_nodes={k: int(new[v]) for k, v in mesh.sensor_nodes.items() if new[v] >= 0},
            info=mesh.info,
        ),
        new,
    )


def _stiffness_and_mass(mesh: Mesh, material: Material, thickness: float):
    """:math:`M^{-1/2} K M^{-1/2}` (sparse) and the lumped masses, as the explicit model has
    them."""
    nodes = np.asarray(mesh.nodes, dtype=float)
    elements = np.asarray(mesh.elements, dtype=np.int64)
    geo = element.element_geometry(nodes, elements)
    lam, mu, rho, eprime = element.materials_per_element(mesh, material)
    khg = element.hourglass_stiffness(geo, eprime, thickness)
    k_el = element.element_stiffness(geo, lam, mu, khg, thickness)
    mass = np.zeros(mesh.n_nodes)
    np.add.at(mass, elements, geo.shape_integrals * (rho * thickness)[:, None])
    return element.assembled_matrix(k_el, elements, mass), mass


def _reduction(
    n_nodes: int, mass: np.ndarray, fixed: np.ndarray, plate: np.ndarray | None
) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """:math:`B` and :math:`P = M^{1/2} B`: ``fixed`` nodes held in both directions; the ``plate``
    nodes held in x and moving together in y (one coordinate with the plate's mass)."""
    n_dof = 2 * n_nodes
    target = np.arange(n_dof)
    drop = np.zeros(n_dof, dtype=bool)
    drop[2 * np.asarray(fixed, dtype=np.int64)] = True
    drop[2 * np.asarray(fixed, dtype=np.int64) + 1] = True
    if plate is not None and len(plate):
        plate = np.asarray(plate, dtype=np.int64)
        drop[2 * plate] = True
        target[2 * plate + 1] = 2 * plate[0] + 1  # every plate node moves with the first
    rows = np.flatnonzero(~drop)
    kept, col = np.unique(target[rows], return_inverse=True)
    m_dof = np.repeat(mass, 2)[rows]
    m_kept = np.bincount(col, weights=m_dof, minlength=len(kept))
    shape = (n_dof, len(kept))
    basis = sp.csr_matrix((1.0 / np.sqrt(m_kept[col]), (rows, col)), shape=shape)
    scaled = sp.csr_matrix((np.sqrt(m_dof / m_kept[col]), (rows, col)), shape=shape)
    return basis, scaled


def modal_model(
    mesh: Mesh,
    material: Material,
    thickness: float = 1.0,
    *,
    fixed: np.ndarray | None = None,
    plate: np.ndarray | None = None,
    springs: list[tuple[np.ndarray, float]] | None = None,
    part: str = "",
    support: str = "free",
    notes: list[str] | None = None,
) -> ModalModel:
    """The modal model of a mesh: the solver's element, lumped masses, supports, springs.

    Parameters
    ----------
    mesh : Mesh
    material : Material
        One material for every part.
    thickness : float
        Plane-strain thickness, m (frequencies do not depend on it; spring stiffnesses
        must be for the same thickness).
    fixed : array of int, optional
        Nodes held in both directions.
    plate : array of int, optional
        Nodes of a rigid plate: x held, one shared y motion (the run's loading plate,
        whose vertical motion is force-controlled).
    springs : list of (ndarray, float), optional
        Linear springs ``(g, k)``: ``g`` (2 n_nodes,) turns nodal displacements into the
        spring's extension, ``k`` its stiffness, N/m.
    part, support : str
        Labels.
    notes : list of str, optional
        How it is held, in words.
    """
    s_full, mass = _stiffness_and_mass(mesh, material, thickness)
    if springs:
        inv = 1.0 / np.sqrt(np.repeat(mass, 2))
        g = sp.csr_matrix(np.stack([gi * inv for gi, _ in springs], axis=1))
        s_full = s_full + g @ sp.diags([k for _, k in springs]) @ g.T
    fixed = np.zeros(0, dtype=np.int64) if fixed is None else np.asarray(fixed, dtype=np.int64)
    basis, scaled = _reduction(mesh.n_nodes, mass, fixed, plate)
    matrix = (scaled.T @ s_full @ scaled).tocsr()
    matrix = 0.5 * (matrix + matrix.T)  # exactly symmetric for the Lanczos solver
    return ModalModel(
        mesh=mesh,
        matrix=matrix.tocsr(),
        basis=basis,
        mass=mass,
        part=part,
        support=support,
        notes=list(notes or []),
        shear_wave_speed=math.sqrt(material.mu / material.density),
    )


def _patch(mesh: Mesh, surface: str, point: np.ndarray, normal: np.ndarray, width: float):
    """Nodes of ``surface`` within ``width`` of ``point`` and weights summing to one:
    hat weights, tilted so that their first moment along the surface is zero (the
    nearest node alone where the surface is coarser than ``width``).

    With a zero moment, turning a roller about its centre does not stretch the spring
    (to first order): rolling stays a zero-energy motion, as in the run.
    """
    ids = np.unique(mesh.surfaces[surface])
    dist = np.hypot(*(mesh.nodes[ids] - point).T)
    w = np.clip(1.0 - dist / width, 0.0, None)
    if not np.any(w > 0):
        w[np.argmin(dist)] = 1.0
    keep = w > 0
    ids, w = ids[keep], w[keep] / w[keep].sum()
    along = (mesh.nodes[ids] - point) @ np.array([-normal[1], normal[0]])
    mean = w @ along
    spread = w @ (along - mean) ** 2
    if spread > 0:
        w = w * (1.0 - mean / spread * (along - mean))
    return ids, w


def _contact_spring(mesh: Mesh, a, b, normal: np.ndarray) -> np.ndarray:
    """``g`` of a spring along ``normal`` between the weighted nodes ``a`` and ``b``."""
    g = np.zeros(2 * mesh.n_nodes)
    for (ids, w), sign in ((a, 1.0), (b, -1.0)):
        for d in (0, 1):
            np.add.at(g, 2 * ids + d, sign * w * normal[d])
    return g


def contact_springs(case: Case, mesh: Mesh) -> tuple[list[tuple[np.ndarray, float]], int]:
    r"""Linearised roller contacts of the statically loaded bearing: one spring along the
    roller's radial line at its outer and at its inner contact, of the Palmgren law's
    tangent stiffness :math:`dQ / d\delta = n K^{1/n} Q^{1 - 1/n}` at the quasi-static force
    (Harris's rigid-ring load distribution with the case's spall, rollers where the run
    starts them). Each end is spread over the surface nodes within two surface elements
    of the contact point. Returns the springs and the number of loaded rollers."""
    from taichi_bearing.analytic.quasistatic import contact_model, solve_case

    cm = contact_model(case.bearing, case.material)
    dist = solve_case(case, case.run.first_roller_angle)
    width = 2.0 * case.mesh.surface_size
    r = case.bearing.roller_radius
    radii = {"outer": case.bearing.outer_raceway_radius, "inner": case.bearing.inner_raceway_radius}
    springs, loaded = [], 0
    for j, centre in enumerate(np.asarray(mesh.info["roller_centres"], dtype=float)):
        e = centre / np.linalg.norm(centre)
        forces = {"outer": dist.outer_force[0, j], "inner": dist.inner_force[0, j]}
        if min(forces.values()) <= 1e-9 * case.operating.load:
            continue
        loaded += 1
        for race, k_c in (("outer", cm.k_outer), ("inner", cm.k_inner)):
            side = 1.0 if race == "outer" else -1.0
            n = cm.exponent
            k_t = n * k_c ** (1.0 / n) * forces[race] ** (1.0 - 1.0 / n)
            on_race = _patch(mesh, f"{race}_raceway", radii[race] * e, e, width)
            on_roller = _patch(mesh, f"roller{j}", centre + side * r * e, e, width)
            springs.append((_contact_spring(mesh, on_race, on_roller, e), float(k_t)))
    return springs, loaded


def bearing_modal_model(case: Case, mesh: Mesh, part: str, support: str) -> ModalModel:
    """The modal model of ``part`` of a case's bearing mesh, ``free`` or held as in the
    run (``support="case"``).

    Held as in the run: the outer ring (with its adapter) rests on the rigid loading
    plate (the adapter top, or the housing round the ring with ``bearing.outer_support:
    housing``), x held and one force-controlled vertical motion; the inner ring's bore
    is held (it turns at a prescribed speed, so a vibration cannot move it); the whole
    bearing adds one linear spring per loaded roller contact
    (:func:`contact_springs`). The rollers carry no tangential stiffness (they roll), so
    each keeps rigid-body modes.
    """
    names = list(mesh.part_names) if part == "bearing" else [part]
    sub, new = sub_mesh(mesh, names)
    notes: list[str] = []
    fixed = plate = springs = None
    if support == "case":
        if part in ("inner_ring", "bearing"):
            fixed = new[mesh.node_sets["inner_bore"]]
            notes.append("inner bore held (it turns at a prescribed speed in the run)")
        if part in ("outer_ring", "bearing"):
            plate = new[support_plate_nodes(case, mesh)]
            where = "housing" if case.bearing.outer_support == "housing" else "adapter top"
            notes.append(
                f"rigid loading plate on the {where}: x held, one vertical motion "
                "(force-controlled in the run, so free here)"
            )
        if part == "bearing":
            springs, loaded = contact_springs(case, sub)
            notes.append(
                f"{loaded} loaded rollers tied to both raceways by the tangent stiffness of "
                "their Hertz (Palmgren) contacts at the quasi-static load"
            )
    else:
        notes.append("free: nothing holds it (rigid-body modes at 0 Hz)")
    return modal_model(
        sub,
        case.material,
        case.bearing.roller_length,
        fixed=fixed,
        plate=plate,
        springs=springs,
        part=part,
        support=support,
        notes=notes,
    )
