"""Does numbering the bearing mesh along a space-filling curve make a step faster?

Builds the case (default ``cases/line_spall.yaml``) with its mesh numbered as the mesher
numbers it, and renumbered along a Morton (Z-order) curve within each part (parts stay
contiguous), each in its own process; preloads it and times ``--steps`` transient steps
(best of three), alternating which order goes first over ``--repeats`` rounds. Prints each
order's mean node-index span of an element (how far apart an element's nodes are in memory)
and microseconds per step. Nothing else should run on the machine meanwhile.

    python benchmarks/taichi_bearing/bench_mesh_order.py --threads 2 --repeats 2
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from benchmarks.taichi_bearing.bench_solver import morton_codes, renumbered  # noqa: E402

ORDERS = ("mesh", "morton")


def morton_within_parts(mesh):
    """``mesh`` with nodes and elements renumbered along a Morton curve within each part
    (nodes by the part of an element they belong to)."""
    part_of_node = np.zeros(mesh.n_nodes, np.int64)
    part_of_node[mesh.elements.ravel()] = np.repeat(mesh.element_part, 4)
    node_order = np.lexsort((morton_codes(mesh.nodes), part_of_node))
    centroids = mesh.nodes[mesh.elements].mean(axis=1)
    element_order = np.lexsort((morton_codes(centroids), mesh.element_part))
    return renumbered(mesh, node_order, element_order)


def worker(case_path: str, order: str, threads: int, steps: int) -> dict:
    """One order's model: preload, then the best of three timed ``steps``-step calls."""
    from benchmarks.taichi_bearing.preloaded import preloaded_model

    renumber = morton_within_parts if order == "morton" else None
    _, mesh, bm, pre = preloaded_model(case_path, (), "cpu", threads, renumber)
    span = float(np.mean(mesh.elements.max(axis=1) - mesh.elements.min(axis=1)))
    model = bm.model
    model.advance(50)
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        model.advance(steps)
        best = min(best, time.perf_counter() - t0)
    return {
        "order": order,
        "span": span,
        "us_per_step": best / steps * 1e6,
        "max_roller_force": max(pre["outer_force_N"]),
        "modes": sorted(model.steps_by_mode),
    }


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("case", nargs="?", default="cases/line_spall.yaml")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--repeats", type=int, default=2)
    p.add_argument("--worker", choices=ORDERS, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.worker:
        print("ROW " + json.dumps(worker(args.case, args.worker, args.threads, args.steps)))
        return 0
    rows: dict[str, list[dict]] = {o: [] for o in ORDERS}
    for r in range(args.repeats):
        for order in ORDERS if r % 2 == 0 else ORDERS[::-1]:
            cmd = [sys.executable, __file__, args.case, "--worker", order,
                   "--threads", str(args.threads), "--steps", str(args.steps)]  # fmt: skip
            out = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, check=True)
            row = json.loads(next(s for s in out.stdout.splitlines() if s.startswith("ROW "))[4:])
            rows[order].append(row)
            print(f"round {r} {order:>7s}: {row['us_per_step']:7.1f} us/step", flush=True)
    print(f"\n{'order':>7s} {'node span':>10s} {'us/step (median)':>17s} "
          f"{'max roller force N':>19s}")  # fmt: skip
    for order in ORDERS:
        med = statistics.median(x["us_per_step"] for x in rows[order])
        first = rows[order][0]
        print(f"{order:>7s} {first['span']:10.1f} {med:17.1f} {first['max_roller_force']:19.6f}")
    ratio = statistics.median(x["us_per_step"] for x in rows["morton"]) / statistics.median(
        x["us_per_step"] for x in rows["mesh"]
    )
    print(f"morton / mesh time per step: {ratio:.3f} ({args.threads} threads)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
