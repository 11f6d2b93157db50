"""The arc patch of the smooth node-to-segment contact (Taichi functions of a
:class:`~taichi_bearing.solver.contact.PenaltyContact` ``c``): each segment is the chord of
a reference arc of curvature ``kappa`` (0 at flats, corners and open ends), and a query
node stands for its tributary arc, so a polygonal roller rolls like a circle."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import taichi as ti

__all__ = ["arc_frame", "patch_overlap"]


@ti.func
def arc_frame(c: ti.template(), s, xi, x: ti.template()):
    """Unit tangent and outward normal of segment s's arc at xi in [0, 1]: the
    chord's turned by kappa L (xi - 1/2) (the chord's own when kappa = 0)."""
    d = x[c.seg_b[s]] - x[c.seg_a[s]]
    ln = d.norm()
    tc = d / ln
    th = c.seg_kappa[s] * ln * (xi - 0.5)
    cs, sn = ti.cos(th), ti.sin(th)
    tv = ti.Vector([cs * tc[0] - sn * tc[1], sn * tc[0] + cs * tc[1]])
    return tv, ti.Vector([tv[1], -tv[0]])


@ti.func
def patch_overlap(c: ti.template(), q, i, s, pen0, xi_raw, x: ti.template()):
    r"""Penetration of the query's tributary arc (half-way to each neighbour) into
    segment s's arc,
    :math:`p(r) = \mathrm{pen}_0 - r \, (u \cdot n) - (\kappa_q + \kappa_s) r^2 / 2` along
    the arc length :math:`r` from the node (:math:`u`: the query surface's direction,
    reversed).

    Returns (mean of :math:`\max(0, p)` over the patch, mean of :math:`\max(0, p)^2 / 2`,
    largest :math:`p`):
    the first is the penalty's penetration (its sum over nodes is the integral of the
    overlap along the surface, which does not ripple as a polygon rolls), the second
    the stored energy per unit k. Exact (3-point Gauss on each piece where p > 0).
    """
    xi = ti.min(ti.max(xi_raw, 0.0), 1.0)
    tv, nv = arc_frame(c, s, xi, x)
    xp, xa, xb = x[i], x[c.q_prev[q]], x[c.q_next[q]]
    h = 0.25 * ((xp - xa).norm() + (xb - xp).norm())  # half the tributary length
    u = xa - xb
    un = u.norm()
    b = 0.0
    # The patch point at r is xp + r u/|u|; its projection on the chord moves by
    # g r. At a corner end (a spall edge) the segment's surface stops: only the
    # part of the patch that projects inside counts (the rest faces the wall or
    # the void; the other pass catches a corner pressing into this surface).
    lo, hi = -h, h
    if un > 0.0:
        b = u.dot(nv) / un
        d = x[c.seg_b[s]] - x[c.seg_a[s]]
        g = u.dot(d) / (un * d.dot(d))
        corner = c.seg_corner[s]
        if corner & 1:
            if g > 0.0:
                lo = ti.max(lo, -xi_raw / g)
            elif g < 0.0:
                hi = ti.min(hi, -xi_raw / g)
            elif xi_raw < 0.0:
                hi = lo
        if corner & 2:
            if g > 0.0:
                hi = ti.min(hi, (1.0 - xi_raw) / g)
            elif g < 0.0:
                lo = ti.max(lo, (1.0 - xi_raw) / g)
            elif xi_raw > 1.0:
                hi = lo
    hi = ti.max(hi, lo)
    kap = c.q_kappa[q] + c.seg_kappa[s]  # curvature of the overlap
    # Roots of p: A r^2 + B r + C = 0 (numerically stable form), clipped to [lo, hi].
    A, B, C = 0.5 * kap, b, -pen0
    r1, r2 = hi, hi
    disc = B * B - 4.0 * A * C
    if disc >= 0.0:
        qq = -0.5 * (B + ti.sqrt(disc)) if B >= 0.0 else -0.5 * (B - ti.sqrt(disc))
        if ti.abs(qq) > 0.0:
            ra = C / qq
            rb = ra
            if ti.abs(A) > 0.0:
                rb = qq / A
            r1 = ti.min(ti.max(ti.min(ra, rb), lo), hi)
            r2 = ti.min(ti.max(ti.max(ra, rb), lo), hi)
    i1, i2 = 0.0, 0.0
    e = ti.Vector([lo, r1, r2, hi])
    g3 = ti.sqrt(0.6)
    for k in ti.static(range(3)):
        a3, b3 = e[k], e[k + 1]
        mid, half = 0.5 * (a3 + b3), 0.5 * (b3 - a3)
        if half > 0.0:
            pm = pen0 - mid * (b + 0.5 * kap * mid)
            if pm > 0.0:
                for j in ti.static(range(3)):
                    r = mid + half * g3 * (j - 1)
                    pr = pen0 - r * (b + 0.5 * kap * r)
                    wgt = half * (8.0 / 9.0 if j == 1 else 5.0 / 9.0)
                    i1 += wgt * pr
                    i2 += wgt * pr * pr
    # Largest p over [lo, hi]: at an end or at the parabola's vertex inside (an empty
    # patch: nothing, so no contact).
    pmax = -1.0
    if hi > lo:
        pmax = ti.max(pen0 - lo * (b + 0.5 * kap * lo), pen0 - hi * (b + 0.5 * kap * hi))
        if kap > 0.0:
            rv = ti.min(ti.max(-b / kap, lo), hi)
            pmax = ti.max(pmax, pen0 - rv * (b + 0.5 * kap * rv))
    w = 2.0 * h
    return i1 / w, 0.5 * i2 / w, pmax
