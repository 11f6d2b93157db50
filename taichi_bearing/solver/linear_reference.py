"""Linear static reference: the solver's element assembled into a scipy.sparse stiffness.

Used to check dynamic relaxation (the explicit model must settle where ``K u = f``).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from taichi_bearing.blas import one_blas_thread
from taichi_bearing.case.material import Material
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.solver.element import (
    element_geometry,
    element_stiffness,
    hourglass_stiffness,
    materials_per_element,
)

__all__ = ["assemble_stiffness", "linear_static"]


def assemble_stiffness(
    mesh: Mesh,
    materials: Material | Mapping[str, Material],
    thickness: float = 1.0,
    hourglass_scale: float = 1.0,
) -> sp.csr_matrix:
    """Global small-strain stiffness (2 n_nodes square, dofs x0, y0, x1, ...), N/m."""
    elements = np.asarray(mesh.elements, dtype=np.int64)
    geo = element_geometry(np.asarray(mesh.nodes, dtype=float), elements)
    lam, mu, _, eprime = materials_per_element(mesh, materials)
    khg = hourglass_stiffness(geo, eprime, thickness, hourglass_scale)
    ke = element_stiffness(geo, lam, mu, khg, thickness)
    dofs = np.stack([2 * elements, 2 * elements + 1], axis=2).reshape(len(elements), 8)
    rows = np.repeat(dofs, 8, axis=1).ravel()
    cols = np.tile(dofs, (1, 8)).ravel()
    n = 2 * mesh.n_nodes
    return sp.csr_matrix((ke.ravel(), (rows, cols)), shape=(n, n))


def linear_static(K: sp.spmatrix, forces: np.ndarray, fixed_dofs: np.ndarray) -> np.ndarray:
    """Solve ``K u = f`` with ``u = 0`` on ``fixed_dofs``.

    Parameters
    ----------
    K : sparse matrix (2 n, 2 n)
    forces : ndarray (n, 2)
        Nodal forces, N.
    fixed_dofs : array of int
        Constrained dof indices (2 node + component).

    Returns
    -------
    ndarray (n, 2)
        Displacements, m.
    """
    n = K.shape[0]
    free = np.setdiff1d(np.arange(n), fixed_dofs)
    u = np.zeros(n)
    Kf = K.tocsr()[free][:, free].tocsc()
    with one_blas_thread():  # the same bits on any BLAS thread count
        u[free] = spla.spsolve(Kf, np.asarray(forces, dtype=float).ravel()[free])
    return u.reshape(-1, 2)
