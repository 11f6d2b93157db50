"""The penalty contact law shared by node-to-segment contact and the rigid cage: normal
force with viscous damping, and Coulomb friction with an elastic stick spring.

Taichi functions of plain scalars; each returns the new forces and what it dissipated in
the step, so the callers keep their own state and energy sums.
"""

# No `from __future__ import annotations`: Taichi reads annotations at definition.
import taichi as ti

__all__ = ["friction_force", "normal_force"]


@ti.func
def normal_force(k, pen, zeta, m_eff, vn, dt):
    """Normal force ``max(0, k pen - c vn)``, ``c = 2 zeta sqrt(k m_eff)``; ``vn`` is the
    separating normal velocity. Returns (force, damping energy dissipated in ``dt``)."""
    fn_el = k * pen
    fn = ti.max(fn_el - 2.0 * zeta * ti.sqrt(k * m_eff) * vn, 0.0)
    return fn, -(fn - fn_el) * vn * dt


@ti.func
def friction_force(ft0, e_t0, k, vt, fn, dt, mu_s, mu_d, decay):
    """Elastic stick ``ft0 - k dt vt`` return-mapped onto ``|ft| <= mu fn``,
    ``mu = mu_d + (mu_s - mu_d) exp(-decay |vt|)``.

    ``ft0`` and ``e_t0`` are the spring force and energy kept from the last step (zero
    after a reset). Returns (ft, spring energy, energy dissipated in ``dt``): the
    midpoint work of the friction force on the slip less the spring's energy change.
    """
    ft = ft0 - k * dt * vt
    mu = mu_d + (mu_s - mu_d) * ti.exp(-decay * ti.abs(vt))
    lim = mu * fn
    if ti.abs(ft) > lim:
        ft = lim if ft > 0.0 else -lim
    e_t = 0.5 * ft * ft / k
    return ft, e_t, -0.5 * (ft0 + ft) * vt * dt - (e_t - e_t0)
