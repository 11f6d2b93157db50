"""History recorders of the bearing run: roller contact forces, roller and cage motion.

Each recorder has ``columns`` and ``sample(model) -> values`` (one value per column) and
is called by :func:`taichi_bearing.simulation.engine.run_transient` once per output sample.
"""

from __future__ import annotations

import math

import numpy as np

from taichi_bearing.output.layout import (
    CAGE_COLUMNS,
    ROLLER_MOTION_QUANTITIES,
    roller_force_columns,
    roller_motion_column,
)
from taichi_bearing.output.recorder import Recorder
from taichi_bearing.simulation.starter import roller_kinematics_matrix

__all__ = ["CageRecorder", "ContactForceRecorder", "RollerMotionRecorder", "roller_motion_columns"]


class ContactForceRecorder(Recorder):
    """``roller<j>_<race>_fx|fy|fn|ft``: the contact force BY roller j ON each raceway,
    averaged over the sample interval (the contact's ``pop_sample_means``).

    ``pair_table[j, r]`` is the contact pair of roller ``j`` on race ``r`` (outer, inner;
    :attr:`taichi_bearing.simulation.starter.Setup.pair_table`).
    """

    def __init__(self, contact, pair_table: np.ndarray) -> None:
        self.contact = contact
        self.pair_table = np.asarray(pair_table)
        self.columns = roller_force_columns(len(self.pair_table))

    def sample(self, model) -> np.ndarray:
        means = np.asarray(self.contact.pop_sample_means(), dtype=float)
        return means[self.pair_table].ravel()


def roller_motion_columns(n_rollers: int) -> list[str]:
    """``roller<j>_angle_rad`` (centre, from 12 o'clock, CCW, unwrapped),
    ``roller<j>_spin_rad_s`` (absolute spin, CCW +) and ``roller<j>_radius_m`` (distance of
    the centre from the bearing centre: shows a roller rising into an outer-race spall)."""
    return [roller_motion_column(j, q) for q in ROLLER_MOTION_QUANTITIES for j in range(n_rollers)]


class RollerMotionRecorder(Recorder):
    r"""Each roller's centre angle, spin and radius at the end of each sample interval.

    The centre is the mass centroid of the roller's nodes; the spin is
    :math:`\sum m \, r \times (v - v_c) / \sum m |r|^2` about it (exact for a rigid roller).
    Both are
    computed on the model's device
    (:class:`~taichi_bearing.simulation.roller_readout.RollerReadout`): a sample reads
    three numbers a roller.

    Parameters
    ----------
    n_rollers : int
    measure : callable
        Returns the ``(n_rollers, 3)`` centres (x, y) and spins of the current state.
    """

    def __init__(self, n_rollers: int, measure) -> None:
        self.n = n_rollers
        self.columns = roller_motion_columns(n_rollers)
        self.measure = measure
        self.angle = None  # last unwrapped angles

    @classmethod
    def of_model(cls, model, mesh, n_rollers: int) -> RollerMotionRecorder:
        """The recorder of a bearing model's rollers (``roller<j>`` parts of ``mesh``)."""
        from taichi_bearing.simulation.roller_readout import RollerReadout

        nodes, owner = roller_kinematics_matrix(mesh, n_rollers)
        readout = RollerReadout([nodes[owner == j] for j in range(n_rollers)], model.mass_np)
        return cls(n_rollers, lambda: readout.measure(model))

    def sample(self, model) -> np.ndarray:
        motion = np.asarray(self.measure())
        cx, cy, spin = motion[:, 0], motion[:, 1], motion[:, 2]
        angle = np.arctan2(-cx, cy)
        if self.angle is not None:
            angle = self.angle + (angle - self.angle + math.pi) % (2 * math.pi) - math.pi
        self.angle = angle
        return np.concatenate([angle, spin, np.hypot(cx, cy)])

    def state_arrays(self) -> dict[str, np.ndarray]:
        a = np.full(self.n, np.nan) if self.angle is None else self.angle
        return {"angle": np.asarray(a, dtype=float)}

    def load_state_arrays(self, arrays) -> None:
        a = np.asarray(arrays["angle"], dtype=float)
        self.angle = None if np.isnan(a).any() else a


class CageRecorder(Recorder):
    """``cage_angle_rad`` (from the start, CCW) and ``cage_speed_rad_s`` at each sample.

    With a rigid cage model, its own angle and speed; without one, the mean orbital angle
    and speed of the rollers (from a :class:`RollerMotionRecorder` sampled first).
    """

    columns = list(CAGE_COLUMNS)

    def __init__(self, cage=None, rollers: RollerMotionRecorder | None = None) -> None:
        if cage is None and rollers is None:
            raise ValueError("CageRecorder needs a cage or a RollerMotionRecorder")
        self.cage = cage
        self.rollers = rollers
        self.start = None
        self.last = (math.nan, math.nan)  # (time, mean angle) of the previous sample

    def sample(self, model) -> np.ndarray:
        if self.cage is not None:
            return np.array([float(self.cage.angle), float(self.cage.speed)])
        mean = float(np.mean(self.rollers.angle))
        t = model.time
        if self.start is None:
            self.start = mean
        speed = (mean - self.last[1]) / (t - self.last[0]) if t > self.last[0] else math.nan
        self.last = (t, mean)
        return np.array([mean - self.start, speed])

    def state_arrays(self) -> dict[str, np.ndarray]:
        start = math.nan if self.start is None else self.start
        return {"start": np.float64(start), "last": np.asarray(self.last, dtype=float)}

    def load_state_arrays(self, arrays) -> None:
        start = float(arrays["start"])
        self.start = None if math.isnan(start) else start
        self.last = tuple(float(v) for v in arrays["last"])
