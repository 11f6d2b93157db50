"""Parallel stepping launched from Python against a compute graph of one-step launches.

Builds the case (default the coarse validation case) on ``--arch``, preloads it, and
steps it in ``parallel`` mode (the GPU's mode) for ``--steps`` steps at a time, one step a
launch from Python (``$TAICHI_BEARING_STEPS_PER_GRAPH`` 1) and ``--graph`` one-step
launches a Taichi compute graph, alternating the order from round to round after a
warm-up of each; prints every round's time per step and the medians' ratio. The motion
is the same either way (``tests/test_solver_team.py``); what differs is the host's work
per launch (Taichi's argument handling, paid once a graph).

    python benchmarks/taichi_bearing/bench_graph.py --arch cpu --threads 1 --graph 16 --steps 2000
    python benchmarks/taichi_bearing/bench_graph.py --arch cuda cases/line_spall.yaml

Nothing else should run on the machine meanwhile.
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from taichi_bearing.solver.stepping import STEPS_PER_GRAPH_ENV  # noqa: E402


def main() -> int:
    from benchmarks.taichi_bearing.preloaded import case_parser

    p = case_parser(__doc__, "cases/validation/coarse_spall.yaml", arch="cpu", threads=1)
    p.add_argument("--graph", type=int, default=16, help="steps a graph")
    p.add_argument("--steps", type=int, default=2000, help="steps a timing")
    p.add_argument("--rounds", type=int, default=4)
    args = p.parse_args()

    import taichi as ti

    from benchmarks.taichi_bearing.preloaded import preloaded_model

    _, mesh, built, pre = preloaded_model(args.case, args.overrides, args.arch, args.threads)
    model = built.model
    print(f"{args.case}: {mesh.n_elements} elements, preload {pre['wall_s']:.1f} s", flush=True)
    ways = {"python": "1", "graph": str(args.graph)}

    def timed(way: str, n: int) -> float:
        os.environ[STEPS_PER_GRAPH_ENV] = ways[way]
        t0 = time.perf_counter()
        model.advance(n, mode="parallel")
        ti.sync()
        return (time.perf_counter() - t0) / n * 1e6

    for way in ways:
        print(f"warm-up {way}: {timed(way, 4 * args.graph):.0f} us a step (compiles)", flush=True)
    times: dict[str, list[float]] = {way: [] for way in ways}
    print(f"\n{'round':>5s} {'launch':>8s} {'us/step':>9s}")
    for r in range(args.rounds):
        for way in ways if r % 2 == 0 else reversed(ways):
            times[way].append(timed(way, args.steps))
            print(f"{r:5d} {way:>8s} {times[way][-1]:9.1f}", flush=True)
    py, gr = (statistics.median(times[w]) for w in ways)
    print(f"\n{args.arch}, {args.threads} thread(s), parallel stepping, {args.steps} steps a "
          f"timing: median {py:.1f} us a step one a launch, {gr:.1f} with {args.graph} a "
          f"graph; graph / python {gr / py:.3f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
