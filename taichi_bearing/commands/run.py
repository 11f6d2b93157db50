"""`python -m taichi_bearing run CASE.yaml`: mesh, preload, spin, record, check, report.

Bad input (case file, ``--set``, arguments) is one line and exit status 2; a run stopped
by the solver (SimulationError) exits with 3; Ctrl-C keeps the histories written so far.
"""

from __future__ import annotations

import argparse
import sys

from taichi_bearing.commands.common import add_case_arguments, case_output_folder
from taichi_bearing.errors import InputError
from taichi_bearing.output.progress import LOG_INTERVAL_S


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument(
        "--arch",
        choices=["cpu", "cuda", "vulkan"],
        default=None,
        help="Taichi backend (default: the case's run.arch)",
    )
    parser.add_argument(
        "--threads",
        type=int,
        default=None,
        metavar="N",
        help="CPU threads (default: the case's run.threads; 0 = all cores)",
    )
    parser.add_argument(
        "--resume", action="store_true", help="continue from the last checkpoint in --out"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar and no stage lines")
    parser.add_argument(
        "--progress-interval",
        type=float,
        default=LOG_INTERVAL_S,
        metavar="S",
        help="wall seconds between progress lines when stderr is not a terminal "
        f"(a log file or a pipe; default {LOG_INTERVAL_S:g})",
    )
    parser.add_argument(
        "--no-post", action="store_true", help="skip figures and report (histories, summary only)"
    )


def main(args: argparse.Namespace) -> int:
    # Validate first, so a bad case file fails with one line and exit 2 (CaseError).
    from taichi_bearing.case import load_case_for_cli

    if args.threads is not None and args.threads < 0:
        raise InputError(f"--threads: must be >= 0, got {args.threads}")
    if not args.progress_interval > 0:  # also NaN
        raise InputError(f"--progress-interval: must be > 0 s, got {args.progress_interval:g}")
    case = load_case_for_cli(args.case, args.overrides)
    out = case_output_folder(args.out, case)
    from taichi_bearing.pipeline import run_case  # Taichi: only once the input is good

    summary = run_case(
        case,
        out,
        resume=args.resume,
        arch=args.arch,
        threads=args.threads,
        quiet=args.quiet,
        progress_interval=args.progress_interval,
        post=not args.no_post,
        log=lambda *a: print(*a, file=sys.stderr),
    )
    if not args.quiet:
        print(f"results in {out}/ (summary.json: {summary['status']})")
    return 0
