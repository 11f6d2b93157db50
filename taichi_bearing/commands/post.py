"""`python -m taichi_bearing post RUN_DIR`: redo the checks, figures and report of a run
from its folder, without running the simulation again (after an update of the checks or
the post-processing).

A run that did not finish (Ctrl-C, a solver stop, ``kill -9``) is checked on what was
recorded and reported as partial. A folder from before runs recorded ``mesh_info.json``
and the flexible-ring reference is refused in one line naming what it lacks; ``--remesh``
computes them from its ``case.yaml``.
"""

from __future__ import annotations

import argparse

from taichi_bearing.commands.common import check_empty, ensure_writable


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("run_dir", help="run folder (case.yaml, preload.json, histories)")
    parser.add_argument(
        "--no-report", dest="post", action="store_false", help="checks only: no figures, report"
    )
    parser.add_argument(
        "--remesh",
        action="store_true",
        help="for a run folder without mesh_info.json or the flexible-ring reference: mesh "
        "its case.yaml and solve them now (written to the folder, labelled)",
    )


def main(args: argparse.Namespace) -> int:
    from taichi_bearing.output.layout import CASE_FILE, SUMMARY_FILE
    from taichi_bearing.pipeline import recheck_run

    run_dir = check_empty(args.run_dir, "RUN_DIR")
    if any((run_dir / name).is_file() for name in (CASE_FILE, SUMMARY_FILE)):
        # a run folder (else recheck_run says what it is not): post rewrites files in it
        ensure_writable(run_dir, "RUN_DIR")
    summary = recheck_run(run_dir, post=args.post, remesh=args.remesh)
    failed = [k for k, c in summary["checks"].items() if c["passed"] is False]
    partial = " (partial run: what was recorded)" if "partial" in summary else ""
    print(
        f"checks{partial}: {len(summary['checks']) - len(failed)} passed or n/a, "
        f"failed: {failed or 'none'}"
    )
    return 0
