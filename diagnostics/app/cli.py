"""Command line of ``diagnostics``: ``python -m diagnostics analyze|benchmark|compare ...``
(the ``bearing-diagnostics`` script).

Each subcommand is a pair ``add_<name>_arguments(parser)`` / ``run_<name>(args) -> int``
registered in ``COMMANDS``: ``analyze`` (one record, :mod:`diagnostics.app.analyze`),
``benchmark`` (a folder of public records, :mod:`diagnostics.app.benchmark`); ``compare``
only points to ``python -m taichi_bearing compare``, which reads a simulated run folder and
calls :mod:`diagnostics.app.compare`. Bad input is reported as one line on stderr with exit
status 2, never a traceback. Building the parsers imports neither scipy nor matplotlib.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from bearing_io.files import atomic_path, output_folder
from bearing_io.progress import LOG_INTERVAL_S, RecordProgress
from diagnostics.app._options import UsageError, parse_bearing
from diagnostics.app.analyze import add_analyze_arguments, run_analyze

__all__ = ["main", "build_parser", "parse_bearing", "UsageError"]


class _Parser(argparse.ArgumentParser):
    # argparse prints the whole usage block on an error; one line is enough.
    def error(self, message: str):  # noqa: D401 - argparse API
        raise UsageError(f"{self.prog}: {message}")


# The comparison of a simulated run folder moved to the simulator's command line; the
# comparison itself (arrays in, figures out) stays in diagnostics.app.compare.
COMPARE_MOVED = (
    "compare moved to the simulator: python -m taichi_bearing compare RUN_DIR MEASURED_FILE "
    "[--fs HZ] [--rpm RPM] [--bearing ...] [--out DIR]"
)


def add_compare_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("args", nargs=argparse.REMAINDER, help=argparse.SUPPRESS)


def run_compare(args: argparse.Namespace) -> int:
    raise UsageError(COMPARE_MOVED)


def add_benchmark_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "folders",
        metavar="DIR",
        nargs="+",
        type=Path,
        help="folder(s) of CWRU or MFPT .mat records, named as the public sets name them",
    )
    parser.add_argument(
        "--records", action="store_true", help="also print one line per record as it is done"
    )
    parser.add_argument("--csv", type=Path, help="write every record's verdict to this CSV file")
    parser.add_argument(
        "--html",
        type=Path,
        metavar="FILE",
        help="write the table, one row per record, as a self-contained HTML page",
    )
    parser.add_argument(
        "--other-bearing",
        action="store_true",
        help="false-alarm check: read each CWRU record's other accelerometer with the other "
        "end's (healthy) bearing; every right verdict is none",
    )
    parser.add_argument(
        "--quiet", action="store_true", help="no progress bar or progress lines on stderr"
    )
    parser.add_argument(
        "--progress-interval",
        type=float,
        default=LOG_INTERVAL_S,
        metavar="S",
        help="seconds between progress lines when stderr is not a terminal (a log, a pipe; "
        f"default {LOG_INTERVAL_S:g}); on a terminal a bar",
    )


def run_benchmark(args: argparse.Namespace) -> int:
    from diagnostics.app import benchmark  # scipy: when the command runs, not for --help

    paths = [p for folder in args.folders for p in benchmark.find_records(folder)]
    if not paths:
        raise UsageError(
            f"{', '.join(map(str, args.folders))}: no CWRU or MFPT record found (.mat files "
            "named e.g. 12k_Drive_End_IR007_0_105.mat, normal_0_97.mat, "
            "InnerRaceFault_vload_1.mat)"
        )

    # The output files are checked before the records are read, not after.
    _check_output_file(args.csv, "--csv", "verdicts.csv")
    _check_output_file(args.html, "--html", "verdicts.html")
    if not math.isfinite(args.progress_interval) or args.progress_interval < 0:
        raise UsageError(f"--progress-interval {args.progress_interval:g}: give seconds, 0 or more")
    # With --records each record's line is the progress.
    progress = RecordProgress(
        len(benchmark.labelled_records(paths, args.other_bearing)),
        log_every_s=args.progress_interval,
        enabled=not (args.quiet or args.records),
    )

    def show(r: benchmark.BenchmarkResult) -> None:
        progress.update(r.path.name)
        if args.records:
            mark = "ok" if r.correct else "MISS"
            print(
                f"{r.path.name}: {r.expected} -> {r.verdict} ({r.confidence:.2f}) {mark} {r.detail}"
            )

    try:
        results = benchmark.run_benchmark(paths, progress=show, other_bearing=args.other_bearing)
    finally:
        progress.close()
    if not results:
        raise UsageError(
            f"{', '.join(map(str, args.folders))}: no CWRU record for --other-bearing (MFPT "
            "records have one bearing)"
        )
    if args.records:
        print()
    speeds = benchmark.speed_summary(results)
    if speeds:
        print(speeds + "\n")
    table = benchmark.summary_table(results)
    print(table)
    rows = benchmark.record_rows(results)
    if args.csv is not None:
        import pandas as pd

        with atomic_path(args.csv) as tmp:
            pd.DataFrame(rows).to_csv(tmp, index=False)
        print(f"wrote {args.csv}")
    if args.html is not None:
        from diagnostics.app.report import write_benchmark_html

        title = f"Benchmark: {', '.join(map(str, args.folders))}"
        write_benchmark_html(args.html, rows, table, title)
        print(f"wrote {args.html}")
    return 0


def _check_output_file(path: Path | None, option: str, example: str) -> None:
    """Refuse an output file that cannot be written (an empty name, a folder, a parent
    that cannot be made or written in), in one line naming ``option``."""
    if path is None:
        return
    if not str(path).strip() or path.is_dir():
        raise UsageError(f"{option} {str(path)!r}: give a file name, e.g. {example}")
    output_folder(path.parent, option)


COMMANDS = {
    "analyze": (
        "diagnose one vibration record: figures, summary.json, report.html and a verdict",
        add_analyze_arguments,
        run_analyze,
    ),
    "compare": (
        "moved: use python -m taichi_bearing compare RUN_DIR MEASURED_FILE ...",
        add_compare_arguments,
        run_compare,
    ),
    "benchmark": (
        "diagnose every CWRU or MFPT record in a folder and tabulate the verdicts",
        add_benchmark_arguments,
        run_benchmark,
    ),
}


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="python -m diagnostics",
        description="Bearing vibration diagnostics on measured or simulated records.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, (help_text, add_arguments, _) in COMMANDS.items():
        add_arguments(sub.add_parser(name, help=help_text, description=help_text))
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help(sys.stderr)
            return 2
        return int(COMMANDS[args.command][2](args) or 0)
    except (UsageError, ValueError, OSError) as exc:
        message = " ".join(str(exc).split())  # one line, whatever the message held
        print(f"error: {message}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
