"""Throughput with one other CPU-bound process on the machine, against a quiet machine.

A team of spinning threads (team stepping) collapses when another process takes a core:
a member spins at a barrier while the one it waits for has no core (on 2 cores, one other
simulation made a run 18x slower). This script runs the case's transient quiet and beside
a spinning competitor (``python -c "while True: pass"``), for this checkout and, with
``--baseline REV``, for another revision, alternating the order, and prints the
element-steps/s of each and the ratio loaded / quiet (a fair share of 2 cores beside one
other process is 50 %). Nothing else should run on the machine meanwhile.

    python benchmarks/taichi_bearing/bench_under_load.py --duration-ms 0.5 --baseline bdc75d3
"""

from __future__ import annotations

import argparse
import contextlib
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.versions import ROOT, run_case, worktree  # noqa: E402


@contextlib.contextmanager
def competitor(on: bool):
    """A CPU-bound process for the duration of the block (when ``on``)."""
    proc = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if on else None
    try:
        yield
    finally:
        if proc is not None:
            proc.kill()
            proc.wait()


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--case", default="cases/line_spall.yaml", help="relative: each version's own")
    p.add_argument("--duration-ms", type=float, default=0.5)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--baseline", default=None, help="also run this git revision")
    args = p.parse_args()
    overrides = [
        f"run.duration_ms={args.duration_ms}",
        f"run.frame_interval_ms={args.duration_ms}",
        f"run.threads={args.threads}",
    ]
    rows = []
    with (
        tempfile.TemporaryDirectory(prefix="bench_under_load_") as tmp,
        contextlib.ExitStack() as st,
    ):
        work = Path(tmp)
        sources = {"current": ROOT}
        if args.baseline:
            sources["baseline"] = st.enter_context(worktree(args.baseline))
        for name, src in sources.items():  # warm each version's kernel cache
            run_case(src, args.case, work / f"warm_{name}", [*overrides, "run.duration_ms=0.02",
                     "run.frame_interval_ms=0.02"], work / f"cache_{name}")  # fmt: skip
        for loaded in (False, True, True, False):
            for name, src in sources.items():
                with competitor(loaded):
                    s = run_case(src, args.case, work / f"{name}_{loaded}_{len(rows)}",
                                 overrides, work / f"cache_{name}")  # fmt: skip
                modes = s.get("steps_by_mode", "")
                rows.append(
                    (name, loaded, s["element_steps_per_s"], s["stage_times_s"]["transient"])
                )
                print(f"{name:>9s} {'loaded' if loaded else 'quiet':>7s} "
                      f"{s['element_steps_per_s']:12.3e} el-steps/s  transient "
                      f"{s['stage_times_s']['transient']:7.1f} s  {modes}", flush=True)  # fmt: skip
    print()
    for name in sources:
        quiet = max(r[2] for r in rows if r[0] == name and not r[1])
        loaded = max(r[2] for r in rows if r[0] == name and r[1])
        print(f"{name}: loaded / quiet throughput {loaded / quiet:.2f} (best of two each)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
