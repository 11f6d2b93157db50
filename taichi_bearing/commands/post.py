"""`python -m taichi_bearing post RUN_DIR`: redo the checks, figures and report of a
finished run from its folder, without running the simulation again (after an update of
the checks or the post-processing)."""

from __future__ import annotations

import argparse


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("run_dir", help="folder of a finished run (holds summary.json)")
    parser.add_argument(
        "--no-report", dest="post", action="store_false", help="checks only: no figures, report"
    )


def main(args: argparse.Namespace) -> int:
    from taichi_bearing.simulate import recheck_run

    summary = recheck_run(args.run_dir, post=args.post)
    failed = [k for k, c in summary["checks"].items() if c["passed"] is False]
    print(
        f"checks: {len(summary['checks']) - len(failed)} passed or n/a, failed: {failed or 'none'}"
    )
    return 0
