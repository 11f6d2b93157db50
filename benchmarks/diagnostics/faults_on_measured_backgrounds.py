"""Faults added to measured channels of healthy bearings: how often each fault is named, and
another fault named, over the backgrounds of a real test rig.

Synthetic scenarios start from white noise and shaft harmonics; a measured channel also
holds the rig's own lines (electrical, the other bearing's fault, structural) at strengths
no scenario guesses. Here the backgrounds are measured: in every CWRU record below the
folders given (``diagnostics.app.benchmark.find_records``), each channel that holds a healthy
bearing, read with that bearing's geometry and the record's speed: the fan-end channel of
a drive-end fault record (left out where it copies the drive-end channel), the drive-end
channel of a fan-end fault record, and both channels of a baseline record. A 48 kHz channel
is first decimated to 12 kHz (``--rate``; the fan-end fault records are 12 kHz). Each
background is diagnosed as it is (the right verdict: ``none``) and with a fault of each
type added (``--draws`` draws a size, seeded by the record's name): impacts at the fault
frequency less 0-1 % of slip, jittered by 0.5 %, modulated as in
``benchmarks/diagnostics/other_source_scenarios.py`` (inner race once a turn, ball once a
cage turn),
ringing a resonance at 0.1-0.3 of the sampling rate, the impact ``--sizes`` times the
channel's standard deviation. It prints each background's misses and one table per end
of the bearing: the fault named, and another fault named, per size and type. Usage::

    python benchmarks/diagnostics/faults_on_measured_backgrounds.py DIR [DIR ...]
        [--sizes 0.15 0.25 0.5 1] [--draws 2] [--rate 12000]
"""

from __future__ import annotations

import argparse
import sys
import zlib
from pathlib import Path

import numpy as np
from scipy import signal

ROOT = Path(__file__).resolve().parents[2]
if __name__ == "__main__":  # run as a script: the repository's packages by name
    sys.path.insert(0, str(ROOT))

from benchmarks.diagnostics.other_source_scenarios import FAULTS, fault_impacts  # noqa: E402
from diagnostics import bearing_frequencies, diagnose  # noqa: E402
from diagnostics.app.benchmark import _copies, find_records  # noqa: E402
from diagnostics.app.datasets import label_from_name, read_labelled_record  # noqa: E402

OTHER_END = {"drive": "fan", "fan": "drive"}


def backgrounds(folders, rate: float):
    """``(name, end, fs, geometry, shaft Hz, x)`` of every healthy bearing's channel."""
    for path in (p for folder in folders for p in find_records(folder)):
        label = label_from_name(path)
        if label is None or label.source != "CWRU":
            continue
        own = read_labelled_record(path, label)
        ends = ["drive", "fan"] if label.fault == "none" else [OTHER_END[label.end]]
        for end in ends:
            rec = own if end == label.end else read_labelled_record(path, label, end=end)
            if end != label.end and _copies(rec.x, own.x):
                continue  # the faulty end's signal under the other end's name
            x, fs = rec.x, rec.fs
            q = int(round(fs / rate)) if rate > 0 else 1
            if q > 1:
                x, fs = signal.decimate(x, q, ftype="fir", zero_phase=True), fs / q
            yield f"{path.name}:{end}", end, fs, rec.geometry, rec.shaft_hz, x


def run(folders, sizes, draws: int, rate: float):
    """Verdicts: a list of ``(name, end, fault added, size, verdict)``."""
    rows = []
    for name, end, fs, geometry, shaft, x in backgrounds(folders, rate):
        rows.append((name, end, "none", 0.0, diagnose(x, fs, geometry, shaft).fault))
        own = bearing_frequencies(geometry, shaft)
        scale = float(np.std(x))
        for fault in FAULTS:
            for size in sizes:
                for draw in range(draws):
                    rng = np.random.default_rng([zlib.crc32(name.encode()), draw])
                    added = x + fault_impacts(rng, fs, x.size, own, fault, size * scale)
                    verdict = diagnose(added, fs, geometry, shaft).fault
                    rows.append((name, end, fault, size, verdict))
    return rows


def tables(rows, sizes) -> list[str]:
    """Per end: the fault named (another fault named) per size and type, and the healthy
    backgrounds' verdicts."""
    out = []
    for end in ("drive", "fan"):
        mine = [r for r in rows if r[1] == end]
        if not mine:
            continue
        healthy = [r for r in mine if r[2] == "none"]
        out += [
            "",
            f"{end}-end bearing, {len(healthy)} backgrounds: "
            f"{sum(r[4] == 'none' for r in healthy)} read none as measured",
            "| impact / channel std | " + " | ".join(FAULTS) + " |",
            "|---|" + "---:|" * len(FAULTS),
        ]
        for size in sizes:
            cells = []
            for fault in FAULTS:
                got = [r[4] for r in mine if r[2] == fault and r[3] == size]
                named = sum(v == fault for v in got)
                wrong = sum(v not in (fault, "none") for v in got)
                cells.append(f"{named} of {len(got)} ({wrong})")
            out.append(f"| {size:g} | " + " | ".join(cells) + " |")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folders", nargs="+", help="folders holding CWRU records")
    ap.add_argument("--sizes", type=float, nargs="+", default=[0.15, 0.25, 0.5, 1.0])
    ap.add_argument("--draws", type=int, default=2, help="draws per fault type and size")
    ap.add_argument("--rate", type=float, default=12000.0, help="decimate to this rate (0: not)")
    args = ap.parse_args(argv)
    rows = run(args.folders, args.sizes, args.draws, args.rate)
    if not rows:
        print("no CWRU record found", file=sys.stderr)
        return 2
    for name in dict.fromkeys(r[0] for r in rows):
        mine = [r for r in rows if r[0] == name]
        wrong = [f"{r[2]} x{r[3]:g} called {r[4]}" for r in mine if r[4] != r[2]]
        if wrong:
            print(f"{name}: {len(wrong)} of {len(mine)} missed ({', '.join(wrong)})")
    print("\n".join(tables(rows, args.sizes)))
    print("\n(in brackets: another fault named)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
