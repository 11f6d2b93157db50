"""This checkout's speed against another revision's, side by side on the same case.

Checks out ``--baseline`` (default bdc75d3, before the house redesign) in a temporary git
worktree and runs the case with both versions, same duration and threads: first one short
run each to compile the kernels into each version's own offline cache, then ``--repeats``
timed runs each, alternating which version goes first (on a shared VM the order alone
changed identical code's time by 1.15-1.32x). Prints every run's preload and transient
wall time and element-steps/s, the medians, and the ratio current / baseline. Nothing else
should run on the machine meanwhile: spinning team threads make a loaded machine look many
times slower.

    python benchmarks/taichi_bearing/bench_versions.py --duration-ms 2 --threads 2 --repeats 3
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.versions import ROOT, run_case, worktree  # noqa: E402


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", default="bdc75d3", help="git revision to compare against")
    p.add_argument("--case", default="cases/line_spall.yaml", help="relative: each version's own")
    p.add_argument("--duration-ms", type=float, default=2.0)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = p.parse_args()
    overrides = [
        f"run.duration_ms={args.duration_ms}",
        f"run.frame_interval_ms={args.duration_ms}",
        f"run.threads={args.threads}",
        *args.set,
    ]
    times: dict[str, list[tuple[float, float, float]]] = {"baseline": [], "current": []}
    with (
        tempfile.TemporaryDirectory(prefix="bench_versions_") as tmp,
        worktree(args.baseline) as base,
    ):
        work = Path(tmp)
        sources = {"baseline": base, "current": ROOT}
        for name, source in sources.items():  # compile and warm each cache
            print(f"warm-up: {name}", flush=True)
            short = [*overrides, "run.duration_ms=0.05", "run.frame_interval_ms=0.05"]
            run_case(source, args.case, work / f"warm_{name}", short, work / f"cache_{name}")
        print(f"{'run':>3s} {'version':>9s} {'preload s':>10s} {'transient s':>12s} "
              f"{'elem-steps/s':>13s}")  # fmt: skip
        for r in range(args.repeats):
            order = ("baseline", "current") if r % 2 == 0 else ("current", "baseline")
            for name in order:
                s = run_case(sources[name], args.case, work / f"run{r}_{name}", overrides,
                             work / f"cache_{name}")  # fmt: skip
                st = s["stage_times_s"]
                row = (st["preload"], st["transient"], s["element_steps_per_s"])
                times[name].append(row)
                print(f"{r:3d} {name:>9s} {row[0]:10.2f} {row[1]:12.2f} {row[2]:13.3e}",
                      flush=True)  # fmt: skip
    med = {k: [statistics.median(c) for c in zip(*v, strict=True)] for k, v in times.items()}
    print()
    print(f"{'median':>13s} {'preload s':>10s} {'transient s':>12s} {'elem-steps/s':>13s}")
    for name in ("baseline", "current"):
        m = med[name]
        print(f"{name:>13s} {m[0]:10.2f} {m[1]:12.2f} {m[2]:13.3e}")
    b, c = med["baseline"], med["current"]
    print(f"current / baseline transient time: {c[1] / b[1]:.3f} (speed-up {b[1] / c[1]:.3f}x); "
          f"preload {c[0] / b[0]:.3f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
