"""The default case on a GPU against the CPU, side by side on one machine.

Runs the case (default ``cases/line_spall.yaml``) for ``--duration-ms`` once per backend
in ``--archs`` (each in its own process, after a short warm-up run that compiles its
kernels into its own offline cache; ``cuda:4`` is cuda with 4 steps a launch, unrolled
(``$TAICHI_BEARING_STEPS_PER_LAUNCH``), ``cuda:g16`` cuda with 16 one-step launches a
compute graph (``$TAICHI_BEARING_STEPS_PER_GRAPH``)), prints each run's stage times (model, preload,
transient) and element-steps/s, the transient's speed-up over the last backend listed,
and how far each backend's histories are from the last one's, column by column, up to
the first spall exit (bit-identical is not expected: a GPU contracts multiply-adds and
has its own sin and cos). With ``--full ARCH`` it then runs the whole case on ``ARCH``
and prints its times and checks.

    python benchmarks/taichi_bearing/bench_gpu.py --archs cuda cuda:g16 cpu --duration-ms 3 \
        --full cuda:g16

Nothing else should run on the machine meanwhile. Taichi writes its offline cache when a
process ends: a run killed while compiling leaves nothing cached, and the next compiles
again.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.versions import ROOT, run_case  # noqa: E402
from taichi_bearing.output.histories import read_histories  # noqa: E402
from taichi_bearing.solver.stepping import (  # noqa: E402
    STEPS_PER_GRAPH_ENV,
    STEPS_PER_LAUNCH_ENV,
)


def run_spec(spec: str, case: str, work: Path, name: str, overrides: list[str]) -> dict:
    """Run ``case`` on backend ``spec`` (``ARCH``, ``ARCH:STEPS_PER_LAUNCH`` or
    ``ARCH:gSTEPS_PER_GRAPH``) into ``work/name_spec``, with that spec's own kernel cache;
    its summary."""
    arch, _, steps = spec.partition(":")
    graph = steps.startswith("g")
    os.environ[STEPS_PER_LAUNCH_ENV] = "1" if graph else steps or "1"
    os.environ[STEPS_PER_GRAPH_ENV] = steps[1:] if graph else "1"
    safe = spec.replace(":", "_")
    return run_case(ROOT, case, work / f"{name}_{safe}", [f"run.arch={arch}", *overrides],
                    work / f"cache_{safe}")  # fmt: skip


def history_differences(a: Path, b: Path) -> list[tuple[str, float, float]]:
    """Per column of run ``a``'s histories that differs from ``b``'s (over the rows both
    have): ``(column, max |a - b|, max |b|)``, the largest relative difference first."""
    ha, hb = read_histories(a), read_histories(b)
    n = min(len(ha), len(hb))
    rows = []
    for col in ha.columns:
        if col not in hb.columns:
            continue
        x, y = ha[col].to_numpy(float)[:n], hb[col].to_numpy(float)[:n]
        d = np.abs(x - y)
        if np.nanmax(d, initial=0.0) > 0 or np.isnan(x).any() != np.isnan(y).any():
            rows.append((col, float(np.nanmax(d)), float(np.nanmax(np.abs(y)))))
    return sorted(rows, key=lambda r: -r[1] / r[2] if r[2] > 0 else -np.inf)


def stage_row(name: str, s: dict) -> str:
    """One table row of a run's summary."""
    t = s["stage_times_s"]
    return (
        f"{name:>10s} {t.get('model', 0):8.1f} {t.get('preload', 0):9.1f} "
        f"{t.get('transient', 0):11.1f} {s['n_steps']:9d} {s['element_steps_per_s']:13.3g}"
    )


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--case", default="cases/line_spall.yaml")
    p.add_argument("--archs", nargs="+", default=["cuda", "cpu"])
    p.add_argument("--threads", type=int, default=0, help="CPU threads (0: all cores)")
    p.add_argument("--duration-ms", type=float, default=3.0)
    p.add_argument("--full", metavar="ARCH", help="then the whole case on this backend")
    p.add_argument("--keep", type=Path, help="keep the run folders here")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = p.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench_gpu_") as tmp:
        work = args.keep or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        common = [f"run.threads={args.threads}", "output.frames=false", *args.set]
        runs: dict[str, dict] = {}
        for arch in args.archs:
            t0 = time.perf_counter()
            short = [*common, "run.duration_ms=0.05", "run.frame_interval_ms=0.05"]
            d = args.duration_ms
            timed = [*common, f"run.duration_ms={d}", f"run.frame_interval_ms={d}"]
            try:
                warm = run_spec(arch, args.case, work, "warm", short)
                warm_s = time.perf_counter() - t0
                pre_s = warm["stage_times_s"]["preload"]
                print(f"{arch}: warm-up (compiles the kernels) {warm_s:.1f} s, "
                      f"preload {pre_s:.1f} s", flush=True)  # fmt: skip
                runs[arch] = run_spec(arch, args.case, work, "run", timed)
            except SystemExit as failed:
                # One backend's failure (say, a launch mode a GPU's Taichi lacks) must not
                # cost the others' results on a machine lent for minutes.
                print(f"{arch}: FAILED, left out of the table\n{failed}", flush=True)
                continue
            print(stage_row(arch, runs[arch]), flush=True)
        if not runs:
            return 1
        base = [arch for arch in args.archs if arch in runs][-1]
        print(f"\n{args.duration_ms} ms of {args.case}, "
              f"{runs[base]['n_elements']} elements; times in s")  # fmt: skip
        print(f"{'backend':>10s} {'model':>8s} {'preload':>9s} {'transient':>11s} "
              f"{'steps':>9s} {'elem-steps/s':>13s} {'speed-up':>9s}")  # fmt: skip
        for arch, s in runs.items():
            up = runs[base]["stage_times_s"]["transient"] / s["stage_times_s"]["transient"]
            print(f"{stage_row(arch, s)} {up:9.2f}")
        for arch in [a for a in runs if a != base]:
            safe, safe_base = arch.replace(":", "_"), base.replace(":", "_")
            diffs = history_differences(work / f"run_{safe}", work / f"run_{safe_base}")
            print(f"\nhistories {arch} against {base}: {len(diffs)} columns differ; largest:")
            for col, d, ref in diffs[:12]:
                rel = d / ref if ref > 0 else float("inf")
                print(f"  {col:34s} max|diff| {d:10.3e}  max|{base}| {ref:10.3e}  rel {rel:9.2e}")
        if args.full:
            s = run_spec(args.full, args.case, work, "full", common)
            checks = s.get("checks", {})
            failed = [k for k, c in checks.items() if c.get("passed") is False]
            print(f"\nthe whole case on {args.full} ({s['n_steps']} steps):")
            print(f"{'backend':>10s} {'model':>8s} {'preload':>9s} {'transient':>11s} "
                  f"{'steps':>9s} {'elem-steps/s':>13s}")  # fmt: skip
            print(stage_row(args.full, s))
            print(f"checks: {len(checks) - len(failed)} of {len(checks)} passed; "
                  f"failed: {failed or 'none'}")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
