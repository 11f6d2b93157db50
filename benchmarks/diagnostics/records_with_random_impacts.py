"""Measured records with impacts at random times added: how often each record's labelled
fault is still named when the band is chosen by the infogram (the default) and by the
kurtogram, side by side on the same records.

Every CWRU or MFPT record below the folders given (``diagnostics.app.benchmark.find_records``;
the channel, speed and bearing its name implies) is diagnosed ``--draws`` times, each
time with impacts at Poisson times added (2-20 a second, each 5-15 times the record's
standard deviation with a log-normal scatter, ringing a resonance at 0.1-0.4 of the
sampling rate; ``benchmarks.diagnostics.aperiodic_impulse_scenarios.random_impacts``), the draws
seeded by the record's name. It prints the records whose verdict differs from the label
and one table: labelled fault named, and another fault named, per selector. Usage::

    python benchmarks/diagnostics/records_with_random_impacts.py DIR [DIR ...] [--draws 2]
"""

from __future__ import annotations

import argparse
import sys
import zlib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if __name__ == "__main__":  # run as a script: the repository's packages by name
    sys.path.insert(0, str(ROOT))

from benchmarks.diagnostics.aperiodic_impulse_scenarios import SELECTORS, random_impacts  # noqa: E402
from diagnostics import diagnose  # noqa: E402
from diagnostics.app.benchmark import find_records, label_from_name, read_labelled_record  # noqa: E402


def with_random_impacts(x: np.ndarray, fs: float, seed: int) -> np.ndarray:
    """``x`` with impacts at random times added (see the module notes)."""
    rng = np.random.default_rng(seed)
    size = rng.uniform(5.0, 15.0) * float(np.std(x))
    per_second, resonance = rng.uniform(2.0, 20.0), rng.uniform(0.1, 0.4) * fs
    return x + random_impacts(rng, fs, x.size, per_second, resonance, size)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folders", nargs="+", help="folders of CWRU or MFPT .mat records")
    ap.add_argument("--draws", type=int, default=2, help="random-impact draws per record")
    args = ap.parse_args(argv)
    if args.draws < 1:
        ap.error("--draws must be at least 1")
    paths = []
    for folder in args.folders:
        try:
            paths += [p for p in find_records(folder) if label_from_name(p) is not None]
        except ValueError as exc:
            ap.error(str(exc))
    if not paths:
        ap.error(f"no CWRU or MFPT records below {' '.join(args.folders)}")
    named = {sel: 0 for sel in SELECTORS}
    other = {sel: 0 for sel in SELECTORS}
    total = 0
    for path in paths:
        label = label_from_name(path)
        rec = read_labelled_record(path, label)
        for draw in range(args.draws):
            x = with_random_impacts(rec.x, rec.fs, zlib.crc32(path.name.encode()) + draw)
            verdicts = [
                diagnose(x, rec.fs, rec.geometry, rec.shaft_hz, band_selector=sel).fault
                for sel in SELECTORS
            ]
            total += 1
            for sel, verdict in zip(SELECTORS, verdicts, strict=True):
                named[sel] += verdict == label.fault
                other[sel] += verdict not in (label.fault, "none")
            if any(v != label.fault for v in verdicts):
                print(f"{path.name} draw {draw}: {label.fault} called {' / '.join(verdicts)}")
    table = [
        f"| band chosen by | labelled fault named ({total}) | another fault named |",
        "|---|---:|---:|",
    ] + [f"| {sel} | {named[sel]} | {other[sel]} |" for sel in SELECTORS]
    print("\n" + "\n".join(table))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
