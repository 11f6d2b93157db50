r"""What happens in one time step: the step body, written once.

A step (central difference, leapfrog) from time ``t_n`` runs five phases in order; every
stepping mode (:mod:`taichi_bearing.solver.stepping`) runs exactly these, and each phase
starts once every member has finished the one before:

1. ``CLEAR``: each force contributor clears its share of what it sums over the step;
   the dead loads at ``t_n``;
2. ``FORCES``: element forces (:func:`~taichi_bearing.solver.element_forces.element_forces`,
   into per-element slots) and each contributor's share of its forces (into the
   fixed-point field ``f_extra``; see :mod:`taichi_bearing.solver.contributor`);
3. ``GATHER``: each contributor's end of the step (sums over the step, a rigid body's own
   update), and each rigid-plate node's force along the plate;
4. ``NODES``: each node gathers its element forces in a fixed order, adds ``f_extra`` and
   the loads, and moves: :math:`v^{n+1/2} = v^{n-1/2} + \Delta t \, a^n`,
   :math:`x^{n+1} = x^n + \Delta t \, v^{n+1/2}`,
   then constraints and the work of the non-elastic forces; a plate node takes the
   plate's one velocity, which each of them sums from the plate forces in one order;
5. ``SENSORS`` (one member): the sensor sums, averaged later over each output interval.

Phases 1 to 4 are split among the members (``share``), what must be serial within them
done by member 0; 5 runs on member 0. On a GPU each phase is one launch and a serial one
runs on one thread, where every dependent memory read waits its full latency: so only
the two sensors' sums are left serial. No sum depends on how the members split the work,
so a run is bit-reproducible on any number of threads. :func:`step_times` says when the
step is (the only place step times are computed).
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import taichi as ti

from taichi_bearing.solver.contributor import force_at
from taichi_bearing.solver.element_forces import element_forces
from taichi_bearing.solver.team import share

__all__ = [
    "CLEAR",
    "FORCES",
    "GATHER",
    "NODES",
    "N_PHASES",
    "SENSORS",
    "SHARED",
    "step_phase",
    "step_times",
]

CLEAR, FORCES, GATHER, NODES, SENSORS = range(5)
N_PHASES = 5
# Phases split among the members (the others run on member 0 alone).
SHARED = (True, True, True, True, False)

# Node flags (Model.bc), bits: constraints, then whether a dead load or a force
# contributor can act on the node (the others skip reading those fields: less memory
# traffic, the same sums), and whether a sensor records it.
FIXED, HELD, ROTATED, PLATE, LOADED, EXTRA, SENSOR = 1, 2, 4, 8, 16, 32, 64
# A force besides the elements' can act on a node with one of these.
ACTED_ON = FIXED | HELD | ROTATED | PLATE | LOADED | EXTRA


@ti.func
def step_times(k, n, step0, dt, first0, rec_last, relax, levels: ti.template()):
    """Step ``k`` of ``n`` launched together from step count ``step0``:
    ``(first, dt_v, rec, t_load, t_rot, moving)``.

    The first step after a restart (``first0``) is a half step for the velocities; the
    nodes' velocities at ``t_n`` are recorded (``rec``) on the last step when
    ``rec_last`` (the elements' energies by a kernel of their own before it:
    :func:`~taichi_bearing.solver.element_forces.record_element_energies`); loads act at
    ``t_n`` and prescribed rotations reach ``t_{n+1}``; dynamic relaxation (``relax``)
    holds the loads at full value and the rotations at angle 0.

    With multi-rate stepping (``levels`` > 0, :mod:`~taichi_bearing.solver.multirate`),
    ``moving`` is the highest step class whose nodes change velocity at this step: the
    number of times 2 divides the step count, at most ``levels``; -1 (every node, as in
    single-rate stepping) in dynamic relaxation or without multi-rate stepping.
    """
    moving = -1
    if ti.static(levels > 0):
        if relax == 0:
            g = step0 + k
            moving = 0
            while moving < levels and ((g >> moving) & 1) == 0:
                moving += 1
    t = (step0 + k) * dt
    first = 0
    dt_v = dt
    if first0 != 0 and k == 0:
        first = 1
        dt_v = 0.5 * dt
    rec = 0
    if rec_last != 0 and k == n - 1:
        rec = 1
    t_load = t
    t_rot = t + dt
    if relax != 0:
        t_load = 1e300
        t_rot = 0.0
    return first, dt_v, rec, t_load, t_rot, moving


@ti.func
def step_phase(m: ti.template(), phase: ti.template(), member, n_members: ti.template(),
               dt, first, dt_v, rec, t_load, t_rot, moving, c_mass,
               damped: ti.template()):  # fmt: skip
    """Member ``member`` of ``n_members``'s part of one phase of a step of model ``m``
    (see the module notes). ``c_mass``: dynamic relaxation's mass damping, 1/s (0: none);
    ``damped``: whether the elements have stiffness-proportional damping; ``moving``: the
    highest step class that moves (:func:`step_times`)."""
    if ti.static(phase == CLEAR):
        for c in ti.static(m.kernel_contributors):
            c.step_begin(member, n_members)
        apply_loads(m, t_load, member, n_members)
    if ti.static(phase == FORCES):
        if ti.static(m.multirate_levels == 0):
            e0, e1 = share(m.n_elements, member, n_members)
            for e in range(e0, e1):
                element_forces(m, e, dt, damped)
        else:
            # Each moving class's elements (a run of the class-sorted list), shared among
            # the members class by class: the same elements stay with the same member
            # (its cache) and every member gets its part of each class (the balance).
            # An element is evaluated once per step of its class, its damping working
            # for that step (2**c steps; one in relaxation, where every class moves).
            top = m.multirate_levels
            if moving >= 0:
                top = moving
            for c in range(top + 1):
                lo = 0
                if c > 0:
                    lo = m.mr_count[c - 1]
                dt_e = dt
                if moving >= 0:
                    dt_e = dt * ti.cast(1 << c, ti.f64)
                j0, j1 = share(m.mr_count[c] - lo, member, n_members)
                for j in range(lo + j0, lo + j1):
                    element_forces(m, m.mr_order[j], dt_e, damped)
        for c in ti.static(m.kernel_contributors):
            c.step_share(member, n_members, m.x, m.v, m.mass, m.f_extra, dt, dt_v)
    if ti.static(phase == GATHER):
        for c in ti.static(m.kernel_contributors):
            c.step_end(member, n_members, m.x, m.v, m.mass, m.f_extra, dt, dt_v)
        plate_forces(m, member, n_members)
    if ti.static(phase == NODES):
        i0, i1 = share(m.n_nodes, member, n_members)
        for i in range(i0, i1):
            if ti.static(m.ensemble_size == 1):
                node_step(m, i, t_rot, dt, dt_v, first, c_mass, rec, moving)
            else:
                # an ensemble: each member its own relaxation damping; one held still
                # keeps its state (its elements' and contributors' forces go unused)
                k = i // m.member_nodes
                if m.member_on[k] != 0:
                    node_step(m, i, t_rot, dt, dt_v, first, m.relax_c[k], rec, moving)
    if ti.static(phase == SENSORS):
        for s in range(m.n_sensor):
            sensor_sum(m, s, dt, dt_v, first)


@ti.func
def load_amplitude(m: ti.template(), k, t_load):
    """Load ``k``'s ramp factor at time ``t_load``."""
    tr = m.load_ramp[k]
    amp = 1.0
    if tr > 0.0 and t_load < tr:
        amp = t_load / tr
    return amp


@ti.func
def apply_loads(m: ti.template(), t_load, member, n_members: ti.template()):
    """Dead loads into ``m.f_load`` at time ``t_load``, ramped: each member its share
    where every load has a node of its own, else member 0 all, in a fixed order."""
    if ti.static(m.loads_unique):
        k0, k1 = share(m.n_load, member, n_members)
        for k in range(k0, k1):
            # zero, then add, as member 0 does below: the same bits (a plain store would
            # keep a -0.0 that 0.0 + -0.0 turns into 0.0)
            m.f_load[m.load_node[k]] = ti.Vector.zero(ti.f64, 2)
            m.f_load[m.load_node[k]] += load_amplitude(m, k, t_load) * m.load_force[k]
    elif member == 0:
        # f_load is non-zero only at load nodes: clear those, not every node each step.
        for k in range(m.n_load):
            m.f_load[m.load_node[k]] = ti.Vector.zero(ti.f64, 2)
        for k in range(m.n_load):
            m.f_load[m.load_node[k]] += load_amplitude(m, k, t_load) * m.load_force[k]


@ti.func
def plate_forces(m: ti.template(), member, n_members: ti.template()):
    """Each plate node's force along its plate (element forces gathered as the node
    update does, plus loads and contributors), this member's share; member 0 keeps each
    plate's velocity before the step."""
    if ti.static(m.n_plate > 0):
        k0, k1 = share(m.n_plate, member, n_members)
        for k in range(k0, k1):
            i = m.plate_node[k]
            f = force_at(m.f_extra, i) + m.f_load[i]
            for s in range(m.adj_ptr[i], m.adj_ptr[i + 1]):
                f += m.fe[m.adj[s]]
            m.plate_f[k] = f.dot(m.plate_dir[m.plate_slot[k]])
        if member == 0:
            for p in range(m.n_plates):
                m.plate_vo[p] = m.v[m.plate_node[p * m.plate_size]].dot(m.plate_dir[p])


@ti.func
def plate_velocity(m: ti.template(), p, dt_v, c_mass):
    """Rigid plate ``p``'s one velocity: its total force along its direction over its
    total mass, summed in one order (each of its nodes computes it alike)."""
    f_sum = 0.0
    m_sum = 0.0
    base = p * m.plate_size
    for j in range(m.plate_size):
        f_sum += m.plate_f[base + j]
        m_sum += m.mass[m.plate_node[base + j]]
    vo = m.plate_vo[p]
    vn = vo + dt_v * f_sum / m_sum
    if c_mass > 0.0:
        vn = ((1.0 - 0.5 * c_mass * dt_v) * vo + dt_v * f_sum / m_sum) / (1.0 + 0.5 * c_mass * dt_v)
    return vn


@ti.func
def rotation_angle(m: ti.template(), g, t):
    """Angle of prescribed rotation ``g`` at time ``t`` (the law of
    :func:`taichi_bearing.solver.loads.rotation_angle`)."""
    p = m.rot_par[g]
    w0, w1, tr = p[0], p[1], p[2]
    th = 0.0
    if t < tr:
        th = w0 * t + 0.5 * (w1 - w0) * t * t / tr
    else:
        th = 0.5 * (w0 + w1) * tr + w1 * (t - tr)
    return th


@ti.func
def node_update(m: ti.template(), i, t_rot, dt, dt_v, first, c_mass, rec):
    """Node ``i``: gather the forces, move, apply its constraint, count the work of the
    non-elastic forces (loads, reactions, contributors)."""
    flag = m.bc[i]
    f_int = ti.Vector.zero(ti.f64, 2)
    for s in range(m.adj_ptr[i], m.adj_ptr[i + 1]):
        f_int += m.fe[m.adj[s]]
    f = f_int
    if flag & EXTRA:
        f += force_at(m.f_extra, i)
        m.f_extra[i] = ti.Vector.zero(ti.i64, 2)
    if flag & LOADED:
        f += m.f_load[i]
    mass = m.mass[i]
    vo = m.v[i]
    xo = m.x[i]
    vn = vo + dt_v * f / mass
    if c_mass > 0.0:  # dynamic relaxation: viscous mass damping
        vn = ((1.0 - 0.5 * c_mass * dt_v) * vo + dt_v * f / mass) / (1.0 + 0.5 * c_mass * dt_v)
    if flag & HELD:
        d = m.held_dir[i]
        vn -= vn.dot(d) * d
    if flag & PLATE:
        p = m.plate_id[i]
        vn = plate_velocity(m, p, dt_v, c_mass) * m.plate_dir[p]
    xn = xo + dt * vn
    if flag & ROTATED:
        g = m.rot_group[i]
        th = rotation_angle(m, g, t_rot)
        cen = m.rot_center[g]
        r = m.X[i] - cen
        cs, sn = ti.cos(th), ti.sin(th)
        xn = cen + ti.Vector([cs * r[0] - sn * r[1], sn * r[0] + cs * r[1]])
        vn = (xn - xo) / dt
    if flag & FIXED:
        xn = m.X[i]
        vn = ti.Vector.zero(ti.f64, 2)
    an = (vn - vo) / dt_v
    if (flag & ACTED_ON) != 0 or c_mass > 0.0:
        # The non-elastic force and its work. On a node no load, constraint, contributor
        # or relaxation damping acts it is zero: computed, only the rounding of
        # mass * an - f_int (most nodes; skipping them is 0.3 of the node update).
        fo = mass * an - f_int
        if first == 0:
            # Trapezoidal work over [t_{n-1}, t_n]: x^n - x^{n-1} = dt v^{n-1/2}.
            m.work[i] = m.work[i] + 0.5 * dt * vo.dot(m.f_other[i] + fo)
        m.f_other[i] = fo
    if rec != 0:
        vi = vo
        if first == 0:
            vi = 0.5 * (vo + vn)
        m.v_int[i] = vi
    m.x[i] = xn
    m.v[i] = vn
    if flag & SENSOR:  # only the sensors read it
        m.a[i] = an


@ti.func
def node_step(m: ti.template(), i, t_rot, dt, dt_v, first, c_mass, rec, moving):
    """Node ``i``'s update at this step, single-rate or multi-rate."""
    if ti.static(m.multirate_levels == 0):
        node_update(m, i, t_rot, dt, dt_v, first, c_mass, rec)
    else:
        node_multirate(m, i, t_rot, dt, dt_v, first, c_mass, rec, moving)


@ti.func
def node_multirate(m: ti.template(), i, t_rot, dt, dt_v, first, c_mass, rec, moving):
    """Node ``i`` under multi-rate stepping: at a step of its class, the update of
    :func:`node_update` with its class's velocity step (:math:`2^c` times ``dt_v``); between
    them it keeps its velocity and moves with it (linear interpolation of its path). Its
    velocity at ``t_n`` where it does not update is its current one. Only nodes nothing but
    their elements acts on are in a class above 0."""
    c = 0
    if moving >= 0:
        c = m.mr_node_class[i]
    if c <= moving or moving < 0:
        scale = ti.cast(1 << c, ti.f64)
        node_update(m, i, t_rot, dt, dt_v * scale, first, c_mass, rec)
    else:
        vo = m.v[i]
        if rec != 0:
            m.v_int[i] = vo
        m.x[i] = m.x[i] + dt * vo


@ti.func
def sensor_sum(m: ti.template(), s, dt, dt_v, first):
    """Add sensor ``s``'s displacement, velocity (at ``t_n``) and acceleration to its sums."""
    i = m.sensor_node[s]
    vn = m.v[i]
    an = m.a[i]
    vo = vn - dt_v * an
    vi = vo
    if first == 0:
        vi = 0.5 * (vo + vn)
    u = m.x[i] - dt * vn - m.X[i]
    m.sensor_sum[s] = m.sensor_sum[s] + ti.Vector([u[0], u[1], vi[0], vi[1], an[0], an[1]])
