"""Where a step's time goes, phase by phase, and what sets the time step.

Builds the case (default ``cases/line_spall.yaml``), preloads it, and from the preloaded
state times, on ONE thread (the phases' own cost, without the team's barriers):

- the whole step as the run steps it (``serial`` on one thread);
- each phase of the step body alone (:mod:`taichi_bearing.solver.step_phases`): CLEAR,
  FORCES (elements and the contributors' shares), GATHER, NODES, SENSORS;
- inside FORCES: the element forces with and without stiffness-proportional damping, the
  contact's queries alone;
- the same mesh without contributors.

Then the stable step of the case with and without element damping and contact damping
(each a model build; no stepping), which is what the number of steps depends on. Prints
a table; best of ``--repeats`` runs of ``--steps`` steps each. Nothing else should run on
the machine meanwhile.

    python benchmarks/taichi_bearing/profile_step.py [CASE] [--steps 300] [--repeats 3]
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def best_time(fn, n: int, repeats: int) -> float:
    """Best seconds per step over ``repeats`` calls of ``fn(n)`` (after one warm-up)."""
    fn(min(n, 10))
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn(n)
        best = min(best, time.perf_counter() - t0)
    return best / n


def main() -> int:
    from benchmarks.taichi_bearing.preloaded import case_parser

    p = case_parser(__doc__)
    p.add_argument("--steps", type=int, default=300)
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()

    import taichi as ti

    from benchmarks.taichi_bearing.preloaded import preloaded_model
    from taichi_bearing.case import load_case
    from taichi_bearing.simulation.simulate import build_model
    from taichi_bearing.solver import Model
    from taichi_bearing.solver.element_forces import element_forces
    from taichi_bearing.solver.step_phases import CLEAR, FORCES, GATHER, NODES, SENSORS
    from taichi_bearing.solver.stepping import advance_phases

    case, mesh, bm, _ = preloaded_model(args.case, args.overrides)
    model = bm.model
    model.advance(1)  # the half first step, and the contributors frozen
    s = bm.setup
    bare = Model(mesh, s.material, thickness=s.thickness, constraints=s.constraints,
                 loads=s.loads, damping=s.damping, max_added_mass=case.run.max_added_mass,
                 time_step=case.run.time_step)  # fmt: skip
    bare.load_state_arrays(model.state_arrays())
    bare.set_dt(model.dt)

    @ti.kernel
    def k_elements(m: ti.template(), n: ti.i32, dt: ti.f64, damped: ti.template()):
        ti.loop_config(serialize=True)
        for _ in range(n):
            for e in range(m.n_elements):
                element_forces(m, e, dt, damped)

    @ti.kernel
    def k_contact(c: ti.template(), m: ti.template(), n: ti.i32, dt: ti.f64):
        ti.loop_config(serialize=True)
        for _ in range(n):
            c.step_share(0, 1, m.x, m.v, m.mass, m.f_extra, dt, dt)

    n, r, dt = args.steps, args.repeats, model.dt
    state = model.state_arrays()
    rows = [("whole step (serial, as a run on one thread)",
             best_time(lambda k: model.advance(k), n, r))]  # fmt: skip
    model.load_state_arrays(state)
    for phase, name in ((CLEAR, "CLEAR"), (FORCES, "FORCES"), (GATHER, "GATHER"),
                        (NODES, "NODES"), (SENSORS, "SENSORS")):  # fmt: skip
        run = lambda k, ph=phase: advance_phases(model, k, ph, ph + 1)  # noqa: E731
        rows.append((f"  phase {name}", best_time(run, n, r)))
        model.load_state_arrays(state)
    rows.append(("    elements, damped", best_time(lambda k: k_elements(model, k, dt, 1), n, r)))
    rows.append(("    elements, no damping",
                 best_time(lambda k: k_elements(model, k, dt, 0), n, r)))  # fmt: skip
    bm.contact.before_steps(model, 1)
    rows.append((f"    contact queries ({bm.contact.n_active} listed)",
                 best_time(lambda k: k_contact(bm.contact, model, k, dt), n, r)))  # fmt: skip
    model.load_state_arrays(state)
    rows.append(("same mesh, no contributors", best_time(lambda k: bare.advance(k), n, r)))
    whole = rows[0][1]
    ne = mesh.n_elements
    print(f"{case.name}: {ne} elements, {mesh.n_nodes} nodes, dt {dt:.4g} s, one thread; "
          f"best of {r} x {n} steps")  # fmt: skip
    print(f"{'':48s} {'us/step':>9s} {'ns/element':>11s} {'of a step':>10s}")
    for name, sec in rows:
        print(f"{name:48s} {sec * 1e6:9.1f} {sec * 1e9 / ne:11.2f} {sec / whole:10.1%}")

    print()
    print("stable step (0.9 of the critical step) and what shortens it:")
    variants = (
        ("as the case says", []),
        ("no element damping", ["damping.ratio=0"]),
        ("no contact damping", ["contact.damping_ratio=0"]),
        ("neither", ["damping.ratio=0", "contact.damping_ratio=0"]),
    )
    ref = None
    for name, extra in variants:
        c = load_case(args.case, [*args.overrides, *extra])
        m = build_model(c, mesh, "cpu", 1).model
        ref = ref or m.dt_stable
        print(f"  {name:22s} dt {m.dt_stable:.4g} s  ({m.dt_stable / ref:.3f} x), damping "
              f"factor {m.damping_step_factor:.3f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
