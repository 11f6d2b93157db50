"""False alarms on fault-free records: how often ``diagnose`` names a fault where there is
none, at the false-alarm level it is given and at looser ones.

``diagnose``'s ``alpha`` bounds the chance that a record without a fault (a random
background) is called faulty. At the default 1e-4 no affordable number of records can show
whether the bound holds; at looser levels (1e-2, 0.1) a few hundred records do, and how far
below ``alpha`` the rate stays shows how much the union bound and the per-line window
bound give away. Each record draws a bearing (CWRU drive end or fan end, MFPT), a sampling
rate (12, 48 or 48.828 kHz), 2-10 s at a shaft rate of 10-40 Hz, and a background:

- ``white``: Gaussian noise,
- ``coloured``: Gaussian noise through two or three structural resonances,
- ``heavy-tailed``: Student-t noise (3-5 degrees of freedom) through one resonance,
- ``mains``: coloured noise and the first six harmonics of 50 or 60 Hz,
- ``shaft``: coloured noise and twelve shaft harmonics, amplitude-modulated at the shaft rate.

No fault is added: every fault named is a false alarm. Usage::

    python benchmarks/diagnostics/noise_false_alarms.py [--records 200] [--seed 0]
        [--alphas 1e-4 1e-2 0.1] [--min-modulation 0.05]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy import signal

ROOT = Path(__file__).resolve().parents[2]
if __name__ == "__main__":  # run as a script: the repository's packages by name
    sys.path.insert(0, str(ROOT))

from diagnostics import diagnose  # noqa: E402
from diagnostics.app.datasets import CWRU_DRIVE_END, CWRU_FAN_END, MFPT_BEARING  # noqa: E402

BEARINGS = {"CWRU drive end": CWRU_DRIVE_END, "CWRU fan end": CWRU_FAN_END, "MFPT": MFPT_BEARING}
KINDS = ("white", "coloured", "heavy-tailed", "mains", "shaft")


def resonate(rng, x: np.ndarray, fs: float, count: int) -> np.ndarray:
    """``x`` through ``count`` resonances at 0.05-0.4 fs, damping 2-8 %."""
    out = np.zeros_like(x)
    for _ in range(count):
        f0 = float(rng.uniform(0.05, 0.4)) * fs
        zeta = float(rng.uniform(0.02, 0.08))
        w = 2.0 * np.pi * f0 / fs
        r = np.exp(-zeta * w)
        out += signal.lfilter([1.0 - r], [1.0, -2.0 * r * np.cos(w), r * r], x)
    return out / out.std()


def harmonics(rng, t: np.ndarray, f0: float, count: int, lo: float, hi: float, fall: int):
    """``count`` harmonics of ``f0`` at random phases, the k-th of amplitude drawn from
    ``lo``-``hi`` over ``k ** fall``."""
    return sum(
        float(rng.uniform(lo, hi)) / k**fall * np.cos(2 * np.pi * k * f0 * t + rng.uniform(0, 6.3))
        for k in range(1, count + 1)
    )


def record(seed: int) -> tuple[str, str, float, object, float, np.ndarray]:
    """One fault-free record: (bearing, kind, fs, geometry, shaft Hz, x)."""
    rng = np.random.default_rng(seed)
    bearing = str(rng.choice(list(BEARINGS)))
    fs = 48828.0 if bearing == "MFPT" else float(rng.choice([12000.0, 48000.0]))
    shaft = float(rng.uniform(10.0, 40.0))
    n = int(rng.uniform(2.0, 10.0) * fs)
    kind = KINDS[seed % len(KINDS)]
    t = np.arange(n) / fs
    white = rng.standard_normal(n)
    if kind == "white":
        x = white
    elif kind == "heavy-tailed":
        x = resonate(rng, rng.standard_t(float(rng.uniform(3.0, 5.0)), n), fs, 1)
    else:
        x = resonate(rng, white, fs, int(rng.integers(2, 4)))
    if kind == "mains":
        mains = float(rng.choice([50.0, 60.0]))
        x = x + harmonics(rng, t, mains, 6, 0.2, 2.0, fall=0)
    elif kind == "shaft":
        lines = harmonics(rng, t, shaft, 12, 0.1, 1.0, fall=1)
        x = x + lines * (1.0 + 0.3 * np.cos(2 * np.pi * shaft * t))
    return bearing, kind, fs, BEARINGS[bearing], shaft, x


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--records", type=int, default=200, help="fault-free records")
    ap.add_argument("--seed", type=int, default=0, help="first record's seed")
    ap.add_argument("--alphas", type=float, nargs="+", default=[1e-4, 1e-2, 0.1])
    ap.add_argument(
        "--min-modulation", type=float, default=0.05,
        help="diagnose's effect-size floor (a tiny value tests the p-values alone)",
    )  # fmt: skip
    args = ap.parse_args(argv)
    if args.records < 1:
        ap.error(f"--records must be at least 1, got {args.records}")
    if not all(0.0 < a < 1.0 for a in args.alphas):
        ap.error(f"--alphas must lie between 0 and 1, got {args.alphas}")
    if args.min_modulation <= 0.0:
        ap.error(f"--min-modulation must be positive, got {args.min_modulation}")
    alarms = {a: {k: 0 for k in KINDS} for a in args.alphas}
    counts = {k: 0 for k in KINDS}
    start = time.perf_counter()
    for seed in range(args.seed, args.seed + args.records):
        bearing, kind, fs, geometry, shaft, x = record(seed)
        counts[kind] += 1
        for a in args.alphas:
            d = diagnose(x, fs, geometry, shaft, alpha=a, min_modulation=args.min_modulation)
            if d.fault != "none":
                alarms[a][kind] += 1
                print(f"seed {seed}: {bearing}, {kind}, {fs:.0f} Hz, {x.size / fs:.1f} s, "
                      f"alpha {a:g}: {d.fault} ({d.confidence:.2f})")  # fmt: skip
    print(f"\n{args.records} fault-free records in {time.perf_counter() - start:.0f} s")
    print(f"{'alpha':>8}  " + "  ".join(f"{k:>12}" for k in KINDS) + "  all      rate")
    for a in args.alphas:
        total = sum(alarms[a].values())
        cells = "  ".join(f"{alarms[a][k]:>5} of {counts[k]:>3}" for k in KINDS)
        print(f"{a:>8g}  {cells}  {total:>3}  {total / args.records:8.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
