r"""Flexible-ring static reference: the roller forces of the preload with the rings'
elasticity, from a linear finite element model of the rings and one Palmgren spring per
roller.

Harris's load distribution (:mod:`taichi_bearing.analytic.quasistatic`) moves the outer ring as a
rigid body: roller :math:`j` at angle :math:`\psi_j` from 12 o'clock is squeezed by
:math:`\delta_j = v \cos\psi_j - c / 2` for a ring drop :math:`v` and clearance :math:`c`.
Here the rings are the case's own mesh (rollers left out), small-strain linear elastic, held as
the explicit model holds them: the bore fixed and the loading plate
(:func:`~taichi_bearing.simulation.starter.support_plate_nodes`) rigid, moving vertically only.
Each roller becomes a pair of equal and opposite forces :math:`Q_j` along its radial line
on the outer and the inner raceway (spread over the raceway nodes within two surface
elements of its foot), so

.. math::

    \delta_j = v \cos\psi_j - c / 2 - g_j - \sum_k C_{jk} Q_k, \quad
    Q_j = K \max(\delta_j, 0)^n, \quad
    \sum_j Q_j \cos\psi_j = W,

with :math:`K` the two Palmgren contacts in series (the analytical model's law),
:math:`g_j` the extra radial gap of the meshed raceways at the roller's foot (a spall
floor under all of it), and :math:`C` the rings' compliance: the opening of gap :math:`j`
per unit force pair :math:`k` with the plate held (one sparse factorisation, one solve per
roller). With :math:`C = 0` the equations are Harris's. Newton's method solves them for
:math:`\delta` and :math:`v`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from taichi_bearing.analytic.bearing import (
    LINE_CONTACT_EXPONENT,
    palmgren_stiffness,
    series_stiffness,
)
from taichi_bearing.case import Case
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.simulation.starter import polar_angle_from_top, support_plate_nodes
from taichi_bearing.solver.linear_reference import assemble_stiffness

__all__ = [
    "RingCompliance",
    "StaticReference",
    "reference_roller_forces",
    "ring_compliance",
    "solve_springs",
]


@dataclass
class RingCompliance:
    """The rings' linear response at the rollers' feet.

    ``compliance[j, k]``: opening of roller ``j``'s gap (m) per newton of the force pair
    of roller ``k``, plate and bore held. ``angles``: roller angles from 12 o'clock, rad.
    ``gaps``: extra radial gap of the meshed raceways at each roller's foot, m.
    """

    compliance: np.ndarray
    angles: np.ndarray
    gaps: np.ndarray


@dataclass
class StaticReference:
    """Solution of the spring model: roller forces ``forces`` (N), approaches
    ``deflections`` (m), plate drop ``drop`` (m), Newton iterations and final residual."""

    forces: np.ndarray
    deflections: np.ndarray
    drop: float
    iterations: int
    residual: float


def _foot_weights(mesh: Mesh, surface: str, radial: np.ndarray, width: float):
    """Nodes of ``surface`` near the ray ``radial`` (unit vector) and hat weights over
    the arc length ``width`` either side of it, summing to one."""
    ids = np.unique(mesh.surfaces[surface])
    xy = mesh.nodes[ids]
    r = np.hypot(xy[:, 0], xy[:, 1])
    along = np.arctan2(radial[0] * xy[:, 1] - radial[1] * xy[:, 0], xy @ radial) * r
    w = np.clip(1.0 - np.abs(along) / width, 0.0, None)
    w[(xy @ radial) <= 0] = 0.0
    if not np.any(w > 0):  # a raceway coarser than width: take the nearest node
        w[np.argmin(np.where(xy @ radial > 0, np.abs(along), np.inf))] = 1.0
    keep = w > 0
    return ids[keep], w[keep] / w[keep].sum(), r[keep]


def ring_compliance(case: Case, mesh: Mesh, width: float | None = None) -> RingCompliance:
    """The rings' compliance at the rollers' feet, from the case's mesh.

    Parameters
    ----------
    case : Case
    mesh : Mesh
        The bearing mesh of the case (parts ``outer_ring``, ``inner_ring``, rollers;
        ``info["roller_centres"]``); the rollers' elements are left out.
    width : float, optional
        Half-width of the hat over which a roller's force is spread on each raceway, m
        (default: two surface elements, so that three or four nodes share it wherever
        the foot falls: a single-node load adds a local, mesh-dependent compliance that
        Palmgren's law already holds).

    Returns
    -------
    RingCompliance
    """
    b, m = case.bearing, case.material
    width = 2.0 * case.mesh.surface_size if width is None else width
    K = assemble_stiffness(mesh, m)
    K = K * b.roller_length
    rings = np.isin(mesh.element_part, [mesh.part_id("outer_ring"), mesh.part_id("inner_ring")])
    ring_nodes = np.unique(mesh.elements[rings])
    held = np.concatenate([mesh.node_sets["inner_bore"], support_plate_nodes(case, mesh)])
    free_nodes = np.setdiff1d(ring_nodes, held)
    free = np.stack([2 * free_nodes, 2 * free_nodes + 1], 1).ravel()
    lu = spla.splu(K.tocsr()[free][:, free].tocsc())
    position = np.full(2 * mesh.n_nodes, -1)
    position[free] = np.arange(len(free))

    centres = np.asarray(mesh.info["roller_centres"], dtype=float)
    n = len(centres)
    feet = []  # (node ids, weights) on the outer and inner raceway, per roller
    gaps = np.zeros(n)
    loads = np.zeros((len(free), n))
    for j, c in enumerate(centres):
        e = c / np.linalg.norm(c)
        o_ids, o_w, o_r = _foot_weights(mesh, "outer_raceway", e, width)
        i_ids, i_w, i_r = _foot_weights(mesh, "inner_raceway", e, width)
        # the raceway points closest to the roller under its foot (a spall floor only
        # when the whole foot is over it)
        gaps[j] = (o_r.min() - b.outer_raceway_radius) + (b.inner_raceway_radius - i_r.max())
        feet.append((o_ids, o_w, i_ids, i_w, e))
        # outward on the outer raceway, inward on the inner one (held nodes take nothing)
        for ids, w, sign in ((o_ids, o_w, 1.0), (i_ids, i_w, -1.0)):
            for d in (0, 1):
                p = position[2 * ids + d]
                ok = p >= 0
                loads[p[ok], j] += sign * w[ok] * e[d]
    u = np.zeros((2 * mesh.n_nodes, n))
    u[free] = lu.solve(loads)
    u = u.reshape(mesh.n_nodes, 2, n)
    comp = np.zeros((n, n))
    for j, (o_ids, o_w, i_ids, i_w, e) in enumerate(feet):
        u_out = np.einsum("i,idk->dk", o_w, u[o_ids])
        u_in = np.einsum("i,idk->dk", i_w, u[i_ids])
        comp[j] = (u_out - u_in).T @ e  # gap opening along the roller's radial line
    angles = np.array([polar_angle_from_top(x, y) for x, y in centres])
    return RingCompliance(comp, angles, gaps)


def solve_springs(
    case: Case,
    rings: RingCompliance,
    exponent: float = LINE_CONTACT_EXPONENT,
    tol: float = 1e-10,
    max_iter: int = 100,
) -> StaticReference:
    """Roller forces of the spring model by Newton's method on ``(delta, v)``.

    Starts from the rigid-ring solution's drop (every roller with a positive approach)
    and halves a step until the residual falls. ``tol``: relative residual (of ``W`` for
    the load balance, of the largest approach for the compatibility rows).
    """
    b = case.bearing
    k_single = palmgren_stiffness(b, case.material)
    k = float(series_stiffness(k_single, k_single, exponent))
    w_load = case.operating.load
    cos = np.cos(rings.angles)
    offset = 0.5 * b.radial_clearance + rings.gaps
    c = rings.compliance
    n = len(cos)

    def force(delta):
        d = np.maximum(delta, 0.0)
        return k * d**exponent, exponent * k * d ** (exponent - 1.0)

    def residual(x):
        delta, v = x[:n], x[n]
        q, _ = force(delta)
        r_comp = delta - v * cos + offset + c @ q
        return np.concatenate([r_comp, [(q @ cos - w_load) / w_load]])

    # start: Harris's Stribeck estimate of the drop, then the rigid-ring approaches
    q0 = 4.08 * w_load / n
    v0 = (q0 / k) ** (1.0 / exponent) + 0.5 * b.radial_clearance
    x = np.concatenate([v0 * cos - offset, [v0]])
    r = residual(x)
    scale = v0
    it = 0
    while it < max_iter and max(np.abs(r[:n]).max() / scale, abs(r[n])) > tol:
        delta = x[:n]
        q, dq = force(delta)
        jac = np.zeros((n + 1, n + 1))
        jac[:n, :n] = np.eye(n) + c * dq[None, :]
        jac[:n, n] = -cos
        jac[n, :n] = cos * dq / w_load
        step = np.linalg.lstsq(jac, -r, rcond=None)[0]
        norm0 = np.linalg.norm(r / np.r_[np.full(n, scale), 1.0])
        t = 1.0
        while t > 1e-6:
            trial = x + t * step
            rt = residual(trial)
            if np.linalg.norm(rt / np.r_[np.full(n, scale), 1.0]) < norm0:
                break
            t *= 0.5
        x, r = trial, rt
        it += 1
    q, _ = force(x[:n])
    res = max(np.abs(r[:n]).max() / scale, abs(r[n]))
    return StaticReference(q, x[:n], float(x[n]), it, float(res))


def reference_roller_forces(case: Case, mesh: Mesh | None = None) -> np.ndarray:
    """Roller forces (N) of the flexible-ring reference for the case's preload.

    ``mesh``: the case's bearing mesh (meshed here when not given).
    """
    if mesh is None:
        from taichi_bearing.mesh import build_bearing_mesh, spec_from_case

        mesh = build_bearing_mesh(spec_from_case(case))
    return solve_springs(case, ring_compliance(case, mesh)).forces
