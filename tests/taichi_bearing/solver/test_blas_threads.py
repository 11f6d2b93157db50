"""The sparse solves that set what the simulator computes give the same bits whatever
number of threads BLAS runs (taichi_bearing/blas.py): a Dask worker (one BLAS thread) and
a process pool (as many as cores) must run the same cells."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from threadpoolctl import threadpool_info

from taichi_bearing.blas import one_blas_thread

ROOT = Path(__file__).resolve().parents[3]

# The global critical step's top eigenvalue (ARPACK's Lanczos over the coarse case's
# 16,328 nodes), printed to the last bit.
_CHILD = """
import numpy as np
from taichi_bearing.case import load_case
from taichi_bearing.solver.element import (assembled_matrix, assembled_max_frequency,
    element_geometry, element_stiffness, hourglass_stiffness)
from taichi_bearing.solver.element import materials_per_element
from taichi_bearing.simulation.starter import build_setup
from taichi_bearing.simulation.simulate import stage_mesh
case = load_case("cases/validation/coarse_spall.yaml")
mesh, _ = stage_mesh(case)
X, E = np.asarray(mesh.nodes, float), np.asarray(mesh.elements, np.int64)
geo = element_geometry(X, E)
setup = build_setup(case, mesh)
lam, mu, rho, ep = materials_per_element(mesh, setup.material)
K = element_stiffness(geo, lam, mu, hourglass_stiffness(geo, ep, setup.thickness, 1.0),
                      setup.thickness)
mass = np.zeros(len(X))
np.add.at(mass, E, geo.shape_integrals * (rho * setup.thickness)[:, None])
print(float.hex(assembled_max_frequency(assembled_matrix(K, E, mass), mass)[0]))
"""


def _omega_hex(blas_threads: int) -> str:
    env = dict(os.environ, OPENBLAS_NUM_THREADS=str(blas_threads))
    res = subprocess.run(
        [sys.executable, "-c", _CHILD], cwd=ROOT, env=env, capture_output=True, text=True
    )
    assert res.returncode == 0, res.stderr[-2000:]
    return res.stdout.strip().splitlines()[-1]


def test_global_step_is_the_same_on_one_and_two_blas_threads():
    # Without one_blas_thread: 0x1.c23797a767d91p+23 on one thread, ...d93p+23 on two.
    assert _omega_hex(1) == _omega_hex(2)


def test_every_blas_library_runs_one_thread_inside_the_context():
    import numpy  # noqa: F401  (numpy's and scipy's BLAS loaded)
    import scipy.sparse.linalg  # noqa: F401

    with one_blas_thread():
        blas = [lib for lib in threadpool_info() if lib["user_api"] == "blas"]
        assert blas and all(lib["num_threads"] == 1 for lib in blas)
