"""Diagnosis at varying speed over random synthetic scenarios: how often the verdict is right
from the true speed profile, from ``estimate_speed`` searched near the true range and over a
wide range, and how often a healthy record is called faulty.

Each scenario draws a sampling rate (12, 20 or 48 kHz), 6-10 s of record, a speed profile
that changes 2-3x (a ramp up, a ramp down, or one sinusoidal swing) from 8-15 Hz, a fault
(outer, inner, ball or none) whose impacts fall at the fault order with 0.5 % jitter and
ring a structural resonance (1.5-15 kHz) growing with speed, inner-race impacts modulated
once a turn and ball impacts once a cage turn, six shaft harmonics (2/m) and unit noise;
every other healthy record also carries mains lines (50, 100, 150 Hz) that do not move
with the speed. Verdicts come from ``diagnose`` in the order domain. Usage::

    python benchmarks/diagnostics/varying_speed_scenarios.py [--faulty 60] [--healthy 80] [--seed 0]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if __name__ == "__main__":  # run as a script: the repository's packages by name
    sys.path.insert(0, str(ROOT))

from diagnostics import (  # noqa: E402
    BearingGeometry,
    bearing_frequencies,
    diagnose,
    estimate_speed,
    shaft_angle,
)

GEOMETRY = BearingGeometry(9, 7.94e-3, 39.04e-3)  # CWRU drive end, SKF 6205
ORDERS = bearing_frequencies(GEOMETRY, 1.0)
FAULTS = ("outer", "inner", "ball", "none")


def scenario(seed: int, fault: str | None = None, mains: bool = False):
    """One random record: (fault, fs, rate per sample, record, description)."""
    rng = np.random.default_rng(seed)
    fs = float(rng.choice([12000.0, 20000.0, 48000.0]))
    seconds = float(rng.uniform(6.0, 10.0))
    t = np.arange(int(seconds * fs)) / fs
    low, ratio = float(rng.uniform(8.0, 15.0)), float(rng.uniform(2.0, 3.0))
    shape = str(rng.choice(["up", "down", "sine"]))
    swing = {"up": t / seconds, "down": 1.0 - t / seconds,
             "sine": 0.5 * (1.0 - np.cos(2 * np.pi * t / seconds))}[shape]  # fmt: skip
    rate = low * (1.0 + (ratio - 1.0) * swing)
    fault = str(rng.choice(FAULTS)) if fault is None else fault
    resonance = min(float(rng.choice([1500.0, 3500.0, 6000.0, 9000.0, 15000.0])), 0.3 * fs)
    theta = shaft_angle(rate, fs)
    x = rng.standard_normal(t.size)
    if fault != "none":
        order = {"outer": ORDERS.bpfo, "inner": ORDERS.bpfi, "ball": 2.0 * ORDERS.bsf}[fault]
        spacing = (1.0 + 0.005 * rng.standard_normal(int(theta[-1] * order) + 5)) / order
        angles = np.cumsum(spacing)
        angles = angles[angles < theta[-1] - 0.02]
        tail = np.arange(int(0.004 * fs)) / fs
        ring = np.exp(-900.0 * tail * resonance / 3500.0) * np.sin(2 * np.pi * resonance * tail)
        strength = float(rng.uniform(2.0, 4.0))
        for angle, when in zip(angles, np.interp(angles, theta, t), strict=True):
            weight = strength * np.interp(when, t, rate) / rate.mean()
            if fault == "inner":
                weight *= 1.0 + 0.8 * np.cos(2 * np.pi * angle)
            elif fault == "ball":
                weight *= 1.0 + 0.8 * np.cos(2 * np.pi * ORDERS.ftf * angle)
            i = int(round(when * fs))
            x[i : i + ring.size] += weight * ring[: t.size - i]
    x += sum(2.0 / m * np.cos(2 * np.pi * m * theta + m) for m in range(1, 7))
    if mains:
        x += sum(2.0 * np.cos(2 * np.pi * 50.0 * k * t) for k in (1, 2, 3))
    text = (
        f"fs {fs / 1000:g} kHz, {shape} {low:.1f}-{low * ratio:.1f} Hz, resonance {resonance:g} Hz"
    )
    return fault, fs, rate, x, text


def verdicts(fs: float, rate: np.ndarray, x: np.ndarray) -> dict[str, str]:
    """The verdict from the true profile and from the speed estimated over two ranges."""
    out = {"true profile": diagnose(x, fs, GEOMETRY, rate).fault}
    for name, (low, high) in (
        ("estimated, 0.8-1.2 x range", (0.8 * rate.min(), 1.2 * rate.max())),
        ("estimated, 5-50 Hz", (5.0, 50.0)),
    ):
        estimate = estimate_speed(x, fs, low, high)
        out[name] = diagnose(x, fs, GEOMETRY, estimate.shaft_hz).fault
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--faulty", type=int, default=60, help="random scenarios (any fault)")
    ap.add_argument("--healthy", type=int, default=80, help="healthy scenarios")
    ap.add_argument("--seed", type=int, default=0, help="first scenario's seed")
    args = ap.parse_args(argv)
    right: dict[str, int] = {}
    alarms: dict[str, int] = {}
    for i in range(args.faulty):
        fault, fs, rate, x, text = scenario(args.seed + i)
        for name, verdict in verdicts(fs, rate, x).items():
            right[name] = right.get(name, 0) + (verdict == fault)
            if verdict != fault:
                print(f"scenario {args.seed + i}: {fault} called {verdict} ({name}; {text})")
    for i in range(args.healthy):
        fault, fs, rate, x, text = scenario(args.seed + 10_000 + i, "none", mains=bool(i % 2))
        for name, verdict in verdicts(fs, rate, x).items():
            alarms[name] = alarms.get(name, 0) + (verdict != "none")
            if verdict != "none":
                print(f"healthy {args.seed + 10_000 + i}: called {verdict} ({name}; {text})")
    print(f"\n| speed from | right, {args.faulty} random | false alarms, {args.healthy} healthy |")
    print("|---|---:|---:|")
    for name in right:
        print(f"| {name} | {right[name]} | {alarms.get(name, 0)} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
