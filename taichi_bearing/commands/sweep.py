"""`python -m taichi_bearing sweep CASE.yaml --vary KEY=v1,v2,... [--vary KEY2=...]`.

Runs a grid of cases over any case keys (:mod:`taichi_bearing.studies.cells`;
``--load-kN 25,50,80 --speed-rpm 300,500,800`` are the shorthands of
``--vary operating.load_kN=...`` and ``--vary operating.speed_rpm=...``) on a local
process pool or, with ``--scheduler ADDRESS``, on a Dask distributed cluster; then writes
``sweep_summary.csv``, figures and ``sweep_report.md`` (a load x speed sweep also the
increase tables). Exit status: 0 all cells finished, 1 some failed (each reported, its
folder marked; the same command again runs only the cells not finished), 2 bad input.

The pool arguments and :func:`run_study` are shared by the ``passages`` and
``convergence`` commands: one cell engine for every study.
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from taichi_bearing.commands.common import add_case_arguments, check_empty, output_folder
from taichi_bearing.errors import InputError
from taichi_bearing.studies.ensemble_task import GPU_ENSEMBLE, parse_ensemble


def add_pool_arguments(parser: argparse.ArgumentParser) -> None:
    """``--workers``, ``--scheduler``, ``--threads``, ``--no-post``, ``--quiet``: how a
    study runs its cells."""
    parser.add_argument("--workers", type=int, default=None, metavar="N",
                        help="cases run at once on this machine, each in its own process "
                        "(default: all cores); each case gets max(1, cores // N) Taichi "
                        "threads")  # fmt: skip
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
        "--no-post",
        action="store_true",
        help="no per-run figures and report (the study's own outputs are made)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.add_argument(
        "--ensemble",
        type=str,
        default="auto",
        metavar="N",
        help="step the cases N at a time as one model (an ensemble: the same kernel "
        "launches for all, what keeps a GPU busy); only cases that share a mesh go "
        "together (they may differ in run.first_roller_angle_deg, operating.load_kN, "
        "operating.speed_rpm), so a study over meshes fills an ensemble per mesh; each "
        "run's folder and histories are those of the case run alone; auto (default): "
        f"each case on its own on the CPU, up to {GPU_ENSEMBLE} a model on a GPU",
    )


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...",
                        help="a case key and its values (read as YAML like --set), e.g. "
                        "--vary mesh.surface_size_mm=1,0.5; keys joined by + take each "
                        "value together; repeatable: a grid over every combination")  # fmt: skip
    parser.add_argument("--load-kN", dest="loads", default=None, metavar="L1,L2,...",
                        help="radial loads in kN, comma-separated: --vary "
                        "operating.load_kN=...")  # fmt: skip
    parser.add_argument("--speed-rpm", dest="speeds", default=None, metavar="S1,S2,...",
                        help="shaft speeds in rpm, comma-separated: --vary "
                        "operating.speed_rpm=...")  # fmt: skip
    add_pool_arguments(parser)
    parser.add_argument(
        "--fixed-duration",
        action="store_true",
        help="keep run.duration_ms at every speed (default: scale it by "
        "case speed / cell speed so every cell covers the same travel)",
    )


def check_pool_arguments(args: argparse.Namespace) -> None:
    """Refuse pool arguments that cannot be used (one line naming the option)."""
    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers: must be >= 1, got {args.workers}")
    if args.threads is not None and args.threads < 1:
        raise InputError(f"--threads: must be >= 1, got {args.threads}")
    if args.scheduler is not None and args.workers is not None:
        raise InputError("--workers: not used with --scheduler (the cluster has its workers)")
    args.ensemble = parse_ensemble(args.ensemble)


def study_folder(args: argparse.Namespace, prefix: str) -> Path:
    """``--out``, or ``runs/<prefix>_<case file stem>`` (not created here)."""
    if args.out is None:
        return Path("runs") / f"{prefix}_{Path(args.case).stem}"
    return check_empty(args.out, "--out")  # Path("") would resolve to here


def run_study(args: argparse.Namespace, axes: list, out: Path, *, scale_duration: bool = False):
    """Make the cells of ``axes`` (every case validated), create ``out``, run the cells
    not yet finished on the pool or cluster of ``args``; returns (cells, results).

    Nothing is written before every cell's case is known to be valid.
    """
    from taichi_bearing.studies.sweep import make_cells, run_sweep

    check_pool_arguments(args)
    cells = make_cells(args.case, axes, out, args.overrides, scale_duration=scale_duration,
                       threads=args.threads, post=not args.no_post)  # fmt: skip
    from taichi_bearing.studies.ensemble_task import group_cells

    group_cells(cells, args.ensemble)  # refuses an --ensemble that would group no two cells
    output_folder(out)  # once the cases are valid: a refused study makes no folder
    results = run_sweep(cells, workers=args.workers, scheduler=args.scheduler,
                        progress=not args.quiet, ensemble=args.ensemble)  # fmt: skip
    return cells, results


def command_text(name: str, args: argparse.Namespace, options: list[str]) -> str:
    """The command line of a study, for its report: the case, ``options``, the ``--set``
    overrides and ``--out`` (how it ran, pool or cluster, does not change the results)."""
    parts = [name, args.case, *options]
    for ov in args.overrides:
        parts += ["--set", ov]
    if args.out is not None:
        parts += ["--out", args.out]
    return "python -m taichi_bearing " + shlex.join(parts)


def report_failures(results) -> list:
    """Print each failed cell on stderr, then how to run them again; returns the failed
    results."""
    failed = [r for r in results if r.status != "finished"]
    for r in failed:
        print(f"failed: {r.name}: {r.error}", file=sys.stderr)
    if failed:
        print("the same command again runs the cells not finished (finished ones are kept)",
              file=sys.stderr)  # fmt: skip
    return failed


def _axes(args: argparse.Namespace) -> list:
    from taichi_bearing.studies.sweep import LOAD_KEY, SPEED_KEY, Axis, parse_values, parse_vary

    axes = []
    if args.loads is not None:
        axes.append(Axis(LOAD_KEY, tuple(parse_values(args.loads, "--load-kN")), "--load-kN"))
    if args.speeds is not None:
        values = tuple(parse_values(args.speeds, "--speed-rpm"))
        axes.append(Axis(SPEED_KEY, values, "--speed-rpm"))
    axes += [parse_vary(text) for text in args.vary]
    if not axes:
        raise InputError("--vary: nothing to vary (give --vary KEY=v1,v2,... or --load-kN "
                         "and --speed-rpm)")  # fmt: skip
    return axes


def main(args: argparse.Namespace) -> int:
    from taichi_bearing.studies.sweep import column_labels

    axes = _axes(args)
    out = study_folder(args, "sweep")
    _, results = run_study(args, axes, out, scale_duration=not args.fixed_duration)
    from taichi_bearing.studies.metrics import summary_rows
    from taichi_bearing.studies.report import how_made_blocks
    from taichi_bearing.studies.sweep_figures import write_sweep_outputs

    labels = list(column_labels(a.key for a in axes).values())
    options = [*(["--load-kN", args.loads] if args.loads is not None else []),
               *(["--speed-rpm", args.speeds] if args.speeds is not None else []),
               *(o for v in args.vary for o in ("--vary", v)),
               *(["--fixed-duration"] if args.fixed_duration else [])]  # fmt: skip
    how = how_made_blocks(command_text("sweep", args, options), args.case, args.overrides)
    paths = write_sweep_outputs(summary_rows(results), out, labels, how)
    failed = report_failures(results)
    ran = sum(r.ran for r in results)
    print(f"{len(results)} cases ({ran} run, {len(results) - ran} already finished, "
          f"{len(failed)} failed); {paths['summary']}, {paths['report']}")  # fmt: skip
    return 1 if failed else 0
