r"""A rigid cage: a ring with one pocket per roller, turning about the bearing centre with
one rotational degree of freedom, driven by penalty contact with the rollers' surfaces.

Pocket ``j`` is centred on the radial line at angle ``pocket_angles[j] + angle`` and has
two flat walls parallel to that line, at ``+-half_gap`` from it (tangentially), spanning
the cage ring ``inner_radius <= r <= outer_radius``. A surface node of roller ``j`` whose
tangential offset from the pocket line exceeds ``half_gap`` penetrates a wall; it gets
the force of its contact law (:mod:`~taichi_bearing.solver.laws.contact`: normal along
the pocket's tangential direction) and friction along the wall
(:mod:`~taichi_bearing.solver.laws.friction`), the cage the reaction torque. The cage
angle and speed are integrated with the model's leapfrog:
:math:`\omega^{n+1/2} = \omega^{n-1/2} + \Delta t \, T^n / I`,
:math:`\varphi^{n+1} = \varphi^n + \Delta t \, \omega^{n+1/2}` (:math:`\varphi` the angle).

Penalty stiffness of a node: the law's
(:meth:`~taichi_bearing.solver.laws.contact.ContactLaw.node_stiffness`): ``"segment"``, the
mean of the LS-DYNA stiffness :math:`f_s K L^2 t / \mathrm{area}` of its two roller
segments; ``"soft"``, :math:`f_s m / \Delta t^2` with the node mass (the cage counts as
infinitely heavy next to one node).
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
from collections.abc import Sequence

import numpy as np
import taichi as ti

from taichi_bearing.errors import InputError
from taichi_bearing.solver import transfer
from taichi_bearing.solver.contact_setup import ContactParameters
from taichi_bearing.solver.contributor import FORCE_QUANTUM, ForceContributor, add_force, force_at
from taichi_bearing.solver.laws.contact import ContactLaw, contact_law
from taichi_bearing.solver.laws.friction import friction_force
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.team import share

__all__ = ["RigidCage"]


@ti.data_oriented
class RigidCage(ForceContributor):
    """Rigid cage as a :class:`~taichi_bearing.solver.contributor.ForceContributor`.

    Parameters
    ----------
    model : Model
    roller_surfaces : sequence of str
        Surface of the roller in each pocket (``Mesh.surfaces`` names), pocket order.
    pocket_angles : sequence of float
        Polar angle of each pocket's centre line at cage angle 0, rad.
    half_gap : float
        Distance of each pocket wall from the pocket's centre line, m (roller radius
        plus half the pocket clearance).
    inner_radius, outer_radius : float
        Radial extent of the pocket walls, m.
    inertia : float
        Polar moment of inertia of the cage about the centre, kg m^2.
    params : ContactParameters
    center : (float, float)
        Bearing centre.
    start_speed : float
        Angular speed at time 0 of a transient (:meth:`start`), rad/s; e.g. ideal
        rolling.
    law : ContactLaw, optional
        The pocket walls' normal law; default the one ``params.penalty_method`` names.
    """

    def __init__(
        self,
        model: Model,
        roller_surfaces: Sequence[str],
        pocket_angles: Sequence[float],
        half_gap: float,
        inner_radius: float,
        outer_radius: float,
        inertia: float,
        params: ContactParameters,
        center: tuple[float, float] = (0.0, 0.0),
        start_speed: float = 0.0,
        law: ContactLaw | None = None,
    ) -> None:
        if len(roller_surfaces) != len(pocket_angles) or not roller_surfaces:
            raise ValueError("need one pocket angle per roller surface")
        if not 0 <= inner_radius < outer_radius:
            raise ValueError("need 0 <= inner_radius < outer_radius")
        if not (half_gap > 0 and inertia > 0):
            raise ValueError("half_gap and inertia must be positive")
        mesh = model.mesh
        self.law = contact_law(params) if law is None else law
        nodes, roller, kk = [], [], []
        for j, name in enumerate(roller_surfaces):
            seg = np.asarray(mesh.surfaces[name], dtype=np.int64)
            ids = np.unique(seg.ravel())
            nodes.append(ids)
            roller.append(np.full(len(ids), j))
            kk.append(self.law.node_stiffness(model, seg, ids))
        node_ids = np.concatenate(nodes).astype(np.int32)
        # a spring and a dashpot to the rigid cage (none for a law that follows the step)
        bound = self.law.node_bound(np.concatenate(kk), model.mass_np[node_ids])
        if bound is not None:
            model.add_stiffness_bound(node_ids, *bound)
        self.n_rollers = nz = len(roller_surfaces)
        self.n_nodes = nn = len(node_ids)
        self.inertia = float(inertia)
        # one starting speed for every member, or one each
        self.start_speed = np.broadcast_to(np.asarray(start_speed, dtype=float),
                                           (model.ensemble_size,)).copy()  # fmt: skip
        self.half_gap = float(half_gap)
        self.params = params
        self._cx, self._cy = (float(c) for c in center)
        self._r_in, self._r_out = float(inner_radius), float(outer_radius)
        self._h = float(half_gap)
        self._mu_s, self._mu_d = float(params.friction_static), float(params.friction_dynamic)
        self._decay = float(params.friction_decay)
        # Deeper than the gap no wall is meant (the node would be past the pocket centre).
        self._capture = float(half_gap)

        self.node = ti.field(ti.i32, shape=nn)
        self.roller = ti.field(ti.i32, shape=nn)
        self.k = ti.field(ti.f64, shape=nn)
        self.ft = ti.field(ti.f64, shape=nn)  # friction spring force along the wall
        self.side = ti.field(ti.i32, shape=nn)  # wall in contact last step: +1, -1, 0
        self.en = ti.field(ti.f64, shape=nn)
        self.et = ti.field(ti.f64, shape=nn)
        # an ensemble: a cage per member, each turning its own pockets (pocket_member)
        self._members, self._member_nodes = model.ensemble_size, model.member_nodes
        nm = self._members
        pocket_member = np.array([model.member_of_nodes(ids) for ids in nodes])
        if np.any(np.diff(pocket_member) < 0) or len(np.unique(pocket_member)) != nm:
            raise ValueError("RigidCage: every ensemble member's pockets, member by member")
        self.member_on = model.member_on
        self.pocket_member = ti.field(ti.i32, shape=nz)
        self.angle0 = ti.field(ti.f64, shape=nz)
        self.radial = ti.Vector.field(2, ti.f64, shape=nz)  # pocket directions this step
        # This step's pocket force on each roller (fx, fy, tangential) and torque on the
        # cage, summed in fixed point (add_force): the same sums whatever order the
        # members add them in, so the pockets are shared among them like the contact's
        # queries.
        self.cur = ti.Vector.field(3, ti.i64, shape=nz)
        self.torque = ti.field(ti.i64, shape=nm)
        self.acc = ti.Vector.field(3, ti.f64, shape=nz)
        self.state = ti.field(ti.f64, shape=2 * nm)  # each member's angle, speed
        # friction and damping energy dissipated, per node (no shared sum)
        self.diss = ti.Vector.field(2, ti.f64, shape=nn)
        transfer.upload(
            [
                (self.node, node_ids),
                (self.roller, np.concatenate(roller).astype(np.int32)),
                (self.k, np.concatenate(kk)),
                (self.angle0, np.asarray(pocket_angles, dtype=float)),
                (self.pocket_member, pocket_member.astype(np.int32)),
            ]
        )
        self.n_samples = 0

    @classmethod
    def from_mesh(
        cls,
        model: Model,
        params: ContactParameters,
        cage_mass: float,
        pocket_clearance: float,
        start_speed: float | Sequence[float] = 0.0,
    ) -> "RigidCage":
        """The cage of a bearing mesh (``mesh.info["cage"]``, rollers ``roller{j}``): a
        ring between the nominal inner and outer radii, :math:`I = m (r_i^2 + r_o^2) / 2`,
        pocket walls at roller radius + half the pocket clearance, turning at
        ``start_speed`` (rad/s, one value or one per ensemble member) at time 0 of a
        transient. An ensemble's model (a stacked mesh,
        :func:`~taichi_bearing.mesh.stack.stack_meshes`) gets a cage per member, its
        pockets where that member's mesh has them."""
        from taichi_bearing.mesh.stack import member_name

        info = model.mesh.info
        members = info.get("member_info", [info])
        cage = info["cage"]
        n = len(cage["pocket_angles"])
        r_i, r_o = float(cage["inner_radius"]), float(cage["outer_radius"])
        names = [f"roller{j}" for j in range(n)]
        if "member_info" in info:  # a stacked mesh: its surfaces are named by member
            names = [member_name(r, k) for k in range(len(members)) for r in names]
        return cls(
            model,
            names,
            np.concatenate([np.asarray(m["cage"]["pocket_angles"], dtype=float) for m in members]),
            float(info["roller_radius"]) + 0.5 * pocket_clearance,
            r_i,
            r_o,
            0.5 * cage_mass * (r_i**2 + r_o**2),
            params,
            start_speed=start_speed,
        )

    # ------------------------------------------------------------------ in the step

    @ti.func
    def step_begin(self, member, n_members):
        """This member's share of the pockets' directions this step; the sums restart."""
        j0, j1 = share(self.n_rollers, member, n_members)
        for j in range(j0, j1):
            if self._on(self.pocket_member[j]):
                self._frame(j)
        if member == 0:
            for k in range(self._members):
                if self._on(k):
                    self.torque[k] = ti.i64(0)

    @ti.func
    def step_share(self, member, n_members, x: ti.template(), v: ti.template(),
                   mass: ti.template(), f_ext: ti.template(), dt, dt_v):  # fmt: skip
        """This member's share of the rollers' surface nodes in the pockets."""
        n0, n1 = share(self.n_nodes, member, n_members)
        for n in range(n0, n1):
            if self._on(self.pocket_member[self.roller[n]]):
                self._pocket(n, x, v, mass, f_ext, dt)

    @ti.func
    def step_end(self, member, n_members, x: ti.template(), v: ti.template(),
                 mass: ti.template(), f_ext: ti.template(), dt, dt_v):  # fmt: skip
        """After every share: this member's share of the pocket sums; member 0 the
        cage's leapfrog step."""
        j0, j1 = share(self.n_rollers, member, n_members)
        for j in range(j0, j1):
            if self._on(self.pocket_member[j]):
                self.acc[j] += force_at(self.cur, j)
        if member == 0:
            for k in range(self._members):
                if self._on(k):
                    self._turn(k, dt, dt_v)

    @ti.func
    def _on(self, k):
        """Whether ensemble member ``k`` steps (always, for one model)."""
        on = True
        if ti.static(self._members > 1):
            on = self.member_on[k] != 0
        return on

    @ti.func
    def _frame(self, j):
        """Pocket j's radial direction this step; its force sum restarts."""
        self.cur[j] = ti.Vector.zero(ti.i64, 3)
        phi = self.angle0[j] + self.state[2 * self.pocket_member[j]]
        self.radial[j] = ti.Vector([ti.cos(phi), ti.sin(phi)])

    @ti.func
    def _pocket(self, n, x: ti.template(), v: ti.template(), mass: ti.template(),
                f_ext: ti.template(), dt):  # fmt: skip
        """Pocket force on roller node n (none outside the pocket walls' reach)."""
        i = self.node[n]
        j = self.roller[n]
        own = self.pocket_member[j]  # its ensemble member
        w = self.state[2 * own + 1]
        er = self.radial[j]
        et = ti.Vector([-er[1], er[0]])
        d = x[i] - ti.Vector([self._cx, self._cy])
        s = d.dot(et)
        r = d.dot(er)
        side = 0
        pen = 0.0
        if r >= self._r_in and r <= self._r_out:
            if s > self._h:
                side, pen = 1, s - self._h
            elif s < -self._h:
                side, pen = -1, -self._h - s
        if pen > self._capture:
            side = 0
        if side == 0 or side != self.side[n]:
            if self.et[n] != 0.0:  # most pocket nodes are free: no write every step
                self.diss[n][0] += self.et[n]  # friction spring released
            self.ft[n] = 0.0
            self.et[n] = 0.0
        self.side[n] = side
        self.en[n] = 0.0
        if side != 0:
            nv = -float(side) * et  # pushes the node back into the pocket
            m = mass[i]
            k = self.law.stiffness(self.k[n], m, dt)
            vrel = v[i] - w * ti.Vector([-d[1], d[0]])
            vn = vrel.dot(nv)
            vt = vrel.dot(er)
            fn, e_damp = self.law.normal(k, pen, m, vn, dt)
            ft, e_t, e_fric = friction_force(
                self.ft[n], self.et[n], k, vt, fn, dt, self._mu_s, self._mu_d, self._decay
            )
            F = fn * nv + ft * er
            add_force(f_ext, i, F)
            add_force(self.cur, j, ti.Vector([F[0], F[1], F.dot(et)]))
            # Reaction -F on the cage at d: torque d x (-F), N m.
            add_force(self.torque, own, -(d[0] * F[1] - d[1] * F[0]))
            self.ft[n] = ft
            self.et[n] = e_t
            self.en[n] = self.law.energy(k, pen)
            self.diss[n] += ti.Vector([e_fric, e_damp])

    @ti.func
    def _turn(self, k, dt, dt_v):
        """Member ``k``'s cage's leapfrog step."""
        w_new = self.state[2 * k + 1] + dt_v * force_at(self.torque, k) / self.inertia
        self.state[2 * k + 1] = w_new
        self.state[2 * k] = self.state[2 * k] + dt * w_new

    # ------------------------------------------------------------------ Python-side hooks

    def after_steps(self, model: Model, n: int) -> None:
        self.n_samples += n

    def force_nodes(self) -> np.ndarray:
        """The rollers' surface nodes: the only ones the pockets push."""
        return self.node.to_numpy()[: self.n_nodes]

    def start(self, model: Model) -> None:
        """Time 0 of a transient: angle 0 and the starting speed (every member's)."""
        state = np.zeros((self._members, 2))
        state[:, 1] = self.start_speed
        transfer.upload([(self.state, state.ravel())])

    # ------------------------------------------------------------------ state and read-out

    @property
    def angle(self) -> float:
        """Cage angle, rad (at the model's current time)."""
        return float(self.state[0])

    @property
    def speed(self) -> float:
        """Cage angular speed, rad/s (at the last half step)."""
        return float(self.state[1])

    def set_state(self, angle: float | None = None, speed: float | None = None) -> None:
        """Set the angle (rad) and/or speed (rad/s), e.g. to ideal rolling at the start."""
        if angle is not None:
            self.state[0] = float(angle)
        if speed is not None:
            self.state[1] = float(speed)

    def pocket_forces(self) -> np.ndarray:
        """Force of the cage on each roller in the last step, shape (Z, 3): fx, fy and the
        component along the pocket's tangential direction (+ = pushed forward, ccw), N."""
        return self.cur.to_numpy()[: self.n_rollers] * FORCE_QUANTUM

    def pop_sample_means(self) -> np.ndarray:
        """Mean of :meth:`pocket_forces` over the steps since the last call; restarts."""
        (acc,) = transfer.download((self.acc,), zero=True)
        s = acc[: self.n_rollers] / max(self.n_samples, 1)
        self.n_samples = 0
        return s

    def energy(self) -> float:
        """Cage kinetic energy plus the penalty energy stored at the pocket walls, J."""
        e = self.energies()
        return e["kinetic"] + e["elastic"]

    def member_energies(self) -> np.ndarray:
        """:meth:`energy` of each ensemble member's cage (its pocket nodes' sums in the
        order its model alone sums them)."""
        n = self.n_nodes
        en, et, state = transfer.download((self.en, self.et, self.state))
        owner = self.pocket_member.to_numpy()[self.roller.to_numpy()[:n]]
        bounds = np.searchsorted(owner, np.arange(self._members + 1))
        return np.array(
            [
                0.5 * self.inertia * float(state[2 * k + 1]) ** 2
                + float(en[a:b].sum() + et[a:b].sum())
                for k, (a, b) in enumerate(zip(bounds[:-1], bounds[1:], strict=True))
            ]
        )

    def energies(self) -> dict[str, float]:
        r"""``kinetic`` (:math:`I \omega^2 / 2`), ``elastic`` (stored penalty), ``friction`` and
        ``damping`` (dissipated so far), J."""
        n = self.n_nodes
        diss, en, et = transfer.download((self.diss, self.en, self.et))
        d = diss[:n].sum(axis=0)
        return {
            "kinetic": 0.5 * self.inertia * self.speed**2,
            "elastic": float(en[:n].sum() + et[:n].sum()),
            "friction": float(d[0]),
            "damping": float(d[1]),
        }

    _STATE = ("ft", "side", "en", "et", "state", "diss", "acc")  # (cur, torque: per step)

    def state_arrays(self) -> dict[str, np.ndarray]:
        """Everything needed to continue a run (checkpoints)."""
        saved = transfer.download([getattr(self, k) for k in self._STATE])
        out = {f"cage_{k}": a for k, a in zip(self._STATE, saved, strict=True)}
        out["cage_n_samples"] = np.int64(self.n_samples)
        return out

    def load_state_arrays(self, arrays) -> None:
        """Restore :meth:`state_arrays`."""
        pairs = []
        for k in self._STATE:
            field, saved = getattr(self, k), np.asarray(arrays[f"cage_{k}"])
            shape = transfer.array_shape(field)
            if saved.shape != shape:  # a checkpoint of an older layout
                raise InputError(
                    f"checkpoint: the cage's {k} has shape {saved.shape}, this version keeps "
                    f"{shape}: written by an older version, run without --resume"
                )
            pairs.append((field, saved))
        transfer.upload(pairs)
        self.n_samples = int(arrays["cage_n_samples"])
