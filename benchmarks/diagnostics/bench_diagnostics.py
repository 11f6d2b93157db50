"""Speed of the diagnostics signal core on 10 s of a 48 kHz record.

Prints one table. Each row times the fast code and a straightforward baseline in the same
run, on the same signal, and checks they agree:

- fast kurtogram (nlevel 7) against the direct port of Antoni's reference
  (``kurtogram_reference.py``: every band filtered with lfilter, then decimated);
- ``diagnose`` with the kurtogram's band against the same with the direct kurtogram
  swapped in;
- ``diagnose`` as by default (the infogram's band: kurtogram and infogram from one pass of
  the filter bank) against ``diagnose`` with the kurtogram's band: what the infogram costs.

Goals (on the 2-core machine): kurtogram < 0.3 s and >= 2x the reference with
identical output; diagnose < 1 s.

Usage: ``python benchmarks/diagnostics/bench_diagnostics.py [--repeat N]``
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
if __name__ == "__main__":  # run as a script: the repository's packages by name
    sys.path.insert(0, str(ROOT))

from benchmarks.diagnostics.kurtogram_reference import reference_kurtogram  # noqa: E402
from diagnostics import Kurtogram, kurtogram  # noqa: E402

FS = 48_000.0
SECONDS = 10.0
SHAFT_HZ = 1797 / 60.0
RESONANCE_HZ = 3_500.0


def bearing_signal(seed: int = 0) -> np.ndarray:
    """Outer-race impacts (BPFO of the CWRU 6205 bearing) ringing at 3.5 kHz, in noise."""
    rng = np.random.default_rng(seed)
    n = int(SECONDS * FS)
    x = rng.normal(size=n)
    t = np.arange(n) / FS
    x += 0.5 * np.sin(2 * np.pi * SHAFT_HZ * t)  # shaft-rate imbalance
    ring = np.arange(int(0.01 * FS)) / FS
    burst = 3.0 * np.exp(-1200.0 * ring) * np.sin(2 * np.pi * RESONANCE_HZ * ring)
    bpfo = 3.5848 * SHAFT_HZ
    for start in np.arange(0.002, SECONDS - 0.01, 1.0 / bpfo):
        i = int(start * FS) + rng.integers(-5, 6)  # slip: small random jitter
        x[i : i + burst.size] += burst
    return x


def paired_times(fast, baseline, repeat: int):
    """Best wall time of each of two calls, alternated so both see the same machine load."""
    t_fast = t_base = np.inf
    out_fast = out_base = None
    for _ in range(repeat):
        start = time.perf_counter()
        out_fast = fast()
        t_fast = min(t_fast, time.perf_counter() - start)
        start = time.perf_counter()
        out_base = baseline()
        t_base = min(t_base, time.perf_counter() - start)
    return t_fast, out_fast, t_base, out_base


def reference_as_kurtogram(x, fs, nlevel=7) -> Kurtogram:
    """The direct port's result in the fast kurtogram's type (a drop-in for diagnose)."""
    ref = reference_kurtogram(x, fs, nlevel)
    return Kurtogram(fs=float(fs), **ref)


def kurtogram_row(x: np.ndarray, repeat: int) -> list[str]:
    t_fast, fast, t_ref, ref = paired_times(
        lambda: kurtogram(x, FS, nlevel=7), lambda: reference_kurtogram(x, FS, nlevel=7), repeat
    )
    diff = float(np.max(np.abs(fast.K - ref["K"])))
    same = (fast.row, fast.column) == (ref["row"], ref["column"])
    ok = t_fast < 0.3 and t_ref / t_fast >= 2.0 and same and diff < 1e-10
    note = f"max|dK| {diff:.1e}, best band same: {same} (fc {fast.fc:.0f} Hz, bw {fast.bw:.0f} Hz)"
    return ["kurtogram nlevel 7", t_fast, t_ref, "< 0.3 s, >= 2x", ok, note]


def diagnose_rows(x: np.ndarray, repeat: int) -> list[list]:
    try:
        # The private module whose kurtogram diagnose calls for its band, swapped below.
        diagnose_module = importlib.import_module("diagnostics._bands")
        from diagnostics import BearingGeometry, diagnose
    except ImportError as exc:
        return [["diagnose", None, None, "< 1 s", None, f"skipped: not importable ({exc})"]]
    geometry = BearingGeometry(9, 7.94e-3, 39.04e-3)
    original = diagnose_module.kurtogram

    def by_kurtogram():
        return diagnose(x, FS, geometry, SHAFT_HZ, band_selector="kurtogram")

    def with_reference_kurtogram():
        diagnose_module.kurtogram = reference_as_kurtogram
        try:
            return by_kurtogram()
        finally:
            diagnose_module.kurtogram = original

    rows = []
    t_fast, fast, t_ref, ref = paired_times(by_kurtogram, with_reference_kurtogram, repeat)
    note = f"verdict {fast.fault!r} (baseline {ref.fault!r}); expected 'outer'"
    ok = t_fast < 1.0 and fast.fault == ref.fault
    rows.append(["diagnose, kurtogram", t_fast, t_ref, "< 1 s", ok, note])
    t_info, info, t_kg, kg = paired_times(
        lambda: diagnose(x, FS, geometry, SHAFT_HZ), by_kurtogram, repeat
    )
    note = (
        f"baseline: the kurtogram's band; verdict {info.fault!r} (baseline {kg.fault!r}), "
        f"bands {info.bands[-1].band} and {kg.bands[-1].band}"
    )
    rows.append(["diagnose, infogram", t_info, t_kg, "< 1 s", t_info < 1.0, note])
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="timed runs per entry (best kept)")
    args = parser.parse_args(argv)
    x = bearing_signal()
    kurtogram(x[: 2**14], FS, nlevel=3)  # warm imports and caches outside the timings
    rows = [kurtogram_row(x, args.repeat), *diagnose_rows(x, args.repeat)]
    print(
        f"signal: {SECONDS:g} s at {FS:g} Hz ({x.size} samples); best of {args.repeat} "
        "alternated runs; baselines in the notes (the direct lfilter kurtogram where not said)"
    )
    header = (
        f"{'case':<20} {'fast [s]':>9} {'baseline [s]':>13} {'speed-up':>9}  "
        f"{'goal':<15} {'met':<4} notes"
    )
    print(header)
    print("-" * len(header))
    for name, t_fast, t_ref, goal, ok, note in rows:
        if t_fast is None:
            print(f"{name:<20} {'-':>9} {'-':>13} {'-':>9}  {goal:<15} {'-':<4} {note}")
            continue
        speedup = t_ref / t_fast
        met = "yes" if ok else "NO"
        print(f"{name:<20} {t_fast:9.3f} {t_ref:13.3f} {speedup:8.2f}x  {goal:<15} {met:<4} {note}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
