"""Force contributors: what adds nodal forces to the model each step besides the elements
(penalty contact, the rigid cage, a test's body force).

A contributor subclasses :class:`ForceContributor` and overrides the hooks it needs; every
hook has a default that does nothing. There are two kinds:

* **kernel contributors** (``in_kernel = True``, the default) define Taichi functions that
  the step body (:mod:`taichi_bearing.solver.step_phases`) calls inside the model's step kernels,
  in the phases of a step: :meth:`~ForceContributor.step_begin` (each member clears its
  share of what it sums), :meth:`~ForceContributor.step_share` (each member's share of the
  forces, beside its share of the elements) and :meth:`~ForceContributor.step_end`
  (member 0 alone, once every share is done). Stepped alone (:meth:`add_forces`), one
  member does all three.
* **Python contributors** (``in_kernel = False``) override :meth:`add_forces`, which the
  model calls between two kernel launches of each step (simplest to write, one launch
  pair per step).

Forces go into the model's fixed-point field ``f_extra`` with :func:`add_force`: integer
adds give the same sum in any order, so several threads adding at once do not change the
result (runs are bit-reproducible on any thread count). Kernel contributors must be added
(:meth:`Model.add_contributor`) before the model's first step: Taichi compiles the step
kernels once, with the contributors they had then.
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
from collections.abc import Mapping
from typing import ClassVar

import numpy as np
import taichi as ti
from taichi.lang.field import Field as TaichiField

from taichi_bearing.solver import transfer
from taichi_bearing.solver.backend import parallel_members

__all__ = ["FORCE_QUANTUM", "ForceContributor", "add_force", "force_at"]

# Extra nodal forces are summed as integers of this many newtons (see add_force): the
# rounding (at most 7e-12 N a contribution) is far below anything a bearing model resolves,
# and one contribution is capped at 2^60 quanta (1.7e7 N, a runaway the energy and
# inversion checks stop), so a node's sum of a few cannot overflow.
FORCE_QUANTUM = 2.0**-36
_FORCE_SCALE = 2.0**36
_FORCE_CAP = 2.0**60


@ti.func
def add_force(f: ti.template(), i, F):
    """Add the force vector ``F`` (N) on node ``i`` to the fixed-point field ``f`` (such
    as ``Model.f_extra``), rounded to :data:`FORCE_QUANTUM`. Safe from any thread."""
    f[i] += ti.cast(ti.round(ti.math.clamp(F * _FORCE_SCALE, -_FORCE_CAP, _FORCE_CAP)), ti.i64)


@ti.func
def force_at(f: ti.template(), i):
    """Node ``i``'s force (N) summed in the fixed-point field ``f``."""
    return ti.cast(f[i], ti.f64) * FORCE_QUANTUM


@ti.data_oriented
class ForceContributor:
    """Base class of the force contributors (see the module notes); every hook defaults
    to doing nothing.

    Attributes
    ----------
    in_kernel : bool
        True: the step kernels call the Taichi hooks; False: the model calls
        :meth:`add_forces` from Python between the kernels of each step.
    """

    in_kernel: ClassVar[bool] = True

    # ---------------------------------------------------------------- inside the step

    @ti.func
    def step_begin(self, member, n_members):
        """First phase of a step: member ``member`` of ``n_members`` clears its share of
        what this contributor sums over the step."""
        pass

    @ti.func
    def step_share(self, member, n_members, x: ti.template(), v: ti.template(),
                   mass: ti.template(), f_ext: ti.template(), dt, dt_v):  # fmt: skip
        """Member ``member``'s share of the forces: reads positions ``x`` (at ``t``) and
        velocities ``v`` (at ``t - dt/2``), adds forces into ``f_ext`` with
        :func:`add_force`. ``dt_v`` is the velocity update's step (``dt / 2`` on the
        first step after a restart)."""
        pass

    @ti.func
    def step_end(self, member, n_members, x: ti.template(), v: ti.template(),
                 mass: ti.template(), f_ext: ti.template(), dt, dt_v):  # fmt: skip
        """After every share and before the nodes move: member ``member``'s share of the
        step's end (sums over the step), and what must be serial (a rigid body's own
        update) on member 0. Adds no forces: the plate reads ``f_ext`` meanwhile."""
        pass

    @ti.kernel
    def _k_alone(self, x: ti.template(), v: ti.template(), mass: ti.template(),
                 f_ext: ti.template(), dt: ti.f64, dt_v: ti.f64,
                 n_members: ti.template()):  # fmt: skip
        # the step's phases for this contributor alone, as a parallel step launches them
        ti.loop_config(serialize=n_members == 1)
        for member in range(n_members):
            self.step_begin(member, n_members)
        ti.loop_config(serialize=n_members == 1)
        for member in range(n_members):
            self.step_share(member, n_members, x, v, mass, f_ext, dt, dt_v)
        ti.loop_config(serialize=n_members == 1)
        for member in range(n_members):
            self.step_end(member, n_members, x, v, mass, f_ext, dt, dt_v)

    # ---------------------------------------------------------------- from Python

    def add_forces(self, model, t: float) -> None:
        """Add this step's forces into ``model.f_extra`` (time ``t``). Python
        contributors override this; for a kernel contributor it runs the Taichi hooks
        in launches of their own, as a parallel step would."""
        self.before_steps(model, 1)
        dt = model.dt
        dt_v = 0.5 * dt if model.first else dt
        self._k_alone(model.x, model.v, model.mass, model.f_extra, dt, dt_v, parallel_members())
        self.after_steps(model, 1)

    def before_steps(self, model, n: int) -> int:
        """Before up to ``n`` steps in one launch: prepare (e.g. a search structure) and
        return how many steps may run before this needs Python again (at least 1)."""
        return n

    def after_steps(self, model, n: int) -> None:
        """After ``n`` steps ran (e.g. count them for sample means)."""

    def force_nodes(self) -> np.ndarray | None:
        """The nodes this contributor may add forces to (None: any node). The node update
        reads the contributors' forces at these nodes only."""
        return None

    def start(self, model) -> None:
        """The model's clock restarts for a transient at ``t = 0``
        (:meth:`Model.set_initial_velocities`): reset what counts from there."""

    # ---------------------------------------------------------------- read-out and state

    def energy(self) -> float:
        """Energy this contributor holds (J): stored springs, a rigid body's kinetic
        energy. Informational: the work of its forces is already in the model's
        ``external_work``."""
        return 0.0

    def member_energies(self) -> np.ndarray:
        """:meth:`energy` of each member of an ensemble (one model: one value). A
        contributor an ensemble uses overrides it."""
        return np.array([self.energy()])

    def state_arrays(self) -> dict[str, np.ndarray]:
        """Everything needed to continue bit for bit after a resume. Default: every
        Taichi field and every plain int/float/bool attribute of the object."""
        out: dict[str, np.ndarray] = {}
        batch = {}  # the fields one copy kernel reads (solver.transfer)
        for name, val in vars(self).items():
            if isinstance(val, TaichiField):
                if transfer.is_transferable(val):
                    batch[name] = val
                else:
                    out[name] = val.to_numpy()
            elif isinstance(val, (bool, int, float)):
                out[name] = np.asarray(val)
        out.update(zip(batch, transfer.download(list(batch.values())), strict=True))
        return {name: out[name] for name in vars(self) if name in out}

    def load_state_arrays(self, arrays: Mapping[str, np.ndarray]) -> None:
        """Restore what :meth:`state_arrays` saved."""
        batch = []  # the fields one copy kernel writes (solver.transfer)
        for name, a in arrays.items():
            if not hasattr(self, name):
                continue  # a checkpoint of an older version: an attribute since removed
            cur = getattr(self, name)
            if isinstance(cur, TaichiField) and transfer.is_transferable(cur):
                batch.append((cur, np.asarray(a)))
            elif isinstance(cur, TaichiField):
                cur.from_numpy(np.asarray(a))
            else:
                setattr(self, name, type(cur)(np.asarray(a).item()))
        transfer.upload(batch)
