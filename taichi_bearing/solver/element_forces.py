r"""The element in the time loop (Taichi functions): the 1-point plane-strain quadrilateral
with the model's constitutive law (``m.material_law``,
:mod:`taichi_bearing.solver.laws.material`; St Venant-Kirchhoff by default),
Flanagan-Belytschko hourglass control and stiffness-proportional damping. Its reference
data (gradients :math:`b`, hourglass vectors :math:`\gamma`, areas) come from
:mod:`taichi_bearing.solver.element`.

Per element :math:`e` with nodes ``c[k]``: :math:`F = \sum_k x_k \otimes b_k`, Green
strain :math:`E = (F^T F - I) / 2`, second Piola-Kirchhoff stress :math:`S(E)` of the law
(St Venant-Kirchhoff: :math:`S = \lambda \operatorname{tr}(E) I + 2 \mu E`), nodal forces
:math:`f_k = -A t F S b_k + \gamma_k f_q` with the hourglass force
:math:`f_q = -k_\mathrm{hg} q`, :math:`q = \sum_k \gamma_k x_k`. Damping adds
:math:`\beta` times the same law of
the Green strain rate (zero for any rigid motion, so spin is not braked), the rate taken
over the element's step from its strain history (:func:`seed_strain_history`).
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import taichi as ti

__all__ = [
    "element_energy",
    "element_forces",
    "gradient",
    "green_strain",
    "record_element_energies",
    "seed_strain_history",
    "store_von_mises",
    "von_mises",
]


@ti.func
def gradient(field: ti.template(), c, bx, by, g):
    r"""Mean gradient :math:`\sum_k y_k \otimes b_k` and hourglass sum
    :math:`\sum_k \gamma_k y_k` of a node field :math:`y` over an element's nodes ``c``."""
    G = ti.Matrix.zero(ti.f64, 2, 2)
    h = ti.Vector.zero(ti.f64, 2)
    for k in ti.static(range(4)):
        yk = field[c[k]]
        G += yk.outer_product(ti.Vector([bx[k], by[k]]))
        h += g[k] * yk
    return G, h


@ti.func
def green_strain(F):
    """The Green strain :math:`(F^T F - I) / 2` of a deformation gradient :math:`F`."""
    return 0.5 * (F.transpose() @ F - ti.Matrix.identity(ti.f64, 2))


@ti.func
def element_forces(m: ti.template(), e, dt, damped: ti.template()):
    """Element ``e``'s nodal forces into its slots ``m.fe[4 e + k]`` (no atomics: the node
    update gathers them in a fixed order). Its energies are recorded apart
    (:func:`record_element_energies`)."""
    c = m.conn[e]
    bx, by, g = m.bx[e], m.by[e], m.gam[e]
    F, q = gradient(m.x, c, bx, by, g)
    lam, mu = m.lam[e], m.mu[e]
    at, k_hg = m.at[e], m.khg[e]
    E = green_strain(F)
    S, tr_e = m.material_law.stress(lam, mu, E)
    fq = -k_hg * q
    if ti.static(damped):
        # The rates over the element's step from its strain history (E and q at its last
        # evaluation): the same as the law of the velocities the nodes moved with, to
        # O(dt |grad v|) (seed_strain_history), without gathering the velocities.
        Ev = ti.Vector([E[0, 0], E[1, 1], E[0, 1]])
        inv_dt = 1.0 / dt
        Edv = (Ev - m.e_prev[e]) * inv_dt
        qd = (q - m.q_prev[e]) * inv_dt
        m.e_prev[e] = Ev
        m.q_prev[e] = q
        beta = m.beta_e[e]
        Ed = ti.Matrix([[Edv[0], Edv[2]], [Edv[2], Edv[1]]])
        Sd, _ = m.material_law.stress(lam, mu, Ed)
        S += beta * Sd
        fq -= beta * k_hg * qd
        power = beta * (at * m.material_law.rate_power(lam, mu, Ed))
        # Plain read-add-write: each element owns its slot, no atomic needed.
        m.e_damp[e] = m.e_damp[e] + dt * (power + beta * k_hg * qd.dot(qd))
    P = F @ S
    for k in ti.static(range(4)):
        m.fe[4 * e + k] = -at * (P @ ti.Vector([bx[k], by[k]])) + g[k] * fq
    if not F.determinant() > 0.0:
        k = e // m.member_elements  # its ensemble member's first
        ti.atomic_min(m.bad_element[k], e - k * m.member_elements)


@ti.kernel
def seed_strain_history(m: ti.template(), dt: ti.f64, multirate: ti.i32):
    r"""Each element's strain history (``m.e_prev``, ``m.q_prev``: the Green strain and
    hourglass sum at its previous evaluation, one element step ``dt_e`` ago) as the
    nodes' present velocities imply it: :math:`E - \Delta t_e \, dE/dt` with the Green
    strain rate :math:`\operatorname{sym}(F^T \nabla v)` and
    :math:`q - \Delta t_e \sum \gamma v`. The next evaluation's rates from the history are
    then those of the velocities, as a restart (half step) takes them.
    ``dt_e`` is ``dt`` times :math:`2^c` for an element of multi-rate class :math:`c` (the
    fastest of its nodes' classes) when ``multirate``, else ``dt``."""
    for e in range(m.n_elements):
        c = m.conn[e]
        bx, by, g = m.bx[e], m.by[e], m.gam[e]
        F, q = gradient(m.x, c, bx, by, g)
        Fd, qd = gradient(m.v, c, bx, by, g)
        E = green_strain(F)
        Ed = 0.5 * (F.transpose() @ Fd + Fd.transpose() @ F)
        dt_e = dt
        if ti.static(m.multirate_levels > 0):
            if multirate != 0:
                cls = m.mr_node_class[c[0]]
                for k in ti.static(range(1, 4)):
                    cls = ti.min(cls, m.mr_node_class[c[k]])
                dt_e = dt * ti.cast(1 << cls, ti.f64)
        m.e_prev[e] = ti.Vector([E[0, 0] - dt_e * Ed[0, 0], E[1, 1] - dt_e * Ed[1, 1],
                                 E[0, 1] - dt_e * Ed[0, 1]])  # fmt: skip
        m.q_prev[e] = q - dt_e * qd


@ti.func
def element_energy(m: ti.template(), e):
    """Element ``e``'s strain and hourglass energies and ``det F`` at the current
    positions, into ``m.e_int``, ``m.e_hg`` and ``m.jac``."""
    c = m.conn[e]
    F, q = gradient(m.x, c, m.bx[e], m.by[e], m.gam[e])
    lam, mu = m.lam[e], m.mu[e]
    E = green_strain(F)
    m.e_int[e] = m.at[e] * m.material_law.energy_density(lam, mu, E)
    m.e_hg[e] = 0.5 * m.khg[e] * q.dot(q)
    m.jac[e] = F.determinant()


@ti.func
def von_mises(m: ti.template(), e):
    """Cauchy von Mises stress of element ``e`` at the current positions, Pa (plane
    strain: ``E_zz = 0``, ``F_zz = 1``)."""
    c = m.conn[e]
    F, _ = gradient(m.x, c, m.bx[e], m.by[e], m.gam[e])
    lam = m.lam[e]
    E = green_strain(F)
    S, tr_e = m.material_law.stress(lam, m.mu[e], E)
    J = F.determinant()
    sig = F @ S @ F.transpose() / J
    szz = lam * tr_e / J
    sxx, syy, sxy = sig[0, 0], sig[1, 1], sig[0, 1]
    return ti.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * sxy * sxy)


# Module-level, not Model methods: Taichi 1.7 compiles a class's kernels without their
# module's globals, so a method kernel cannot call a module-level function.
@ti.kernel
def record_element_energies(m: ti.template()):
    """Every element's energies and ``det F`` (:func:`element_energy`) at the current
    positions. One kernel of its own, whatever the stepping mode, so that the recorded
    energies do not depend on it: inside a stepping kernel the compiler groups an
    element's energy terms differently from mode to mode (fast math), which changed
    their last bit, and the dynamic relaxation's damping is computed from them."""
    for e in range(m.n_elements):
        element_energy(m, e)


@ti.kernel
def store_von_mises(m: ti.template()):
    """Every element's von Mises stress into ``m.von_mises``."""
    for e in range(m.n_elements):
        m.von_mises[e] = von_mises(m, e)
