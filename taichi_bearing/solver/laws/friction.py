"""Coulomb friction with an elastic stick spring, shared by node-to-segment contact and the
rigid cage whatever their normal law (:mod:`taichi_bearing.solver.laws.contact`).

A Taichi function of plain scalars; it returns the new force and what it dissipated in
the step, so the callers keep their own state and energy sums.
"""

# No `from __future__ import annotations`: Taichi reads annotations at definition.
import taichi as ti

__all__ = ["friction_force"]


@ti.func
def friction_force(ft0, e_t0, k, vt, fn, dt, mu_s, mu_d, decay):
    r"""Elastic stick :math:`f_{t0} - k \, \Delta t \, v_t` return-mapped onto
    :math:`|f_t| \le \mu f_n`,
    :math:`\mu = \mu_d + (\mu_s - \mu_d) \exp(-\mathrm{decay} \, |v_t|)`.

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
