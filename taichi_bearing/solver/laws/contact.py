"""Contact laws: how hard a penetrating node is pushed back (a zoo of small classes, one
per law, in the manner of FEMcy's materials).

A law owns four things, and the node-to-segment contact
(:class:`~taichi_bearing.solver.contact.PenaltyContact`) and the rigid cage
(:class:`~taichi_bearing.solver.cage.RigidCage`) ask it for nothing else:

- its stiffness rule at set-up, from the contact's reference geometry and the model's
  materials (:meth:`ContactLaw.segment_stiffness` for a master segment,
  :meth:`ContactLaw.node_stiffness` for a node against a rigid wall or, for a law whose
  :attr:`ContactLaw.side` is ``"query"``, for the querying node), and in the step
  (:meth:`ContactLaw.stiffness`: what a law that follows the time step makes of them);
- its normal force and damping, one Taichi function (:meth:`ContactLaw.normal`);
- its stored energy (:meth:`ContactLaw.energy`, :meth:`ContactLaw.patch_energy`);
- its bound on the stable time step (:meth:`ContactLaw.contact_bound`,
  :meth:`ContactLaw.node_bound`; None for a law that follows the step).

The laws here are linear in the penetration: the force is :math:`k` times the penetration
(for a smoothed contact, the mean overlap of the node's tributary patch), so a patch's
stored energy is :math:`k` times the mean of :math:`p^2 / 2` over it. Friction (an elastic stick
spring of the same :math:`k`, return-mapped onto Coulomb's cone) is
:func:`~taichi_bearing.solver.laws.friction.friction_force`, common to every law.
"""

# No `from __future__ import annotations`: Taichi reads annotations at definition.
from collections.abc import Sequence
from typing import ClassVar

import numpy as np
import taichi as ti

from taichi_bearing.mesh.types import Mesh
from taichi_bearing.solver.contact_setup import segment_elements

__all__ = [
    "CONTACT_LAWS",
    "ContactLaw",
    "PressurePenalty",
    "SegmentPenalty",
    "SoftPenalty",
    "contact_law",
    "penalty_bounds",
    "segment_stiffness",
    "window_share",
]


@ti.data_oriented
class ContactLaw:
    r"""Base of the contact laws: a linear penalty whose stiffness each law sets.

    Parameters
    ----------
    scale : float
        The law's scale factor (LS-DYNA's :math:`f_s` for the penalty laws).
    damping_ratio : float
        Viscous damping :math:`c = 2 \zeta \sqrt{k m_\mathrm{eff}}` as a fraction of critical.

    Notes
    -----
    A subclass sets :attr:`name` and overrides :meth:`segment_stiffness` (and
    :meth:`stiffness` where the stiffness follows the step). The Taichi functions are
    inlined into the contact's and the cage's step kernels: the constants they read
    (``self.scale``, ``self.zeta``) are compiled in.
    """

    name: ClassVar[str] = ""
    bounded: ClassVar[bool] = True
    """Whether the law's springs enter the stable step (with False, the law follows it)."""
    side: ClassVar[str] = "segment"
    """Whose set-up stiffness :meth:`stiffness` receives in node-to-segment contact:
    ``"segment"``, the touched master segment's; ``"query"``, the querying node's own
    (:meth:`node_stiffness` over its surface), shared equally by the two passes of a
    two-pass pair so that the pair's pressure is the law's."""

    def __init__(self, scale: float = 0.1, damping_ratio: float = 0.0) -> None:
        self.scale = float(scale)
        self.zeta = float(damping_ratio)

    # ---------------------------------------------------------------- set-up (numpy)

    def segment_stiffness(self, model, segments: np.ndarray) -> np.ndarray:
        """Stiffness (N/m) of each master segment ``segments`` (n, 2) of ``model``'s mesh,
        as :meth:`stiffness` receives it."""
        raise NotImplementedError

    def node_stiffness(self, model, segments: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """Stiffness (N/m) of each of ``nodes`` against a rigid wall: the mean of
        :meth:`segment_stiffness` over the node's segments among ``segments`` (its own
        surface's)."""
        segs = np.asarray(segments, dtype=np.int64)
        k_seg = self.segment_stiffness(model, segs)
        k_sum = np.zeros(model.mesh.n_nodes)
        count = np.zeros(model.mesh.n_nodes)
        for end in (0, 1):
            np.add.at(k_sum, segs[:, end], k_seg)
            np.add.at(count, segs[:, end], 1.0)
        return k_sum[nodes] / count[nodes]

    def contact_bound(
        self, model, passes: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]]
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Per-node bound on the springs and dashpots this law adds in node-to-segment
        contact (for the stable step), from each pass's (query surface segments, master
        segments, their stiffness); None when the law follows the step.
        :func:`~taichi_bearing.solver.laws.contact.penalty_bounds` for a linear spring."""
        if not self.bounded:
            return None
        return penalty_bounds(model.mesh.nodes, passes, model.mass_np, self.zeta)

    def node_bound(self, k_node: np.ndarray, mass: np.ndarray):
        """Bound on the spring and dashpot of a node against a rigid wall: ``2 k`` and
        ``2 c`` (a spring to a fixed point, on the node alone); None when the law follows
        the step."""
        if not self.bounded:
            return None
        c_node = 2.0 * self.zeta * np.sqrt(k_node * mass)
        return 2.0 * k_node, 2.0 * c_node

    # ---------------------------------------------------------------- in the step (Taichi)

    @ti.func
    def stiffness(self, k_set, m_eff, dt):
        """The stiffness of a contact this step, from the one set up for it (``k_set``),
        the contact's effective mass and the step. Default: the set-up one."""
        return k_set

    @ti.func
    def normal(self, k, pen, m_eff, vn, dt):
        r"""Normal force :math:`\max(0, k \, \mathrm{pen} - c \, \mathrm{vn})`,
        :math:`c = 2 \zeta \sqrt{k m_\mathrm{eff}}`; ``vn`` is
        the separating normal velocity. Returns (force, damping energy dissipated in
        ``dt``)."""
        fn_el = k * pen
        fn = ti.max(fn_el - 2.0 * self.zeta * ti.sqrt(k * m_eff) * vn, 0.0)
        return fn, -(fn - fn_el) * vn * dt

    @ti.func
    def energy(self, k, pen):
        """Stored energy of a point contact penetrating ``pen``."""
        return 0.5 * k * pen * pen

    @ti.func
    def patch_energy(self, k, half_square_mean):
        """Stored energy of a patch contact whose overlap :math:`p` has mean :math:`p^2 / 2` of
        ``half_square_mean`` over the patch (times the patch's weight in the force)."""
        return k * half_square_mean


@ti.data_oriented
class SegmentPenalty(ContactLaw):
    r"""LS-DYNA's segment-based penalty: :math:`k = f_s K A^2 / V` of the master segment,
    with :math:`K = \lambda + 2 \mu / 3` the bulk modulus of the element the segment bounds,
    :math:`A = L t` the segment's area (length x thickness) and
    :math:`V = \mathrm{area} \, t` the element's volume, i.e.
    :math:`k = f_s K L^2 t / \mathrm{area}`. Its pressure per unit overlap is therefore set
    by the mesh (about :math:`2 f_s K / h` with two passes, :math:`h` the element size)."""

    name = "segment"

    def segment_stiffness(self, model, segments: np.ndarray) -> np.ndarray:
        return segment_stiffness(
            model.mesh,
            np.asarray(segments, dtype=np.int64),
            model.lam_np,
            model.mu_np,
            model.area_np,
            model.thickness,
            self.scale,
        )


@ti.data_oriented
class PressurePenalty(ContactLaw):
    r"""A pressure per unit overlap :math:`p_s` (Pa/m), the same on every mesh: a query node
    stands for its tributary length :math:`l` of surface, so its stiffness is
    :math:`k = p_s l t` (:math:`t` the thickness), and a smoothed contact's force
    (:math:`k` times the mean overlap) is :math:`p_s t` times the overlap integrated over
    the node's patch. The two passes of a two-pass pair each carry half (each sees the same
    overlap), so the pair presses with :math:`p_s` times the overlap. Refining the mesh
    refines the geometry only; the contact's compliance stays :math:`1 / p_s`.

    Parameters
    ----------
    pressure : float
        :math:`p_s`, Pa/m; :math:`\alpha E^* / b_\mathrm{ref}` makes the penalty's overlap
        under a Hertz pressure about :math:`1 / \alpha` of the Hertz approach
        (:func:`taichi_bearing.analytic.penalty.pressure_penalty`).
    damping_ratio : float
        As for :class:`ContactLaw`.
    """

    name = "pressure"
    side = "query"

    def __init__(self, pressure: float, damping_ratio: float = 0.0) -> None:
        super().__init__(scale=1.0, damping_ratio=damping_ratio)
        if not pressure > 0:
            raise ValueError(f"the pressure penalty must be positive, got {pressure!r} Pa/m")
        self.pressure = float(pressure)

    def segment_stiffness(self, model, segments: np.ndarray) -> np.ndarray:
        # p_s L t for a segment of reference length L: a node's mean over its two
        # segments (node_stiffness) is p_s t times its tributary length
        segs = np.asarray(segments, dtype=np.int64).reshape(-1, 2)
        X = np.asarray(model.mesh.nodes, dtype=float)
        length = np.linalg.norm(X[segs[:, 1]] - X[segs[:, 0]], axis=1)
        return self.pressure * length * model.thickness


@ti.data_oriented
class SoftPenalty(ContactLaw):
    r"""LS-DYNA's SOFT=1 idea: :math:`k = f_s m_\mathrm{eff} / \Delta t^2` with
    :math:`m_\mathrm{eff} = m_s m_m / (m_s + m_m)` (the slave node's mass and the master's
    interpolated at the contact point; a node's own mass against the rigid cage) and the
    model's current step. It follows the step, so it never limits it."""

    name = "soft"
    bounded = False

    def segment_stiffness(self, model, segments: np.ndarray) -> np.ndarray:
        # nothing set up: the stiffness is made in the step
        return np.zeros(len(np.asarray(segments).reshape(-1, 2)))

    @ti.func
    def stiffness(self, k_set, m_eff, dt):
        return self.scale * m_eff / (dt * dt)


# ---------------------------------------------------------------- the rules (numpy)


def segment_stiffness(
    mesh: Mesh,
    segments: np.ndarray,
    lam: np.ndarray,
    mu: np.ndarray,
    element_area: np.ndarray,
    thickness: float,
    scale: float,
) -> np.ndarray:
    r"""LS-DYNA segment penalty :math:`f_s K A^2 / V` (N/m) of each segment.

    :math:`K = \lambda + 2 \mu / 3` of the owning element, :math:`A = L t`,
    :math:`V = \mathrm{area} \, t`.
    """
    elem = segment_elements(mesh, segments)
    length = np.linalg.norm(mesh.nodes[segments[:, 1]] - mesh.nodes[segments[:, 0]], axis=1)
    bulk = lam[elem] + 2.0 * mu[elem] / 3.0
    return scale * bulk * (length * thickness) ** 2 / (element_area[elem] * thickness)


def window_share(nodes: np.ndarray, surface_segments: np.ndarray, length: float) -> float:
    r"""Largest :math:`\sum_j \max(0, 1 - s_j / \mathrm{length})` over the nodes of a surface
    (chains of segments), :math:`s_j` the arc distance from one of its nodes to node
    :math:`j` (itself included): the most the shape functions :math:`N` of a segment node
    can gather from that surface's nodes laid along its two segments of at most ``length``
    each. Uniform spacing :math:`h` gives :math:`1 + 2 \sum_j (1 - j h / \mathrm{length})`;
    a few short segments (a spall's walls)
    raise it only where they are. The sum of hats peaks at a node, so the nodes are the
    only candidates."""
    X = np.asarray(nodes, dtype=float)
    segs = np.asarray(surface_segments, dtype=np.int64).reshape(-1, 2)
    seg_len = np.linalg.norm(X[segs[:, 1]] - X[segs[:, 0]], axis=1)
    links: dict[int, list[tuple[int, float]]] = {}
    for (a, b), ln in zip(segs.tolist(), seg_len.tolist(), strict=True):
        links.setdefault(a, []).append((b, ln))
        links.setdefault(b, []).append((a, ln))
    best = 1.0
    for j, first in links.items():
        total = 1.0
        for nxt, ln in first:  # walk each way along the chain
            prev, cur, dist = j, nxt, ln
            while dist < length:
                total += 1.0 - dist / length
                ahead = [(n, lk) for n, lk in links[cur] if n != prev]
                if not ahead or ahead[0][0] == j:
                    break
                prev, (cur, lk) = cur, ahead[0]
                dist += lk
        best = max(best, total)
    return best


def penalty_bounds(
    nodes: np.ndarray,
    passes: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray]],
    nodal_mass: np.ndarray,
    damping_ratio: float,
) -> tuple[np.ndarray, np.ndarray]:
    r"""Per-node bound on the springs and dashpots penalty contact can add (for the
    global time step, :meth:`~taichi_bearing.solver.model.Model.add_stiffness_bound`).

    A query node in contact holds one spring :math:`k` of the segment it touches (normal,
    and the same stiffness tangentially while it sticks) to the point
    :math:`N_1 x_1 + N_2 x_2` of that segment, one contact at a time over all its passes.
    Since :math:`(x_s - N_1 x_1 - N_2 x_2)^2 \le 2 (x_s^2 + N_1 x_1^2 + N_2 x_2^2)`, the
    spring is bounded by :math:`2 k` on the query node and :math:`2 k N_i` on each segment
    node, where the :math:`N_i` of
    all the query nodes on a segment node's two segments sum to at most
    :func:`window_share` of the querying surface (query nodes laid along the segments).
    One body touches a surface at a time, so each role takes its largest pass. A dashpot
    :math:`2 \zeta \sqrt{k m_\mathrm{eff}}`, :math:`m_\mathrm{eff} = m_q m_s / (m_q + m_s)`
    of the query node and the segment point, is bounded the same way with the largest
    :math:`m_\mathrm{eff}` the pass allows
    (heaviest node on the other side, heaviest of the node and its neighbours on the
    segment side).

    Parameters
    ----------
    nodes : ndarray (n_nodes, 2)
        Reference coordinates.
    passes : sequence of (query_segments, segments, segment_stiffness)
        One entry per contact pass: the querying surface's segments (n, 2), the segments
        (m, 2) it is checked against and their penalty stiffnesses (N/m).
    nodal_mass : ndarray (n_nodes,)
    damping_ratio : float

    Returns
    -------
    stiffness, damping : ndarray (n_nodes,)
        N/m and N s/m, zero off the contact surfaces.
    """
    X = np.asarray(nodes, dtype=float)
    m = np.asarray(nodal_mass, dtype=float)
    # largest bound over the passes, per role
    k_query_role, k_seg_role = np.zeros(len(m)), np.zeros(len(m))
    c_query_role, c_seg_role = np.zeros(len(m)), np.zeros(len(m))
    shares: dict[tuple[bytes, float], float] = {}

    def reduced_mass(a: float | np.ndarray, b: float | np.ndarray):
        return a * b / (a + b)  # increasing in both: a bound from bounds on a and b

    for query_segs, segs, k_seg in passes:
        q = np.unique(query_segs)
        seg_nodes = np.unique(segs)
        k_max = float(np.max(k_seg))
        m_eff_q = reduced_mass(m[q], float(m[seg_nodes].max()))
        k_query_role[q] = np.maximum(k_query_role[q], 2.0 * k_max)
        c_query_role[q] = np.maximum(
            c_query_role[q], 4.0 * damping_ratio * np.sqrt(k_max * m_eff_q)
        )
        length = float(np.max(np.linalg.norm(X[segs[:, 1]] - X[segs[:, 0]], axis=1)))
        key = (np.ascontiguousarray(query_segs).tobytes(), length)
        if key not in shares:
            shares[key] = window_share(X, query_segs, length)
        share = shares[key]
        local_k = np.zeros(len(m))  # stiffest segment at each node
        local_m = np.zeros(len(m))  # heaviest node of the segments at each node
        for end in (0, 1):
            np.maximum.at(local_k, segs[:, end], k_seg)
            np.maximum.at(local_m, segs[:, end], np.maximum(m[segs[:, 0]], m[segs[:, 1]]))
        m_eff_s = reduced_mass(float(m[q].max()), local_m[seg_nodes])
        k_seg_role[seg_nodes] = np.maximum(k_seg_role[seg_nodes], 2.0 * share * local_k[seg_nodes])
        c_seg_role[seg_nodes] = np.maximum(
            c_seg_role[seg_nodes],
            4.0 * damping_ratio * share * np.sqrt(local_k[seg_nodes] * m_eff_s),
        )
    return k_query_role + k_seg_role, c_query_role + c_seg_role


CONTACT_LAWS: dict[str, type[ContactLaw]] = {
    law.name: law for law in (SegmentPenalty, SoftPenalty, PressurePenalty)
}
"""The laws by the name ``contact.penalty_method`` gives them."""


def contact_law(params) -> ContactLaw:
    """The law of a contact's parameters
    (:class:`~taichi_bearing.solver.contact_setup.ContactParameters`: ``penalty_method``
    names it, ``penalty_scale`` (``penalty_pressure`` for the pressure law) and
    ``damping_ratio`` set it)."""
    try:
        law = CONTACT_LAWS[params.penalty_method]
    except KeyError:
        raise ValueError(
            f"no contact law {params.penalty_method!r}; the laws are {sorted(CONTACT_LAWS)}"
        ) from None
    if law is PressurePenalty:
        return law(params.penalty_pressure, params.damping_ratio)
    return law(params.penalty_scale, params.damping_ratio)
