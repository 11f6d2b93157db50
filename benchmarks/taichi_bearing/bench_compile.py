"""What a new model costs before it steps: Taichi's kernel compiles, this checkout against
another revision, side by side.

Every ``Model`` compiles its own kernels (they take its fields as template arguments), and
a process that builds many models (the test suite, a sweep's cells) pays that again for
each. This script builds the bearing model of a case ``--models`` times in one fresh
process per version (a cold offline kernel cache each time, as on a clean CI machine),
runs one step and reads the energies and a checkpoint state of each, and prints:

* per version, the wall time of each phase (build, first step, read-outs) for the first
  model and the later ones, and the ratio current / baseline;
* per version, the kernels compiled, counted and timed at their first call (compile and
  first launch), by kernel: the per-field copy kernels of Taichi's ``from_numpy``,
  ``to_numpy`` and ``fill`` against the shared ones of :mod:`taichi_bearing.solver.transfer`.

``--repeats`` processes per version, alternating which goes first; nothing else should
run on the machine meanwhile.

    python benchmarks/taichi_bearing/bench_compile.py          # baseline 59504cc, 3 models
    python benchmarks/taichi_bearing/bench_compile.py --baseline HEAD~1 --repeats 3
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# No path change at import: the child process must import the `taichi_bearing` of the
# checkout it is given (first on its PYTHONPATH), not this one.
ROOT = Path(__file__).resolve().parents[2]
PHASES = ("build", "first_step", "readouts")


def _count_compiles() -> tuple[collections.Counter, collections.Counter]:
    """Wrap Taichi's kernel call: time and count each kernel's calls that compiled."""
    from taichi.lang.kernel_impl import Kernel

    seconds: collections.Counter = collections.Counter()
    count: collections.Counter = collections.Counter()
    call = Kernel.__call__

    def timed(self, *args, **kwargs):
        n0 = len(self.compiled_kernels)
        t0 = time.perf_counter()
        try:
            return call(self, *args, **kwargs)
        finally:
            if len(self.compiled_kernels) > n0:
                seconds[self.func.__name__] += time.perf_counter() - t0
                count[self.func.__name__] += 1

    Kernel.__call__ = timed
    return seconds, count


def child(case_path: str, n_models: int) -> dict:
    """Build, step and read ``n_models`` models of the case in this process."""
    import taichi_bearing
    from taichi_bearing.case import load_case

    if (Path(taichi_bearing.__file__).parent / "simulation").is_dir():
        from taichi_bearing.simulation.simulate import build_model, stage_mesh
    else:  # a revision from before the packages by stage (issue 42)
        from taichi_bearing.simulate import build_model, stage_mesh

    seconds, count = _count_compiles()
    case = load_case(case_path, ["run.threads=1"])
    mesh, _ = stage_mesh(case)
    walls = []
    for _ in range(n_models):
        t0 = time.perf_counter()
        built = build_model(case, mesh, "cpu", 1)
        t1 = time.perf_counter()
        built.model.advance(1, record_last=True)
        t2 = time.perf_counter()
        built.model.energies()
        built.model.state_arrays()
        for c in built.model.contributors:
            c.energy()
            c.state_arrays()
        t3 = time.perf_counter()
        walls.append({"build": t1 - t0, "first_step": t2 - t1, "readouts": t3 - t2})
    package = str(Path(taichi_bearing.__file__).parent)
    return {"walls": walls, "seconds": dict(seconds), "count": dict(count), "package": package}


def run_child(source: Path, case: str, n_models: int) -> dict:
    """:func:`child` in a fresh process whose ``taichi_bearing`` is checkout ``source``."""
    with tempfile.TemporaryDirectory(prefix="bench_compile_cache_") as cache:
        path = os.pathsep.join(p for p in (str(source), os.environ.get("PYTHONPATH")) if p)
        env = dict(os.environ, PYTHONPATH=path, TAICHI_BEARING_CACHE_DIR=cache)
        cmd = [sys.executable, __file__, "--child", case, str(n_models)]
        res = subprocess.run(cmd, cwd=source, env=env, capture_output=True, text=True)
    if res.returncode != 0:
        raise SystemExit(f"{source}: failed (exit {res.returncode})\n{res.stderr[-2000:]}")
    line = next(x for x in res.stdout.splitlines() if x.startswith("RESULT "))
    return json.loads(line[len("RESULT ") :])


def _copy_kernel(name: str) -> bool:
    # Taichi's per-field copies, and solver.transfer's
    prefixes = ("ext_arr_to_", "tensor_to_", "matrix_to_", "fill", "field_fill", "_k_copy")
    return name.startswith(prefixes) or name == "_k_fill"


def main() -> int:
    if sys.argv[1:2] == ["--child"]:
        print("RESULT", json.dumps(child(sys.argv[2], int(sys.argv[3]))))
        return 0
    sys.path.insert(0, str(ROOT))
    from benchmarks.versions import worktree

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", default="59504cc", help="git revision to compare against")
    p.add_argument("--case", default="cases/validation/coarse_spall.yaml")
    p.add_argument("--models", type=int, default=3, help="models built in each process")
    p.add_argument("--repeats", type=int, default=2, help="processes per version")
    args = p.parse_args()
    results: dict[str, list[dict]] = {"baseline": [], "current": []}
    with worktree(args.baseline) as base:
        # the scripts run from this checkout; the simulator from each version's
        sources = {"baseline": base, "current": ROOT}
        for r in range(args.repeats):
            order = list(sources) if r % 2 == 0 else list(sources)[::-1]
            for name in order:
                res = run_child(sources[name], str(ROOT / args.case), args.models)
                results[name].append(res)
                total = sum(sum(w.values()) for w in res["walls"])
                print(f"run {r + 1} {name:8s}: {total:6.2f} s for {args.models} models "
                      f"(taichi_bearing of {res['package']})")  # fmt: skip

    print(f"\nmedian wall time, s ({args.case}, 1 thread, {args.models} models a process)")
    print(f"{'phase':30s} {'baseline':>9s} {'current':>9s} {'ratio':>7s}")
    for label, models in (("first model", slice(0, 1)), ("each later model", slice(1, None))):
        for phase in (*PHASES, "total"):
            med = {}
            for name, runs in results.items():
                per_run = []
                for res in runs:
                    walls = res["walls"][models]
                    if not walls:
                        continue
                    keys = PHASES if phase == "total" else (phase,)
                    per_run.append(sum(w[k] for w in walls for k in keys) / len(walls))
                med[name] = statistics.median(per_run) if per_run else float("nan")
            ratio = med["current"] / med["baseline"] if med["baseline"] else float("nan")
            print(f"{label + ': ' + phase:30s} {med['baseline']:9.3f} {med['current']:9.3f} "
                  f"{ratio:7.3f}")  # fmt: skip

    print("\nkernels compiled (first run of each version): count, seconds at first call")
    names = sorted(
        {k for runs in results.values() for k in runs[0]["count"]},
        key=lambda k: -max(runs[0]["seconds"].get(k, 0.0) for runs in results.values()),
    )
    print(f"{'kernel':28s} {'baseline':>15s} {'current':>15s}")
    sums = {name: [0, 0.0, 0, 0.0] for name in results}
    for k in names:
        cells = []
        for name, runs in results.items():
            n, s = runs[0]["count"].get(k, 0), runs[0]["seconds"].get(k, 0.0)
            cells.append(f"{n:5d} {s:8.2f} s")
            i = 0 if _copy_kernel(k) else 2
            sums[name][i] += n
            sums[name][i + 1] += s
        print(f"{k:28s} {cells[0]:>15s} {cells[1]:>15s}")
    for label, i in (("all copy kernels", 0), ("all other kernels", 2)):
        cells = [f"{sums[n][i]:5d} {sums[n][i + 1]:8.2f} s" for n in results]
        print(f"{label:28s} {cells[0]:>15s} {cells[1]:>15s}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
