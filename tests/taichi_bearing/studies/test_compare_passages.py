"""benchmarks/taichi_bearing/compare_passages.py: two passage studies as distributions
(Mann-Whitney)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from benchmarks.taichi_bearing.compare_passages import compare, main


def study(rng, shift: float, n: int = 12) -> pd.DataFrame:
    return pd.DataFrame(
        {
            "exit_force_peak_ratio": 1.3 + shift + 0.05 * rng.standard_normal(n),
            "exit_impulses": rng.integers(10, 14, n),
            "exit_time_s": np.full(n, 4.8e-3),
        }
    )


def test_a_shift_is_told_apart_and_a_resample_is_not(tmp_path, capsys):
    rng = np.random.default_rng(0)
    base, same, shifted = study(rng, 0.0), study(rng, 0.0), study(rng, 0.2)
    rows = {r[0]: r for r in compare(base, shifted)}
    assert rows["exit force peak / F0"][3] < 1e-3  # 4 standard deviations apart
    rows = {r[0]: r for r in compare(base, same)}
    assert rows["exit force peak / F0"][3] > 0.05
    assert rows["exit time, ms"][1:4] == ("4.8 (4.8-4.8)", "4.8 (4.8-4.8)", 1.0)
    # the command line: folders holding passages.csv, a table row per quantity both have
    for name, df in (("a", base), ("b", shifted)):
        (tmp_path / name).mkdir()
        df.to_csv(tmp_path / name / "passages.csv", index=False)
    assert main([str(tmp_path / "a"), str(tmp_path / "b"), "--names", "old", "new"]) == 0
    out = capsys.readouterr().out
    assert "| quantity | old median (IQR) | new median (IQR) | Mann-Whitney p |" in out
    assert out.count("\n| ") == 5  # header, rule, three quantities
