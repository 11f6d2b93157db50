"""Diagnosis beside impacts at random times, and of weak faults alone: how often a fault is
named, and a healthy bearing still healthy, when the band is chosen by the infogram (the
default) and by the kurtogram, side by side on the same records.

Smith and Randall (2015) saw the kurtogram misled on CWRU records by impulses that had
nothing to do with the fault: a few strong impacts at random times (a knock, a loose part,
electrical spikes) are more impulsive than a fault's train, so the kurtogram takes their
band, where the envelope spectrum holds no fault lines. Each scenario draws the bearing
(CWRU drive end or fan end), a sampling rate (12 or 48 kHz), 2-8 s of record at a shaft
rate of 25-30 Hz, unit noise and six shaft harmonics; odd scenarios add an outer-race,
inner-race or ball fault (impacts 1.5-3 times the noise ringing a resonance at 0.1-0.3 of
the sampling rate, jittered by 0.5 %, modulated as in
``benchmarks/diagnostics/other_source_scenarios.py``). Every scenario adds impacts at Poisson times,
2-30 a second, each 3-20 times a fault impact (log-normal scatter), ringing at 0.5-1.8
times the fault's resonance.

A second table gives weak faults with no other source (``--weak`` records per size, the
same draws at each size): an outer-race, inner-race or ball fault whose impacts are 0.6 to
1.3 times the noise's standard deviation, 3-8 s, 12 or 48 kHz, either bearing; a third
the same per fault type. Usage::

    python benchmarks/diagnostics/aperiodic_impulse_scenarios.py [--scenarios 60] [--seed 0]
        [--weak 24]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if __name__ == "__main__":  # run as a script: the repository's packages by name
    sys.path.insert(0, str(ROOT))

from benchmarks.diagnostics.other_source_scenarios import (  # noqa: E402
    BEARINGS,
    FAULTS,
    base_record,
    fault_impacts,
    rings,
)
from diagnostics import bearing_frequencies, diagnose  # noqa: E402

SELECTORS = ("kurtogram", "infogram")


def random_impacts(rng, fs: float, n: int, per_second: float, resonance: float, size: float):
    """Impacts at Poisson times, each ``size`` times a log-normal factor (median 1)."""
    seconds = n / fs
    times = np.sort(rng.uniform(0.0, seconds - 0.01, rng.poisson(per_second * seconds)))
    return rings(fs, n, times, resonance, size * rng.lognormal(0.0, 0.5, times.size))


def scenario(seed: int) -> tuple[str, str, float, object, float, np.ndarray]:
    """One record: (fault, text, fs, geometry, shaft Hz, x)."""
    rng = np.random.default_rng(10_000 + seed)
    end = str(rng.choice(list(BEARINGS)))
    geometry = BEARINGS[end][0]
    fs = float(rng.choice([12000.0, 48000.0]))
    shaft = float(rng.uniform(25.0, 30.0))
    n = int(rng.uniform(2.0, 8.0) * fs)
    own = bearing_frequencies(geometry, shaft)
    fault = str(rng.choice(FAULTS)) if seed % 2 else "none"
    x = base_record(rng, fs, n, shaft)
    strength = float(rng.uniform(1.5, 3.0))
    resonance = float(rng.uniform(0.1, 0.3)) * fs
    if fault != "none":
        x += fault_impacts(rng, fs, n, own, fault, strength, resonance)
    per_second = float(math.exp(rng.uniform(math.log(2.0), math.log(30.0))))
    size = float(rng.uniform(3.0, 20.0))
    # The random impacts ring elsewhere than the fault (below it where above would fold).
    factor = float(rng.choice([0.5, 0.6, 1.5, 1.8])) if 0.45 * fs > 1.8 * resonance else 0.5
    x += random_impacts(rng, fs, n, per_second, factor * resonance, size * strength)
    text = (
        f"{end}, fs {fs / 1000:g} kHz, {n / fs:.1f} s, {per_second:.1f} random impacts/s "
        f"x{size:.1f} at {factor:g} x the fault's resonance"
    )
    return fault, text, fs, geometry, shaft, x


WEAK_SIZES = (0.6, 0.8, 1.0, 1.3)


def weak_scenario(seed: int, size: float) -> tuple[str, float, object, float, np.ndarray]:
    """A fault alone, impacts ``size`` times the noise: (fault, fs, geometry, shaft Hz, x)."""
    rng = np.random.default_rng(777 + seed)
    geometry = BEARINGS[("drive end", "fan end")[seed % 2]][0]
    fs = (12000.0, 48000.0)[(seed // 2) % 2]
    shaft = float(rng.uniform(25.0, 30.0))
    n = int(rng.uniform(3.0, 8.0) * fs)
    own = bearing_frequencies(geometry, shaft)
    fault = FAULTS[(seed // 4) % 3]
    x = base_record(rng, fs, n, shaft) + fault_impacts(rng, fs, n, own, fault, size)
    return fault, fs, geometry, shaft, x


def weak_table(records: int) -> list[str]:
    """Faults named (and other faults named) per impact size and selector, then the faults
    named per fault type."""
    table = [
        f"| impacts / noise ({records} faults each) | kurtogram: named (wrong) | "
        "infogram: named (wrong) |",
        "|---|---:|---:|",
    ]
    by_fault = [
        "| impacts / noise | band chosen by | " + " | ".join(FAULTS) + " |",
        "|---|---|" + "---:|" * len(FAULTS),
    ]
    for size in WEAK_SIZES:
        cells = []
        for sel in SELECTORS:
            verdicts = []
            for seed in range(records):
                fault, fs, geometry, shaft, x = weak_scenario(seed, size)
                verdicts.append((fault, diagnose(x, fs, geometry, shaft, band_selector=sel).fault))
            named = sum(v == f for f, v in verdicts)
            wrong = sum(v not in (f, "none") for f, v in verdicts)
            cells.append(f"{named} ({wrong})")
            counts = [
                f"{sum(v == f for f, v in verdicts if f == fault)} of "
                f"{sum(f == fault for f, _ in verdicts)}"
                for fault in FAULTS
            ]
            by_fault.append(f"| {size:g} | {sel} | " + " | ".join(counts) + " |")
        table.append(f"| {size:g} | {cells[0]} | {cells[1]} |")
    return table + ["", "by fault type"] + by_fault


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenarios", type=int, default=60, help="records, half of them healthy")
    ap.add_argument("--seed", type=int, default=0, help="first scenario's seed")
    ap.add_argument("--weak", type=int, default=24, help="weak faults per size (0: none)")
    args = ap.parse_args(argv)
    if args.scenarios < 1:
        ap.error("--scenarios must be at least 1")
    if args.weak < 0:
        ap.error("--weak must be 0 or more")
    right = {(sel, kind): 0 for sel in SELECTORS for kind in ("healthy", "faulty")}
    count = {"healthy": 0, "faulty": 0}
    for seed in range(args.seed, args.seed + args.scenarios):
        fault, text, fs, geometry, shaft, x = scenario(seed)
        kind = "healthy" if fault == "none" else "faulty"
        count[kind] += 1
        verdicts = []
        for sel in SELECTORS:
            verdict = diagnose(x, fs, geometry, shaft, band_selector=sel).fault
            right[sel, kind] += verdict == fault
            verdicts.append(verdict)
        if any(v != fault for v in verdicts):
            print(f"scenario {seed}: {fault} called {' / '.join(verdicts)} ({text})")
    table = [
        f"| band chosen by | healthy: none ({count['healthy']}) | faulty: fault named "
        f"({count['faulty']}) |",
        "|---|---:|---:|",
    ] + [f"| {sel} | {right[sel, 'healthy']} | {right[sel, 'faulty']} |" for sel in SELECTORS]
    print("\n" + "\n".join(table))
    if args.weak:
        print("\nweak faults alone\n" + "\n".join(weak_table(args.weak)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
