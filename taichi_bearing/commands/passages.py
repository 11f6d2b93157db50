"""`python -m taichi_bearing passages CASE.yaml --runs N [--spread-deg 0.5]`.

Runs the case N times with ``run.first_roller_angle_deg`` spread evenly over
``+- spread / 2`` around the case's value: slightly different starting angles give
independent samples of the chaotic exit. Every passage's signature comes from the runs'
summaries into ``passages.csv`` (one row per passage), and ``passages_report.md`` /
``.html`` give the median and interquartile range of each quantity, with a figure. The
runs go to the sweep's process pool or Dask cluster (the same cell engine). Exit status:
0 every run finished with at least one passage, 1 a run failed or no passage was
recorded, 2 bad input.
"""

from __future__ import annotations

import argparse
import math

from taichi_bearing.commands.common import add_case_arguments
from taichi_bearing.commands.sweep import (
    add_pool_arguments,
    command_text,
    report_failures,
    run_study,
    study_folder,
)
from taichi_bearing.errors import InputError


def add_spread_arguments(parser: argparse.ArgumentParser, runs_option: str) -> None:
    """``--spread-deg``: how far apart the starting angles of a study's runs lie."""
    parser.add_argument(
        "--spread-deg",
        type=float,
        default=0.5,
        metavar="DEG",
        help=f"the {runs_option} runs start roller 0 at angles spread evenly over the "
        "case's run.first_roller_angle_deg +- DEG/2 (default 0.5)",
    )


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument("--runs", type=int, required=True, metavar="N",
                        help="runs of the case, each from its own starting angle")  # fmt: skip
    add_spread_arguments(parser, "N")
    add_pool_arguments(parser)


def angle_axis(args: argparse.Namespace, runs: int, option: str):
    """The starting angles of ``runs`` runs around the case's (after ``--set``) as an
    axis of the study's grid.

    Raises
    ------
    InputError
        ``runs < 1`` (naming ``option``) or a negative or non-finite ``--spread-deg``.
    """
    from taichi_bearing.case import load_case
    from taichi_bearing.studies.passage_study import ANGLE_KEY, spread_angles
    from taichi_bearing.studies.sweep import Axis

    if runs < 1:
        raise InputError(f"{option}: must be >= 1, got {runs}")
    if not (math.isfinite(args.spread_deg) and args.spread_deg >= 0):
        raise InputError(f"--spread-deg: must be a number >= 0, got {args.spread_deg}")
    centre = math.degrees(load_case(args.case, args.overrides).run.first_roller_angle)
    angles = spread_angles(round(centre, 9), args.spread_deg, runs)
    return Axis(ANGLE_KEY, tuple(angles), f"--spread-deg {args.spread_deg:g}")


def main(args: argparse.Namespace) -> int:
    axis = angle_axis(args, args.runs, "--runs")
    out = study_folder(args, "passages")
    _, results = run_study(args, [axis], out)

    from taichi_bearing.studies.passage_study import collect
    from taichi_bearing.studies.passages_report import write_passages_outputs
    from taichi_bearing.studies.report import how_made_blocks
    from taichi_bearing.studies.sweep import column_labels

    angle = column_labels([axis.key])[axis.key]
    passages, runs = collect(results, column_labels([axis.key]))
    command = command_text("passages", args, ["--runs", str(args.runs), "--spread-deg",
                                              f"{args.spread_deg:g}"])  # fmt: skip
    values = ", ".join(f"{a:g}" for a in axis.values)
    intro = (
        f"{args.runs} runs of `{args.case}` with {axis.key} = {values} deg (spread "
        f"{args.spread_deg:g} deg around the case's value)."
    )
    paths = write_passages_outputs(
        passages, runs, out, title=f"Passage statistics: {args.case}", intro=intro,
        angle=angle, results=results, how=how_made_blocks(command, args.case, args.overrides),
    )  # fmt: skip
    failed = report_failures(results)
    print(f"{len(results)} runs ({len(failed)} failed), {len(passages)} passages; "
          f"{paths['passages']}, {paths['report']}")  # fmt: skip
    return 1 if failed or passages.empty else 0
