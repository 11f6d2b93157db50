"""What the stepping does when other processes keep the cores busy: a team of spinning
threads would wait on each other's time slices, so it steps on one thread instead, and
comes back to the team when the machine is free; the results do not change."""

import numpy as np
import pytest

from taichi_bearing.mesh.primitives import rectangle_mesh
from taichi_bearing.solver import Material, Model, backend, init_taichi, stepping
from taichi_bearing.solver.backend import current_threads


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")
    if current_threads() < 2:
        pytest.skip("the team needs two CPU threads")


def _model() -> Model:
    # above SERIAL_MAX_ELEMENTS, so that a quiet machine steps it as a team
    model = Model(rectangle_mesh(0.1, 0.05, 80, 40), Material(210e9, 0.3, 7850.0))
    rng = np.random.default_rng(0)
    model.set_state(v=rng.normal(scale=1e-3, size=(model.n_nodes, 2)))
    return model


def test_team_stands_down_while_the_cores_are_busy(monkeypatch):
    model = _model()
    assert model.n_elements > stepping.SERIAL_MAX_ELEMENTS
    load = {"cores": 0.0}
    monkeypatch.setattr(backend, "other_load", lambda: load["cores"])
    assert stepping.choose_mode(model) == "team"
    load["cores"] = 1.0  # one other CPU-bound process
    assert stepping.choose_mode(model) == "serial"
    model.advance(20)
    load["cores"] = 0.0  # it ended
    model.advance(30)
    assert model.steps_by_mode == {"serial": 20, "team": 30}
    # the same motion as a run that never switched
    ref = _model()
    monkeypatch.setattr(backend, "other_load", lambda: 0.0)
    ref.advance(50)
    np.testing.assert_array_equal(model.positions(), ref.positions())
    np.testing.assert_array_equal(model.velocities(), ref.velocities())


def test_other_load_reads_what_other_processes_use():
    import subprocess
    import sys
    import time

    reading = backend._OtherLoad()
    reading()
    spin = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(1.5)
        busy = reading()
    finally:
        spin.kill()
    # one spinning process: about one core (more with other work on the machine)
    assert busy > 0.5
