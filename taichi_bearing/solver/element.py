r"""Reference-configuration data of the 1-point quadrilateral (numpy, computed once).

The element is the Flanagan-Belytschko uniform-strain quadrilateral: the deformation
gradient is :math:`F = \sum_I x_I \otimes b_I` with the mean shape-function gradients
:math:`b_I` over the reference element, which is exact for any linear field (patch test).
The hourglass modes are caught by :math:`q = \sum_I \gamma_I x_I` with the FB vectors
:math:`\gamma_I = (h_I - (h \cdot X_j) b_{jI}) / 4`, :math:`h = (1, -1, 1, -1)`, which
vanish for every linear field; the hourglass force :math:`f_I = -k \gamma_I q` turns with
the body, so it is objective, and it derives from the energy :math:`k |q|^2 / 2`.

The hourglass stiffness :math:`k = \frac{2}{3} E' t A (b \cdot b)` is the value for which
a square element carries exactly the bending energy of a plane-strain beam
(:math:`E' = E / (1 - \nu^2)`), so a few elements through a thickness bend without shear
locking.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

from taichi_bearing.blas import one_blas_thread
from taichi_bearing.case.material import Material
from taichi_bearing.errors import InputError
from taichi_bearing.mesh.types import Mesh

__all__ = [
    "ElementGeometry",
    "assembled_matrix",
    "assembled_max_frequency",
    "critical_time_steps",
    "element_geometry",
    "element_max_frequencies",
    "element_stiffness",
    "hooke_tangent",
    "hourglass_stiffness",
    "materials_per_element",
    "selective_mass_scale",
]

_H = np.array([1.0, -1.0, 1.0, -1.0])
_GAUSS = np.array([-1.0, 1.0]) / np.sqrt(3.0)
_XI = np.array([-1.0, 1.0, 1.0, -1.0])
_ETA = np.array([-1.0, -1.0, 1.0, 1.0])


class ElementGeometry:
    """Per-element reference data.

    Attributes
    ----------
    b : ndarray (n_elements, 4, 2)
        Mean shape-function gradients dN_I/dX.
    gamma : ndarray (n_elements, 4)
        Flanagan-Belytschko hourglass vectors.
    area : ndarray (n_elements,)
        Reference areas, m^2.
    shape_integrals : ndarray (n_elements, 4)
        Integrals of N_I over each element (row sums of the consistent mass / rho).
    """

    def __init__(self, b, gamma, area, shape_integrals) -> None:
        self.b = b
        self.gamma = gamma
        self.area = area
        self.shape_integrals = shape_integrals


def element_geometry(nodes: np.ndarray, elements: np.ndarray) -> ElementGeometry:
    """Reference-element data of a quadrilateral mesh.

    Parameters
    ----------
    nodes : ndarray (n_nodes, 2)
    elements : ndarray of int (n_elements, 4), counter-clockwise

    Raises
    ------
    InputError
        If an element has a non-positive area or Jacobian (clockwise or folded).
    """
    X = nodes[elements]  # (ne, 4, 2)
    x, y = X[..., 0], X[..., 1]
    # Shoelace area; the FB mean gradients are b_I = (y_{I+1} - y_{I-1}, x_{I-1} - x_{I+1})/2A.
    xn, yn = np.roll(x, -1, axis=1), np.roll(y, -1, axis=1)
    xp, yp = np.roll(x, 1, axis=1), np.roll(y, 1, axis=1)
    area = 0.5 * np.sum(x * yn - xn * y, axis=1)
    # Jacobian at the 4 Gauss points: catches folded (bow-tie) elements that have A > 0.
    s_int = np.zeros(elements.shape, dtype=float)
    min_det = np.full(len(elements), np.inf)
    for xi in _GAUSS:
        for eta in _GAUSS:
            n = 0.25 * (1 + _XI * xi) * (1 + _ETA * eta)
            dn_dxi = 0.25 * _XI * (1 + _ETA * eta)
            dn_deta = 0.25 * _ETA * (1 + _XI * xi)
            j11, j12 = x @ dn_dxi, y @ dn_dxi
            j21, j22 = x @ dn_deta, y @ dn_deta
            det = j11 * j22 - j12 * j21
            min_det = np.minimum(min_det, det)
            s_int += n[None, :] * det[:, None]
    bad = np.flatnonzero((area <= 0) | (min_det <= 0))
    if bad.size:
        raise InputError(
            f"mesh: element {int(bad[0])} (and {bad.size - 1} more) has a non-positive "
            "Jacobian; elements must be convex and counter-clockwise"
        )
    b = np.empty(X.shape)
    b[..., 0] = (yn - yp) / (2.0 * area[:, None])
    b[..., 1] = (xp - xn) / (2.0 * area[:, None])
    hx = x @ _H
    hy = y @ _H
    gamma = 0.25 * (_H[None, :] - hx[:, None] * b[..., 0] - hy[:, None] * b[..., 1])
    return ElementGeometry(b, gamma, area, s_int)


def element_stiffness(
    geo: ElementGeometry,
    lam: np.ndarray,
    mu: np.ndarray,
    khg: np.ndarray,
    thickness: float,
    tangent: np.ndarray | None = None,
) -> np.ndarray:
    """Small-strain stiffness matrices (n_elements, 8, 8), dofs ordered (x0, y0, x1, ...).

    The tangent of the solver's element at the reference configuration: 1-point
    uniform-strain part with the law's tangent (``tangent``, (n, 3, 3) in Voigt form, as
    :meth:`~taichi_bearing.solver.laws.material.ElementLaw.tangent` gives it; default
    Hooke's, :func:`hooke_tangent`) plus the hourglass stiffness ``khg`` (already times
    thickness).
    """
    ne = len(geo.area)
    B = np.zeros((ne, 3, 8))
    B[:, 0, 0::2] = geo.b[..., 0]
    B[:, 1, 1::2] = geo.b[..., 1]
    B[:, 2, 0::2] = geo.b[..., 1]
    B[:, 2, 1::2] = geo.b[..., 0]
    D = hooke_tangent(lam, mu) if tangent is None else tangent
    K = np.einsum("eia,eij,ejb->eab", B, D, B) * (geo.area * thickness)[:, None, None]
    gg = np.einsum("ei,ej->eij", geo.gamma, geo.gamma) * khg[:, None, None]
    K[:, 0::2, 0::2] += gg
    K[:, 1::2, 1::2] += gg
    return K


def element_max_frequencies(
    geo: ElementGeometry,
    lam: np.ndarray,
    mu: np.ndarray,
    rho: np.ndarray,
    khg: np.ndarray,
    thickness: float,
    stiffness: np.ndarray | None = None,
) -> np.ndarray:
    r"""Highest angular frequency :math:`\omega_e` of each element alone with its lumped mass
    (``stiffness``: the :func:`element_stiffness` matrices, when already at hand).

    By the element eigenvalue theorem no frequency of the assembled mesh exceeds the
    largest :math:`\omega_e`. For a square of side :math:`L`,
    :math:`2 / \omega_e = 0.707 L / c`: the familiar
    characteristic length (area / longest diagonal) over the dilatational wave speed.
    """
    K = element_stiffness(geo, lam, mu, khg, thickness) if stiffness is None else stiffness
    m = np.repeat(geo.shape_integrals * (rho * thickness)[:, None], 2, axis=1)  # (ne, 8)
    s = 1.0 / np.sqrt(m)
    A = K * s[:, :, None] * s[:, None, :]
    return np.sqrt(np.maximum(np.linalg.eigvalsh(A)[:, -1], 0.0))


def assembled_matrix(
    values: np.ndarray, elements: np.ndarray, nodal_mass: np.ndarray
) -> sp.csr_matrix:
    r""":math:`M^{-1/2} (\sum_e A_e) M^{-1/2}` of element matrices :math:`A_e` (n_elements, 8,
    8), dofs ordered (x0, y0, x1, ...), with the lumped masses :math:`M` (n_nodes,)."""
    ne = len(elements)
    n_dof = 2 * len(nodal_mass)
    dof = np.stack([2 * elements, 2 * elements + 1], axis=2).reshape(ne, 8)
    rows = np.repeat(dof, 8, axis=1).ravel()
    cols = np.tile(dof, (1, 8)).ravel()
    s = sp.diags(1.0 / np.sqrt(np.repeat(np.asarray(nodal_mass, dtype=float), 2)))
    return (s @ sp.csr_matrix((values.ravel(), (rows, cols)), shape=(n_dof, n_dof)) @ s).tocsr()


@one_blas_thread()
def assembled_max_frequency(
    stiffness: sp.csr_matrix,
    nodal_mass: np.ndarray,
    damping: sp.csr_matrix | None = None,
    node_stiffness: np.ndarray | None = None,
    node_damping: np.ndarray | None = None,
) -> tuple[float, float]:
    r"""Highest angular frequency of the assembled mesh with lumped masses, and the damping
    ratio of that mode.

    The element bound (:func:`element_max_frequencies`) is reached only when the highest
    mode lives in equal elements of the smallest size; where small elements sit beside
    larger ones (graded layers under a surface, the corners of a spall) the shared nodes
    carry the larger elements' mass and the mesh's highest frequency is lower. This is
    the global estimate an explicit code can use instead (Abaqus/Explicit's "global
    estimator"): the largest eigenvalue of :math:`M^{-1/2} K M^{-1/2}`, by Lanczos. Constraints
    are left out, which can only raise it (eigenvalue interlacing).

    Parameters
    ----------
    stiffness : sparse matrix
        :math:`M^{-1/2} K M^{-1/2}` (:func:`assembled_matrix` of :func:`element_stiffness`).
    nodal_mass : ndarray (n_nodes,)
        Lumped masses, kg.
    damping : sparse matrix, optional
        :math:`M^{-1/2} C M^{-1/2}` of the stiffness-proportional damping
        :math:`C = \sum_e \beta_e K_e`.
    node_stiffness, node_damping : ndarray (n_nodes,), optional
        Springs (N/m) and dashpots (N s/m) to ground on both directions of each node: a
        bound on what penalty contact can add there.

    Returns
    -------
    omega : float
        Highest angular frequency, rad/s (the Ritz value raised by its error bound).
    zeta : float
        Damping ratio of that mode, :math:`\phi^T C \phi / (2 \omega)` (0 without damping).
    """
    m2 = np.repeat(np.asarray(nodal_mass, dtype=float), 2)
    a = stiffness
    if node_stiffness is not None and np.any(node_stiffness):
        a = a + sp.diags(np.repeat(node_stiffness, 2) / m2)
    # A fixed start vector: the same mesh gives the same step on every run (resume).
    v0 = np.cos(np.arange(a.shape[0]) * 0.618034) + 1.5
    # The Ritz value is within tol of an eigenvalue (rel.) and never above the top one:
    # raised by 10 tol it bounds it. Tighter costs Lanczos restarts when the top
    # eigenvalue is clustered (identical rollers).
    tol = 1e-6
    lam, vec = eigsh(a, k=1, which="LA", v0=v0, tol=tol)
    omega = float(np.sqrt(max(lam[0], 0.0) * (1.0 + 10.0 * tol)))
    phi = vec[:, 0] / np.linalg.norm(vec[:, 0])
    c_phi = 0.0
    if damping is not None:
        c_phi += float(phi @ (damping @ phi))
    if node_damping is not None:
        c_phi += float(np.sum(phi**2 * np.repeat(node_damping, 2) / m2))
    zeta = c_phi / (2.0 * omega) if omega > 0 else 0.0
    return omega, zeta


def critical_time_steps(omega: np.ndarray, beta: np.ndarray | float = 0.0) -> np.ndarray:
    r"""Stable central-difference step of each element, s: :math:`2 / \omega_e`, lowered by
    stiffness-proportional damping :math:`\beta` by :math:`\sqrt{1 + \zeta^2} - \zeta`,
    :math:`\zeta = \beta \omega_e / 2`."""
    zeta = 0.5 * np.asarray(beta) * omega
    return 2.0 / omega * (np.sqrt(1.0 + zeta**2) - zeta)


def hourglass_stiffness(
    geo: ElementGeometry, eprime: np.ndarray, thickness: float, scale: float = 1.0
) -> np.ndarray:
    r""":math:`k = \mathrm{scale} \cdot \frac{2}{3} E' t A (b \cdot b)`: bending-exact for
    square elements."""
    bb = np.sum(geo.b**2, axis=(1, 2))
    return scale * (2.0 / 3.0) * eprime * thickness * geo.area * bb


def selective_mass_scale(
    omega: np.ndarray, element_mass: np.ndarray, part: np.ndarray, max_added: float
) -> np.ndarray:
    r"""Density factors that lift the smallest elements' critical steps to a common target.

    Selective mass scaling: an element whose step :math:`2 / \omega_e` is below the target
    :math:`T` gets its density times :math:`(T \omega_e / 2)^2`, which puts its step at
    :math:`T`. :math:`T` is the
    largest element step for which the mass added to every part stays within ``max_added``
    of that part's mass, so a few small elements (a spall corner) stop setting the step of
    the whole model while the parts' inertia is unchanged to that fraction.

    Parameters
    ----------
    omega : ndarray (n_elements,)
        Highest angular frequency of each element with its own lumped mass.
    element_mass : ndarray (n_elements,)
        Mass of each element, kg.
    part : ndarray of int (n_elements,)
        Part of each element.
    max_added : float
        Largest added mass as a fraction of a part's mass; 0 turns scaling off.

    Returns
    -------
    ndarray (n_elements,)
        Factor on each element's density (1 where unscaled); the scaled elements'
        frequencies become :math:`\omega / \sqrt{\mathrm{factor}}`.
    """
    scale = np.ones(len(omega))
    if not max_added > 0 or len(omega) < 2:
        return scale
    step = 2.0 / np.asarray(omega, dtype=float)
    m = np.asarray(element_mass, dtype=float)
    part = np.asarray(part)
    budget = max_added * np.bincount(part, weights=m)
    a = np.zeros_like(budget)  # sum of m / step^2 over the scaled elements of each part
    b = np.zeros_like(budget)  # sum of m over them
    order = np.argsort(step, kind="stable")
    n_scaled = 0
    for k in range(1, len(order)):
        i = order[k - 1]
        a[part[i]] += m[i] / step[i] ** 2
        b[part[i]] += m[i]
        # scaling elements order[:k] to the step of order[k] adds T^2 a - b to each part
        if np.any(step[order[k]] ** 2 * a - b > budget):
            break
        n_scaled = k
    if n_scaled:
        target = step[order[n_scaled]]
        idx = order[:n_scaled]
        # equal steps differ in the last bits: leave those elements as they are
        f = (target / step[idx]) ** 2
        scale[idx] = np.where(f > 1.0 + 1e-9, f, 1.0)
    return scale


def hooke_tangent(lam: np.ndarray, mu: np.ndarray) -> np.ndarray:
    """Hooke's plane-strain tangent in Voigt form (xx, yy, xy engineering shear), shape
    (n, 3, 3) for arrays of the Lame constants (St Venant-Kirchhoff's at zero strain)."""
    lam, mu = np.asarray(lam, dtype=float), np.asarray(mu, dtype=float)
    D = np.zeros((*lam.shape, 3, 3))
    D[..., 0, 0] = D[..., 1, 1] = lam + 2 * mu
    D[..., 0, 1] = D[..., 1, 0] = lam
    D[..., 2, 2] = mu
    return D


def materials_per_element(
    mesh: Mesh, materials: Material | Mapping[str, Material]
) -> tuple[np.ndarray, ...]:
    """Per-element (lambda, mu, rho, E') arrays from one material or a part -> material map."""
    if isinstance(materials, Material):
        mats = [materials] * len(mesh.part_names)
    else:
        missing = [p for p in mesh.part_names if p not in materials]
        if missing:
            raise ValueError(f"no material given for parts {missing}")
        mats = [materials[p] for p in mesh.part_names]
    lam = np.array([m.lam for m in mats])[mesh.element_part]
    mu = np.array([m.mu for m in mats])[mesh.element_part]
    rho = np.array([m.density for m in mats])[mesh.element_part]
    eprime = np.array([m.plane_strain_modulus for m in mats])[mesh.element_part]
    return lam, mu, rho, eprime
