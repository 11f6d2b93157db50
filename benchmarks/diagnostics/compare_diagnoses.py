"""Do two versions of ``diagnostics`` diagnose alike? Every field of every diagnosis, a
baseline revision's beside this checkout's, compared bit for bit.

A refactor of ``diagnose`` must leave its outputs unchanged to the last bit, as a refactor of
the solver must leave the histories (``benchmarks/compare_histories.py``). This script
checks out ``--baseline`` (default HEAD) in a temporary git worktree and, in a subprocess
whose ``diagnostics`` is that checkout's, diagnoses the same records as this checkout:

- every record below the folders given (CWRU and MFPT names), with both band selectors,
  and each CWRU record's other channel with the other end's bearing (``--other-bearing``),
- synthetic records drawn from the scenario scripts of this checkout: 12 beside another
  impact source (with and without ``use_drs``), 8 weak faults, 4 at a varying speed
  (diagnosed in orders).

Each diagnosis is reduced to plain data (every dataclass field, arrays as their bytes,
floats as their hex) and the two sets compared; it prints each diagnosis that differs and
the first field where it does, and exits with status 1 if any does. Where the verdict
itself moved (``fault``), the line says from what to what (``outer -> outer or ball``),
and a last line counts the verdicts moved: which diagnoses a change moved, not only
which numbers. Usage::

    python benchmarks/diagnostics/compare_diagnoses.py DIR [DIR ...] [--baseline REV]
    python benchmarks/diagnostics/compare_diagnoses.py --synthetic-only [--baseline REV]
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib
import os
import pickle
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def plain(obj):
    """``obj`` as plain, comparable data: dataclasses as (name, fields), arrays as (dtype,
    shape, bytes), floats as their hex."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        fields = {f.name: plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
        return (type(obj).__name__, fields)
    if isinstance(obj, dict):
        return {key: plain(value) for key, value in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [plain(value) for value in obj]
    if isinstance(obj, np.ndarray):
        return ("ndarray", obj.dtype.str, obj.shape, obj.tobytes())
    if isinstance(obj, (float, np.floating)):
        return float(obj).hex()
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def first_difference(a, b, where: str = "") -> str:
    """The path of the first field where ``a`` and ``b`` (from :func:`plain`) differ, e.g.
    ``.bands[0].families.BPFI.threshold`` ('' where they do not)."""
    if type(a) is not type(b):
        return where or "(type)"
    if isinstance(a, tuple) and len(a) == 2 and isinstance(a[1], dict):  # a dataclass
        return f"{where} ({a[0]})" if a[0] != b[0] else first_difference(a[1], b[1], where)
    if isinstance(a, dict):
        for key in sorted(a.keys() | b.keys(), key=str):
            if key not in a or key not in b:
                return f"{where}.{key}"
            found = first_difference(a[key], b[key], f"{where}.{key}")
            if found:
                return found
        return ""
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{where} (length)"
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            found = first_difference(x, y, f"{where}[{i}]")
            if found:
                return found
        return ""
    return "" if a == b else (where or "(value)")


def verdict(diagnosis) -> str:
    """The verdict (``fault``) of a diagnosis reduced by :func:`plain` ('?' where none)."""
    if isinstance(diagnosis, tuple) and len(diagnosis) == 2 and isinstance(diagnosis[1], dict):
        return str(diagnosis[1].get("fault", "?"))
    return "?"


def snapshot(folders: list[str], synthetic: bool) -> dict:
    """Every diagnosis this process's ``diagnostics`` gives, as plain data by a key."""
    # diagnostics first, the one on this process's PYTHONPATH; this checkout's folder goes
    # on the path only afterwards (for its scenario scripts), and the package imported stays.
    from diagnostics import diagnose

    benchmark, datasets = _app_modules()
    find_records, labelled_records = benchmark.find_records, benchmark.labelled_records
    read_labelled_record = datasets.read_labelled_record

    out = {}
    paths = [p for folder in folders for p in find_records(folder)]
    for other in (False, True):
        for path, label in labelled_records(paths, other):
            end = ("fan" if label.end == "drive" else "drive") if other else None
            rec = read_labelled_record(path, label, end=end)
            for selector in ("infogram", "kurtogram"):
                d = diagnose(rec.x, rec.fs, rec.geometry, rec.shaft_hz, band_selector=selector)
                out[(Path(path).name, "other end" if other else "", selector)] = plain(d)
    if synthetic:
        # This checkout's scenario scripts, after diagnostics: the one imported stays.
        sys.path.insert(0, str(ROOT))
        from benchmarks.diagnostics.aperiodic_impulse_scenarios import weak_scenario
        from benchmarks.diagnostics.other_source_scenarios import scenario
        from benchmarks.diagnostics.varying_speed_scenarios import GEOMETRY
        from benchmarks.diagnostics.varying_speed_scenarios import scenario as varying_scenario

        for seed in range(12):
            *_, fs, geometry, shaft, x = scenario(seed)
            for drs in (False, True):
                d = diagnose(x, fs, geometry, shaft, use_drs=drs)
                out[("other source", seed, "use_drs" if drs else "")] = plain(d)
        for seed in range(8):
            _, fs, geometry, shaft, x = weak_scenario(seed, 0.8)
            out[("weak fault", seed)] = plain(diagnose(x, fs, geometry, shaft))
        for seed in range(4):
            _, fs, rate, x, _ = varying_scenario(seed)
            out[("varying speed", seed)] = plain(diagnose(x, fs, GEOMETRY, rate))
    return out


def _app_modules():
    """``(benchmark, datasets)`` of this process's ``diagnostics``: in ``diagnostics.app``
    since issue 42, at the package's top level before. A baseline from before the move gets
    its modules registered under the new names too, for the scenario scripts of this
    checkout (which import ``diagnostics.app.datasets``)."""
    try:
        from diagnostics.app import benchmark, datasets
    except ModuleNotFoundError as exc:
        if exc.name != "diagnostics.app":
            raise
        import types

        benchmark = importlib.import_module("diagnostics.benchmark")
        datasets = importlib.import_module("diagnostics.datasets")
        app = types.ModuleType("diagnostics.app")
        app.benchmark, app.datasets = benchmark, datasets
        sys.modules.update(
            {
                "diagnostics.app": app,
                "diagnostics.app.benchmark": benchmark,
                "diagnostics.app.datasets": datasets,
            }
        )
    return benchmark, datasets


def run_snapshot(source: Path, folders: list[str], synthetic: bool, out: Path) -> None:
    """This script's snapshot with the ``diagnostics`` of checkout ``source``, into ``out``."""
    cmd = [sys.executable, str(Path(__file__).resolve()), *folders, "--snapshot", str(out)]
    if not synthetic:
        cmd.append("--no-synthetic")
    path = os.pathsep.join(p for p in (str(source), os.environ.get("PYTHONPATH")) if p)
    res = subprocess.run(cmd, cwd=source, env=dict(os.environ, PYTHONPATH=path), text=True)
    if res.returncode != 0:
        raise SystemExit(f"{source}: the snapshot failed (exit {res.returncode})")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folders", nargs="*", help="folders holding CWRU or MFPT records")
    ap.add_argument("--baseline", default="HEAD", help="git revision to compare with")
    ap.add_argument("--synthetic-only", action="store_true", help="no measured records")
    ap.add_argument("--no-synthetic", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--snapshot", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    synthetic = not args.no_synthetic
    if not args.folders and not args.synthetic_only and args.snapshot is None:
        ap.error("give folders of records, or --synthetic-only")
    for folder in args.folders:
        if not Path(folder).is_dir():
            ap.error(f"{folder}: no such folder")
    if args.snapshot is not None:
        args.snapshot.write_bytes(pickle.dumps(snapshot(args.folders, synthetic)))
        return 0
    folders = [str(Path(f).resolve()) for f in args.folders]
    # (only here: a snapshot's process must import the diagnostics its PYTHONPATH names)
    sys.path.insert(0, str(ROOT))
    from benchmarks.versions import worktree

    with (
        tempfile.TemporaryDirectory(prefix="compare_diagnoses_") as tmp,
        worktree(args.baseline) as base,
    ):
        files = {"baseline": Path(tmp) / "baseline.pkl", "this checkout": Path(tmp) / "now.pkl"}
        run_snapshot(base, folders, synthetic, files["baseline"])
        run_snapshot(ROOT, folders, synthetic, files["this checkout"])
        before, after = (pickle.loads(f.read_bytes()) for f in files.values())
    differ = verdicts = 0
    for key in sorted(before.keys() | after.keys(), key=str):
        if key not in before or key not in after:
            print(f"{key}: only in {'this checkout' if key in after else 'the baseline'}")
            differ += 1
            continue
        where = first_difference(before[key], after[key])
        if where:
            old, new = verdict(before[key]), verdict(after[key])
            moved = f"; verdict {old} -> {new}" if old != new else ""
            print(f"{key}: differs first at {where}{moved}")
            differ += 1
            verdicts += bool(moved)
    total = len(before.keys() | after.keys())
    print(f"{differ} of {total} diagnoses differ" if differ else f"{total} diagnoses identical")
    if differ:
        print(f"{verdicts} of {total} verdicts moved")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
