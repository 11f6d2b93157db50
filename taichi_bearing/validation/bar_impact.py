r"""An elastic bar striking a rigid wall, against the one-dimensional wave solution: the
contact's pressure plateau and duration, and what the penalty adds to them.

A bar of length :math:`L` and Poisson's ratio 0 in plane strain carries one-dimensional
waves (no lateral coupling) at :math:`c = \sqrt{E / \rho}`. Striking a rigid wall at
:math:`v_0` it is pressed by :math:`\rho c v_0` over its end for exactly :math:`2 L / c`:
the compression wave runs to the free end and back, and the bar leaves the wall at
:math:`v_0` (Johnson, Impact Strength of Materials, 1972, ch. 1; Timoshenko and Goodier,
Theory of Elasticity, sec. 144). A penalty contact of pressure :math:`p_s` per unit overlap
is a spring in front of the bar's end: the end slows by :math:`\sigma / (\rho c)` as the
spring presses it, so the overlap grows as :math:`\dot\delta = v_0 - p_s \delta / (\rho c)`
and the pressure rises as :math:`\rho c v_0 (1 - e^{-t / \tau})`,
:math:`\tau = \rho c / p_s`: half the plateau at :math:`\tau \ln 2`. It lets go as late,
so the time above half the plateau keeps :math:`2 L / c`. A stiff
penalty on a coarse mesh rings with the mesh's highest modes instead (the plateau's mean
and the duration then move by a few %).

The wall is a block whose every node is fixed (rigid); the pressure law's contact
(:class:`~taichi_bearing.solver.laws.contact.PressurePenalty`) joins them, two passes, no
friction, no damping, the global stable step.

``python -m taichi_bearing.validation.bar_impact`` prints the table of
``docs/results/bar_impact/``.
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import argparse
import math
from dataclasses import dataclass

import numpy as np

__all__ = ["BarImpact", "bar_impact", "main"]

E, RHO = 210e9, 7850.0
LENGTH, HEIGHT = 20e-3, 2e-3  # m; thickness 1 m
V0 = 1.0  # m/s


@dataclass(frozen=True)
class BarImpact:
    r"""One run: the contact force history and its reading against the wave solution.

    Attributes
    ----------
    elements : int
        Elements along the bar.
    pressure : float
        The penalty ``p_s``, Pa/m.
    time, force : ndarray
        Mid-times (s) and mean pair force over each sample (N, compressive positive).
    plateau, plateau_exact : float
        Mean force over the middle half of the contact, N; :math:`\rho c v_0 A`.
    duration, duration_exact : float
        Time the force stays above half the exact plateau, s; :math:`2 L / c`.
    onset : float
        When the force first reaches half the exact plateau (linear between samples), s.
    rebound : float
        The bar's mean velocity after the impact over ``v0`` (1 for the elastic bar).
    """

    elements: int
    pressure: float
    time: np.ndarray
    force: np.ndarray
    plateau: float
    plateau_exact: float
    duration: float
    duration_exact: float
    onset: float
    rebound: float

    @property
    def plateau_error(self) -> float:
        return self.plateau / self.plateau_exact - 1.0

    @property
    def duration_error(self) -> float:
        return self.duration / self.duration_exact - 1.0


def bar_impact(elements: int, pressure: float, samples_per_duration: int = 200) -> BarImpact:
    """Strike the bar (``elements`` along it, square elements) on the wall with the
    pressure law ``pressure`` (Pa/m); Taichi must be started first
    (:func:`taichi_bearing.solver.backend.init_taichi`)."""
    from taichi_bearing.case.material import Material
    from taichi_bearing.mesh.bodies import merge_meshes
    from taichi_bearing.mesh.primitives import rectangle_mesh
    from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
    from taichi_bearing.solver.laws import PressurePenalty
    from taichi_bearing.solver.loads import FixedNodes
    from taichi_bearing.solver.model import Model

    h = LENGTH / elements
    ny = max(1, round(HEIGHT / h))
    bar = rectangle_mesh(LENGTH, HEIGHT, elements, ny, origin=(0.0, 0.0))
    wall = rectangle_mesh(4 * h, HEIGHT + 2 * h, 4, ny + 2, origin=(-4 * h, -h))
    mesh = merge_meshes({"bar": bar, "wall": wall})
    wall_nodes = np.unique(mesh.elements[mesh.element_part == mesh.part_id("wall")])
    model = Model(
        mesh,
        Material(E, 0.0, RHO),
        constraints=[FixedNodes(wall_nodes)],
        time_step="global",
        dt_factor=0.9,
    )
    pair = ContactPair("bar_wall", "bar.left", "wall.right", two_pass=True)
    contact = PenaltyContact(model, [pair], ContactParameters(), law=PressurePenalty(pressure))
    model.add_contributor(contact)
    bar_nodes = model.part_nodes("bar")
    v = np.zeros((model.n_nodes, 2))
    v[bar_nodes, 0] = -V0
    model.set_state(v=v)
    model.restart_accounting()
    c = math.sqrt(E / RHO)
    duration_exact = 2.0 * LENGTH / c
    plateau_exact = RHO * c * V0 * HEIGHT
    dt = model.dt
    every = max(1, round(duration_exact / samples_per_duration / dt))
    contact.pop_sample_means()
    times, forces = [], []
    while model.time < 1.5 * duration_exact:
        model.advance(every)
        times.append(model.time - 0.5 * (every + 1) * dt)
        # the pair resultant is the force by the bar on the wall: -x
        forces.append(-float(contact.pop_sample_means()[0][0]))
    t, f = np.asarray(times), np.asarray(forces)
    above = np.flatnonzero(f > 0.5 * plateau_exact)
    t_on, t_off = t[above[0]], t[above[-1]]
    duration = float(t_off - t_on)
    middle = (t > t_on + 0.25 * duration) & (t < t_off - 0.25 * duration)
    # the first crossing, from (0, 0): the bar touches the wall at t = 0
    k = above[0]
    t_up, f_up = np.concatenate([[0.0], t[: k + 1]]), np.concatenate([[0.0], f[: k + 1]])
    onset = float(np.interp(0.5 * plateau_exact, f_up[-2:], t_up[-2:]))
    mass = model.mass_np[bar_nodes]
    rebound = float(np.sum(mass * model.velocities()[bar_nodes, 0]) / np.sum(mass) / V0)
    return BarImpact(
        elements=elements,
        pressure=float(pressure),
        time=t,
        force=f,
        plateau=float(np.mean(f[middle])),
        plateau_exact=plateau_exact,
        duration=duration,
        duration_exact=duration_exact,
        onset=onset,
        rebound=rebound,
    )


def main(argv: list[str] | None = None) -> int:
    """Print the table: plateau and duration errors by mesh and penalty."""
    p = argparse.ArgumentParser(prog="python -m taichi_bearing.validation.bar_impact")
    p.add_argument("--elements", default="20,40,80", help="elements along the bar")
    p.add_argument("--pressure-GPa-mm", default="100,1000,10000", help="p_s values")
    args = p.parse_args(argv)
    from taichi_bearing.solver.backend import init_taichi

    init_taichi("cpu")
    print("| elements | p_s (GPa/mm) | plateau error | duration error | onset (ns) "
          "| tau ln 2 (ns) | rebound |")  # fmt: skip
    print("|---:|---:|---:|---:|---:|---:|---:|")
    c = math.sqrt(E / RHO)
    for n in (int(s) for s in args.elements.split(",")):
        for ps in (float(s) * 1e12 for s in args.pressure_GPa_mm.split(",")):
            r = bar_impact(n, ps)
            delay = RHO * c / ps * math.log(2.0)
            print(f"| {n} | {ps / 1e12:g} | {r.plateau_error:+.2%} | {r.duration_error:+.2%} "
                  f"| {r.onset * 1e9:.1f} | {delay * 1e9:.1f} | {r.rebound:.3f} |")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
