"""Each roller's centre and spin computed where the model's state lives (the device), so
that an output sample reads three numbers a roller instead of every node's position and
velocity.

On an H200 a third of an output sample was reading roller motion back to the host and
summing it with NumPy; an ensemble of N members would read N times as much.
The sums here run over each roller's nodes in the order the NumPy read-out took them
(:func:`taichi_bearing.simulation.starter.roller_kinematics_matrix`), one roller a thread.
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import numpy as np
import taichi as ti

from taichi_bearing.solver import transfer

__all__ = ["RollerReadout"]


@ti.data_oriented
class RollerReadout:
    """The mass centroid and the spin of every roller of a model (of every ensemble
    member: roller ``j`` of member ``k`` is row ``k Z + j``).

    Parameters
    ----------
    nodes : sequence of ndarray
        Each roller's node indices in the model, in the order its sums take them.
    mass : ndarray
        The model's nodal masses (``Model.mass_np``).
    """

    def __init__(self, nodes, mass: np.ndarray) -> None:
        sizes = [len(n) for n in nodes]
        self.n = n = len(nodes)
        ids = np.concatenate(nodes).astype(np.int32)
        self.node = ti.field(ti.i32, shape=max(len(ids), 1))
        self.mass = ti.field(ti.f64, shape=max(len(ids), 1))
        self.ptr = ti.field(ti.i32, shape=n + 1)
        # per roller: centre x, y, spin
        self.out = ti.Vector.field(3, ti.f64, shape=max(n, 1))
        transfer.upload(
            [
                (self.node, ids),
                (self.mass, np.asarray(mass, dtype=float)[ids]),
                (self.ptr, np.concatenate([[0], np.cumsum(sizes)]).astype(np.int32)),
            ]
        )

    @ti.kernel
    def _measure(self, x: ti.template(), v: ti.template()):
        for j in range(self.n):
            lo, hi = self.ptr[j], self.ptr[j + 1]
            m_sum = 0.0
            mx = ti.Vector([0.0, 0.0])
            mv = ti.Vector([0.0, 0.0])
            for k in range(lo, hi):
                m = self.mass[k]
                i = self.node[k]
                m_sum += m
                mx += m * x[i]
                mv += m * v[i]
            c = mx / m_sum
            vc = mv / m_sum
            num = 0.0
            den = 0.0
            for k in range(lo, hi):
                m = self.mass[k]
                i = self.node[k]
                r = x[i] - c
                dv = v[i] - vc
                num += m * (r[0] * dv[1] - r[1] * dv[0])
                den += m * (r[0] * r[0] + r[1] * r[1])
            self.out[j] = ti.Vector([c[0], c[1], num / den])

    def measure(self, model) -> np.ndarray:
        """``(n_rollers, 3)``: each roller's centre (x, y, m) and spin (rad/s, CCW +) at
        the model's current state."""
        self._measure(model.x, model.v)
        (out,) = transfer.download((self.out,))
        return out[: self.n]
