"""How well each phase of a step shares out among the team's threads.

Builds the case (default ``cases/line_spall.yaml``) on the CPU with ``--threads`` threads,
preloads it, and from the preloaded state times each phase of the step body
(:mod:`taichi_bearing.solver.step_phases`) two ways, side by side: on one thread (the phase
alone, serial) and by a team of ``--threads`` members (each its share, then the spin
barrier, as team stepping runs it); then the whole step both ways. The ratio is the
phase's speed-up on the team: what its threads gain, less the barriers' cost and any
imbalance between the shares. Best of ``--repeats`` runs of ``--steps`` steps each, each
run from the same state. Nothing else should run on the machine meanwhile.

    python benchmarks/taichi_bearing/profile_team.py [CASE] [--threads 2] [--steps 300] \
        [--repeats 5]
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def main() -> int:
    from benchmarks.taichi_bearing.preloaded import case_parser

    p = case_parser(__doc__, threads=2)
    p.add_argument("--steps", type=int, default=300)
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    if args.threads < 2:
        p.error("--threads: a team needs 2 or more")

    from benchmarks.taichi_bearing.preloaded import preloaded_model
    from taichi_bearing.solver.step_phases import CLEAR, FORCES, GATHER, NODES, SENSORS
    from taichi_bearing.solver.stepping import advance_phases

    case, mesh, bm, _ = preloaded_model(args.case, args.overrides, "cpu", args.threads)
    model = bm.model
    model.advance(1)  # the half first step, and the contributors frozen

    state = model.state_arrays()
    n, members = args.steps, args.threads

    def best(fn) -> float:
        """Best microseconds per step of ``fn(n)`` over the repeats, each from ``state``."""
        fn(10)
        b = float("inf")
        for _ in range(args.repeats):
            model.load_state_arrays(state)
            t0 = time.perf_counter()
            fn(n)
            b = min(b, time.perf_counter() - t0)
        model.load_state_arrays(state)
        return b / n * 1e6

    rows = []
    for name, phase in (("CLEAR", CLEAR), ("FORCES", FORCES), ("GATHER", GATHER),
                        ("NODES", NODES), ("SENSORS", SENSORS)):  # fmt: skip
        one = best(lambda k, ph=phase: advance_phases(model, k, ph, ph + 1))
        team = best(lambda k, ph=phase: advance_phases(model, k, ph, ph + 1, members))
        rows.append((f"phase {name}", one, team))
    one = best(lambda k: model.advance(k, mode="serial"))
    team = best(lambda k: model.advance(k, mode="team"))
    rows.append(("whole step (as a run steps it)", one, team))
    print(f"{case.name}: {mesh.n_elements} elements, {mesh.n_nodes} nodes; a team of "
          f"{members} against one thread; best of {args.repeats} x {n} steps")  # fmt: skip
    print(f"{'':32s} {'1 thread us':>12s} {'team us':>9s} {'speed-up':>9s}")
    for name, a, b in rows:
        print(f"{name:32s} {a:12.1f} {b:9.1f} {a / b:9.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
