r"""What a mode shape is, in words: rigid-body motion, or the number of nodal diameters of
a ring's (or roller's) radial displacement on its mid-circle, found by Fourier analysis.

A ring mode with :math:`n` nodal diameters has a radial displacement
:math:`u_r \propto \cos n\theta` round the ring. In-plane bending (inextensional) modes
move mostly radially (:math:`|u_\theta| = |u_r| / n` for a thin ring); extensional modes
mostly tangentially.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from taichi_bearing.mesh.types import Mesh

__all__ = ["BodyGeometry", "body_geometry", "describe", "kinetic_shares", "ring_harmonics"]

# bins round a body over which its outline radii are taken (medians ignore an adapter)
_ANGLE_BINS = 72
# share of a mode's kinetic energy a body needs to be named in a rigid-body mode
_NAMED_SHARE = 0.1
# an elastic mode in which a body moves this much as a rigid body is that body moving on
# what holds it (a roller on its contacts, the ring swinging on its plate)
_RIGID_LIKE = 0.5


@dataclass(frozen=True)
class BodyGeometry:
    r"""A body's centre (m), the radius of its mid-circle (m, rings) or outline (m,
    disks), whether it is a ring round its centre, and what the Fourier analysis of its
    motion uses: the nodes near that circle, their angles about the centre and the
    least-squares projector onto :math:`\cos n\theta`, :math:`\sin n\theta`."""

    centre: np.ndarray
    radius: float
    ring: bool
    nodes: np.ndarray
    theta: np.ndarray
    projector: np.ndarray

    @property
    def n_max(self) -> int:
        return (self.projector.shape[0] - 1) // 2


def _surrounds(xy: np.ndarray, centre: np.ndarray) -> bool:
    """Whether the points go all the way round ``centre`` (a ring, not a disk) with the
    centre itself outside the material."""
    d = xy - centre
    r = np.hypot(*d.T)
    theta = np.arctan2(d[:, 1], d[:, 0])
    filled = np.unique(np.floor((theta + np.pi) / (2 * np.pi) * _ANGLE_BINS).astype(int))
    return len(filled) >= _ANGLE_BINS - 1 and r.min() > 0.05 * r.max()


def _fourier(ids: np.ndarray, d: np.ndarray, n_max: int):
    """Angles of the nodes and the least-squares projector of their values onto the
    harmonics ``0 .. n_max`` (fewer where the nodes are too few): rows ``a_0 .. a_n``,
    then ``b_1 .. b_n``. Uneven spacing does not matter."""
    theta = np.arctan2(d[:, 1], d[:, 0])
    n_max = int(min(n_max, max(1, (len(theta) - 1) // 4)))
    n = np.arange(n_max + 1)
    basis = np.concatenate([np.cos(np.outer(theta, n)), np.sin(np.outer(theta, n[1:]))], axis=1)
    return theta, np.linalg.pinv(basis)


def body_geometry(mesh: Mesh, n_max: int = 40) -> dict[str, BodyGeometry]:
    """The geometry of every part: a ring about the origin (the bearing centre), with the
    mid-circle halfway between the medians over angle of its inner and outer radii (an
    adapter on top does not move it), or a body about its centroid and outline radius.
    The Fourier analysis takes a ring's nodes within a quarter of its thickness of the
    mid-circle, a disk's within a tenth of its radius of the outline."""
    out = {}
    for p, name in enumerate(mesh.part_names):
        ids = np.unique(mesh.elements[mesh.element_part == p])
        xy = mesh.nodes[ids]
        origin = np.zeros(2)
        ring = _surrounds(xy, origin)
        centre = origin if ring else xy.mean(axis=0)
        d = xy - centre
        r = np.hypot(*d.T)
        bins = np.floor((np.arctan2(d[:, 1], d[:, 0]) + np.pi) / (2 * np.pi) * _ANGLE_BINS)
        lo = np.median([r[bins == b].min() for b in np.unique(bins)])
        hi = np.median([r[bins == b].max() for b in np.unique(bins)])
        radius = 0.5 * (lo + hi) if ring else hi
        band = 0.25 * (hi - lo) if ring else 0.1 * hi
        near = np.abs(r - radius) <= band
        if near.sum() < 8:  # a coarse mesh: the nearest tenth of the nodes
            near = np.abs(r - radius) <= np.quantile(np.abs(r - radius), 0.1)
        theta, projector = _fourier(ids[near], d[near], n_max)
        out[name] = BodyGeometry(centre, float(radius), ring, ids[near], theta, projector)
    return out


def kinetic_shares(mesh: Mesh, mass: np.ndarray, shape: np.ndarray) -> np.ndarray:
    """Each part's share of the mode's kinetic energy (sum of m |u|^2 over its nodes)."""
    e_node = mass * np.sum(shape**2, axis=1)
    shares = np.zeros(len(mesh.part_names))
    for p in range(len(shares)):
        shares[p] = e_node[np.unique(mesh.elements[mesh.element_part == p])].sum()
    return shares / max(shares.sum(), 1e-300)


def ring_harmonics(body: BodyGeometry, shape: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""Fourier amplitudes :math:`\sqrt{a_n^2 + b_n^2}` of the radial and the tangential
    displacement on a body's circle, harmonics :math:`n` from 0 to ``body.n_max``."""
    u = shape[body.nodes]
    c, s = np.cos(body.theta), np.sin(body.theta)
    coef = body.projector @ np.stack([u[:, 0] * c + u[:, 1] * s, -u[:, 0] * s + u[:, 1] * c], 1)
    n_max = body.n_max
    amp = coef[: n_max + 1] ** 2
    amp[1:] += coef[n_max + 1 :] ** 2
    return np.sqrt(amp[:, 0]), np.sqrt(amp[:, 1])


def _rigid_fit(mesh: Mesh, part: int, mass: np.ndarray, shape: np.ndarray) -> tuple[str, float]:
    """The best rigid motion (translation of the centre of mass plus a turn about it)
    of a part's displacement: ``translation``, ``rotation`` or both, by their kinetic
    energies, and the share of the part's kinetic energy that it explains."""
    ids = np.unique(mesh.elements[mesh.element_part == part])
    m, u = mass[ids], shape[ids]
    c = np.average(mesh.nodes[ids], axis=0, weights=m)
    d = mesh.nodes[ids] - c
    t = np.average(u, axis=0, weights=m)
    inertia = float(np.sum(m * np.sum(d**2, axis=1)))
    omega = float(np.sum(m * (d[:, 0] * u[:, 1] - d[:, 1] * u[:, 0]))) / max(inertia, 1e-300)
    e_t, e_r = m.sum() * float(t @ t), inertia * omega**2
    share = (e_t + e_r) / max(float(np.sum(m * np.sum(u**2, axis=1))), 1e-300)
    if e_t > 9.0 * e_r:
        return "translation", share
    if e_r > 9.0 * e_t:
        return "rotation", share
    return "translation and rotation", share


def _elastic_words(order: int, radial: float, tangential: float) -> str:
    if order == 0:
        return "breathing (n=0)" if radial >= tangential else "torsional (n=0)"
    kind = "in-plane bending" if radial >= tangential else "extensional"
    return f"n={order} {kind}"


def describe(
    mesh: Mesh,
    mass: np.ndarray,
    shape: np.ndarray,
    rigid: bool,
    bodies: dict[str, BodyGeometry] | None = None,
) -> tuple[str, str, float, int | None]:
    """A short description of a mode shape.

    Returns
    -------
    description : str
        e.g. ``"rigid-body (rotation)"``, ``"n=3 in-plane bending"``,
        ``"outer_ring: n=2 in-plane bending (82 % of the kinetic energy)"`` (the body is
        named when the mesh holds several).
    body : str
        The part with the largest share of the kinetic energy.
    share : float
        Its share.
    order : int or None
        Nodal diameters of that body's radial motion (None for a rigid-body mode).
    """
    bodies = body_geometry(mesh) if bodies is None else bodies
    shares = kinetic_shares(mesh, mass, shape)
    top = int(np.argmax(shares))
    name = mesh.part_names[top]
    several = len(mesh.part_names) > 1
    if rigid:
        moving = [p for p in np.argsort(-shares) if shares[p] >= _NAMED_SHARE][:3]
        kinds = [_rigid_fit(mesh, p, mass, shape)[0] for p in moving]
        if not several:
            return f"rigid-body ({kinds[0]})", name, float(shares[top]), None
        parts = ", ".join(f"{mesh.part_names[p]} {k}" for p, k in zip(moving, kinds, strict=True))
        return f"rigid-body: {parts}", name, float(shares[top]), None
    radial, tangential = ring_harmonics(bodies[name], shape)
    order = int(np.argmax(np.hypot(radial, tangential)))
    words = _elastic_words(order, radial[order], tangential[order])
    kind, rigid_share = _rigid_fit(mesh, top, mass, shape)
    if rigid_share > _RIGID_LIKE:  # the body moves as a whole against what holds it
        words = f"{kind} on its supports"
    if several:
        words = f"{name}: {words} ({100 * shares[top]:.0f} % of the kinetic energy)"
    return words, name, float(shares[top]), order
