"""Rigid cage: no force on a roller centred in its pocket; a roller orbiting at constant
speed drives a cage at rest up to its own angular speed, without adding energy."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np
import pytest

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.primitives import disk_mesh
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.cage import RigidCage
from taichi_bearing.solver.contact import ContactParameters
from taichi_bearing.solver.contributor import ForceContributor
from taichi_bearing.solver.loads import PrescribedRotation
from taichi_bearing.solver.model import Model

R_PITCH, R_ROLLER, CLEARANCE = 0.03, 0.005, 20e-6
OMEGA = 100.0
INERTIA = 0.05 * R_PITCH**2  # a 50 g ring on the pitch circle


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def orbiting_roller(omega: float, in_kernel: bool = True) -> tuple[Model, RigidCage]:
    """One roller on the pitch circle at 12 o'clock, orbiting rigidly at ``omega``, in
    the pocket of a cage at rest (stepped in the model's kernels, or from Python)."""
    mesh = disk_mesh(R_ROLLER, 32)
    mesh.nodes = mesh.nodes + np.array([0.0, R_PITCH])
    mesh.surfaces["roller0"] = mesh.surfaces["outer"]
    ids = np.arange(mesh.n_nodes)
    model = Model(
        mesh,
        Material(210e9, 0.3, 7850.0),
        constraints=[PrescribedRotation(ids, (0.0, 0.0), omega=omega)],
    )
    cage = RigidCage(
        model,
        ["roller0"],
        [np.pi / 2],
        half_gap=R_ROLLER + 0.5 * CLEARANCE,
        inner_radius=R_PITCH - 0.6 * R_ROLLER,
        outer_radius=R_PITCH + 0.6 * R_ROLLER,
        inertia=INERTIA,
        params=ContactParameters(damping_ratio=0.2),
    )
    model.add_contributor(cage if in_kernel else _FromPython(cage))
    return model, cage


def test_no_pocket_force_on_a_centred_roller():
    model, cage = orbiting_roller(OMEGA)
    cage.set_state(speed=OMEGA)  # turning with the roller, the roller stays centred
    for _ in range(20):
        model.advance(50)
        assert np.all(cage.pocket_forces() == 0.0)
    assert cage.speed == OMEGA
    assert cage.angle == pytest.approx(OMEGA * model.time, rel=1e-9)


def test_orbiting_roller_drives_the_cage_to_its_speed():
    model, cage = orbiting_roller(OMEGA)
    gap_angle = 0.5 * CLEARANCE / R_PITCH
    times, angles, speeds = [], [], []
    pushed = 0.0
    for _ in range(200):
        model.advance(100)
        times.append(model.time)
        angles.append(cage.angle)
        speeds.append(cage.speed)
        pushed = max(pushed, cage.pop_sample_means()[0, 2])
    t, th, w = map(np.asarray, (times, angles, speeds))
    lag = th - OMEGA * t  # cage angle less the roller's
    # The roller pushed the cage forward (tangential force on it from the cage < 0 while
    # it pushes: the cage pushes back), and the cage stays within the pocket clearance.
    assert pushed != 0.0
    # Penetration bound: the cage's kinetic energy relative to the roller, I w^2 / 2,
    # taken up by one node's penalty spring.
    k_min = cage.k.to_numpy().min()
    pen_angle = np.sqrt(INERTIA * OMEGA**2 / k_min) / R_PITCH
    bound = gap_angle + pen_angle
    print(f"largest |lag| / (gap + penetration bound) = {np.abs(lag).max() / bound:.3f}")
    assert np.all(np.abs(lag) < bound)
    # No energy from the contact: relative to the roller, the cage never moves faster
    # than it did when it was hit at rest.
    assert np.all(np.abs(w - OMEGA) <= 1.01 * OMEGA)
    # Mean speed over the second half: the roller's (bounded by the clearance).
    half = t > t[-1] / 2
    mean = (th[-1] - th[half][0]) / (t[-1] - t[half][0])
    print(f"cage mean speed / roller speed - 1 = {mean / OMEGA - 1:+.2e}, dt {model.dt:.3g}")
    assert mean == pytest.approx(OMEGA, rel=0.01)


class _FromPython(ForceContributor):
    """The cage behind a Python ``add_forces``: the model then calls the cage's own
    kernel between the two launches of each step."""

    in_kernel = False

    def __init__(self, inner) -> None:
        self.inner = inner

    def add_forces(self, model, t) -> None:
        self.inner.add_forces(model, t)


def test_in_step_cage_matches_its_own_kernel_called_from_python():
    # The model runs the cage inside its step kernel (many steps per launch on a small
    # mesh); the same forces through the cage's own kernel, one launch per step, must give
    # the same motion bit for bit (same operations in the same order).
    runs = []
    for in_kernel in (True, False):
        model, cage = orbiting_roller(OMEGA, in_kernel)
        assert (model.python_contributors == ()) is in_kernel
        for _ in range(30):
            model.advance(100)
        runs.append((model.positions(), model.velocities(), cage.angle, cage.speed))
    (x1, v1, a1, w1), (x2, v2, a2, w2) = runs
    assert a1 != 0.0 and w1 != 0.0  # the cage was pushed and moved
    np.testing.assert_array_equal(x1, x2)
    np.testing.assert_array_equal(v1, v2)
    assert (a1, w1) == (a2, w2)


def test_checkpoint_state_round_trips_and_an_older_layout_is_refused():
    """The cage's state comes back exactly; a checkpoint written when the cage kept its
    torque in its state (three entries) is refused with one line, not a Taichi error."""
    from taichi_bearing.errors import InputError

    model, cage = orbiting_roller(OMEGA)
    model.advance(200)
    saved = cage.state_arrays()
    speed = cage.speed
    model.advance(50)
    cage.load_state_arrays(saved)
    assert cage.speed == speed
    old = dict(saved, cage_state=np.append(saved["cage_state"], 0.0))
    with pytest.raises(InputError, match="cage's state has shape"):
        cage.load_state_arrays(old)
