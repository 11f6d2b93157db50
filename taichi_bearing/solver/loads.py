"""Constraints, loads and initial velocities: plain data, applied by the solver's kernels.

All node indices refer to the :class:`~taichi_bearing.mesh.types.Mesh` given to the model.
Forces are in newtons for the model's plane-strain thickness (not per metre).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "FixedNodes",
    "HeldDirection",
    "NodalForces",
    "PrescribedRotation",
    "RigidPlate",
    "RigidVelocity",
    "line_load",
    "rotation_angle",
    "uniform_load",
]


def _ids(nodes) -> np.ndarray:
    a = np.unique(np.asarray(nodes, dtype=np.int64).ravel())
    if a.size == 0:
        raise ValueError("a constraint or load needs at least one node")
    return a


def _unit(direction, what: str) -> tuple[float, float]:
    d = np.asarray(direction, dtype=float)
    if d.shape != (2,) or not np.linalg.norm(d) > 0:
        raise ValueError(f"{what}.direction must be a non-zero 2-vector, got {d}")
    return tuple(d / np.linalg.norm(d))


@dataclass
class FixedNodes:
    """Nodes held at their reference position (zero velocity)."""

    nodes: np.ndarray

    def __post_init__(self) -> None:
        self.nodes = _ids(self.nodes)


@dataclass
class HeldDirection:
    """Nodes whose motion along the unit ``direction`` is held (e.g. (1, 0): no sliding)."""

    nodes: np.ndarray
    direction: tuple[float, float]

    def __post_init__(self) -> None:
        self.nodes = _ids(self.nodes)
        self.direction = _unit(self.direction, "HeldDirection")


@dataclass
class RigidPlate:
    """Nodes that move together as one rigid loading plate along the unit ``direction``
    and are held across it: one shared velocity, driven by the sum of the forces on the
    nodes (loads, element and contact forces) over the sum of their masses.

    Unlike :class:`HeldDirection` alone, the plate cannot tilt, so a body hanging from it
    has no zero-energy rotation about the plate's centre.
    """

    nodes: np.ndarray
    direction: tuple[float, float] = (0.0, 1.0)

    def __post_init__(self) -> None:
        self.nodes = _ids(self.nodes)
        self.direction = _unit(self.direction, "RigidPlate")


@dataclass
class PrescribedRotation:
    """Nodes turned rigidly about ``center``: angular speed ramps linearly from
    ``omega_start`` to ``omega`` over ``ramp_time`` s, then stays constant (rad/s, CCW +).
    The angle is zero at time 0, so the nodes start at their reference position."""

    nodes: np.ndarray
    center: tuple[float, float]
    omega: float
    omega_start: float = 0.0
    ramp_time: float = 0.0

    def __post_init__(self) -> None:
        self.nodes = _ids(self.nodes)
        if self.ramp_time < 0:
            raise ValueError(f"PrescribedRotation.ramp_time must be >= 0, got {self.ramp_time}")


def rotation_angle(rot: PrescribedRotation, t: float) -> float:
    """Angle of a :class:`PrescribedRotation` at time ``t`` (the kernels use the same law)."""
    w0, w1, tr = rot.omega_start, rot.omega, rot.ramp_time
    if t < tr:
        return w0 * t + 0.5 * (w1 - w0) * t * t / tr
    return 0.5 * (w0 + w1) * tr + w1 * (t - tr)


@dataclass
class NodalForces:
    """Dead nodal forces ``forces[k]`` (N) on ``nodes[k]``, scaled by a linear ramp from 0
    to 1 over ``ramp_time`` s (0: applied at once). Repeated nodes add up."""

    nodes: np.ndarray
    forces: np.ndarray
    ramp_time: float = 0.0

    def __post_init__(self) -> None:
        self.nodes = np.asarray(self.nodes, dtype=np.int64).ravel()
        self.forces = np.asarray(self.forces, dtype=float).reshape(len(self.nodes), 2)
        if self.ramp_time < 0:
            raise ValueError(f"NodalForces.ramp_time must be >= 0, got {self.ramp_time}")

    @property
    def total(self) -> np.ndarray:
        """Resultant at full load, N."""
        return self.forces.sum(axis=0)


def uniform_load(nodes, total_force, ramp_time: float = 0.0) -> NodalForces:
    """The force ``total_force`` (N, 2-vector) split equally over ``nodes``."""
    ids = _ids(nodes)
    f = np.tile(np.asarray(total_force, dtype=float) / len(ids), (len(ids), 1))
    return NodalForces(ids, f, ramp_time)


def line_load(coords: np.ndarray, nodes, total_force, ramp_time: float = 0.0) -> NodalForces:
    """A uniform pressure along a straight row of nodes, lumped by tributary length.

    Parameters
    ----------
    coords : ndarray (n_nodes, 2)
        Reference node coordinates (``mesh.nodes``).
    nodes : array of int
        The row of nodes (any order; sorted along the row here).
    total_force : 2-vector
        Resultant, N (pressure x loaded length x thickness).
    ramp_time : float
        Linear ramp duration, s.

    Returns
    -------
    NodalForces
        Each node gets half of the length of its neighbouring segments (ends: one half).
    """
    ids = _ids(nodes)
    if len(ids) == 1:
        return uniform_load(ids, total_force, ramp_time)
    p = coords[ids]
    # Order along the row's main direction (largest extent).
    axis = p - p.mean(axis=0)
    _, _, vt = np.linalg.svd(axis, full_matrices=False)
    order = np.argsort(axis @ vt[0])
    ids, p = ids[order], p[order]
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    w = np.zeros(len(ids))
    w[:-1] += 0.5 * seg
    w[1:] += 0.5 * seg
    f = np.outer(w / w.sum(), np.asarray(total_force, dtype=float))
    return NodalForces(ids, f, ramp_time)


@dataclass
class RigidVelocity:
    """Initial rigid-body velocity of every node of a part:
    ``v = velocity + omega x (X - center)`` (omega CCW +, rad/s)."""

    part: str | int
    omega: float = 0.0
    center: tuple[float, float] = (0.0, 0.0)
    velocity: tuple[float, float] = (0.0, 0.0)
