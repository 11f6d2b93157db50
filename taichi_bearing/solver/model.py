"""The explicit model: Taichi fields of nodes and elements, and the kernels of one step.

One step (central difference, leapfrog) from time ``t_n``:

1. element loop: ``F``, Green strain, St Venant-Kirchhoff stress, hourglass and
   stiffness-proportional damping forces -> per-element nodal forces (no atomics);
2. extra force contributors (contact, cage) add into ``f_extra``, a fixed-point field
   (integer multiples of :data:`FORCE_QUANTUM`): integer adds give the same sum in any
   order, so the atomic adds of several threads do not change the result;
3. dead loads (into ``f_load``, in a fixed order), then the node loop: gather element
   forces (fixed order), so runs are bit-reproducible on any thread count;
   ``v^{n+1/2} = v^{n-1/2} + dt a^n``,
   ``x^{n+1} = x^n + dt v^{n+1/2}``, constraints, work of the non-elastic forces;
4. sensor sums (averaged later over each output interval).

Without contributors, steps 1-4 are one kernel launch; small meshes can also run many
steps in one serial kernel, and on several CPU threads many steps run in one launch as a
team of persistent threads that meet at spin barriers (:meth:`Model.advance` chooses).
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import os
from collections.abc import Mapping, Sequence
from typing import Protocol

import numpy as np
import taichi as ti

from taichi_bearing.mesh.types import Mesh
from taichi_bearing.solver.backend import current_arch, current_threads, serial_loops
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.element import (
    assembled_matrix,
    assembled_max_frequency,
    critical_time_steps,
    element_geometry,
    element_max_frequencies,
    element_stiffness,
    hourglass_stiffness,
    selective_mass_scale,
)
from taichi_bearing.solver.loads import (
    FixedNodes,
    HeldDirection,
    NodalForces,
    PrescribedRotation,
    RigidPlate,
    RigidVelocity,
)
from taichi_bearing.solver.materials import Material, materials_per_element

# StiffnessDamping: re-export
__all__ = [
    "FORCE_QUANTUM",
    "ForceContributor",
    "Model",
    "StiffnessDamping",
    "add_force",
    "force_at",
]

_FIXED, _HELD, _ROT, _PLATE = 1, 2, 4, 8
TIME_STEP_METHODS = ("element", "global")
# Below this many elements a block of steps runs as one serial kernel (launch-bound regime).
SERIAL_MAX_ELEMENTS = 3000
# Team stepping: a barrier spin this long means a team member never came (then the launch
# stops and advance raises): seconds, far beyond any one phase of a step.
TEAM_SPIN_LIMIT = 1 << 28
TEAM_MAX_THREADS = 256

# Extra nodal forces are summed as integers of this many newtons (see add_force): the
# rounding (at most 7e-12 N a contribution) is far below anything a bearing model resolves,
# and one contribution is capped at 2^60 quanta (1.7e7 N, a runaway the energy and
# inversion checks stop), so a node's sum of a few cannot overflow.
FORCE_QUANTUM = 2.0**-36
_FORCE_SCALE = 2.0**36
_FORCE_CAP = 2.0**60


class ForceContributor(Protocol):
    """Something that adds nodal forces each step (e.g. contact).

    ``add_forces(model, t)`` is called after the element forces of step n and before the
    velocity update; it reads ``model.x`` / ``model.v`` (positions at ``t``, velocities at
    ``t - dt/2``) and adds forces (N) into ``model.f_extra`` with :func:`add_force` (a
    fixed-point field: the sum does not depend on the order of the atomic adds).

    A contributor can also be fused into the model's step kernels (one launch per step,
    or per chunk of steps on one thread) by defining the Taichi function
    ``step_forces(x, v, mass, f_ext, dt, dt_v)`` (the same forces as ``add_forces``),
    ``before_steps(model, n) -> int`` (Python, before up to ``n`` fused steps; returns how
    many may run before it needs Python again, at least 1) and ``after_steps(model, n)``.

    For team stepping on several CPU threads (one launch runs many steps; the threads meet
    at barriers) a fused contributor also defines the Taichi functions
    ``team_begin(member, n_members)`` (before the forces: each member clears its share),
    ``team_share(member, n_members, x, v, mass, f_ext, dt, dt_v)`` (each member's share of
    the forces, beside its share of the elements; adds to shared nodes with add_force) and
    ``team_end(x, v, mass, f_ext, dt, dt_v)`` (member 0 alone, after all shares).
    """

    def add_forces(self, model: "Model", t: float) -> None: ...


@ti.func
def add_force(f: ti.template(), i, F):
    """Add the force vector ``F`` (N) on node ``i`` to the fixed-point field ``f`` (such
    as ``Model.f_extra``), rounded to :data:`FORCE_QUANTUM`. Safe from any thread."""
    f[i] += ti.cast(ti.round(ti.math.clamp(F * _FORCE_SCALE, -_FORCE_CAP, _FORCE_CAP)), ti.i64)


@ti.func
def force_at(f: ti.template(), i):
    """Node ``i``'s force (N) summed in the fixed-point field ``f``."""
    return ti.cast(f[i], ti.f64) * FORCE_QUANTUM


@ti.func
def share(count, member, n_members):
    """Member's contiguous share ``[lo, hi)`` of ``count`` items split among
    ``n_members`` (team stepping)."""
    return member * count // n_members, (member + 1) * count // n_members


def _adjacency(elements: np.ndarray, n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """CSR lists of the element-force slots (4 e + I) that act on each node."""
    slots = np.arange(elements.size, dtype=np.int64)
    node_of_slot = elements.ravel()
    order = np.argsort(node_of_slot, kind="stable")
    ptr = np.zeros(n_nodes + 1, dtype=np.int64)
    np.cumsum(np.bincount(node_of_slot, minlength=n_nodes), out=ptr[1:])
    return ptr.astype(np.int32), slots[order].astype(np.int32)


def _vec_field(n: int, dim: int = 2, dtype=ti.f64):
    return ti.Vector.field(dim, dtype, shape=max(n, 1))


def _scalar_field(n: int, dtype=ti.f64):
    return ti.field(dtype, shape=max(n, 1))


@ti.data_oriented
class Model:
    """A plane-strain explicit model built from a :class:`Mesh`.

    Parameters
    ----------
    mesh : Mesh
        Nodes, elements and parts; ``mesh.sensor_nodes`` are the default sensors.
    materials : Material or mapping of part name to Material
    thickness : float
        Plane-strain thickness, m; masses, forces and energies are for this thickness.
    constraints : sequence of FixedNodes, HeldDirection, PrescribedRotation, RigidPlate
        (at most one RigidPlate)
    loads : sequence of NodalForces
    initial_velocities : sequence of RigidVelocity
    damping : StiffnessDamping, optional
    hourglass_scale : float
        Multiplies the physical hourglass stiffness (1 = bending-exact for squares).
    sensors : mapping of str to int, optional
        Sensor name -> node; default ``mesh.sensor_nodes``.
    dt_factor : float
        Time step as a fraction of the critical step.
    time_step : {"element", "global"}
        How the critical step is found. ``"element"``: the smallest element's own
        (``2 / omega_e``, the element eigenvalue bound; with a square element this is
        the characteristic length over the wave speed). ``"global"``: the assembled
        mesh's highest frequency (:func:`~taichi_bearing.solver.element.assembled_max_frequency`),
        never smaller, and larger where small elements border larger ones; force
        contributors bound their stiffness with :meth:`add_stiffness_bound`.
    max_added_mass : float
        Selective mass scaling (:func:`~taichi_bearing.solver.element.selective_mass_scale`):
        the densest this may make the smallest elements, as added mass over each part's
        mass; 0 (default) = none. ``added_mass`` (kg per part) and ``n_mass_scaled`` say
        what was done (``part_mass``: each part's mass before it).

    Notes
    -----
    Taichi must be initialised first (:func:`taichi_bearing.solver.backend.init_taichi`).
    ``contributors`` is a list of :class:`ForceContributor` objects called every step.
    The critical step is found at its first read (``dt``, ``dt_stable``,
    ``critical_step``), after the contributors declared their bounds, and again after
    any later bound.
    """

    def __init__(
        self,
        mesh: Mesh,
        materials: Material | Mapping[str, Material],
        *,
        thickness: float = 1.0,
        constraints: Sequence[FixedNodes | HeldDirection | PrescribedRotation | RigidPlate] = (),
        loads: Sequence[NodalForces] = (),
        initial_velocities: Sequence[RigidVelocity] = (),
        damping: StiffnessDamping | None = None,
        hourglass_scale: float = 1.0,
        sensors: Mapping[str, int] | None = None,
        dt_factor: float = 0.9,
        max_added_mass: float = 0.0,
        time_step: str = "element",
    ) -> None:
        if current_arch() is None:
            # Otherwise Taichi would start itself on a default arch with f32.
            raise RuntimeError("call taichi_bearing.solver.init_taichi() before building a Model")
        if not thickness > 0:
            raise ValueError(f"thickness must be positive, got {thickness!r}")
        if time_step not in TIME_STEP_METHODS:
            raise ValueError(f"time_step must be one of {TIME_STEP_METHODS}, got {time_step!r}")
        self.mesh = mesh
        self.thickness = float(thickness)
        self.n_nodes = nn = mesh.n_nodes
        self.n_elements = ne = mesh.n_elements
        elements = np.asarray(mesh.elements, dtype=np.int64)
        geo = element_geometry(np.asarray(mesh.nodes, dtype=float), elements)
        lam, mu, rho, eprime = materials_per_element(mesh, materials)
        khg = hourglass_stiffness(geo, eprime, self.thickness, hourglass_scale)
        k_el = element_stiffness(geo, lam, mu, khg, self.thickness)
        omega_e = element_max_frequencies(geo, lam, mu, rho, khg, self.thickness, k_el)
        part = np.asarray(mesh.element_part)
        element_mass = rho * geo.area * self.thickness
        rho_scale = selective_mass_scale(omega_e, element_mass, part, max_added_mass)
        self.n_mass_scaled = int(np.count_nonzero(rho_scale > 1.0))
        self.part_mass = np.bincount(part, weights=element_mass)  # before scaling
        self.added_mass = np.bincount(part, weights=(rho_scale - 1.0) * element_mass)
        rho = rho * rho_scale
        omega_e = omega_e / np.sqrt(rho_scale)  # one element alone: omega ~ 1/sqrt(mass)
        self.damping = damping
        beta_e = damping.element_beta(omega_e) if damping is not None else np.zeros(ne)
        self.damped = bool(np.any(beta_e > 0))
        self.element_dt = critical_time_steps(omega_e, beta_e)
        self._omega_e_max = float(omega_e.max())
        mass = np.zeros(nn)
        np.add.at(mass, elements, geo.shape_integrals * (rho * self.thickness)[:, None])
        if np.any(mass <= 0):
            raise ValueError(f"node {int(np.argmin(mass))} belongs to no element (zero mass)")
        self.mass_np = mass
        self.area_np = geo.area
        self.time_step = time_step
        self.dt_factor = float(dt_factor)
        # contributors' springs and dashpots, see add_stiffness_bound
        self.node_stiffness = np.zeros(nn)
        self.node_damping = np.zeros(nn)
        self._global = None
        if time_step == "global":
            c = None
            if self.damped:
                c = assembled_matrix(k_el * beta_e[:, None, None], elements, mass)
            self._global = (assembled_matrix(k_el, elements, mass), c)
        # The critical step is found when first read (contributors add their bounds
        # first); a step set with set_dt is kept while it stays stable.
        self._step: tuple[float, float, float] | None = None
        self._dt_set: float | None = None

        # ---- nodes
        self.X = _vec_field(nn)
        self.x = _vec_field(nn)
        self.v = _vec_field(nn)
        self.a = _vec_field(nn)
        self.f_extra = _vec_field(nn, dtype=ti.i64)  # fixed point: see add_force
        self.f_load = _vec_field(nn)  # dead loads, added in a fixed order (any size)
        self.f_other = _vec_field(nn)  # non-elastic force of the last step (for work)
        self.v_int = _vec_field(nn)  # velocity at the last recorded integer step
        self.mass = _scalar_field(nn)
        self.work = _scalar_field(nn)  # external work done on each node so far
        self.bc = _scalar_field(nn, ti.i32)
        self.held_dir = _vec_field(nn)
        self.rot_group = _scalar_field(nn, ti.i32)
        ptr, adj = _adjacency(elements, nn)
        self.adj_ptr = _scalar_field(nn + 1, ti.i32)
        self.adj = _scalar_field(adj.size, ti.i32)
        # ---- elements
        self.conn = _vec_field(ne, 4, ti.i32)
        self.bx = _vec_field(ne, 4)
        self.by = _vec_field(ne, 4)
        self.gam = _vec_field(ne, 4)
        self.at = _scalar_field(ne)  # reference area x thickness
        self.khg = _scalar_field(ne)
        self.lam = _scalar_field(ne)
        self.beta_e = _scalar_field(ne)  # stiffness-damping coefficient, s
        self.mu = _scalar_field(ne)
        self.fe = _vec_field(4 * ne)  # element nodal forces, slot 4 e + I
        self.e_int = _scalar_field(ne)  # strain energy at the last recorded step
        self.e_hg = _scalar_field(ne)  # hourglass energy at the last recorded step
        self.e_damp = _scalar_field(ne)  # energy dissipated by damping so far
        self.jac = _scalar_field(ne)  # det F at the last recorded step
        self.von_mises = _scalar_field(ne)
        self.bad_element = ti.field(ti.i32, shape=())
        self.sums = ti.field(ti.f64, shape=6)
        # team stepping: barrier counter, who joined, and a failed-barrier flag
        self.team_bar = ti.field(ti.i64, shape=())
        self.team_joined = ti.field(ti.i32, shape=TEAM_MAX_THREADS)
        self.team_failed = ti.field(ti.i32, shape=())

        self.X.from_numpy(np.asarray(mesh.nodes, dtype=float))
        self.x.from_numpy(np.asarray(mesh.nodes, dtype=float))
        self.mass.from_numpy(mass)
        self.adj_ptr.from_numpy(ptr)
        self.adj.from_numpy(adj)
        self.conn.from_numpy(elements.astype(np.int32))
        self.bx.from_numpy(geo.b[..., 0].copy())
        self.by.from_numpy(geo.b[..., 1].copy())
        self.gam.from_numpy(geo.gamma)
        self.at.from_numpy(geo.area * self.thickness)
        self.khg.from_numpy(khg)
        self.lam.from_numpy(lam)
        self.mu.from_numpy(mu)
        self.beta_e.from_numpy(beta_e)
        self.bad_element[None] = ne

        self._setup_constraints(constraints)
        self._setup_loads(loads)
        self._setup_sensors(mesh.sensor_nodes if sensors is None else sensors)
        self.initial_velocities = list(initial_velocities)
        self.contributors: list[ForceContributor] = []
        self._fused: tuple | None = None  # contributors built into the step kernels
        self.step_count = 0
        self.set_initial_velocities()

    # ------------------------------------------------------------------ setup helpers

    def _setup_constraints(self, constraints) -> None:
        nn = self.n_nodes
        bc = np.zeros(nn, dtype=np.int32)
        held = np.zeros((nn, 2))
        rgroup = np.full(nn, -1, dtype=np.int32)
        rots: list[PrescribedRotation] = []
        plates = [c for c in constraints if isinstance(c, RigidPlate)]
        if len(plates) > 1:
            raise ValueError("RigidPlate: at most one plate per model")
        for c in constraints:
            ids = np.asarray(c.nodes)
            if ids.min() < 0 or ids.max() >= nn:
                raise ValueError(f"{type(c).__name__}: node index out of range 0..{nn - 1}")
            if isinstance(c, FixedNodes):
                bc[ids] |= _FIXED
            elif isinstance(c, HeldDirection):
                if np.any(bc[ids] & _HELD):
                    raise ValueError("HeldDirection: a node can hold only one direction")
                bc[ids] |= _HELD
                held[ids] = c.direction
            elif isinstance(c, PrescribedRotation):
                if np.any(rgroup[ids] >= 0):
                    raise ValueError("PrescribedRotation: a node is in two rotation sets")
                bc[ids] |= _ROT
                rgroup[ids] = len(rots)
                rots.append(c)
            elif isinstance(c, RigidPlate):
                if np.any(bc[ids] & (_HELD | _ROT)):
                    raise ValueError("RigidPlate: nodes already held or rotated")
                bc[ids] |= _PLATE
            else:
                raise TypeError(f"unknown constraint {type(c).__name__}")
        self.rotations = rots
        self.plate = plates[0] if plates else None
        self.n_plate = len(self.plate.nodes) if plates else 0
        self.plate_node = _scalar_field(self.n_plate, ti.i32)
        self.plate_dir = ti.Vector.field(2, ti.f64, shape=())
        self.plate_v = ti.field(ti.f64, shape=())
        if plates:
            self.plate_node.from_numpy(self.plate.nodes.astype(np.int32))
            self.plate_dir[None] = self.plate.direction
        self.bc.from_numpy(bc)
        self.held_dir.from_numpy(held)
        self.rot_group.from_numpy(rgroup)
        nr = len(rots)
        self.n_rot = nr
        self.rot_center = _vec_field(nr)
        self.rot_par = _vec_field(nr, 3)  # omega_start, omega, ramp_time
        if nr:
            self.rot_center.from_numpy(np.array([r.center for r in rots], dtype=float))
            self.rot_par.from_numpy(
                np.array([[r.omega_start, r.omega, r.ramp_time] for r in rots], dtype=float)
            )

    def _setup_loads(self, loads: Sequence[NodalForces]) -> None:
        nodes, forces, ramps = [], [], []
        for load in loads:
            if len(load.nodes) and (load.nodes.min() < 0 or load.nodes.max() >= self.n_nodes):
                raise ValueError("NodalForces: node index out of range")
            nodes.append(load.nodes)
            forces.append(load.forces)
            ramps.append(np.full(len(load.nodes), load.ramp_time))
        self.loads = list(loads)
        self.n_load = nl = int(sum(len(n) for n in nodes))
        self.load_node = _scalar_field(nl, ti.i32)
        self.load_force = _vec_field(nl)
        self.load_ramp = _scalar_field(nl)
        if nl:
            self.load_node.from_numpy(np.concatenate(nodes).astype(np.int32))
            self.load_force.from_numpy(np.concatenate(forces))
            self.load_ramp.from_numpy(np.concatenate(ramps))

    def _setup_sensors(self, sensors: Mapping[str, int]) -> None:
        self.sensor_names = list(sensors)
        ids = np.array([int(sensors[k]) for k in self.sensor_names], dtype=np.int32)
        if ids.size and (ids.min() < 0 or ids.max() >= self.n_nodes):
            raise ValueError("sensor node index out of range")
        self.n_sensor = ns = len(ids)
        self.sensor_node = _scalar_field(ns, ti.i32)
        self.sensor_sum = _vec_field(ns, 6)  # ux, uy, vx, vy, ax, ay
        if ns:
            self.sensor_node.from_numpy(ids)

    def part_nodes(self, part: str | int) -> np.ndarray:
        """Indices of the nodes of one part."""
        pid = self.mesh.part_id(part) if isinstance(part, str) else int(part)
        return np.unique(self.mesh.elements[self.mesh.element_part == pid])

    def set_initial_velocities(self) -> None:
        """Velocities from the :class:`RigidVelocity` list (zero elsewhere); restarts the
        leapfrog (the next step is a half step) and the work/damping accumulators."""
        X = np.asarray(self.mesh.nodes, dtype=float)
        v = np.zeros((self.n_nodes, 2))
        for rv in self.initial_velocities:
            ids = self.part_nodes(rv.part)
            v[ids] = rigid_velocity_field(X[ids], rv.omega, rv.center, rv.velocity)
        self.v.from_numpy(v)
        self.restart_accounting()

    def restart_accounting(self) -> None:
        """Zero the work/damping accumulators and start the leapfrog with a half step."""
        self.work.fill(0.0)
        self.e_damp.fill(0.0)
        self.f_other.fill(0.0)
        self.f_extra.fill(0)
        self.f_load.fill(0.0)
        self.sensor_sum.fill(0.0)
        self.first = True
        self.step_count = 0

    def _critical(self) -> tuple[float, float, float]:
        """(critical step, damping step factor, stable step) of the chosen estimate, found
        again after a bound was added."""
        if self._step is None:
            if self._global is None:
                step, undamped = float(self.element_dt.min()), 2.0 / self._omega_e_max
            else:
                k, c = self._global
                omega, zeta = assembled_max_frequency(
                    k, self.mass_np, c, self.node_stiffness, self.node_damping
                )
                step = float(critical_time_steps(np.array([omega]), 2.0 * zeta / omega)[0])
                undamped = 2.0 / omega
            self._step = (step, step / undamped, self.dt_factor * step)
        return self._step

    @property
    def critical_step(self) -> float:
        """Critical step of the chosen estimate, s (damping included)."""
        return self._critical()[0]

    @property
    def damping_step_factor(self) -> float:
        """By how much damping shortened the critical step (1 = not at all)."""
        return self._critical()[1]

    @property
    def dt_stable(self) -> float:
        """``dt_factor`` times the critical step, s."""
        return self._critical()[2]

    @property
    def dt(self) -> float:
        """Time step, s: the stable one, or the one given to :meth:`set_dt` (lowered to
        the stable one if a later bound made that smaller)."""
        stable = self.dt_stable
        return stable if self._dt_set is None else min(self._dt_set, stable)

    def add_stiffness_bound(
        self, nodes: np.ndarray, stiffness: np.ndarray, damping: np.ndarray | float = 0.0
    ) -> None:
        """Declare the springs (N/m) and dashpots (N s/m) a force contributor can add at
        ``nodes``, each as if to ground in both directions (a spring ``k`` between two
        nodes is bounded by ``2 k`` on each). With ``time_step="global"`` the critical
        step takes them in; the element estimate ignores them."""
        idx = np.asarray(nodes, dtype=np.int64)
        np.add.at(self.node_stiffness, idx, stiffness)
        np.add.at(self.node_damping, idx, damping)
        self._step = None

    def set_dt(self, dt: float) -> None:
        """Use a time step not above the stable one (e.g. to fit the output interval)."""
        if not 0 < dt <= self.dt_stable * (1 + 1e-12):
            raise ValueError(f"dt {dt!r} must lie in (0, {self.dt_stable!r}] (stable step)")
        self._dt_set = float(dt)

    @property
    def time(self) -> float:
        """Time of the current state, s (``step_count * dt``)."""
        return self.step_count * self.dt

    # ------------------------------------------------------------------ Taichi functions

    @ti.func
    def _rot_angle(self, g, t):
        p = self.rot_par[g]
        w0, w1, tr = p[0], p[1], p[2]
        th = 0.0
        if t < tr:
            th = w0 * t + 0.5 * (w1 - w0) * t * t / tr
        else:
            th = 0.5 * (w0 + w1) * tr + w1 * (t - tr)
        return th

    @ti.func
    def _gradient(self, field: ti.template(), c, bx, by, g):
        """Mean gradient sum_I y_I (x) b_I and hourglass sum_I gamma_I y_I of a node field."""
        G = ti.Matrix.zero(ti.f64, 2, 2)
        h = ti.Vector.zero(ti.f64, 2)
        for k in ti.static(range(4)):
            yk = field[c[k]]
            G += yk.outer_product(ti.Vector([bx[k], by[k]]))
            h += g[k] * yk
        return G, h

    @ti.func
    def _element(self, e, dt, damped: ti.template(), rec):
        c = self.conn[e]
        bx, by, g = self.bx[e], self.by[e], self.gam[e]
        F, q = self._gradient(self.x, c, bx, by, g)
        lam, mu = self.lam[e], self.mu[e]
        at, k_hg = self.at[e], self.khg[e]
        E = 0.5 * (F.transpose() @ F - ti.Matrix.identity(ti.f64, 2))
        tr_e = E[0, 0] + E[1, 1]
        S = lam * tr_e * ti.Matrix.identity(ti.f64, 2) + 2.0 * mu * E
        fq = -k_hg * q
        if ti.static(damped):
            Fd, qd = self._gradient(self.v, c, bx, by, g)
            beta = self.beta_e[e]
            # Green strain rate: zero for any rigid motion, so spin is not damped.
            Ed = 0.5 * (F.transpose() @ Fd + Fd.transpose() @ F)
            tr_d = Ed[0, 0] + Ed[1, 1]
            S += beta * (lam * tr_d * ti.Matrix.identity(ti.f64, 2) + 2.0 * mu * Ed)
            fq -= beta * k_hg * qd
            power = beta * (at * (lam * tr_d * tr_d + 2.0 * mu * (Ed * Ed).sum()))
            # Plain read-add-write: each element owns its slot, no atomic needed.
            self.e_damp[e] = self.e_damp[e] + dt * (power + beta * k_hg * qd.dot(qd))
        P = F @ S
        for k in ti.static(range(4)):
            self.fe[4 * e + k] = -at * (P @ ti.Vector([bx[k], by[k]])) + g[k] * fq
        J = F.determinant()
        if not J > 0.0:
            ti.atomic_min(self.bad_element[None], e)
        if rec != 0:
            self.e_int[e] = at * (0.5 * lam * tr_e * tr_e + mu * (E * E).sum())
            self.e_hg[e] = 0.5 * k_hg * q.dot(q)
            self.jac[e] = J

    @ti.func
    def _apply_loads(self, t_load):
        # f_load is non-zero only at load nodes: clear those, not every node each step.
        for k in range(self.n_load):
            self.f_load[self.load_node[k]] = ti.Vector.zero(ti.f64, 2)
        for k in range(self.n_load):
            tr = self.load_ramp[k]
            amp = 1.0
            if tr > 0.0 and t_load < tr:
                amp = t_load / tr
            self.f_load[self.load_node[k]] += amp * self.load_force[k]

    @ti.func
    def _plate_update(self, dt_v, c_mass):
        # The plate's one velocity: total force along its direction over its total mass
        # (element forces gathered as the node loop does, plus loads and contributors).
        if ti.static(self.n_plate > 0):
            d = self.plate_dir[None]
            f_sum = 0.0
            m_sum = 0.0
            for k in range(self.n_plate):
                i = self.plate_node[k]
                f = force_at(self.f_extra, i) + self.f_load[i]
                for s in range(self.adj_ptr[i], self.adj_ptr[i + 1]):
                    f += self.fe[self.adj[s]]
                f_sum += f.dot(d)
                m_sum += self.mass[i]
            vo = self.v[self.plate_node[0]].dot(d)
            vn = vo + dt_v * f_sum / m_sum
            if c_mass > 0.0:
                vn = ((1.0 - 0.5 * c_mass * dt_v) * vo + dt_v * f_sum / m_sum) / (
                    1.0 + 0.5 * c_mass * dt_v
                )
            self.plate_v[None] = vn

    @ti.func
    def _node(self, i, t_rot, dt, dt_v, first, c_mass, rec):
        f_int = ti.Vector.zero(ti.f64, 2)
        for s in range(self.adj_ptr[i], self.adj_ptr[i + 1]):
            f_int += self.fe[self.adj[s]]
        f = f_int + force_at(self.f_extra, i) + self.f_load[i]
        self.f_extra[i] = ti.Vector.zero(ti.i64, 2)
        m = self.mass[i]
        vo = self.v[i]
        xo = self.x[i]
        vn = vo + dt_v * f / m
        if c_mass > 0.0:  # dynamic relaxation: viscous mass damping
            vn = ((1.0 - 0.5 * c_mass * dt_v) * vo + dt_v * f / m) / (1.0 + 0.5 * c_mass * dt_v)
        flag = self.bc[i]
        if flag & _HELD:
            d = self.held_dir[i]
            vn -= vn.dot(d) * d
        if flag & _PLATE:
            vn = self.plate_v[None] * self.plate_dir[None]
        xn = xo + dt * vn
        if flag & _ROT:
            g = self.rot_group[i]
            th = self._rot_angle(g, t_rot)
            cen = self.rot_center[g]
            r = self.X[i] - cen
            cs, sn = ti.cos(th), ti.sin(th)
            xn = cen + ti.Vector([cs * r[0] - sn * r[1], sn * r[0] + cs * r[1]])
            vn = (xn - xo) / dt
        if flag & _FIXED:
            xn = self.X[i]
            vn = ti.Vector.zero(ti.f64, 2)
        an = (vn - vo) / dt_v
        # Non-elastic force on the node: loads, reactions, contributors.
        fo = m * an - f_int
        if first == 0:
            # Trapezoidal work over [t_{n-1}, t_n]: x^n - x^{n-1} = dt v^{n-1/2}.
            self.work[i] = self.work[i] + 0.5 * dt * vo.dot(self.f_other[i] + fo)
        self.f_other[i] = fo
        if rec != 0:
            vi = vo
            if first == 0:
                vi = 0.5 * (vo + vn)
            self.v_int[i] = vi
        self.x[i] = xn
        self.v[i] = vn
        self.a[i] = an

    @ti.func
    def _sensor(self, s, dt, dt_v, first):
        i = self.sensor_node[s]
        vn = self.v[i]
        an = self.a[i]
        vo = vn - dt_v * an
        vi = vo
        if first == 0:
            vi = 0.5 * (vo + vn)
        u = self.x[i] - dt * vn - self.X[i]
        self.sensor_sum[s] = self.sensor_sum[s] + ti.Vector(
            [u[0], u[1], vi[0], vi[1], an[0], an[1]]
        )

    @ti.func
    def _element_loop(self, dt, damped: ti.template(), rec, serial: ti.template()):
        ti.loop_config(serialize=serial)
        for e in range(self.n_elements):
            self._element(e, dt, damped, rec)

    @ti.func
    def _node_loops(self, t_load, t_rot, dt, dt_v, first, c_mass, rec, serial: ti.template()):
        # Inlined at kernel top level, so each loop is its own task; small meshes run them
        # on the calling thread (a thread-pool dispatch costs more than the work).
        ti.loop_config(serialize=True)  # loads: few entries, fixed order (reproducible)
        for _ in range(1):
            self._apply_loads(t_load)
            self._plate_update(dt_v, c_mass)
        ti.loop_config(serialize=serial)
        for i in range(self.n_nodes):
            self._node(i, t_rot, dt, dt_v, first, c_mass, rec)
        ti.loop_config(serialize=True)
        for s in range(self.n_sensor):
            self._sensor(s, dt, dt_v, first)

    # ------------------------------------------------------------------ kernels

    @ti.kernel
    def _k_elements(
        self, dt: ti.f64, damped: ti.template(), rec: ti.template(), serial: ti.template()
    ):
        self._element_loop(dt, damped, rec, serial)

    @ti.kernel
    def _k_nodes(
        self,
        t_load: ti.f64,
        t_rot: ti.f64,
        dt: ti.f64,
        dt_v: ti.f64,
        first: ti.i32,
        c_mass: ti.f64,
        rec: ti.template(),
        serial: ti.template(),
    ):
        self._node_loops(t_load, t_rot, dt, dt_v, first, c_mass, rec, serial)

    @ti.kernel
    def _k_step(
        self,
        t_load: ti.f64,
        t_rot: ti.f64,
        dt: ti.f64,
        dt_v: ti.f64,
        first: ti.i32,
        c_mass: ti.f64,
        rec: ti.template(),
        damped: ti.template(),
        serial: ti.template(),
        fused: ti.template(),
    ):
        self._element_loop(dt, damped, rec, serial)
        if ti.static(fused):
            for c in ti.static(self._fused):
                c.step_forces(self.x, self.v, self.mass, self.f_extra, dt, dt_v)
        self._node_loops(t_load, t_rot, dt, dt_v, first, c_mass, rec, serial)

    @ti.func
    def _step_times(self, k, n, step0, dt, first0, rec_last, relax):
        """Step k of n launched together: (first, dt_v, rec, t_load, t_rot). The first
        step after a restart is a half step for v; energies are recorded on the last;
        dynamic relaxation holds loads at full value and rotations at angle 0."""
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
        return first, dt_v, rec, t_load, t_rot

    @ti.func
    def _barrier(self, passed, n_members):
        """Spin until all ``n_members`` reached their ``passed + 1``-th barrier; returns
        ``passed + 1``, or -1 (and sets ``team_failed``) if one never comes. The atomic
        add is a full fence: what a member wrote before, the others read after."""
        out = passed + 1
        target = ti.i64(n_members) * out
        seen = ti.atomic_add(self.team_bar[None], 1) + 1
        spins = 0
        while seen < target:
            seen = ti.atomic_add(self.team_bar[None], 0)  # an atomic read, never hoisted
            spins += 1
            if spins > TEAM_SPIN_LIMIT:
                self.team_failed[None] = 1
                out = -1
                break
        return out

    @ti.kernel
    def _k_steps(
        self,
        n: ti.i32,
        step0: ti.i32,
        dt: ti.f64,
        first0: ti.i32,
        c_mass: ti.f64,
        rec_last: ti.i32,
        damped: ti.template(),
        relax: ti.i32,
        fused: ti.template(),
        n_members: ti.template(),
    ):
        # n steps in one launch: on the calling thread (n_members = 0) or by a team
        if ti.static(n_members == 0):
            ti.loop_config(serialize=True)
            for k in range(n):
                first, dt_v, rec, t_load, t_rot = self._step_times(
                    k, n, step0, dt, first0, rec_last, relax
                )
                for e in range(self.n_elements):
                    self._element(e, dt, damped, rec)
                if ti.static(fused):
                    for c in ti.static(self._fused):
                        c.step_forces(self.x, self.v, self.mass, self.f_extra, dt, dt_v)
                self._apply_loads(t_load)
                self._plate_update(dt_v, c_mass)
                for i in range(self.n_nodes):
                    self._node(i, t_rot, dt, dt_v, first, c_mass, rec)
                for s in range(self.n_sensor):
                    self._sensor(s, dt, dt_v, first)
        else:
            # n steps in one launch on n_members threads. Each worker thread runs one member
            # (its thread index) through all the steps, on a fixed share of the elements,
            # contributor items and nodes; phases that need every share done meet at a
            # barrier (~1 us) instead of ending a parallel loop (a thread-pool dispatch,
            # ~100 us on the 2-core VM).
            ti.loop_config(serialize=True)
            for _ in range(1):
                self.team_bar[None] = 0
                self.team_failed[None] = 0
                for j in range(TEAM_MAX_THREADS):
                    self.team_joined[j] = 0
            # Enough items for a task per thread (Taichi's CPU blocks are >= 512 items): a
            # member busy in its first item cannot take another task, so every thread joins.
            for _item in range(n_members * 1024):
                m = ti.global_thread_idx()
                if ti.atomic_add(self.team_joined[m], 1) == 0:
                    self._team_member(
                        m, n, step0, dt, first0, c_mass, rec_last, damped, relax, fused, n_members
                    )

    @ti.func
    def _team_member(
        self,
        m,
        n,
        step0,
        dt,
        first0,
        c_mass,
        rec_last,
        damped: ti.template(),
        relax,
        fused: ti.template(),
        n_members: ti.template(),
    ):
        """Member m's n steps: its share of the elements, of the contributors' items and
        of the nodes, and (member 0) the serial parts, with a barrier between phases."""
        e0, e1 = share(self.n_elements, m, n_members)
        i0, i1 = share(self.n_nodes, m, n_members)
        passed = 0
        for k in range(n):
            first, dt_v, rec, t_load, t_rot = self._step_times(
                k, n, step0, dt, first0, rec_last, relax
            )
            if ti.static(fused):
                for c in ti.static(self._fused):
                    c.team_begin(m, n_members)
            passed = self._barrier(passed, n_members)
            if passed < 0:
                break
            for e in range(e0, e1):
                self._element(e, dt, damped, rec)
            if ti.static(fused):
                for c in ti.static(self._fused):
                    c.team_share(m, n_members, self.x, self.v, self.mass, self.f_extra, dt, dt_v)
            passed = self._barrier(passed, n_members)
            if passed < 0:
                break
            if m == 0:
                if ti.static(fused):
                    for c in ti.static(self._fused):
                        c.team_end(self.x, self.v, self.mass, self.f_extra, dt, dt_v)
                self._apply_loads(t_load)
                self._plate_update(dt_v, c_mass)
            passed = self._barrier(passed, n_members)
            if passed < 0:
                break
            for i in range(i0, i1):
                self._node(i, t_rot, dt, dt_v, first, c_mass, rec)
            passed = self._barrier(passed, n_members)
            if passed < 0:
                break
            if m == 0:
                for s in range(self.n_sensor):
                    self._sensor(s, dt, dt_v, first)

    @ti.kernel
    def _k_measure(self):
        for j in range(6):
            self.sums[j] = 0.0
        # In a fixed order: the same sums on any thread count (a few 10^4 light items,
        # once an output sample).
        ti.loop_config(serialize=True)
        for i in range(self.n_nodes):
            m = self.mass[i]
            u = self.x[i] - self.X[i]
            self.sums[0] += 0.5 * m * self.v_int[i].dot(self.v_int[i])
            self.sums[4] += self.work[i]
            self.sums[5] += m * u.dot(u)
        ti.loop_config(serialize=True)
        for e in range(self.n_elements):
            self.sums[1] += self.e_int[e]
            self.sums[2] += self.e_hg[e]
            self.sums[3] += self.e_damp[e]

    @ti.kernel
    def _k_von_mises(self):
        for e in range(self.n_elements):
            c = self.conn[e]
            F = ti.Matrix.zero(ti.f64, 2, 2)
            for k in ti.static(range(4)):
                F += self.x[c[k]].outer_product(ti.Vector([self.bx[e][k], self.by[e][k]]))
            lam, mu = self.lam[e], self.mu[e]
            E = 0.5 * (F.transpose() @ F - ti.Matrix.identity(ti.f64, 2))
            tr_e = E[0, 0] + E[1, 1]
            S = lam * tr_e * ti.Matrix.identity(ti.f64, 2) + 2.0 * mu * E
            J = F.determinant()
            sig = F @ S @ F.transpose() / J
            szz = lam * tr_e / J  # plane strain: E_zz = 0, F_zz = 1
            sxx, syy, sxy = sig[0, 0], sig[1, 1], sig[0, 1]
            self.von_mises[e] = ti.sqrt(
                0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3.0 * sxy * sxy
            )

    # ------------------------------------------------------------------ stepping

    def advance(
        self,
        n: int,
        record_last: bool = False,
        serial: bool | None = None,
        relax_damping: float | None = None,
    ) -> None:
        """Take ``n`` steps.

        Parameters
        ----------
        n : int
            Number of steps.
        record_last : bool
            Store energies, ``v_int`` and Jacobians of the last step for :meth:`energies`.
        serial : bool, optional
            Run the steps serially, many in one kernel launch (default: on one CPU
            thread or a mesh of at most ``SERIAL_MAX_ELEMENTS`` elements, when the
            contributors can be fused, see below). Otherwise, on several CPU threads,
            many steps run in one launch as a team of threads (when the contributors
            can be fused and take part, see :class:`ForceContributor`); else each step
            is one kernel launch with parallel loops (or two plus the contributors' own
            launches when some contributor has no ``step_forces``).
        relax_damping : float, optional
            Dynamic relaxation: mass-damping coefficient c (1/s); loads at full value,
            prescribed rotations held at angle 0, time not advanced.
        """
        if n <= 0:
            return
        relax = relax_damping is not None
        c_mass = float(relax_damping) if relax else 0.0
        fused = self._fusable()
        # Serial loops on one thread or small meshes: a Taichi CPU parallel loop costs
        # ~20 % more per element than a plain loop, and a thread-pool dispatch per loop.
        small = self.n_elements <= SERIAL_MAX_ELEMENTS or serial_loops()[1]
        if serial is None:
            serial = (fused or not self.contributors) and small
        if serial and self.contributors and not fused:
            raise ValueError("serial stepping cannot call force contributors without step_forces")
        dt, damped = self.dt, int(self.damped)
        fused_list = self._fused if fused else ()
        team = not serial and self._team_size(fused)
        if serial or team:
            # Chunks of steps in one launch (a launch costs ~30 us); a contributor can ask
            # for a break (the contact's search-grid check).
            done = 0
            while done < n:
                chunk = n - done
                for c in fused_list:
                    chunk = max(1, min(chunk, c.before_steps(self, chunk)))
                last = int(record_last and done + chunk == n)
                args = (chunk, self.step_count, dt, int(self.first), c_mass, last, damped,
                        int(relax), fused)  # fmt: skip
                self._k_steps(*args, team)
                if team and self.team_failed[None]:
                    raise RuntimeError(
                        f"team stepping: a barrier waited in vain for one of {team} CPU "
                        "threads; run with one thread (--threads 1)"
                    )
                for c in fused_list:
                    c.after_steps(self, chunk)
                self.first = False
                if not relax:
                    self.step_count += chunk
                done += chunk
            return
        one_kernel = fused or not self.contributors
        for k in range(n):
            t = self.step_count * dt
            first = int(self.first)
            dt_v = 0.5 * dt if first else dt
            rec = int(record_last and k == n - 1)
            t_load, t_rot = (1e300, 0.0) if relax else (t, t + dt)
            if one_kernel:
                for c in fused_list:
                    c.before_steps(self, 1)
                self._k_step(t_load, t_rot, dt, dt_v, first, c_mass, rec, damped, small, fused)
                for c in fused_list:
                    c.after_steps(self, 1)
            else:
                self._k_elements(dt, damped, rec, small)
                for c in self.contributors:
                    c.add_forces(self, t)
                self._k_nodes(t_load, t_rot, dt, dt_v, first, c_mass, rec, small)
            self.first = False
            if not relax:
                self.step_count += 1

    def _team_size(self, fused: bool) -> int:
        """Threads for team stepping (0 = not used): CPU with several threads, no more
        than the cores this process may run on (a member spinning at a barrier while
        another waits for a core would waste its time slice), and every contributor
        fused with its team functions."""
        threads = current_threads()
        cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
        if current_arch() != "cpu" or not 2 <= threads <= min(cores or threads, TEAM_MAX_THREADS):
            return 0
        if self.contributors and not (
            fused and all(hasattr(c, "team_share") for c in self.contributors)
        ):
            return 0
        return threads

    def _fusable(self) -> bool:
        """Whether the contributors run inside the step kernels: all of them have a
        ``step_forces`` Taichi function (with ``before_steps`` / ``after_steps``), and
        they are the ones the fused kernels were first built with (Taichi keeps a kernel
        compiled once; other contributors go through their own ``add_forces``)."""
        if not self.contributors:
            return False
        if self._fused is None:
            if not all(hasattr(c, "step_forces") for c in self.contributors):
                return False
            self._fused = tuple(self.contributors)
        return len(self._fused) == len(self.contributors) and all(
            a is b for a, b in zip(self._fused, self.contributors, strict=True)
        )

    # ------------------------------------------------------------------ read-out

    def energies(self) -> dict[str, float]:
        """Energies at the last step run with ``record_last`` (J, for the thickness):
        kinetic, internal (strain), hourglass, damping (dissipated), external_work (done by
        loads, constraints and contributors), and ``mass_u2`` = sum m |u|^2."""
        self._k_measure()
        s = self.sums.to_numpy()
        return {
            "kinetic": float(s[0]),
            "internal": float(s[1]),
            "hourglass": float(s[2]),
            "damping": float(s[3]),
            "external_work": float(s[4]),
            "mass_u2": float(s[5]),
        }

    def take_sensor_means(self, n_steps: int) -> np.ndarray:
        """Mean (ux, uy, vx, vy, ax, ay) of each sensor over the last ``n_steps`` steps
        (shape (n_sensors, 6)), and zero the sums."""
        if self.n_sensor == 0:
            return np.zeros((0, 6))
        s = self.sensor_sum.to_numpy()[: self.n_sensor] / max(n_steps, 1)
        self.sensor_sum.fill(0.0)
        return s

    def von_mises_stress(self) -> np.ndarray:
        """Cauchy von Mises stress of each element at the current positions, Pa."""
        self._k_von_mises()
        return self.von_mises.to_numpy()[: self.n_elements]

    def bad_element_index(self) -> int | None:
        """First element found with det F <= 0 (or NaN) since the last reset, else None."""
        e = int(self.bad_element[None])
        return None if e >= self.n_elements else e

    def positions(self) -> np.ndarray:
        return self.x.to_numpy()[: self.n_nodes]

    def velocities(self) -> np.ndarray:
        return self.v.to_numpy()[: self.n_nodes]

    def displacements(self) -> np.ndarray:
        return self.positions() - np.asarray(self.mesh.nodes, dtype=float)

    def set_state(self, x: np.ndarray | None = None, v: np.ndarray | None = None) -> None:
        """Overwrite positions and/or velocities (shape (n_nodes, 2))."""
        if x is not None:
            self.x.from_numpy(np.ascontiguousarray(x, dtype=float))
        if v is not None:
            self.v.from_numpy(np.ascontiguousarray(v, dtype=float))

    # ------------------------------------------------------------------ checkpoint state

    _STATE_FIELDS = ("x", "v", "a", "f_other", "work", "e_damp", "sensor_sum", "v_int")

    def state_arrays(self) -> dict[str, np.ndarray]:
        """Everything needed to continue bit for bit (see :meth:`load_state_arrays`)."""
        out = {name: getattr(self, name).to_numpy() for name in self._STATE_FIELDS}
        out["step_count"] = np.int64(self.step_count)
        out["first"] = np.int64(self.first)
        out["dt"] = np.float64(self.dt)
        return out

    def load_state_arrays(self, arrays: Mapping[str, np.ndarray]) -> None:
        """Restore a state from :meth:`state_arrays`."""
        for name in self._STATE_FIELDS:
            field = getattr(self, name)
            a = np.asarray(arrays[name])
            if a.shape != field.to_numpy().shape:
                raise ValueError(f"checkpoint array {name!r} has shape {a.shape}, model differs")
            field.from_numpy(a)
        self.step_count = int(arrays["step_count"])
        self.first = bool(arrays["first"])
        self._dt_set = float(arrays["dt"])


def rigid_velocity_field(
    nodes: np.ndarray, omega: float, center=(0.0, 0.0), velocity=(0.0, 0.0)
) -> np.ndarray:
    """Velocities ``velocity + omega x (X - center)`` of points ``nodes`` (n, 2)."""
    r = nodes - np.asarray(center, dtype=float)
    return np.asarray(velocity, dtype=float) + omega * np.stack([-r[:, 1], r[:, 0]], axis=1)
