"""Is there any harmonic series in a record, and is it at a fault frequency?

A record that ``diagnose`` calls ``none`` may hold no periodic impacts at all, or a series
at a rate the bearing's kinematics does not predict. This script tells the two apart on
measured records: for every fundamental from ``--fmin`` to ``--fmax`` it scores the harmonic
series of the squared envelope spectrum (the sum of the ``--top`` strongest of ``--harmonics``
harmonics, each over its local background, shaft harmonics masked) in every band of a
dyadic and one-third band tree of the prewhitened record, and prints:

- the strongest series found (fundamental, band, score), and where the record's fault
  frequencies (BPFO, BPFI, 2 x BSF, each within +-2 %) rank among all fundamentals;
- the verdict of ``diagnose`` on the record, and on the record decimated by each
  ``--decimate`` factor that keeps ``--min-fs`` (a 48 kHz record read as 12 kHz: the same
  analysis on the band where a 12 kHz record has its content).

A healthy record (CWRU 97) gives the scale: its strongest series is what a fault-free
bearing shows. Usage::

    python benchmarks/diagnostics/periodicity_scan.py ../shared/data/cwru48k/*174.mat \
        ../shared/data/cwru48k/*201.mat ../shared/data/cwru/normal_0_97.mat --decimate 4
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
from scipy import signal

ROOT = Path(__file__).resolve().parents[2]
if __name__ == "__main__":  # run as a script: the repository's packages by name
    sys.path.insert(0, str(ROOT))

from diagnostics import (  # noqa: E402
    bearing_frequencies,
    diagnose,
    normalised_envelope_spectrum,
    prewhiten,
)
from diagnostics._bands import _demod_band  # noqa: E402
from diagnostics._comb import _line_values, _shaft_mask  # noqa: E402
from diagnostics.app.datasets import read_labelled_record  # noqa: E402

SLIP = 0.02


def tree_bands(fs: float, levels: int) -> list[tuple[float, float]]:
    """Bands of a fast kurtogram of ``levels`` levels: the whole band, then 2**k equal bands
    for k = 1..levels and 3 * 2**(k-1) between levels k and k + 1 (k < levels)."""
    counts = (
        {1} | {2**k for k in range(1, levels + 1)} | {3 * 2 ** (k - 1) for k in range(1, levels)}
    )
    half = fs / 2.0
    return [(i * half / n, (i + 1) * half / n) for n in sorted(counts) for i in range(n)]


def series_scores(
    z: np.ndarray, df: float, fundamentals: np.ndarray, harmonics: int, top: int
) -> np.ndarray:
    """Sum of the ``top`` largest of ``harmonics`` harmonic values for each fundamental."""
    k = np.arange(1, harmonics + 1)
    values = np.sort(_line_values(z, df, np.outer(fundamentals, k)), axis=1)
    return values[:, -top:].sum(axis=1)


def scan_signal(
    x,
    fs: float,
    shaft_hz: float,
    geometry,
    fmin: float = 40.0,
    fmax: float = 220.0,
    levels: int = 3,
    harmonics: int = 5,
    top: int = 3,
) -> dict:
    """Strongest harmonic series of one record over all bands, and its fault frequencies'.

    Returns
    -------
    dict
        ``f0`` (Hz), ``band`` and ``score`` of the strongest series, ``n_bands`` scanned, and
        ``faults``: for BPFO, BPFI and 2xBSF the best score within +-2 % and the share of
        fundamentals scoring higher.
    """
    freqs = bearing_frequencies(geometry, shaft_hz)
    white = prewhiten(x, fs)
    f_max = (harmonics + 1) * fmax
    grid = None
    best = None
    bands = []
    for band in tree_bands(fs, levels):
        if band[1] - band[0] < 1.25 * 2 * fmax:
            continue  # too narrow for two harmonics of the fastest fundamental
        f, z, _ = normalised_envelope_spectrum(white, fs, _demod_band(band, fs), f_max, 0.1 * fmin)
        df = f[1] - f[0]
        if grid is None:
            grid = np.arange(fmin, fmax, df / (2.0 * harmonics))
        s = series_scores(np.where(_shaft_mask(f, freqs.shaft), 0.0, z), df, grid, harmonics, top)
        best = s if best is None else np.maximum(best, s)
        bands.append((band, s))
    i = int(np.argmax(best))
    where = max(bands, key=lambda b: b[1][i])[0]
    faults = {"BPFO": freqs.bpfo, "BPFI": freqs.bpfi, "2xBSF": 2.0 * freqs.bsf}
    at_fault = {}
    for name, f0 in faults.items():
        window = np.abs(grid - f0) <= SLIP * f0
        score = float(best[window].max()) if window.any() else math.nan
        at_fault[name] = (score, float((best > score).mean()))
    return dict(
        n_bands=len(bands), f0=float(grid[i]), band=where, score=float(best[i]), faults=at_fault
    )


def verdicts(path, factors: list[int], min_fs: float) -> str:
    """``diagnose``'s verdict on the record and on each decimation that keeps ``min_fs``."""
    rec = read_labelled_record(path)
    out = []
    for q in [1, *factors]:
        if q > 1 and rec.fs / q < min_fs:
            continue
        x = signal.decimate(rec.x, q, ftype="fir", zero_phase=True) if q > 1 else rec.x
        d = diagnose(x, rec.fs / q, rec.geometry, rec.shaft_hz)
        out.append(f"{rec.fs / q / 1000:g}k {d.fault}")
    return ", ".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("records", nargs="+", help="CWRU or MFPT .mat records")
    ap.add_argument("--fmin", type=float, default=40.0, help="lowest fundamental, Hz")
    ap.add_argument("--fmax", type=float, default=220.0, help="highest fundamental, Hz")
    ap.add_argument("--levels", type=int, default=3, help="levels of the band tree")
    ap.add_argument("--harmonics", type=int, default=5, help="harmonics per series")
    ap.add_argument("--top", type=int, default=3, help="strongest harmonics summed")
    ap.add_argument("--decimate", type=int, nargs="*", default=[], help="decimation factors")
    ap.add_argument(
        "--min-fs", type=float, default=12000.0, help="no decimation below this rate, Hz"
    )
    args = ap.parse_args(argv)
    print(
        f"score: sum of the {args.top} strongest of {args.harmonics} harmonics over the local "
        f"background, best band; fundamentals {args.fmin:g}-{args.fmax:g} Hz; 'above' is the "
        "share of fundamentals scoring higher than the fault frequency's best"
    )
    head = f"{'record':34s} {'fault':6s} {'strongest series':26s} " + " ".join(
        f"{n + ' (above)':>15s}" for n in ("BPFO", "BPFI", "2xBSF")
    )
    print(head + "  verdicts")
    for path in args.records:
        rec = read_labelled_record(path)
        r = scan_signal(
            rec.x,
            rec.fs,
            rec.shaft_hz,
            rec.geometry,
            args.fmin,
            args.fmax,
            args.levels,
            args.harmonics,
            args.top,
        )
        lo, hi = r["band"]
        strongest = f"{r['f0']:6.1f} Hz {r['score']:5.1f} {lo / 1000:.1f}-{hi / 1000:.1f}k"
        cells = " ".join(f"{s:6.1f} ({above:5.1%})" for s, above in r["faults"].values())
        name = Path(path).name[:34]
        print(
            f"{name:34s} {rec.label.fault:6s} {strongest:26s} {cells}  "
            f"{verdicts(path, args.decimate, args.min_fs)}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
