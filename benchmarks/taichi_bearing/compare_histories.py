"""Are two versions' histories identical? The default case run by a baseline revision and
by this checkout, side by side, compared column by column.

A refactor of the solver must leave the physics unchanged to the last bit. This script
checks out ``--baseline`` (default bdc75d3, before the house redesign) in a temporary git
worktree, runs the same case with the same overrides and threads in both, and prints, for
every history column that differs, how many rows differ and the largest absolute
difference; the exit status is 1 when any column differs.

    python benchmarks/taichi_bearing/compare_histories.py              # 3 ms, 1 thread
    python benchmarks/taichi_bearing/compare_histories.py --threads 2
    python benchmarks/taichi_bearing/compare_histories.py --runs A B   # two run folders

The default duration stops short of the first spall exit (4.8 ms on the default case):
after it the exit bounce is chaotic, and a difference in the last bit (which this script
exists to rule out) grows to the size of the signal.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from benchmarks.versions import ROOT, run_case, worktree  # noqa: E402
from taichi_bearing.output.histories import read_histories  # noqa: E402


def compare(a: Path, b: Path) -> int:
    """Print the history columns whose values differ; return how many do."""
    ha, hb = read_histories(a), read_histories(b)
    if list(ha.columns) != list(hb.columns):
        print(f"the column sets differ: {sorted(set(ha.columns) ^ set(hb.columns))}")
    if len(ha) != len(hb):
        print(f"row counts differ: {len(ha)} vs {len(hb)}")
        return 1
    common = [c for c in ha.columns if c in hb.columns]
    print(f"{len(ha)} rows, {len(common)} common columns")
    differ = 0
    for col in common:
        x, y = ha[col].to_numpy(), hb[col].to_numpy()
        same = (x == y) | (np.isnan(x) & np.isnan(y))
        if same.all():
            continue
        if not differ:
            print(f"{'column':34s} {'rows differing':>14s} {'max |diff|':>12s} "
                  f"{'max |value|':>12s}")  # fmt: skip
        differ += 1
        d = np.abs(x - y)
        print(f"{col:34s} {int((~same).sum()):14d} {np.nanmax(d):12.3e} "
              f"{np.nanmax(np.abs(x)):12.3e}")  # fmt: skip
    print(f"{differ} of {len(common)} columns differ" if differ else "histories identical")
    return differ


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--baseline", default="bdc75d3", help="git revision to compare against")
    p.add_argument("--case", default="cases/line_spall.yaml", help="relative: each version's own")
    p.add_argument("--duration-ms", type=float, default=3.0)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    p.add_argument("--runs", nargs=2, type=Path, metavar="DIR", help="compare two run folders")
    p.add_argument("--keep", type=Path, help="keep the two run folders here")
    args = p.parse_args()
    if args.runs:
        return int(compare(*args.runs) > 0)
    overrides = [
        f"run.duration_ms={args.duration_ms}",
        f"run.frame_interval_ms={args.duration_ms}",
        f"run.threads={args.threads}",
        *args.set,
    ]
    with tempfile.TemporaryDirectory(prefix="compare_histories_") as tmp:
        work = args.keep or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        runs = {}
        with worktree(args.baseline) as base:
            for name, source in (("baseline", base), ("current", ROOT)):
                runs[name] = work / f"{name}_run"
                print(f"running the {name} version ({source})", flush=True)
                run_case(source, args.case, runs[name], overrides, work / f"{name}_cache")
        return int(compare(runs["baseline"], runs["current"]) > 0)


if __name__ == "__main__":
    sys.exit(main())
