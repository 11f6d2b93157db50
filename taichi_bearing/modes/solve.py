"""Natural frequencies and mode shapes of a :class:`~taichi_bearing.modes.model.ModalModel`
by scipy's sparse Lanczos solver in shift-invert mode: the lowest modes (shift just below
0, so the rigid-body modes' singular stiffness still factorises), or those nearest a
frequency."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import eigsh

from taichi_bearing.blas import one_blas_thread
from taichi_bearing.modes.model import ModalModel
from taichi_bearing.modes.shapes import body_geometry, describe

__all__ = ["Mode", "ModalResult", "rigid_threshold_hz", "solve_modes"]

# A mode below this fraction of c_s / (2 pi L) (L: the model's size) is a rigid-body
# mode: a free steel ring's first bending mode lies above 1e-2 of it even at a thickness
# of 1 % of its radius, and round-off leaves rigid-body modes below 1e-6 of it.
RIGID_FRACTION = 1e-3


@dataclass
class Mode:
    """One mode: ``number`` from 1 in frequency order, ``frequency`` (Hz), ``shape``
    (n_nodes, 2) scaled so that its largest displacement component is +1, whether it
    is a rigid-body mode, its description, the body with most of its kinetic energy and
    that share, and the nodal diameters of that body's motion."""

    number: int
    frequency: float
    shape: np.ndarray
    rigid: bool
    description: str
    body: str
    share: float
    order: int | None


@dataclass
class ModalResult:
    """Modes of a model, lowest first, with the threshold (Hz) below which a mode counts
    as a rigid-body mode."""

    model: ModalModel
    modes: list[Mode]
    rigid_threshold: float

    @property
    def frequencies(self) -> np.ndarray:
        return np.array([m.frequency for m in self.modes])

    @property
    def elastic(self) -> list[Mode]:
        return [m for m in self.modes if not m.rigid]


def rigid_threshold_hz(model: ModalModel) -> float:
    """Frequency below which a mode is a rigid-body mode, Hz (see :data:`RIGID_FRACTION`)."""
    size = float(np.hypot(*np.ptp(model.mesh.nodes, axis=0)))
    return RIGID_FRACTION * model.shear_wave_speed / (2.0 * math.pi * size)


def _eig(model: ModalModel, k: int, sigma: float):
    n = model.matrix.shape[0]
    # a fixed start vector: the same model gives the same modes (and signs) every time
    v0 = np.cos(np.arange(n) * 0.618034) + 1.5
    with one_blas_thread():  # the same modes on any BLAS thread count
        lam, vec = eigsh(model.matrix, k=k, sigma=sigma, which="LM", v0=v0)
    order = np.argsort(lam)
    return lam[order], vec[:, order]


def solve_modes(model: ModalModel, count: int, near_hz: float | None = None) -> ModalResult:
    """The modes of a model.

    Parameters
    ----------
    model : ModalModel
    count : int
        How many elastic modes: the lowest ``count``, with every rigid-body mode below
        them as well (``near_hz`` None); or the ``count`` modes nearest ``near_hz``.
    near_hz : float, optional
        Centre frequency, Hz.

    Returns
    -------
    ModalResult

    Raises
    ------
    ValueError
        If ``count`` is not positive or exceeds what the model holds.
    """
    n = model.matrix.shape[0]
    if count < 1 or count > n - 2:
        raise ValueError(f"count: need 1 to {n - 2} modes for this model, got {count}")
    threshold = rigid_threshold_hz(model)
    if near_hz is not None:
        lam, vec = _eig(model, count, (2.0 * math.pi * near_hz) ** 2)
    else:
        # every body can add three rigid-body modes; ask for more until count are elastic
        k = min(count + 3 * model.n_bodies, n - 2)
        sigma = -((2.0 * math.pi * threshold) ** 2)
        while True:
            lam, vec = _eig(model, k, sigma)
            freq = np.sqrt(np.maximum(lam, 0.0)) / (2.0 * math.pi)
            elastic = np.flatnonzero(freq >= threshold)
            if len(elastic) >= count or k == n - 2:
                break
            k = min(2 * k, n - 2)
        keep = np.concatenate([np.flatnonzero(freq < threshold), elastic[:count]])
        lam, vec = lam[keep], vec[:, keep]
    freq = np.sqrt(np.maximum(lam, 0.0)) / (2.0 * math.pi)
    bodies = body_geometry(model.mesh)
    shapes = (model.basis @ vec).T.reshape(len(lam), model.mesh.n_nodes, 2)
    modes = []
    for i, (f, u) in enumerate(zip(freq, shapes, strict=True)):
        flat = u.ravel()
        u = u / flat[np.argmax(np.abs(flat))]  # largest component +1
        rigid = bool(f < threshold)
        text, body, share, order = describe(model.mesh, model.mass, u, rigid, bodies)
        modes.append(Mode(i + 1, float(f), u, rigid, text, body, share, order))
    return ModalResult(model, modes, threshold)
