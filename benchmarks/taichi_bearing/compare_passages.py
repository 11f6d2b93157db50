"""Two passage studies side by side: is a change of the solver's arithmetic visible in
the passages' statistics?

The exit of a roller from the spall is chaotic, so two versions of the solver whose
histories part after the first exit are compared as distributions over passages, never
passage by passage. Reads the ``passages.csv`` of two ``python -m taichi_bearing passages``
studies (each a folder holding it, or the file) and prints, per passage quantity, each
study's median and interquartile range and the two-sided Mann-Whitney U test's p-value
(no assumption on the distributions' shape; a small p says the two differ).

    python benchmarks/taichi_bearing/compare_passages.py docs/results/passages OUT \
        --names before after
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

# column, label, scale to the unit shown
QUANTITIES = (
    ("entry_destress_time_s", "de-stressing at entry, ms", 1e3),
    ("exit_force_peak_ratio", "exit force peak / F0", 1.0),
    ("exit_impulses", "impulses at exit", 1.0),
    ("exit_impulse_width_s", "exit impulse width, us", 1e6),
    ("exit_reload_time_s", "exit edge to full load, ms", 1e3),
    ("exit_entry_accel_ratio", "exit / entry acceleration peak", 1.0),
    ("exit_peak_frequency_hz", "frequency the re-stressing excites, kHz", 1e-3),
    ("entry_time_s", "entry time, ms", 1e3),
    ("exit_time_s", "exit time, ms", 1e3),
)


def read_passages(path: Path) -> pd.DataFrame:
    """A study's passages (``passages.csv`` in ``path``, or ``path`` itself)."""
    path = Path(path)
    csv = path / "passages.csv" if path.is_dir() else path
    if not csv.is_file():
        raise SystemExit(f"{path}: no passages.csv (run `python -m taichi_bearing passages`)")
    return pd.read_csv(csv)


def summary(values: np.ndarray) -> str:
    """``median (q1-q3)`` of the finite values."""
    v = values[np.isfinite(values)]
    if v.size == 0:
        return "-"
    q1, med, q3 = np.percentile(v, [25, 50, 75])
    return f"{med:.4g} ({q1:.4g}-{q3:.4g})"


def compare(a: pd.DataFrame, b: pd.DataFrame) -> list[tuple[str, str, str, float, int, int]]:
    """Per quantity both studies have: ``(label, summary a, summary b, p, n a, n b)``."""
    rows = []
    for column, label, scale in QUANTITIES:
        if column not in a or column not in b:
            continue
        x = a[column].to_numpy(float) * scale
        y = b[column].to_numpy(float) * scale
        x, y = x[np.isfinite(x)], y[np.isfinite(y)]
        if x.size and y.size and np.ptp(np.concatenate([x, y])) > 0:
            p = float(stats.mannwhitneyu(x, y, alternative="two-sided").pvalue)
        else:
            p = 1.0 if x.size and y.size else float("nan")
        rows.append((label, summary(x), summary(y), p, x.size, y.size))
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("studies", nargs=2, type=Path, metavar="STUDY")
    p.add_argument("--names", nargs=2, default=["a", "b"], metavar="NAME")
    args = p.parse_args(argv)
    a, b = (read_passages(s) for s in args.studies)
    na, nb = args.names
    print(f"{na}: {len(a)} passages ({args.studies[0]}); {nb}: {len(b)} ({args.studies[1]})\n")
    print(f"| quantity | {na} median (IQR) | {nb} median (IQR) | Mann-Whitney p |")
    print("| --- | --- | --- | ---: |")
    for label, sa, sb, pv, _, _ in compare(a, b):
        print(f"| {label} | {sa} | {sb} | {pv:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
