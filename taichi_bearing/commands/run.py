"""`python -m taichi_bearing run CASE.yaml`: mesh, preload, spin, record, check, report.

Bad input (case file, ``--set``, arguments) is one line and exit status 2; a run stopped
by the solver (SimulationError) exits with 3; Ctrl-C keeps the histories written so far.
"""

from __future__ import annotations

import argparse
import sys

from taichi_bearing.case import load_case_for_cli
from taichi_bearing.commands.common import add_case_arguments
from taichi_bearing.errors import InputError


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
        "--no-post", action="store_true", help="skip figures and report (histories, summary only)"
    )


def main(args: argparse.Namespace) -> int:
    # Validate first, so a bad case file fails with one line and exit 2 (CaseError).
    if args.threads is not None and args.threads < 0:
        raise InputError(f"--threads: must be >= 0, got {args.threads}")
    case = load_case_for_cli(args.case, args.overrides)
    from taichi_bearing.simulate import run_case

    out = args.out if args.out is not None else case.out_dir
    summary = run_case(
        case,
        out,
        resume=args.resume,
        arch=args.arch,
        threads=args.threads,
        quiet=args.quiet,
        post=not args.no_post,
        log=lambda *a: print(*a, file=sys.stderr),
    )
    if not args.quiet:
        print(f"results in {out}/ (summary.json: {summary['status']})")
    return 0
