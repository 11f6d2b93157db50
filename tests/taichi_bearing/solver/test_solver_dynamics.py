"""Dynamics against analytic values: wave speed, ring bending frequencies, energy drift."""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.primitives import annulus_mesh, disk_mesh, rectangle_mesh
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.loads import HeldDirection, RigidVelocity, line_load
from taichi_bearing.solver.model import Model

STEEL = Material(210e9, 0.3, 7850.0)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def first_crossing(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """Time where y first rises through level (linear interpolation)."""
    k = int(np.flatnonzero(y >= level)[0])
    return float(t[k - 1] + (level - y[k - 1]) * (t[k] - t[k - 1]) / (y[k] - y[k - 1]))


def test_plane_strain_dilatational_wave_speed_within_2_percent():
    length, height = 0.2, 0.004
    mesh = rectangle_mesh(length, height, 200, 4)
    X = mesh.nodes
    # Every node held vertically: uniaxial strain, so the front runs at sqrt((l + 2 mu)/rho).
    left = np.flatnonzero(np.isclose(X[:, 0], 0.0))
    stress = 1e6
    load = line_load(X, left, (stress * height, 0.0))  # thickness 1 m
    s1 = int(np.argmin(np.hypot(X[:, 0] - 0.05, X[:, 1] - 0.002)))
    s2 = int(np.argmin(np.hypot(X[:, 0] - 0.15, X[:, 1] - 0.002)))
    model = Model(
        mesh,
        STEEL,
        constraints=[HeldDirection(np.arange(mesh.n_nodes), (0.0, 1.0))],
        loads=[load],
        sensors={"near": s1, "far": s2},
    )
    c = STEEL.wave_speed
    v_plateau = stress / (STEEL.density * c)  # particle velocity behind a step front
    n = int(0.17 / c / model.dt)
    t, vel = np.empty(n), np.empty((n, 2))
    for k in range(n):
        t[k] = model.time
        model.advance(1)
        vel[k] = model.take_sensor_means(1)[:, 2]
    t1 = first_crossing(t, vel[:, 0], 0.5 * v_plateau)
    t2 = first_crossing(t, vel[:, 1], 0.5 * v_plateau)
    c_measured = (X[s2, 0] - X[s1, 0]) / (t2 - t1)
    print(f"wave speed: measured {c_measured:.1f} m/s, analytic {c:.1f} m/s")
    assert c_measured == pytest.approx(c, rel=0.02)
    # Behind the front the particle velocity is sigma / (rho c).
    assert vel[-1, 0] == pytest.approx(v_plateau, rel=0.1)


def ring_mode_velocity(nodes: np.ndarray, n: int, amplitude: float) -> np.ndarray:
    """Inextensional in-plane mode n of a ring: v_r = A cos n th, v_th = -(A/n) sin n th."""
    th = np.arctan2(nodes[:, 1], nodes[:, 0])
    vr = amplitude * np.cos(n * th)
    vt = -amplitude / n * np.sin(n * th)
    return np.stack([vr * np.cos(th) - vt * np.sin(th), vr * np.sin(th) + vt * np.cos(th)], 1)


def test_free_thin_ring_bending_frequencies_n2_n3_n4_within_3_percent():
    radius, thickness, layers = 0.1, 0.1 / 15, 3
    n_theta = 8 * round(2 * np.pi * radius / (thickness / layers) / 8)  # square elements
    mesh = annulus_mesh(radius - thickness / 2, radius + thickness / 2, n_theta, layers)
    X = mesh.nodes
    probe = int(np.argmin(np.hypot(X[:, 0] - (radius + thickness / 2), X[:, 1])))
    model = Model(mesh, STEEL, sensors={"probe": probe})
    ep = STEEL.plane_strain_modulus
    inertia, area = thickness**3 / 12, thickness
    errors = {}
    for n in (2, 3, 4):
        f_exact = (
            n
            * (n * n - 1)
            / (2 * np.pi * radius**2 * np.sqrt(n * n + 1))
            * np.sqrt(ep * inertia / (STEEL.density * area))
        )
        model.set_state(x=X, v=ring_mode_velocity(X, n, 1e-3))
        model.restart_accounting()
        model.advance(1)
        model.take_sensor_means(1)
        every = 10
        n_samples = int(1.2 / f_exact / model.dt / every)
        t, ur = np.empty(n_samples), np.empty(n_samples)
        for k in range(n_samples):
            model.advance(every)
            t[k] = (model.step_count - 0.5 * (every + 1)) * model.dt  # mean of the window
            ur[k] = model.take_sensor_means(every)[0, 0]
        # u_r = (A / omega) sin(omega t): the second zero crossing after t = 0 is one period.
        k = np.flatnonzero(np.sign(ur[1:]) != np.sign(ur[:-1]))[1]
        period = t[k] - ur[k] * (t[k + 1] - t[k]) / (ur[k + 1] - ur[k])
        errors[n] = 1.0 / period / f_exact - 1.0
    print("ring bending relative errors:", {n: f"{e:+.4f}" for n, e in errors.items()})
    assert all(abs(e) < 0.03 for e in errors.values())


def test_energy_drift_undamped_vibrating_ring_below_half_percent():
    mesh = annulus_mesh(0.045, 0.055, 96, 3)
    model = Model(mesh, STEEL)
    model.set_state(v=ring_mode_velocity(mesh.nodes, 2, 0.5) + [0.2, -0.1])
    model.advance(1, record_last=True)
    e = model.energies()
    e0 = e["kinetic"] + e["internal"] + e["hourglass"]
    drift, strain_peak = 0.0, 0.0
    for _ in range(100):  # 1e4 steps, checked every 100
        model.advance(100, record_last=True)
        e = model.energies()
        drift = max(drift, abs(e["kinetic"] + e["internal"] + e["hourglass"] - e0) / e0)
        strain_peak = max(strain_peak, e["internal"])
    assert strain_peak > 0.05 * e0  # the ring really vibrates (energy goes into strain)
    print(f"energy drift over 1e4 steps: {drift:.2e}")
    assert drift < 5e-3


def test_stiffness_damping_gives_its_ratio_at_its_frequency():
    length = 0.02
    mesh = rectangle_mesh(length, 0.001, 20, 1)
    X = mesh.nodes
    c = STEEL.wave_speed
    f1 = c / (2 * length)  # first free-free longitudinal mode (uniaxial strain)
    zeta = 0.02
    model = Model(
        mesh,
        STEEL,
        constraints=[HeldDirection(np.arange(mesh.n_nodes), (0.0, 1.0))],
        damping=StiffnessDamping(zeta, f1),
        sensors={"end": 0},
    )
    assert 0 < model.damping_step_factor < 1
    model.set_state(v=np.stack([1e-3 * np.cos(np.pi * X[:, 0] / length), 0 * X[:, 0]], 1))
    model.advance(1)
    model.take_sensor_means(1)
    half = 0.5 / f1 / model.dt
    n = int(10.5 * half)
    u = np.empty(n)
    for k in range(n):
        model.advance(1)
        u[k] = model.take_sensor_means(1)[0, 0]
    # Peaks of |u| half a period apart decay by exp(-pi zeta / sqrt(1 - zeta^2)).
    peaks = [np.max(np.abs(u[int(j * half) : int((j + 1) * half)])) for j in range(10)]
    zeta_measured = np.log(peaks[0] / peaks[9]) / 9 / np.pi
    print(f"damping ratio at f1: measured {zeta_measured:.5f}, target {zeta}")
    assert zeta_measured == pytest.approx(zeta, rel=0.05)
    assert model.energies()["damping"] > 0
    # Without a cap the fine elements' own modes are damped at zeta_e > 0.1, which
    # shortens the step; a cap of 0.1 bounds the cost to sqrt(1 + 0.1^2) - 0.1.
    capped = Model(mesh, STEEL, damping=StiffnessDamping(zeta, f1, max_element_ratio=0.1))
    assert capped.damping_step_factor == pytest.approx(np.sqrt(1.01) - 0.1, rel=1e-9)
    assert model.damping_step_factor < capped.damping_step_factor


def test_stiffness_damping_does_not_brake_spin():
    radius = 0.01
    mesh = disk_mesh(radius, 12)
    spin = 1e-3 * STEEL.wave_speed / radius
    damping = StiffnessDamping(0.05, STEEL.wave_speed / radius)
    model = Model(
        mesh, STEEL, damping=damping, initial_velocities=[RigidVelocity("disk", omega=spin)]
    )
    model.advance(1, record_last=True)
    ke0 = model.energies()["kinetic"]
    model.advance(int(np.pi / spin / model.dt), record_last=True)  # half a turn
    e = model.energies()
    # Only the small centrifugal stretching vibration (~(omega R / c)^2 of KE) is damped.
    print(f"spin with damping: dissipated {e['damping'] / ke0:.2e} of KE")
    assert e["damping"] < 1e-5 * ke0
    assert abs(e["kinetic"] / ke0 - 1) < 1e-5
