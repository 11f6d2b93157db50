"""`python -m taichi_bearing sweep CASE.yaml --load-kN 25,50,80 --speed-rpm 300,500,800`.

Runs the load x speed matrix (:mod:`taichi_bearing.sweep`) on a local process pool or,
with ``--scheduler ADDRESS``, on a Dask distributed cluster; then writes
``sweep_summary.csv``, the increase tables, figures and ``sweep_report.md``. Exit status:
0 all cells finished, 1 some failed (each reported), 2 bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from taichi_bearing.commands.common import add_case_arguments, check_empty, output_folder
from taichi_bearing.errors import InputError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument("--load-kN", dest="loads", required=True, metavar="L1,L2,...",
                        help="radial loads in kN, comma-separated")  # fmt: skip
    parser.add_argument("--speed-rpm", dest="speeds", required=True, metavar="S1,S2,...",
                        help="shaft speeds in rpm, comma-separated")  # fmt: skip
    parser.add_argument("--workers", type=int, default=None, metavar="N",
                        help="local process pool size (default: all cores); each case "
                        "gets max(1, cores // N) Taichi threads")  # fmt: skip
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="Dask scheduler address (tcp://host:8786): run the cases on "
                        "that cluster (needs the [distributed] extra and a shared file "
                        "system for the case and --out)")  # fmt: skip
    parser.add_argument(
        "--threads",
        type=int,
        default=None,
        metavar="N",
        help="Taichi threads per case (default: cores / concurrent cases)",
    )
    parser.add_argument(
        "--fixed-duration",
        action="store_true",
        help="keep run.duration_ms at every speed (default: scale it by "
        "case speed / cell speed so every cell covers the same travel)",
    )
    parser.add_argument(
        "--no-post",
        action="store_true",
        help="no per-run figures and report (the sweep outputs are made)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def main(args: argparse.Namespace) -> int:
    from taichi_bearing.sweep import make_cells, parse_values, run_sweep

    loads = parse_values(args.loads, "--load-kN")
    speeds = parse_values(args.speeds, "--speed-rpm")
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers: must be >= 1, got {args.workers}")
    if args.threads is not None and args.threads < 1:
        raise InputError(f"--threads: must be >= 1, got {args.threads}")
    if args.scheduler is not None and args.workers is not None:
        raise InputError("--workers: not used with --scheduler (the cluster has its workers)")
    if args.out is None:
        out = Path("runs") / f"sweep_{Path(args.case).stem}"
    else:
        out = check_empty(args.out, "--out")  # Path("") would resolve to here
    cells = make_cells(args.case, loads, speeds, out, args.overrides,
                       scale_duration=not args.fixed_duration, threads=args.threads,
                       post=not args.no_post)  # fmt: skip
    output_folder(out)  # once the cases are valid: a refused sweep makes no folder
    results = run_sweep(cells, workers=args.workers, scheduler=args.scheduler,
                        progress=not args.quiet)  # fmt: skip
    from taichi_bearing.post.sweep_figures import write_sweep_outputs
    from taichi_bearing.sweep_metrics import summary_rows

    paths = write_sweep_outputs(summary_rows(results), out)
    failed = [r for r in results if r.status != "finished"]
    ran = sum(r.ran for r in results)
    for r in failed:
        print(f"failed: {r.name}: {r.error}", file=sys.stderr)
    print(f"{len(results)} cases ({ran} run, {len(results) - ran} already finished, "
          f"{len(failed)} failed); {paths['summary']}, {paths['report']}")  # fmt: skip
    return 1 if failed else 0
