"""Multi-rate stepping against single-rate on one case, side by side.

Each level runs in its own process: the case is built with ``run.multirate_levels`` set,
preloaded (dynamic relaxation is single-rate at every level, so every process starts the
transient from the same state), warmed up (its kernels compiled) and timed over
``--steps`` transient steps (best of three); the levels alternate in order over
``--repeats`` rounds. Prints each level's share of elements per class, its element work
against single rate and its microseconds per step, and the ratio to level 0. Nothing else
should run on the machine meanwhile. The default is the convergence study's finest local
refinement (``docs/results/convergence``), where multi-rate stepping is meant to pay:

    python benchmarks/taichi_bearing/bench_multirate.py --levels 0 3 --threads 2 --repeats 2
    python benchmarks/taichi_bearing/bench_multirate.py cases/line_spall.yaml --no-refine \
        --levels 0 2
    python benchmarks/taichi_bearing/bench_multirate.py --arch cuda --levels 0 3   # on a GPU
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

# docs/results/convergence, local_refinement at its finest level
REFINED = [
    "mesh.spall_size_mm=0.125",
    "mesh.roller_surface_size_mm=0.125",
    "mesh.fine_rollers=1",
    "mesh.spall_zone_mm=3.5",
]


def worker(case: str, sets: list[str], level: int, arch: str, threads: int, steps: int) -> dict:
    """One level's model: preload, warm up, then the best of three timed calls."""
    from benchmarks.taichi_bearing.preloaded import preloaded_model

    _, mesh, built, pre = preloaded_model(
        case, [*sets, f"run.multirate_levels={level}"], arch, threads
    )
    model = built.model
    model.advance(1, record_last=True)  # the half step out of t = 0
    model.advance(8 * model.cycle_steps)
    steps -= steps % model.cycle_steps
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        model.advance(steps)
        best = min(best, time.perf_counter() - t0)
    classes = model.step_classes
    return {
        "level": level,
        "n_elements": mesh.n_elements,
        "dt_ns": model.dt * 1e9,
        "element_share": classes.summary()["element_share"] if classes else [1.0],
        "element_work": classes.element_work if classes else 1.0,
        "us_per_step": best / steps * 1e6,
        "preload_s": pre["wall_s"],
        "modes": sorted(model.steps_by_mode),
    }


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("case", nargs="?", default="cases/single_passage.yaml")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE")
    p.add_argument("--no-refine", action="store_true", help="leave out the refined-mesh keys")
    p.add_argument("--levels", type=int, nargs="+", default=[0, 3])
    p.add_argument("--arch", default="cpu", choices=["cpu", "cuda", "vulkan"])
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--steps", type=int, default=4000)
    p.add_argument("--repeats", type=int, default=2)
    p.add_argument("--worker", type=int, help=argparse.SUPPRESS)
    args = p.parse_args()
    sets = ([] if args.no_refine else REFINED) + args.sets
    if args.worker is not None:
        row = worker(args.case, sets, args.worker, args.arch, args.threads, args.steps)
        print("ROW " + json.dumps(row))
        return 0
    rows: dict[int, list[dict]] = {level: [] for level in args.levels}
    for r in range(args.repeats):
        for level in args.levels if r % 2 == 0 else args.levels[::-1]:
            cmd = [sys.executable, __file__, args.case, "--worker", str(level),
                   "--arch", args.arch, "--threads", str(args.threads), "--steps", str(args.steps),
                   "--no-refine", *[a for s in sets for a in ("--set", s)]]  # fmt: skip
            out = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, check=True)
            row = json.loads(next(s for s in out.stdout.splitlines() if s.startswith("ROW "))[4:])
            rows[level].append(row)
            print(f"round {r} level {level}: {row['us_per_step']:8.1f} us/step", flush=True)
    base = statistics.median(x["us_per_step"] for x in rows[args.levels[0]])
    first = rows[args.levels[0]][0]
    print(
        f"\n{Path(args.case).name} {' '.join(sets)}: {first['n_elements']} elements, "
        f"dt {first['dt_ns']:.2f} ns, {args.arch}, {args.threads} threads, {args.steps} steps, "
        f"modes {first['modes']}"
    )
    print(f"{'levels':>6}  {'elements per class':<32} {'element work':>12} "
          f"{'us/step (median)':>16} {'time ratio':>10}")  # fmt: skip
    for level in args.levels:
        med = statistics.median(x["us_per_step"] for x in rows[level])
        row = rows[level][0]
        shares = " ".join(f"{s:.3f}" for s in row["element_share"])
        print(f"{level:>6}  {shares:<32} {row['element_work']:>12.3f} {med:>16.1f} "
              f"{med / base:>10.3f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
