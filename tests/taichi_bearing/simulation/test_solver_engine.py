"""Transient engine: loads, constraints, averaged sensors, safety stop, checkpoint/resume."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np
import pytest
import taichi as ti

from taichi_bearing.case.material import Material
from taichi_bearing.errors import SimulationError
from taichi_bearing.mesh.primitives import annulus_mesh, disk_mesh, rectangle_mesh
from taichi_bearing.output.histories import read_histories
from taichi_bearing.simulation.engine import RunConfig, run_transient
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.contributor import ForceContributor, add_force
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.loads import (
    FixedNodes,
    NodalForces,
    PrescribedRotation,
    RigidPlate,
    RigidVelocity,
    rotation_angle,
    uniform_load,
)
from taichi_bearing.solver.model import Model

STEEL = Material(210e9, 0.3, 7850.0)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def driven_ring(damping: StiffnessDamping | None = None, dt_factor: float = 0.9) -> Model:
    """A ring whose bore turns with a speed ramp; sensor on the outer surface."""
    mesh = annulus_mesh(0.02, 0.026, 48, 2)
    X = mesh.nodes
    bore = np.flatnonzero(np.isclose(np.hypot(X[:, 0], X[:, 1]), 0.02))
    probe = int(np.argmax(X[:, 1]))
    rot = PrescribedRotation(bore, (0.0, 0.0), omega=400.0, ramp_time=2e-4)
    return Model(
        mesh, STEEL, constraints=[rot], damping=damping, sensors={"top": probe}, dt_factor=dt_factor
    )


def test_prescribed_rotation_ramp_drives_the_ring():
    model = driven_ring(StiffnessDamping(0.05, 20e3))
    rot = model.rotations[0]
    res = run_transient(model, RunConfig(duration=5e-4, sample_rate=2e5))
    t = res.column("time_s")
    x = model.positions()
    bore, top = rot.nodes, int(model.sensor_node.to_numpy()[0])
    # Bore nodes sit exactly on the prescribed rigid rotation at the final time.
    theta = rotation_angle(rot, model.time)
    c, s = np.cos(theta), np.sin(theta)
    expected = model.mesh.nodes[bore] @ np.array([[c, s], [-s, c]])
    assert np.max(np.abs(x[bore] - expected)) < 1e-12
    # The outer surface follows (elastic lag tiny): angle of the probe node.
    ang = np.arctan2(x[top, 1], x[top, 0]) - np.pi / 2
    assert ang == pytest.approx(theta, abs=2e-3 * theta)
    # Averaged probe velocity: tangential speed omega(t) r at constant speed.
    vx = res.column("top_vx")
    assert vx[-1] == pytest.approx(-400.0 * 0.026, rel=0.02)
    # Energy: the prescribed rotation's work equals kinetic + strain + damping.
    bal = res.column("energy_balance_error")
    assert np.max(np.abs(bal)) < 0.01
    assert res.column("energy_kinetic")[-1] > 0.9 * res.column("energy_external_work")[-1]
    assert np.all(np.diff(t) > 0)


def test_ramped_force_gives_free_body_the_impulse_and_sensor_means_are_window_averages():
    mesh = disk_mesh(0.01, 12)
    ids = np.arange(mesh.n_nodes)
    force, ramp = np.array([300.0, -100.0]), 1e-4
    model = Model(mesh, STEEL, loads=[uniform_load(ids, force, ramp_time=ramp)])
    model.sensor_names = []
    res = run_transient(model, RunConfig(duration=2e-4, sample_rate=1e5))
    # Momentum at t_{n+1/2}: integral of the ramped force up to there (rectangle rule).
    t_half = model.time - 0.5 * model.dt
    impulse = force * (t_half - 0.5 * ramp)
    p = (model.mass_np[:, None] * model.velocities()).sum(axis=0)
    assert np.allclose(p, impulse, rtol=1e-3)
    bal = res.column("energy_balance_error")
    assert np.max(np.abs(bal)) < 0.01
    w = res.column("energy_external_work")
    assert w[-1] > 0


def test_a_rigid_plate_loaded_at_one_node_closes_the_energy_balance():
    """A block on a fixed base pressed through a rigid plate on its top by a load at one
    plate node: the plate's constraint forces carry the load to its other nodes. Their
    work sums to zero over the plate only, so the balance closes only if it is counted
    at every plate node, loaded or not (without the unloaded ones it read 0.95)."""
    mesh = rectangle_mesh(0.02, 0.01, 20, 10)
    top = mesh.node_sets["top"]
    plate = RigidPlate(top, (0.0, 1.0))
    load = NodalForces([top[2]], [(0.0, -2.0e5)], ramp_time=2e-6)
    model = Model(mesh, STEEL, constraints=[FixedNodes(mesh.node_sets["bottom"]), plate],
                  loads=[load])  # fmt: skip
    model.sensor_names = []
    res = run_transient(model, RunConfig(duration=2e-5, sample_rate=2e6))
    bal = res.column("energy_balance_error")
    assert np.max(np.abs(bal)) < 0.03  # 0.024 during the 2 us ramp, below 0.01 after
    assert np.max(np.abs(bal[4:])) < 0.01
    assert res.column("energy_external_work")[-1] > 0
    uy = model.displacements()[top, 1]
    assert uy.max() < 0 and np.ptp(uy) < 1e-12 * abs(uy.max())  # down, and rigid


def test_sensor_history_is_the_mean_over_each_interval():
    mesh = disk_mesh(0.01, 12)
    v0 = np.array([2.0, -1.0])
    model = Model(
        mesh,
        STEEL,
        initial_velocities=[RigidVelocity("disk", velocity=tuple(v0))],
        sensors={"c": 0},
    )
    res = run_transient(model, RunConfig(duration=1e-4, sample_rate=1e5))
    # Uniform translation: u(t) = v0 t; its mean over ((k-1)T, kT] sampled at the steps
    # t_n = n dt is v0 (kT - (T - dt) / 2).
    t = res.column("time_s")
    T = 1e-5
    expected = v0[0] * (t - 0.5 * (T - model.dt))
    assert np.allclose(res.column("c_ux"), expected, rtol=1e-9)
    assert np.allclose(res.column("c_vy"), v0[1], rtol=1e-12)
    assert np.allclose(res.column("c_ax"), 0.0, atol=1e-4)  # round-off of E * 1e-16 stress


def test_checkpoint_resume_reproduces_uninterrupted_run(tmp_path):
    damping = StiffnessDamping(0.02, 20e3)
    cfg = RunConfig(duration=4e-4, sample_rate=1e5, checkpoint_interval=2e-4, frame_interval=2e-4)
    straight = driven_ring(damping)
    run_transient(straight, cfg, out_dir=tmp_path / "a", fingerprint="fp")
    # Run b "crashes" after the checkpoint at 0.2 ms: same run, stopped half-way.
    first = driven_ring(damping)
    half = RunConfig(**{**cfg.__dict__, "duration": 3e-4})
    run_transient(first, half, out_dir=tmp_path / "b", fingerprint="fp")
    resumed = driven_ring(damping)
    tail = run_transient(resumed, cfg, out_dir=tmp_path / "b", resume=True, fingerprint="fp")
    assert tail.rows[0, 0] > 2e-4  # it really started from the checkpoint
    # Same state bit for bit (element forces are gathered in a fixed order).
    assert np.array_equal(resumed.positions(), straight.positions())
    assert np.array_equal(resumed.velocities(), straight.velocities())
    a = read_histories(tmp_path / "a")
    b = read_histories(tmp_path / "b")
    assert list(a.columns) == list(b.columns) and len(a) == len(b) == 40
    sensors = [c for c in a.columns if c.startswith("top_")]
    assert np.array_equal(a[sensors].to_numpy(), b[sensors].to_numpy())
    # every column, energies included: a resumed run is the uninterrupted one bit for bit
    np.testing.assert_array_equal(a.to_numpy(), b.to_numpy())
    assert (tmp_path / "b" / "frames" / "frames.pvd").is_file()


def test_unstable_step_stops_with_message_and_keeps_histories(tmp_path):
    model = driven_ring(dt_factor=2.25)  # beyond the stability limit on purpose
    with pytest.raises(SimulationError) as info:
        run_transient(model, RunConfig(duration=2e-3, sample_rate=2e5), out_dir=tmp_path)
    msg = str(info.value)
    assert "step" in msg and "ms" in msg and "likely cause" in msg
    assert "node" in msg and "element" in msg
    rows = read_histories(tmp_path)
    assert len(rows) >= 1 and np.all(np.isfinite(rows.to_numpy()))


@ti.data_oriented
class Gravity(ForceContributor):
    """A Python force contributor: body force m g on every node."""

    in_kernel = False

    def __init__(self, g: tuple[float, float]) -> None:
        self.g = g
        self.calls = 0

    @ti.kernel
    def _add(self, f: ti.template(), m: ti.template(), gx: ti.f64, gy: ti.f64):
        for i in f:
            add_force(f, i, m[i] * ti.Vector([gx, gy]))

    def add_forces(self, model: Model, t: float) -> None:
        self.calls += 1
        self._add(model.f_extra, model.mass, *self.g)


def test_force_contributor_is_called_every_step_and_its_work_is_counted():
    mesh = disk_mesh(0.01, 12)
    model = Model(mesh, STEEL, sensors={"c": 0})
    g = (3.0, -9.81)
    gravity = Gravity(g)
    model.add_contributor(gravity)
    res = run_transient(model, RunConfig(duration=1e-4, sample_rate=1e5))
    assert gravity.calls == model.step_count
    # Uniform acceleration: leapfrog with a half first step is exact, u = g t^2 / 2.
    t = model.time
    assert np.allclose(model.displacements(), 0.5 * np.array(g) * t**2, rtol=1e-9)
    assert np.allclose(res.column("c_ay"), g[1], atol=1e-4)  # round-off stress, as above
    ke = res.column("energy_kinetic")[-1]
    assert res.column("energy_external_work")[-1] == pytest.approx(ke, rel=1e-9)


def test_inverted_element_stops_the_run_naming_the_element():
    mesh = rectangle_mesh(0.1, 0.01, 20, 2)
    X = mesh.nodes
    corner = int(np.argmax(X[:, 0] + X[:, 1]))
    model = Model(
        mesh,
        STEEL,
        constraints=[FixedNodes(np.flatnonzero(X[:, 0] == 0))],
        loads=[uniform_load([corner], (0.0, -5e9))],  # crushes the corner element
    )
    with pytest.raises(SimulationError, match=r"element \d+ inverted") as info:
        run_transient(model, RunConfig(duration=1e-3, sample_rate=1e6))
    bad = int(str(info.value).split("element ")[-1].split()[0])
    assert corner in mesh.elements[bad]
