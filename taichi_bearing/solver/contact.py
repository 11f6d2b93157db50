r"""2-D penalty node-to-segment contact with Coulomb friction and viscous damping, a
:class:`~taichi_bearing.solver.contributor.ForceContributor`.

Each step, for every node of every surface that takes part in a pass (a "query"):

1. candidate segments: the segments binned in the node's cell of a uniform search grid
   (segments of the surfaces this node's surface is paired with, each pass of a pair);
2. the candidate segment closest to the node (true distance to the segment, so the line
   of a segment beyond a convex vertex never wins; ties to the lower index); contact if
   the node is behind it, gap :math:`g = (x - a) \cdot n < 0`, no deeper than the capture
   depth (a node in the wedge outside a convex vertex is caught by the other pass);
   with ``smoothing`` the gap and normal are those of the segment's reference arc laid
   on the current chord: :math:`g` less :math:`\kappa L^2 \xi (1 - \xi) / 2` and the
   normal turned by :math:`\kappa L (\xi - 1/2)` (:math:`\kappa` from
   :func:`~taichi_bearing.solver.contact_setup.segment_curvature`; 0 at flats, corners
   and open ends), so a polygonal roller rolls like a circle (no facet ripple);
3. normal force :math:`f_n = \max(0, k (-g) - c v_n)`,
   :math:`c = 2 \zeta \sqrt{k m_\mathrm{eff}}`;
4. friction: elastic stick :math:`f_t^\mathrm{trial} = f_t^\mathrm{old} - k \Delta t v_t`
   (tangential spring of the normal penalty stiffness), return-mapped onto
   :math:`|f_t| \le \mu f_n` with
   :math:`\mu = \mu_d + (\mu_s - \mu_d) \exp(-\mathrm{decay} \, |v_t|)`; :math:`f_t` is kept
   per query while the node stays on the same segment or moves to a neighbouring segment
   (sharing a node), and reset to zero when the contact opens or jumps elsewhere;
5. the force :math:`f_n n + f_t t` on the node, its reaction on the segment's two nodes
   split by the projection :math:`\xi` (clamped to [0, 1]); the pair resultant (force BY
   the slave body ON the master body) summed.

Velocities are ``model.v`` = :math:`v^{n-1/2}`, positions ``model.x`` = :math:`x^n` (what
the model has when the contributors are called).

Search: a uniform square grid over the surfaces' box (see
:func:`~taichi_bearing.solver.contact_setup.grid_spec`), each segment binned in the cells
its box grown by capture depth + margin overlaps, rebuilt when some surface node has
moved a quarter of the margin since the last build (checked on a schedule from the
fastest surface node's speed, not every step). Each build lists the nodes within reach
of a paired segment (capture depth + margin + patch reach); only those are visited, each
reading its own cell. No shape assumption (circles, flats, spall walls alike); the cost
is linear in the number of surface nodes as long as the bodies stay in the box the grid
was sized for (outside it, points fall into the border cells: still correct, slower).
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
from collections.abc import Sequence

import numpy as np
import taichi as ti

from taichi_bearing.solver import transfer
from taichi_bearing.solver.backend import serial_loops
from taichi_bearing.solver.contact_patch import arc_frame, patch_overlap
from taichi_bearing.solver.contact_readout import ContactReadout
from taichi_bearing.solver.contact_search import (
    build_grid,
    candidate,
    cell_xy,
    list_active,
    member_cells,
    scan_blocks,
    surface_motion,
)
from taichi_bearing.solver.contact_setup import (
    ContactPair,
    ContactParameters,
    grid_spec,
    query_corners,
    query_neighbours,
    segment_curvature,
    segment_end_corners,
)
from taichi_bearing.solver.contributor import ForceContributor, add_force, force_at
from taichi_bearing.solver.laws.contact import ContactLaw, contact_law
from taichi_bearing.solver.laws.friction import friction_force
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.team import share

__all__ = ["ContactPair", "ContactParameters", "PenaltyContact"]


@ti.data_oriented
class PenaltyContact(ContactReadout, ForceContributor):
    """Penalty contact between named surface pairs of a :class:`Model`.

    Parameters
    ----------
    model : Model
    pairs : sequence of ContactPair
    params : ContactParameters
    law : ContactLaw, optional
        The normal law (:mod:`taichi_bearing.solver.laws.contact`); default the one
        ``params.penalty_method`` names.

    Attributes
    ----------
    pair_names : list of str
    rebuilds : int
        How many times the search grid was rebuilt.

    Notes
    -----
    A query node holds at most one contact at a time (the closest penetrated segment
    among all surfaces paired with its own). Two passes of a pair both apply penalty
    forces, so the effective normal stiffness of a two-pass contact is about twice ``k``.
    """

    def __init__(
        self,
        model: Model,
        pairs: Sequence[ContactPair],
        params: ContactParameters,
        law: ContactLaw | None = None,
    ) -> None:
        if not pairs:
            raise ValueError("PenaltyContact needs at least one ContactPair")
        mesh = model.mesh
        self.model_mesh_surfaces = mesh.surfaces
        self.params = params
        self.law = contact_law(params) if law is None else law
        self.pairs = list(pairs)
        self.pair_names = [p.name for p in self.pairs]
        if len(set(self.pair_names)) != len(self.pair_names):
            raise ValueError("contact pair names must be unique")
        names: list[str] = []
        for p in self.pairs:
            for s in (p.slave_surface, p.master_surface):
                if s not in mesh.surfaces:
                    raise KeyError(f"pair {p.name!r}: no surface {s!r} in the mesh")
                if s not in names:
                    names.append(s)
        self.surface_names = names
        ns = len(names)
        sid = {s: k for k, s in enumerate(names)}
        # pass table: query surface S against segment surface M -> pair, sign of resultant
        table = np.full(ns * ns, -1, dtype=np.int32)
        sign = np.zeros(ns * ns)
        # a query-side law's stiffness is shared by the passes of its pair
        pass_share = np.ones(ns * ns)
        for k, p in enumerate(self.pairs):
            s, m = sid[p.slave_surface], sid[p.master_surface]
            if s == m:
                raise ValueError(f"pair {p.name!r}: a surface cannot contact itself")
            for a, b, sg in ((s, m, -1.0), (m, s, 1.0))[: 2 if p.two_pass else 1]:
                if table[a * ns + b] >= 0:
                    raise ValueError(f"pair {p.name!r} duplicates another pair")
                table[a * ns + b] = k
                sign[a * ns + b] = sg
                pass_share[a * ns + b] = 0.5 if p.two_pass else 1.0
        query_surfaces = sorted({i // ns for i in np.flatnonzero(table >= 0)})
        seg_surfaces = sorted({i % ns for i in np.flatnonzero(table >= 0)})

        # queries: unique nodes of each querying surface
        q_node, q_surf = [], []
        for s in query_surfaces:
            nodes = np.unique(mesh.surfaces[names[s]].ravel())
            q_node.append(nodes)
            q_surf.append(np.full(len(nodes), s))
        q_node = np.concatenate(q_node).astype(np.int32)
        q_surf = np.concatenate(q_surf).astype(np.int32)
        q_prev, q_next, q_kappa = query_neighbours(
            mesh, [names[s] for s in query_surfaces], q_node, params.smoothing
        )
        # segments of the surfaces queried against
        segs, seg_surf = [], []
        for m in seg_surfaces:
            seg = np.asarray(mesh.surfaces[names[m]], dtype=np.int64)
            segs.append(seg)
            seg_surf.append(np.full(len(seg), m))
        segs = np.concatenate(segs)
        seg_surf = np.concatenate(seg_surf).astype(np.int32)
        k_seg = self.law.segment_stiffness(model, segs)
        self._query_side = self.law.side == "query"
        q_k = np.zeros(len(q_node))
        if self._query_side:
            for sq in query_surfaces:
                on_s = q_surf == sq
                q_k[on_s] = self.law.node_stiffness(model, mesh.surfaces[names[sq]], q_node[on_s])
        if self.law.bounded:  # a law that follows the step (soft) needs no bound
            passes = [
                (np.asarray(mesh.surfaces[names[i // ns]]), segs[seg_surf == i % ns],
                 self._pass_stiffness(k_seg[seg_surf == i % ns], q_k[q_surf == i // ns],
                                      pass_share[i]))
                for i in np.flatnonzero(table >= 0)
            ]  # fmt: skip
            k_node, c_node = self.law.contact_bound(model, passes)
            on = np.flatnonzero(k_node)
            model.add_stiffness_bound(on, k_node[on], c_node[on])
        kappa = np.zeros(len(segs))
        if params.smoothing:
            kappa = segment_curvature(mesh.nodes, segs, seg_surf)
        self.seg_kappa_np = kappa
        corner_a, corner_b = segment_end_corners(mesh.nodes, segs, seg_surf)
        track = np.unique(np.concatenate([q_node, segs.ravel()])).astype(np.int32)
        X = np.asarray(mesh.nodes, dtype=float)
        lengths = np.linalg.norm(X[segs[:, 1]] - X[segs[:, 0]], axis=1)
        self.grid = g = grid_spec(X[track], lengths)

        self.n_pairs = len(self.pairs)
        self.n_surf = ns
        self.n_query = nq = len(q_node)
        self.n_seg = nseg = len(segs)
        self.n_track = len(track)
        self.cap = 9 * nseg + 16
        self.q_node_np = q_node
        self.q_surf_np = q_surf

        f = ti.field
        v2 = lambda n: ti.Vector.field(2, ti.f64, shape=max(n, 1))  # noqa: E731
        self.pass_pair = f(ti.i32, shape=ns * ns)
        self.pass_sign = f(ti.f64, shape=ns * ns)
        self.pass_share = f(ti.f64, shape=ns * ns)
        self.q_node = f(ti.i32, shape=nq)
        self.q_surf = f(ti.i32, shape=nq)
        self.q_prev = f(ti.i32, shape=nq)  # neighbours along the query's own surface
        self.q_next = f(ti.i32, shape=nq)
        self.q_kappa = f(ti.f64, shape=nq)  # reference curvature of its surface there
        self.q_corner = f(ti.i32, shape=nq)  # 1: a corner of its surface (point contact)
        self.q_hmax = f(ti.f64, shape=nq)  # 1.5 x half the reference tributary length
        self.q_k = f(ti.f64, shape=nq)  # a query-side law's stiffness of the node
        self.q_seg = f(ti.i32, shape=nq)  # segment in contact, -1 open
        self.q_ft = f(ti.f64, shape=nq)  # tangential spring force along the segment
        self.q_fn = f(ti.f64, shape=nq)  # last normal force
        self.q_gap = f(ti.f64, shape=nq)  # last gap (negative: penetration)
        self.q_en = f(ti.f64, shape=nq)  # normal penalty energy stored
        self.q_et = f(ti.f64, shape=nq)  # tangential spring energy stored
        self.q_active = f(ti.i32, shape=nq)  # queries near a paired segment, in order
        self.q_near = f(ti.i32, shape=nq)  # 1: listed at the last build
        self.seg_a = f(ti.i32, shape=nseg)
        self.seg_b = f(ti.i32, shape=nseg)
        self.seg_surf = f(ti.i32, shape=nseg)
        self.seg_k = f(ti.f64, shape=nseg)
        self.seg_kappa = f(ti.f64, shape=nseg)  # reference arc curvature, 0: straight
        self.seg_corner = f(ti.i32, shape=nseg)  # bit 0: start (a) is a corner, bit 1: end
        self.track = f(ti.i32, shape=len(track))
        self.x_ref = v2(len(track))
        # an ensemble's members each have a grid of their own (contact_search.member_cells)
        self._members, self._member_nodes = model.ensemble_size, model.member_nodes
        self._n_cells = n_cells = g.n_cells * self._members
        self.member_on = model.member_on  # members held still are skipped
        self.pair_member = f(ti.i32, shape=self.n_pairs)
        self.cell_start = f(ti.i32, shape=n_cells + 1)
        self.cell_fill = f(ti.i32, shape=n_cells)
        # running totals of blocks of cells and of queries (contact_search.SCAN_BLOCK)
        self.cell_block = f(ti.i32, shape=scan_blocks(n_cells))
        self.query_block = f(ti.i32, shape=scan_blocks(nq))
        self.cell_items = f(ti.i32, shape=self.cap)
        self.cell_surf = f(ti.i32, shape=self.cap)  # surface of each item (contiguous read)
        self.status = f(ti.i32, shape=2)  # 0: overflow flag, 1: active query count
        self.motion = f(ti.f64, shape=2)  # largest move since the build, largest speed
        # Forces summed over queries in fixed point (model.add_force): the same sums
        # whatever order the threads add them in.
        self.node_force = ti.Vector.field(2, ti.i64, shape=max(model.n_nodes, 1))  # last step
        self.cur = ti.Vector.field(4, ti.i64, shape=self.n_pairs)
        self.acc = ti.Vector.field(4, ti.f64, shape=self.n_pairs)
        # Friction and damping energy dissipated (J): each query sums its own (no shared
        # sum, so the totals are the same on any thread count); diss holds what
        # checkpoints from before the per-query sums carried.
        self.diss = f(ti.f64, shape=2)
        self.q_diss = ti.Vector.field(2, ti.f64, shape=nq)

        Xq = np.asarray(mesh.nodes, dtype=float)
        half = 0.25 * (
            np.linalg.norm(Xq[q_node] - Xq[q_prev], axis=1)
            + np.linalg.norm(Xq[q_next] - Xq[q_node], axis=1)
        )
        q_corner = query_corners(mesh.nodes, q_node, q_prev, q_next).astype(np.int32)
        seg_corner = (corner_a.astype(np.int32) + 2 * corner_b).astype(np.int32)
        # one copy kernel for them all (solver.transfer)
        transfer.upload(
            [
                (self.pass_pair, table),
                (self.pass_sign, sign),
                (self.pass_share, pass_share),
                (self.q_k, q_k),
                (self.q_node, q_node),
                (self.q_surf, q_surf),
                (self.q_prev, q_prev),
                (self.q_next, q_next),
                (self.q_kappa, q_kappa),
                (self.q_corner, q_corner),
                (self.q_hmax, 1.5 * half),
                (self.seg_a, segs[:, 0].astype(np.int32)),
                (self.seg_b, segs[:, 1].astype(np.int32)),
                (self.seg_surf, seg_surf),
                (self.seg_k, k_seg),
                (self.seg_kappa, kappa),
                (self.seg_corner, seg_corner),
                (self.track, track),
                (self.pair_member, self._pair_members(model).astype(np.int32)),
                *transfer.constant((self.q_seg,), -1),
            ]
        )
        self.track_np = track
        self.n_samples = 0
        self.rebuilds = 0
        self._built = False
        self._countdown = 0
        # Constants baked into this instance's kernels (fewer launch arguments).
        self._ox, self._oy = (float(o) for o in g.origin)
        self._h, self._nx, self._ny = float(g.cell), int(g.nx), int(g.ny)
        self._capture, self._grow = float(g.capture), float(g.capture + g.margin)
        self._mu_s, self._mu_d = float(params.friction_static), float(params.friction_dynamic)
        self._decay = float(params.friction_decay)
        self._smooth = bool(params.smoothing)
        self._serial_light = serial_loops()[0]  # the grid check's loop over tracked nodes
        # Active-query reach (see _k_activate): curvature bound of a patch and the
        # largest arc offset from its chord.
        self._kappa_max = float(np.max(np.abs(kappa)) + np.max(np.abs(q_kappa)))
        sagitta = float(np.max(np.abs(kappa) * lengths**2)) / 8.0
        self._activate_base = float(g.capture + g.margin) + sagitta

    def _pair_members(self, model: Model) -> np.ndarray:
        """The ensemble member of each pair (both its surfaces in one member)."""
        surfaces = self.model_mesh_surfaces
        return np.array(
            [
                model.member_of_nodes(
                    np.concatenate(
                        [surfaces[p.slave_surface].ravel(), surfaces[p.master_surface].ravel()]
                    )  # fmt: skip
                )
                for p in self.pairs
            ]
        )

    def _pass_stiffness(self, k_seg: np.ndarray, k_query: np.ndarray, share: float):
        """The stiffness a pass's segments hold for the stable-step bound: their own, or
        for a query-side law the stiffest querying node's share on every segment."""
        if not self._query_side:
            return k_seg
        return np.full(len(k_seg), share * float(np.max(k_query)))

    # ------------------------------------------------------------------ search grid

    @ti.func
    def _open(self, q):
        """No contact: the tangential spring's energy is lost (counted as friction).
        Nothing to do for a query already open (most of them)."""
        if self.q_seg[q] >= 0:
            self.q_diss[q][0] += self.q_et[q]
            self.q_seg[q] = -1
            self.q_ft[q] = 0.0
            self.q_fn[q] = 0.0
            self.q_gap[q] = 0.0
            self.q_en[q] = 0.0
            self.q_et[q] = 0.0

    def _k_activate(self, x) -> None:
        list_active(self, x)

    def _check_grid(self, model: Model) -> None:
        """Rebuild the grid if a surface node has moved half the margin; schedule the next
        check from the fastest surface node (4x safety on its speed), so that positions
        are read back only every so many steps."""
        half = 0.5 * self.grid.margin
        moved = 0.0
        if self._built:
            surface_motion(self, model.x, model.v)
            moved, speed = (float(a) for a in self.motion.to_numpy())
        if not self._built or moved > 0.5 * half:
            self._rebuild(model)
            moved = 0.0
            surface_motion(self, model.x, model.v)
            speed = float(self.motion[1])
        steps = (half - moved) / (4.0 * max(speed, 1e-30) * model.dt)
        self._countdown = int(min(max(steps, 1.0), 1000.0))

    def after_state_load(self) -> None:
        """After a checkpoint is loaded: rebuild the search grid and the active query
        list at the next call (a checkpoint from before the list existed has none)."""
        self._built = False
        self._countdown = 0

    @property
    def n_active(self) -> int:
        """Queries the contact loop visits (listed at the last grid build)."""
        return int(self.status[1])

    def _rebuild(self, model: Model) -> None:
        build_grid(self, model.x)
        if int(self.status[0]):
            raise RuntimeError("contact search grid overflow: segments far larger than meshed")
        self._k_activate(model.x)
        self.rebuilds += 1
        self._built = True

    # ------------------------------------------------------------------ contact forces

    @ti.func
    def step_begin(self, member, n_members):
        """Clear this member's share of the pairs' and the tracked nodes' forces."""
        p0, p1 = share(self.n_pairs, member, n_members)
        for p in range(p0, p1):
            if self._pair_on(p):
                self.cur[p] = ti.Vector.zero(ti.i64, 4)
        t0, t1 = share(self.n_track, member, n_members)
        for t in range(t0, t1):
            if self._node_on(self.track[t]):
                self.node_force[self.track[t]] = ti.Vector.zero(ti.i64, 2)

    @ti.func
    def step_share(self, member, n_members, x: ti.template(), v: ti.template(),
                   mass: ti.template(), f_ext: ti.template(), dt, dt_v):  # fmt: skip
        """This member's share of the listed queries."""
        q0, q1 = share(self.status[1], member, n_members)
        for qa in range(q0, q1):
            if self._node_on(self.q_node[self.q_active[qa]]):
                self._query(qa, x, v, mass, f_ext, dt)

    @ti.func
    def step_end(self, member, n_members, x: ti.template(), v: ti.template(),
                 mass: ti.template(), f_ext: ti.template(), dt, dt_v):  # fmt: skip
        """After every share: this member's share of the pair resultants into the sample
        sums."""
        p0, p1 = share(self.n_pairs, member, n_members)
        for p in range(p0, p1):
            if self._pair_on(p):
                self.acc[p] += force_at(self.cur, p)

    @ti.func
    def _node_on(self, i):
        """Whether node ``i``'s ensemble member steps (always, for one model): one held
        still keeps its contact states and last forces."""
        on = True
        if ti.static(self._members > 1):
            on = self.member_on[i // self._member_nodes] != 0
        return on

    @ti.func
    def _pair_on(self, p):
        """Whether pair ``p``'s ensemble member steps."""
        on = True
        if ti.static(self._members > 1):
            on = self.member_on[self.pair_member[p]] != 0
        return on

    @ti.func
    def _query(self, qa, x: ti.template(), v: ti.template(), mass: ti.template(),
               f_ext: ti.template(), dt):  # fmt: skip
        """The contact of the ``qa``-th listed query: closest segment, patch, forces."""
        q = self.q_active[qa]
        i = self.q_node[q]
        S = self.q_surf[q]
        xp = x[i]
        cx, cy = cell_xy(self, xp)
        c = member_cells(self, i) + cy * self._nx + cx
        best = -1
        best_d2 = 1e300
        best_pen = 0.0
        best_xi = 0.0
        for k in range(self.cell_start[c], self.cell_start[c + 1]):
            s, xi, d2 = candidate(self, S, i, k, xp, x)
            # Closest segment (true distance, so an extended line beyond a convex
            # vertex never wins); ties to the lower index.
            if s >= 0 and (d2 < best_d2 or (d2 == best_d2 and s < best)):
                best, best_d2, best_xi = s, d2, xi
                a = x[self.seg_a[s]]
                d = x[self.seg_b[s]] - a
                l2 = d.dot(d)
                best_pen = -(xp - a).dot(ti.Vector([d[1], -d[0]])) / ti.sqrt(l2)
                # Against the arc: its offset from the chord (parabolic sagitta, zero
                # at the nodes) adds to the penetration.
                xc = ti.min(ti.max(xi, 0.0), 1.0)
                best_pen += 0.5 * self.seg_kappa[s] * l2 * xc * (1.0 - xc)
        pen_eff = best_pen
        e_el = 0.0
        if ti.static(self._smooth):
            if self.q_corner[q] != 0:
                # A corner of its own surface (a spall's edge): a point contact.
                e_el = 0.5 * ti.max(best_pen, 0.0) ** 2
            else:
                # Most queries are far from contact: skip the patch when even a patch
                # of 1.5x the reference size, tilted 90 degrees, could not reach.
                hq = self.q_hmax[q]
                kap = ti.abs(self.q_kappa[q] + self.seg_kappa[best])
                reach = hq * (1.0 + 0.5 * kap * hq)
                if best >= 0 and best_pen + reach > 0.0:
                    pen_eff, e_el, best_pen = patch_overlap(self, q, i, best, best_pen, best_xi, x)
        if best_pen <= 0.0 or best_pen >= self._capture:
            best = -1
        if best < 0:
            self._open(q)
        else:
            self._apply(q, i, S, best, pen_eff, e_el, best_xi, x, v, mass, f_ext, dt)

    @ti.func
    def _apply(
        self,
        q,
        i,
        S,
        s,
        pen,
        e_el,
        xi_raw,
        x: ti.template(),
        v: ti.template(),
        mass: ti.template(),
        f_ext: ti.template(),
        dt,
    ):
        ia, ib = self.seg_a[s], self.seg_b[s]
        xi = ti.min(ti.max(xi_raw, 0.0), 1.0)
        tv, nv = arc_frame(self, s, xi, x)
        m_m = (1.0 - xi) * mass[ia] + xi * mass[ib]
        m_eff = mass[i] * m_m / (mass[i] + m_m)
        k_set = self.seg_k[s]
        if ti.static(self._query_side):
            k_set = self.q_k[q] * self.pass_share[S * self.n_surf + self.seg_surf[s]]
        k = self.law.stiffness(k_set, m_eff, dt)
        vrel = v[i] - ((1.0 - xi) * v[ia] + xi * v[ib])
        vn = vrel.dot(nv)
        vt = vrel.dot(tv)
        fn, e_damp = self.law.normal(k, pen, m_eff, vn, dt)
        # Friction: keep the stick state on the same or a neighbouring segment.
        old = self.q_seg[q]
        keep = 0
        if old == s:
            keep = 1
        elif old >= 0:
            if self.seg_surf[old] == self.seg_surf[s]:
                if self.seg_a[old] == ib or self.seg_b[old] == ia:
                    keep = 1
        ft0 = 0.0
        e_t0 = 0.0
        lost = 0.0
        if keep != 0:
            ft0 = self.q_ft[q]
            e_t0 = self.q_et[q]
        else:
            lost = self.q_et[q]  # reset: the old spring energy is lost
        ft, e_t, e_fric = friction_force(
            ft0, e_t0, k, vt, fn, dt, self._mu_s, self._mu_d, self._decay
        )
        self.q_diss[q] += ti.Vector([e_fric + lost, e_damp])
        F = fn * nv + ft * tv
        for f in ti.static((f_ext, self.node_force)):
            add_force(f, i, F)
            add_force(f, ia, -(1.0 - xi) * F)
            add_force(f, ib, -xi * F)
        key = S * self.n_surf + self.seg_surf[s]
        p = self.pass_pair[key]
        sg = self.pass_sign[key]
        add_force(self.cur, p, ti.Vector([sg * F[0], sg * F[1], fn, -ft]))
        self.q_seg[q] = s
        self.q_ft[q] = ft
        self.q_fn[q] = fn
        self.q_gap[q] = -pen
        self.q_en[q] = self.law.energy(k, pen)
        if ti.static(self._smooth):
            self.q_en[q] = self.law.patch_energy(k, e_el)
        self.q_et[q] = e_t

    # ------------------------------------------------------------------ Python-side hooks

    def before_steps(self, model: Model, n: int) -> int:
        """Before ``n`` steps in one launch: checks the search grid when due, and returns
        how many steps may run before the next check."""
        if self._countdown <= 0:
            self._check_grid(model)
        return min(n, self._countdown)

    def after_steps(self, model: Model, n: int) -> None:
        """After ``n`` steps: counts them (grid schedule, sample means)."""
        self._countdown -= n
        self.n_samples += n

    def force_nodes(self) -> np.ndarray:
        """Query and segment nodes: the only ones this contact pushes."""
        return self.track_np

    def start(self, model: Model) -> None:
        """Time 0 of a transient: the dissipation counts from here."""
        self.reset_dissipation()

    def load_state_arrays(self, arrays) -> None:
        """Restore a checkpoint's state; the search grid and the active query list are
        rebuilt at the next step."""
        super().load_state_arrays(arrays)
        self.after_state_load()
