"""Diagnosis beside another source of impacts: how often a healthy bearing is called faulty,
and how often a fault is still named, when the record also holds an impact train at a rate
that is no fault frequency of the bearing diagnosed.

Each scenario draws the bearing (CWRU drive end or fan end), a sampling rate (12 or 48 kHz),
2-8 s of record at a shaft rate of 25-30 Hz, unit noise, six shaft harmonics, and another
source: an impact train ringing its own resonance, its impacts jittered by 0.5 %, at

- ``other bearing``: the other CWRU bearing's BPFO or BPFI, modulated once a turn (a
  neighbouring bearing's fault),
- ``sub-multiple``: half or a third of one of this bearing's race fault frequencies, or
- ``random``: a rate drawn log-uniformly from 1.2 to 8 shaft orders, at least 3 % from every
  fault frequency of this bearing, its double and triple, BSF and the cage rate's first
  multiples,

at 1 to 4 times the strength of the fault's impacts. Half the scenarios are healthy, the
others hold an outer-race, inner-race or ball fault. Usage::

    python benchmarks/diagnostics/other_source_scenarios.py [--scenarios 240] [--seed 0]
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

from diagnostics import bearing_frequencies, diagnose  # noqa: E402
from diagnostics.app.datasets import CWRU_DRIVE_END, CWRU_FAN_END  # noqa: E402

BEARINGS = {"drive end": (CWRU_DRIVE_END, CWRU_FAN_END), "fan end": (CWRU_FAN_END, CWRU_DRIVE_END)}
KINDS = ("other bearing", "sub-multiple", "random")
FAULTS = ("outer", "inner", "ball")


def impacts(rng, fs: float, n: int, rate: float, resonance: float, weight) -> np.ndarray:
    """A train of decaying resonances at ``rate`` (0.5 % period jitter); ``weight(t)`` scales
    each impact."""
    seconds = n / fs
    times = np.cumsum((1.0 + 0.005 * rng.standard_normal(int(seconds * rate) + 10)) / rate)
    times = times[times < seconds - 0.01]
    return rings(fs, n, times, resonance, [weight(t) for t in times])


def rings(fs: float, n: int, times, resonance: float, sizes) -> np.ndarray:
    """Decaying resonances struck at ``times`` (s), each scaled by its size."""
    tail = np.arange(int(0.004 * fs)) / fs
    ring = np.exp(-900.0 * tail * resonance / 3500.0) * np.sin(2 * np.pi * resonance * tail)
    x = np.zeros(n)
    for t, size in zip(times, sizes, strict=True):
        i = int(round(t * fs))
        x[i : i + ring.size] += size * ring[: n - i]
    return x


def base_record(rng, fs: float, n: int, shaft: float) -> np.ndarray:
    """Unit noise and six shaft harmonics: what every scenario's record starts from."""
    t = np.arange(n) / fs
    x = rng.standard_normal(n)
    return x + sum(2.0 / m * np.cos(2 * np.pi * m * shaft * t) for m in range(1, 7))


def fault_impacts(rng, fs: float, n: int, own, fault: str, size: float, resonance=None):
    """A fault's impact train: at its fault frequency less 0-1 % (slip), ``size`` times a
    unit impact, modulated 80 % at the rate a turning fault passes the load zone (none for
    the outer race); ringing ``resonance`` Hz, drawn at 0.1-0.3 fs where not given."""
    rate = {"outer": own.bpfo, "inner": own.bpfi, "ball": 2.0 * own.bsf}[fault]
    mod = {"outer": 0.0, "inner": own.shaft, "ball": own.ftf}[fault]
    rate *= rng.uniform(0.99, 1.0)
    if resonance is None:
        resonance = float(rng.uniform(0.1, 0.3)) * fs
    return impacts(
        rng, fs, n, rate, resonance,
        lambda s: size * (1.0 + 0.8 * math.cos(2 * math.pi * mod * s)),
    )  # fmt: skip


def other_rate(rng, kind: str, shaft: float, own, other) -> float:
    """Rate (Hz) of the other source."""
    if kind == "other bearing":
        return float(rng.choice([other.bpfo, other.bpfi])) * rng.uniform(0.995, 1.005)
    if kind == "sub-multiple":
        return float(rng.choice([own.bpfo, own.bpfi])) / float(rng.choice([2, 3]))
    kept = [own.bpfo, own.bpfi, 2 * own.bsf, own.bsf] + [own.ftf * m for m in (1, 2, 3)]
    kept = [f * m for f in kept for m in (1, 2, 3)]
    while True:
        rate = shaft * math.exp(rng.uniform(math.log(1.2), math.log(8.0)))
        if all(abs(rate / f - 1.0) > 0.03 for f in kept):
            return rate


def scenario(seed: int) -> tuple[str, str, str, str, float, object, float, np.ndarray]:
    """One record: (bearing, fault, kind, text, fs, geometry, shaft Hz, x)."""
    rng = np.random.default_rng(seed)
    end = str(rng.choice(list(BEARINGS)))
    geometry, neighbour = BEARINGS[end]
    fs = float(rng.choice([12000.0, 48000.0]))
    shaft = float(rng.uniform(25.0, 30.0))
    n = int(rng.uniform(2.0, 8.0) * fs)
    own = bearing_frequencies(geometry, shaft)
    fault = str(rng.choice(FAULTS)) if seed % 2 else "none"
    kind = KINDS[(seed // 2) % len(KINDS)]
    x = base_record(rng, fs, n, shaft)
    strength = float(rng.uniform(2.0, 4.0))
    if fault != "none":
        x += fault_impacts(rng, fs, n, own, fault, strength)
    rate = other_rate(rng, kind, shaft, own, bearing_frequencies(neighbour, shaft))
    factor = float(rng.uniform(1.0, 4.0))
    x += impacts(
        rng, fs, n, rate, float(rng.uniform(0.05, 0.3)) * fs,
        lambda s: factor * strength * (1.0 + 0.5 * math.cos(2 * math.pi * shaft * s)),
    )  # fmt: skip
    text = (
        f"{end}, fs {fs / 1000:g} kHz, {n / fs:.1f} s, other source at "
        f"{rate / shaft:.3f} orders x{factor:.1f}"
    )
    return end, fault, kind, text, fs, geometry, shaft, x


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenarios", type=int, default=240, help="records, half of them healthy")
    ap.add_argument("--seed", type=int, default=0, help="first scenario's seed")
    args = ap.parse_args(argv)
    table: dict[tuple[str, str], list[int]] = {}
    for seed in range(args.seed, args.seed + args.scenarios):
        end, fault, kind, text, fs, geometry, shaft, x = scenario(seed)
        verdict = diagnose(x, fs, geometry, shaft).fault
        row = table.setdefault((kind, "healthy" if fault == "none" else "faulty"), [0, 0])
        row[0] += 1
        row[1] += verdict == fault
        if verdict != fault:
            print(f"scenario {seed}: {fault} called {verdict} ({text})")
    print("\n| other source | records | healthy: none | faulty: fault named |")
    print("|---|---:|---:|---:|")
    for kind in KINDS:
        healthy = table.get((kind, "healthy"), [0, 0])
        faulty = table.get((kind, "faulty"), [0, 0])
        print(
            f"| {kind} | {healthy[0] + faulty[0]} | {healthy[1]} of {healthy[0]} | "
            f"{faulty[1]} of {faulty[0]} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
