"""The energy read-out (``Model.energies``) sums every node and element once, on any
thread count: its sums by blocks against the same sums taken on the host."""

from __future__ import annotations

import math

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.primitives import annulus_mesh
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.model import MEASURE_BLOCK, Model

STEEL = Material(210e9, 0.3, 7850.0)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def vibrating_ring() -> Model:
    """A damped ring of 197 x 4 nodes (not a whole number of blocks), vibrating and moving."""
    mesh = annulus_mesh(0.045, 0.055, 197, 3)
    assert mesh.n_nodes % MEASURE_BLOCK and mesh.n_elements % MEASURE_BLOCK
    assert mesh.n_nodes > 2 * MEASURE_BLOCK
    model = Model(mesh, STEEL, damping=StiffnessDamping(0.05, 5000.0))
    rng = np.random.default_rng(3)
    model.set_state(v=rng.normal(0.0, 0.3, (mesh.n_nodes, 2)) + [0.2, -0.1])
    model.advance(40, record_last=True)
    return model


def host_sums(model: Model) -> dict[str, float]:
    """The energies from the per-node and per-element values, summed exactly."""

    def arr(f, n):
        return f.to_numpy()[:n]

    nn, ne = model.n_nodes, model.n_elements
    m, v = arr(model.mass, nn), arr(model.v_int, nn)
    u = arr(model.x, nn) - arr(model.X, nn)
    return {
        "kinetic": math.fsum(0.5 * m * (v * v).sum(axis=1)),
        "internal": math.fsum(arr(model.e_int, ne)),
        "hourglass": math.fsum(arr(model.e_hg, ne)),
        "damping": math.fsum(arr(model.e_damp, ne)),
        "external_work": math.fsum(arr(model.work, nn)),
        "mass_u2": math.fsum(m * (u * u).sum(axis=1)),
    }


def test_energy_sums_cover_every_node_and_element_once():
    model = vibrating_ring()
    e, ref = model.energies(), host_sums(model)
    for kind in ("kinetic", "internal", "hourglass", "damping", "mass_u2"):
        assert ref[kind] > 0, kind
    for kind, value in ref.items():
        # Rounding of a few hundred terms; a block left out or counted twice is ~1e-2.
        assert e[kind] == pytest.approx(value, rel=1e-12, abs=1e-14 * abs(ref["kinetic"])), kind


def test_energy_sums_do_not_depend_on_the_thread_count():
    sums = []
    for threads in (1, 2):
        init_taichi("cpu", threads=threads)
        sums.append(vibrating_ring().energies())
    init_taichi("cpu")
    assert sums[0] == sums[1]  # bit for bit
