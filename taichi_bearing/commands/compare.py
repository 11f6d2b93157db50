"""`python -m taichi_bearing compare RUN_DIR MEASURED_FILE... [--fs HZ] [--rpm RPM]
[--bearing n=..,d=..,D=..] [--out DIR]`: a simulated run against measured records.

The run folder is read here (:func:`taichi_bearing.output.run_folder.load_run`: the analysed
sensor acceleration, its sampling rate, shaft speed, BPFO and re-stressing times; a run
that did not finish gives what it recorded); the measured records are read and everything
is analysed and drawn by :func:`diagnostics.app.compare.compare_records`, which takes arrays
only. Writes the four comparison figures and ``summary.json`` into ``--out`` (default
``RUN_DIR/compare``).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from taichi_bearing.commands.common import check_empty, output_folder
from taichi_bearing.errors import InputError

RESTRESS_LABEL = "re-stressing (exit), from the run"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "run_dir",
        metavar="RUN_DIR",
        help="run folder of python -m taichi_bearing run (finished or not)",
    )
    parser.add_argument(
        "measured",
        metavar="MEASURED_FILE",
        nargs="+",
        type=Path,
        help="measured vibration record(s) (csv, txt, wav, mat, ...)",
    )
    parser.add_argument("--fs", type=float, help="sampling rate of the measured records, Hz")
    parser.add_argument(
        "--rpm", type=float, help="shaft speed of the measured records (default: from the file)"
    )
    parser.add_argument(
        "--bearing",
        help="measured bearing: n=ROLLERS,d=ROLLER_DIAMETER,D=PITCH_DIAMETER[,angle=DEG] "
        "(default: the simulated bearing, from the run's case.yaml)",
    )
    parser.add_argument("--channel", help="column, variable or key of the measured records")
    parser.add_argument(
        "--sensor",
        help="sensor of the run (its radial acceleration) or a history column "
        "(default: the signal the run's checks analysed)",
    )
    parser.add_argument("--out", metavar="DIR", help="output folder (default: RUN_DIR/compare)")


def _positive(value: float | None, option: str, what: str) -> None:
    if value is not None and not (math.isfinite(value) and value > 0):
        raise InputError(f"{option} must be a positive {what}, got {value:g}")


def _run_case(run_dir: Path):
    """The run's ``case.yaml`` as a Case; None when it cannot be read."""
    from taichi_bearing.case import load_case
    from taichi_bearing.output.layout import CASE_FILE

    try:
        return load_case(run_dir / CASE_FILE)
    except (InputError, OSError, ValueError):
        return None


def simulated_record(run_dir: Path, sensor: str | None = None):
    """The run folder and its sensor acceleration as a :class:`diagnostics.app.compare.Record`,
    with the run's re-stressing times (from its first history row) as the events.

    Shaft speed and BPFO come from ``summary.json`` or, for a run killed before its checks
    wrote them, from its ``case.yaml``.
    """
    import numpy as np

    from diagnostics.app.compare import Record
    from taichi_bearing.analytic.bearing import fault_frequencies
    from taichi_bearing.output.run_folder import acceleration_signal, load_run

    run = load_run(run_dir)
    case = _run_case(run_dir)
    if "bpfo_hz" in run.summary and "shaft_hz" in run.summary:
        shaft_hz, bpfo_hz = run.shaft_hz, run.bpfo_hz
    elif case is not None:
        shaft_hz = case.operating.shaft_hz
        bpfo_hz = fault_frequencies(case.bearing, shaft_hz).bpfo
    else:
        raise ValueError(f"{run_dir}: neither summary.json nor case.yaml gives BPFO")
    signal = acceleration_signal(run, sensor)
    exits = np.array([e["exit_time_s"] for e in run.events], dtype=float)
    name = signal.column or signal.label
    record = Record(
        label=f"simulated: {run.case_name} ({name})",
        source="simulated",
        x=signal.x,
        fs=run.fs,
        shaft_hz=shaft_hz,
        bpfo_hz=bpfo_hz,
        unit="m/s^2",
        frequencies=None if case is None else fault_frequencies(case.bearing, shaft_hz),
        events_s=exits[np.isfinite(exits)] - run.t0,
        events_label=RESTRESS_LABEL,
        meta={"run_dir": str(run_dir), "column": name},
    )
    return run, case, record


def main(args: argparse.Namespace) -> int:
    from diagnostics.app.cli import UsageError, parse_bearing
    from diagnostics.app.compare import compare_records, measured_record, summary_lines
    from taichi_bearing.output.layout import COMPARE_DIR

    _positive(args.fs, "--fs", "frequency in Hz")
    _positive(args.rpm, "--rpm", "speed")
    run_dir = check_empty(args.run_dir, "RUN_DIR")
    if not run_dir.is_dir():
        raise InputError(f"{run_dir}: not a folder (give a simulated run folder)")
    out = run_dir / COMPARE_DIR if args.out is None else check_empty(args.out, "--out")
    try:
        run, case, sim = simulated_record(run_dir, args.sensor)
        if args.bearing:
            geometry = parse_bearing(args.bearing)
        else:
            geometry = None if case is None else case.bearing.geometry
        if geometry is None:
            raise InputError(
                f"{run_dir}: no bearing geometry in case.yaml; give --bearing for the "
                "measured records"
            )
        records = [sim] + [
            measured_record(path, geometry, rpm=args.rpm, fs=args.fs, channel=args.channel)
            for path in args.measured
        ]
        output_folder(out, "--out")  # once every record has been read
        summary = compare_records(records, out)
    except (UsageError, ValueError, OSError) as exc:
        raise InputError(" ".join(str(exc).split())) from None
    if run.partial:
        print(
            f"note: the run did not finish (status {run.status}); compared on the "
            f"{1e3 * (run.t_end - run.t0):.4g} ms recorded",
            file=sys.stderr,
        )
    print("\n".join(summary_lines(summary)))
    print(f"wrote {len(summary['figures']) + 1} files to {out}")
    return 0
