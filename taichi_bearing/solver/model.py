"""The explicit model: the Taichi fields of a mesh's nodes and elements, its constraints,
loads and sensors, its force contributors, and what is read back from it.

What one step does is in :mod:`taichi_bearing.solver.step_phases` (written once); how the steps
are launched, in :mod:`taichi_bearing.solver.stepping`; the element law, in
:mod:`taichi_bearing.solver.element_forces`; the stable step, in
:mod:`taichi_bearing.solver.time_step`. :meth:`Model.advance` is the entry point.
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager

import numpy as np
import taichi as ti

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.stack import member_layout
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.solver import stepping, transfer
from taichi_bearing.solver.backend import current_arch
from taichi_bearing.solver.contributor import ForceContributor
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.energy_sums import MEASURE_BLOCK
from taichi_bearing.solver.laws.material import ElementLaw, StVenantKirchhoff
from taichi_bearing.solver.loads import (
    FixedNodes,
    HeldDirection,
    NodalForces,
    PrescribedRotation,
    RigidPlate,
    RigidVelocity,
)
from taichi_bearing.solver.model_setup import (
    constraint_tables,
    element_data,
    load_tables,
    rigid_velocity_field,
)
from taichi_bearing.solver.model_state import ModelState
from taichi_bearing.solver.multirate import MAX_LEVELS, StepClasses, step_classes
from taichi_bearing.solver.step_phases import (
    ACTED_ON,
    EXTRA,
    LOADED,
    SENSOR,
)
from taichi_bearing.solver.team import TeamState
from taichi_bearing.solver.time_step import CriticalStep

__all__ = ["Model"]


def _vec_field(n: int, dim: int = 2, dtype=ti.f64):
    return ti.Vector.field(dim, dtype, shape=max(n, 1))


def _scalar_field(n: int, dtype=ti.f64):
    return ti.field(dtype, shape=max(n, 1))


@ti.data_oriented
class Model(ModelState):
    r"""A plane-strain explicit model built from a :class:`Mesh`.

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
        (:math:`2 / \omega_e`, the element eigenvalue bound; with a square element this is
        the characteristic length over the wave speed). ``"global"``: the assembled
        mesh's highest frequency (:func:`~taichi_bearing.solver.element.assembled_max_frequency`),
        never smaller, and larger where small elements border larger ones; force
        contributors bound their stiffness with :meth:`add_stiffness_bound`.
    max_added_mass : float
        Selective mass scaling (:func:`~taichi_bearing.solver.element.selective_mass_scale`):
        the densest this may make the smallest elements, as added mass over each part's
        mass; 0 (default) = none. ``added_mass`` (kg per part) and ``n_mass_scaled`` say
        what was done (``part_mass``: each part's mass before it).
    multirate_levels : int
        Multi-rate stepping (:mod:`~taichi_bearing.solver.multirate`): nodes whose elements
        allow it change their velocity only every 2, 4, ... ``2**multirate_levels`` steps;
        0 (default) = every node every step. Dynamic relaxation always steps every node.
    material_law : ElementLaw, optional
        The elements' constitutive law (:mod:`taichi_bearing.solver.laws.material`);
        default St Venant-Kirchhoff.
    members : int
        Independent members of an ensemble (:mod:`taichi_bearing.simulation.ensemble`) the
        mesh holds one after another: member ``k`` owns nodes ``k nn .. (k+1) nn - 1`` and
        elements ``k ne .. (k+1) ne - 1`` (``nn``, ``ne``: the mesh's counts over
        ``members``), which touch no other member's nodes. Each has its own energies,
        rigid plate, relaxation damping and first bad element, and can be held still
        (:meth:`set_members_active`). Default 1: one model.

    Notes
    -----
    Taichi must be initialised first (:func:`taichi_bearing.solver.backend.init_taichi`).
    Force contributors (:class:`~taichi_bearing.solver.contributor.ForceContributor`)
    are added with :meth:`add_contributor`, kernel contributors before the first step.
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
        multirate_levels: int = 0,
        material_law: ElementLaw | None = None,
        members: int = 1,
    ) -> None:
        if current_arch() is None:
            # Otherwise Taichi would start itself on a default arch with f32.
            raise RuntimeError("call taichi_bearing.solver.init_taichi() before building a Model")
        if not thickness > 0:
            raise ValueError(f"thickness must be positive, got {thickness!r}")
        self.mesh = mesh
        self.thickness = float(thickness)
        self.n_nodes = nn = mesh.n_nodes
        self.n_elements = ne = mesh.n_elements
        self.ensemble_size, self.member_nodes, self.member_elements = member_layout(mesh, members)
        self.material_law = StVenantKirchhoff() if material_law is None else material_law
        el = element_data(
            mesh, materials, self.thickness, hourglass_scale, max_added_mass, damping,
            self.material_law,
        )  # fmt: skip
        elements, geo, mass, beta_e = el.elements, el.geometry, el.mass, el.beta_e
        self.n_mass_scaled, self.part_mass, self.added_mass = (
            el.n_mass_scaled, el.part_mass, el.added_mass,
        )  # fmt: skip
        self.damping = damping
        self.damped = bool(np.any(beta_e > 0))
        self.mass_np = mass
        self.lam_np, self.mu_np = el.lam, el.mu  # Lame constants per element, Pa
        self.area_np = geo.area
        self.time_step = time_step
        # The critical step is found when first read (contributors add their bounds
        # first); a step set with set_dt is kept while it stays stable.
        self.critical = CriticalStep(
            time_step, el.stiffness, elements, mass, el.omega_e, beta_e, dt_factor
        )
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
        ptr, adj = el.adjacency
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
        # strain history of the damped elements: Green strain (xx, yy, xy) and hourglass
        # sum at each element's previous evaluation (element_forces.seed_strain_history)
        self.e_prev = _vec_field(ne if self.damped else 1, 3)
        self.q_prev = _vec_field(ne if self.damped else 1, 2)
        self.history_stale = True  # seed it before the next step
        self.history_key: tuple | None = None  # (dt, multi-rate) it was taken with
        self.jac = _scalar_field(ne)  # det F at the last recorded step
        self.von_mises = _scalar_field(ne)
        nm = self.ensemble_size
        # each member's first element found inverted (member_elements: none)
        self.bad_element = ti.field(ti.i32, shape=nm)
        self.sums = ti.field(ti.f64, shape=6 * nm)
        # the energy sums' partial sums, member by member: blocks of MEASURE_BLOCK of its
        # nodes, then of its elements (the blocks of one model, whatever the members)
        self.n_node_blocks = -(-self.member_nodes // MEASURE_BLOCK)
        self.n_sum_blocks = self.n_node_blocks + -(-self.member_elements // MEASURE_BLOCK)
        self.sum_parts = _vec_field(nm * self.n_sum_blocks, 3)
        # per member: stepped (1) or held still (0), and its relaxation damping, 1/s
        self.member_on = _scalar_field(nm, ti.i32)
        self.relax_c = _scalar_field(nm)
        self.team = TeamState()
        # ---- multi-rate stepping (classes found at the first step, from the run's dt)
        if not 0 <= int(multirate_levels) <= MAX_LEVELS:
            raise ValueError(
                f"multirate_levels must lie in [0, {MAX_LEVELS}], got {multirate_levels!r}"
            )
        self.multirate_levels = int(multirate_levels)
        self.step_classes: StepClasses | None = None
        self._classes_dt: float | None = None
        if self.multirate_levels:
            self.mr_node_class = _scalar_field(nn, ti.i32)
            self.mr_order = _scalar_field(ne, ti.i32)
            self.mr_count = _scalar_field(self.multirate_levels + 1, ti.i32)

        # every field's first values go up in one copy kernel (solver.transfer): the
        # setup helpers add theirs to this list
        self._uploads = [
            (self.X, np.asarray(mesh.nodes, dtype=float)),
            (self.x, np.asarray(mesh.nodes, dtype=float)),
            (self.mass, mass),
            (self.adj_ptr, ptr),
            (self.adj, adj),
            (self.conn, elements.astype(np.int32)),
            (self.bx, geo.b[..., 0]),
            (self.by, geo.b[..., 1]),
            (self.gam, geo.gamma),
            (self.at, geo.area * self.thickness),
            (self.khg, el.khg),
            (self.lam, el.lam),
            (self.mu, el.mu),
            (self.beta_e, beta_e),
            *transfer.constant((self.member_on,), 1),
        ]
        self.reset_bad_elements()

        self._setup_constraints(constraints)
        self._setup_loads(loads)
        self._setup_sensors(mesh.sensor_nodes if sensors is None else sensors)
        self.initial_velocities = list(initial_velocities)
        # force contributors in the order added; the kernel ones are frozen at the first
        # step (Taichi compiles the step kernels once, with the contributors they had)
        self._contributors: list[ForceContributor] = []
        self.kernel_contributors: tuple[ForceContributor, ...] = ()
        self.python_contributors: tuple[ForceContributor, ...] = ()
        self._frozen = False
        self.steps_by_mode: dict[str, int] = {}  # steps taken in each stepping mode
        self.step_graphs: dict = {}  # compute graphs of parallel stepping, made on first use
        self.step_count = 0
        # set_initial_velocities (no contributor yet), in the one upload of every field
        self._restart(self._uploads + [(self.bc, self.bc_np), (self.v, self._rigid_velocities())])
        del self._uploads

    # ------------------------------------------------------------------ setup helpers

    def _setup_constraints(self, constraints) -> None:
        bc, held, rgroup, rots, plates = constraint_tables(constraints, self.n_nodes)
        self.rotations = rots
        # rigid plates: at most one per member, each within its member; a plate node
        # knows its plate, plate p's nodes are plate_node[p * plate_size ...]
        owner = [self.member_of_nodes(p.nodes) for p in plates]
        if len(set(owner)) != len(owner):
            raise ValueError("RigidPlate: at most one plate per model (per ensemble member)")
        self.plates = plates
        self.plate = plates[0] if plates else None
        self.n_plates = npl = len(plates)
        sizes = [len(p.nodes) for p in plates]
        if len(set(sizes)) > 1:
            raise ValueError("RigidPlate: an ensemble's plates must have the same node count")
        # a plate's nodes, a compile-time count: its force sum's loop is compiled as for
        # one model's plate (a loop with other bounds may sum in another order)
        self.plate_size = sizes[0] if sizes else 0
        self.n_plate = int(sum(sizes))
        self.plate_node = _scalar_field(self.n_plate, ti.i32)
        self.plate_slot = _scalar_field(self.n_plate, ti.i32)  # plate of each slot
        self.plate_id = _scalar_field(self.n_nodes, ti.i32)  # plate of a plate node
        self.plate_dir = _vec_field(npl)
        # per plate node, its force along the plate's direction (summed by every plate
        # node in one order), and each plate's velocity before the step
        self.plate_f = _scalar_field(self.n_plate)
        self.plate_vo = _scalar_field(npl)
        if plates:
            plate_id = np.zeros(self.n_nodes, dtype=np.int32)
            for k, p in enumerate(plates):
                plate_id[p.nodes] = k
            self._uploads += [
                (self.plate_node, np.concatenate([p.nodes for p in plates]).astype(np.int32)),
                (self.plate_slot, np.repeat(np.arange(npl), sizes).astype(np.int32)),
                (self.plate_id, plate_id),
                (self.plate_dir, np.array([p.direction for p in plates], dtype=float)),
            ]
        self.bc_np = bc  # uploaded once the loads have added theirs
        self._uploads += [(self.held_dir, held), (self.rot_group, rgroup)]
        nr = len(rots)
        self.n_rot = nr
        self.rot_center = _vec_field(nr)
        self.rot_par = _vec_field(nr, 3)  # omega_start, omega, ramp_time
        if nr:
            centers = np.array([r.center for r in rots], dtype=float)
            par = np.array([[r.omega_start, r.omega, r.ramp_time] for r in rots], dtype=float)
            self._uploads += [(self.rot_center, centers), (self.rot_par, par)]

    def _setup_loads(self, loads: Sequence[NodalForces]) -> None:
        nodes, forces, ramps = load_tables(loads, self.n_nodes)
        self.loads = list(loads)
        self.n_load = nl = int(sum(len(n) for n in nodes))
        self.load_node = _scalar_field(nl, ti.i32)
        self.load_force = _vec_field(nl)
        self.load_ramp = _scalar_field(nl)
        # Each load on a node of its own: the members may set their share of the loads
        # (a node's sum of one load is that load); else member 0 adds them in order.
        all_nodes = np.concatenate(nodes) if nl else np.zeros(0, np.int64)
        self.loads_unique = bool(len(np.unique(all_nodes)) == nl)
        if nl:
            self._uploads += [
                (self.load_node, np.concatenate(nodes).astype(np.int32)),
                (self.load_force, np.concatenate(forces)),
                (self.load_ramp, np.concatenate(ramps)),
            ]
            self.bc_np[np.concatenate(nodes)] |= LOADED

    def _setup_sensors(self, sensors: Mapping[str, int]) -> None:
        self.sensor_names = list(sensors)
        ids = np.array([int(sensors[k]) for k in self.sensor_names], dtype=np.int32)
        if ids.size and (ids.min() < 0 or ids.max() >= self.n_nodes):
            raise ValueError("sensor node index out of range")
        self.n_sensor = ns = len(ids)
        self.sensor_node = _scalar_field(ns, ti.i32)
        self.sensor_sum = _vec_field(ns, 6)  # ux, uy, vx, vy, ax, ay
        if ns:
            self._uploads.append((self.sensor_node, ids))
        self.bc_np &= ~SENSOR
        self.bc_np[ids] |= SENSOR  # the node update stores their accelerations

    def member_of_nodes(self, nodes) -> int:
        """The ensemble member that owns every one of ``nodes``.

        Raises
        ------
        ValueError
            If they belong to more than one member.
        """
        owner = np.unique(np.asarray(nodes, dtype=np.int64) // self.member_nodes)
        if len(owner) != 1:
            raise ValueError(f"nodes of several ensemble members ({owner.tolist()}) in one set")
        return int(owner[0])

    def part_nodes(self, part: str | int) -> np.ndarray:
        """Indices of the nodes of one part."""
        pid = self.mesh.part_id(part) if isinstance(part, str) else int(part)
        return np.unique(self.mesh.elements[self.mesh.element_part == pid])

    def set_initial_velocities(self) -> None:
        """Velocities from the :class:`RigidVelocity` list (zero elsewhere): time 0 of a
        transient. Restarts the leapfrog (the next step is a half step) and the
        work/damping accumulators, and tells each contributor (``start``)."""
        self._restart([(self.v, self._rigid_velocities())])
        for c in self._contributors:
            c.start(self)

    def _rigid_velocities(self) -> np.ndarray:
        X = np.asarray(self.mesh.nodes, dtype=float)
        v = np.zeros((self.n_nodes, 2))
        for rv in self.initial_velocities:
            ids = self.part_nodes(rv.part)
            v[ids] = rigid_velocity_field(X[ids], rv.omega, rv.center, rv.velocity)
        return v

    def restart_accounting(self) -> None:
        """Zero the work/damping accumulators and start the leapfrog with a half step."""
        self._restart([])

    def _restart(self, uploads: list) -> None:
        # restart_accounting, with other fields' values in the same copy kernel
        zeroed = (self.work, self.e_damp, self.f_other, self.f_extra, self.f_load, self.sensor_sum)
        transfer.upload(uploads + transfer.constant(zeroed, 0.0))
        self.first = True
        self.step_count = 0
        self.history_stale = True

    # ------------------------------------------------------------------ time step

    @property
    def element_dt(self) -> np.ndarray:
        """Each element's own critical step, s (damping included)."""
        return self.critical.element_dt

    @property
    def critical_step(self) -> float:
        """Critical step of the chosen estimate, s (damping included)."""
        return self.critical.values()[0]

    @property
    def damping_step_factor(self) -> float:
        """By how much damping shortened the critical step (1 = not at all)."""
        return self.critical.values()[1]

    @property
    def dt_stable(self) -> float:
        """``dt_factor`` times the critical step, s."""
        return self.critical.values()[2]

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
        ``nodes`` (see :meth:`CriticalStep.add_bound`); the global estimate takes them in."""
        self.critical.add_bound(nodes, stiffness, damping)

    def set_dt(self, dt: float) -> None:
        """Use a time step not above the stable one (e.g. to fit the output interval)."""
        if not 0 < dt <= self.dt_stable * (1 + 1e-12):
            raise ValueError(f"dt {dt!r} must lie in (0, {self.dt_stable!r}] (stable step)")
        self._dt_set = float(dt)

    @contextmanager
    def contributor_masses(self) -> Iterator[int]:
        """Within: the nodes that force contributors' springs act on (penalty contact, the
        cage) carry the masses of :meth:`CriticalStep.contributor_mass_scale`, and the
        step is the stable one with them, so the springs no longer shorten it; after, the
        masses and the step are the model's again. For dynamic relaxation only: a static
        state does not depend on the masses, the motion towards it does. Yields the number
        of nodes whose mass was raised. Needs ``time_step="global"`` and contributors whose
        stiffness does not follow the step (the soft penalty's does)."""
        mass = self.critical.contributor_mass_scale()
        saved = (self.critical, self._dt_set)
        self.critical = self.critical.with_masses(mass)
        self._dt_set = None
        self.mass.from_numpy(mass)
        try:
            yield int(np.count_nonzero(mass > self.mass_np))
        finally:
            self.mass.from_numpy(self.mass_np)
            self.critical, self._dt_set = saved

    @property
    def time(self) -> float:
        """Time of the current state, s (``step_count * dt``)."""
        return self.step_count * self.dt

    # ------------------------------------------------------------------ contributors

    @property
    def contributors(self) -> tuple[ForceContributor, ...]:
        """The force contributors, in the order added."""
        return tuple(self._contributors)

    def add_contributor(self, contributor: ForceContributor) -> None:
        """Add a force contributor, called every step from now on.

        Raises
        ------
        TypeError
            If it is not a :class:`ForceContributor`.
        RuntimeError
            For a kernel contributor once the model has stepped (its step kernels are
            compiled with the kernel contributors they had).
        """
        if not isinstance(contributor, ForceContributor):
            raise TypeError(f"{type(contributor).__name__} is not a ForceContributor")
        if contributor.in_kernel:
            if self._frozen:
                raise RuntimeError(
                    "kernel contributors must be added before the model's first step"
                )
            self.kernel_contributors += (contributor,)
        else:
            self.python_contributors += (contributor,)
        self._contributors.append(contributor)
        if self._frozen:
            self._flag_force_nodes()

    def freeze_contributors(self) -> None:
        """No more kernel contributors (called by the first step)."""
        if not self._frozen:
            self._frozen = True
            self._flag_force_nodes()

    def _flag_force_nodes(self) -> None:
        """Flag the nodes some contributor may push (the node update reads the
        contributors' force there only)."""
        self.bc_np &= ~EXTRA
        for c in self._contributors:
            nodes = c.force_nodes()
            self.bc_np[slice(None) if nodes is None else np.asarray(nodes)] |= EXTRA
        self.bc.from_numpy(self.bc_np)
        self._classes_dt = None  # the nodes held at class 0 may have changed

    # ------------------------------------------------------------------ stepping

    def prepare_step_classes(self) -> None:
        """Find the multi-rate step classes for the current step (again if it changed):
        called before steps are taken, with the contributors frozen."""
        if not self.multirate_levels or self._classes_dt == self.dt:
            return
        fast = (self.bc_np & (ACTED_ON | SENSOR)) != 0
        element_dt = self.critical.element_dt * self.critical.dt_factor
        elements = np.asarray(self.mesh.elements)
        c = step_classes(element_dt, elements, self.dt, self.multirate_levels, fast)
        transfer.upload(
            [
                (self.mr_node_class, c.node_class.astype(np.int32)),
                (self.mr_order, c.element_order.astype(np.int32)),
                (self.mr_count, c.element_count.astype(np.int32)),
            ]
        )
        self.step_classes = c
        self._classes_dt = self.dt

    @property
    def cycle_steps(self) -> int:
        """Steps between the times every node moves together (``2**multirate_levels``):
        recorded steps fall on multiples of it."""
        return 2**self.multirate_levels

    def advance(
        self,
        n: int,
        record_last: bool = False,
        mode: str | None = None,
        relax_damping: float | Sequence[float] | None = None,
    ) -> None:
        """Take ``n`` steps (:func:`taichi_bearing.solver.stepping.advance`).

        Parameters
        ----------
        n : int
            Number of steps.
        record_last : bool
            Store energies, ``v_int`` and Jacobians of the last step for :meth:`energies`.
        mode : {"serial", "team", "parallel"}, optional
            How the steps are launched (default: chosen for the backend, threads, mesh
            size and contributors; see :mod:`taichi_bearing.solver.stepping`). The
            results do not depend on it.
        relax_damping : float or sequence of float, optional
            Dynamic relaxation: mass-damping coefficient c (1/s), one per member of an
            ensemble (or one for all); loads at full value, prescribed rotations held at
            angle 0, time not advanced.
        """
        stepping.advance(self, n, record_last, mode, relax_damping)
