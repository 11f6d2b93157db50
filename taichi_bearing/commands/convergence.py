"""`python -m taichi_bearing convergence CASE.yaml --vary KEY=L1,L2,L3,... [--passages N]`.

Runs the case at every level of one key (at least three, coarse to fine: e.g.
``mesh.surface_size_mm=1,0.5,0.25,0.125`` or ``contact.penalty_scale=0.03,0.1,0.3,1``;
keys joined by ``+`` take each level together, e.g. the locally refined mesh's
``mesh.spall_size_mm+mesh.roller_surface_size_mm=0.5,0.25,0.125``),
each level N times from starting angles spread over ``--spread-deg`` (N passages of a
single-passage case, as ``passages`` does), on the sweep's pool or Dask cluster. For every
quantity of :data:`taichi_bearing.studies.passage_study.QUANTITIES` it reports the value per level
(dynamic ones as the median and interquartile range over the level's passages), the
relative change between successive levels, the observed order and Richardson's estimate
where the order is meaningful (:mod:`taichi_bearing.studies.convergence`), with figures and
``convergence_report.md`` / ``.html`` led by the verdict. Exit status: 0 every run
finished, 1 some failed (each reported), 2 bad input.
"""

from __future__ import annotations

import argparse

from taichi_bearing.commands.common import add_case_arguments
from taichi_bearing.commands.passages import add_spread_arguments, angle_axis
from taichi_bearing.commands.sweep import (
    add_pool_arguments,
    command_text,
    report_failures,
    run_study,
    study_folder,
)
from taichi_bearing.errors import InputError

# keys whose refinement goes one known way: levels given the other way are refused
REFINES = {
    "mesh.surface_size_mm": "decrease",
    "mesh.max_size_mm": "decrease",
    "mesh.spall_size_mm": "decrease",
    "mesh.roller_surface_size_mm": "decrease",
    "contact.penalty_scale": "increase",
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument("--vary", required=True, metavar="KEY=L1,L2,L3,...",
                        help="one case key (or several joined by +, set together) and at "
                        "least three levels, coarse to fine, e.g. "
                        "mesh.surface_size_mm=1,0.5,0.25,0.125, "
                        "mesh.spall_size_mm+mesh.roller_surface_size_mm=0.5,0.25,0.125 or "
                        "contact.penalty_scale=0.03,0.1,0.3,1")  # fmt: skip
    parser.add_argument("--passages", type=int, default=1, metavar="N",
                        help="runs per level, each from its own starting angle (N "
                        "passages of a single-passage case; default 1)")  # fmt: skip
    add_spread_arguments(parser, "N")
    add_pool_arguments(parser)


def level_axis(text: str):
    """The ``--vary`` axis and its levels as floats: at least three positive numbers
    going one way, the way a known key refines.

    Raises
    ------
    InputError
        Naming the ``--vary`` argument.
    """
    from taichi_bearing.studies.convergence import spacings
    from taichi_bearing.studies.sweep import numeric_axis, parse_vary

    axis = parse_vary(text)
    levels = numeric_axis(axis, minimum=3)
    try:
        spacings(levels)
    except ValueError as exc:
        raise InputError(f"{axis.option}: {exc}") from None
    way = "decrease" if levels[-1] < levels[0] else "increase"
    for key in axis.keys:
        if REFINES.get(key, way) != way:
            raise InputError(f"{axis.option}: give the levels coarse to fine: {key} must "
                             f"{REFINES[key]}")  # fmt: skip
    return axis, levels


def main(args: argparse.Namespace) -> int:
    axis, levels = level_axis(args.vary)
    axes = [axis]
    if args.passages != 1:
        axes.append(angle_axis(args, args.passages, "--passages"))
    out = study_folder(args, "convergence")
    _, results = run_study(args, axes, out)

    from taichi_bearing.studies.convergence_report import write_convergence_outputs
    from taichi_bearing.studies.passage_study import collect
    from taichi_bearing.studies.report import how_made_blocks
    from taichi_bearing.studies.sweep import column_labels

    labels = column_labels(a.key for a in axes)
    passages, runs = collect(results, labels)
    options = ["--vary", args.vary, "--passages", str(args.passages)]
    if args.passages > 1:
        options += ["--spread-deg", f"{args.spread_deg:g}"]
    starts = (
        f" from starting angles {', '.join(f'{a:g}' for a in axes[1].values)} deg"
        if len(axes) > 1
        else ""
    )
    intro = (
        f"{len(levels)} levels of {axis.key} of `{args.case}`, {args.passages} run(s) per "
        f"level{starts}: {len(passages)} passages from "
        f"{int((runs['status'] == 'finished').sum())} finished runs."
    )
    paths = write_convergence_outputs(
        passages, runs, out, key=axis.key, column=labels[axis.key], levels=levels,
        intro=intro, results=results,
        how=how_made_blocks(command_text("convergence", args, options), args.case,
                            args.overrides),
    )  # fmt: skip
    failed = report_failures(results)
    print(f"{len(results)} runs ({len(failed)} failed), {len(passages)} passages; "
          f"{paths['report']}")  # fmt: skip
    return 1 if failed else 0
