"""benchmarks/diagnostics/periodicity_scan.py: the strongest harmonic series of a record, and where
its fault frequencies rank."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.diagnostics.periodicity_scan import scan_signal, series_scores, tree_bands
from diagnostics import BearingGeometry, bearing_frequencies

GEOMETRY = BearingGeometry(9, 7.94e-3, 39.04e-3)  # CWRU drive end
SHAFT_HZ = 29.95
FS = 12000.0


def impacts(rate_hz: float, seconds: float = 4.0, seed: int = 0) -> np.ndarray:
    """A 3 kHz resonance struck at ``rate_hz`` (0.5 % period jitter), in unit noise."""
    rng = np.random.default_rng(seed)
    n = int(seconds * FS)
    times = np.cumsum((1.0 + 0.005 * rng.standard_normal(int(seconds * rate_hz))) / rate_hz)
    tail = np.arange(120) / FS
    ring = 2.0 * np.exp(-600.0 * tail) * np.sin(2 * np.pi * 3000.0 * tail)
    x = rng.standard_normal(n)
    for t in times[times < seconds - 0.02]:
        i = int(t * FS)
        x[i : i + ring.size] += ring
    return x


def test_tree_bands_tile_the_band_at_each_level():
    bands = tree_bands(FS, 2)  # 1, 2, 3 and 4 equal bands (levels 0, 1, 1.6, 2)
    assert len(bands) == 1 + 2 + 3 + 4
    widths = sorted({round(hi - lo, 6) for lo, hi in bands})
    assert widths == pytest.approx([1500.0, 2000.0, 3000.0, 6000.0])


def test_the_fault_series_is_the_strongest_and_noise_scores_far_less():
    bpfo = bearing_frequencies(GEOMETRY, SHAFT_HZ).bpfo
    fault = scan_signal(impacts(1.01 * bpfo), FS, SHAFT_HZ, GEOMETRY)
    assert fault["f0"] == pytest.approx(1.01 * bpfo, rel=2e-3)
    score, above = fault["faults"]["BPFO"]
    assert score == fault["score"] and above == 0.0
    assert fault["faults"]["BPFI"][1] > 0.0  # no inner-race series
    noise = scan_signal(
        np.random.default_rng(1).standard_normal(int(4 * FS)), FS, SHAFT_HZ, GEOMETRY
    )
    assert fault["score"] > 5.0 * noise["score"]


def test_a_series_scores_the_sum_of_its_strongest_harmonics():
    df = 0.25
    z = np.ones(4000)
    f0 = 100.0  # harmonics at bins 400, 800, ...: values 20, 1, 15, 10, 1
    for k, value in ((1, 20.0), (3, 15.0), (4, 10.0)):
        z[int(k * f0 / df)] = value
    scores = series_scores(z, df, np.array([f0, 97.0]), harmonics=5, top=3)
    assert scores[0] == 45.0
    assert scores[1] == 3.0  # off the series: background only


def test_shaft_rate_series_are_masked():
    """Noise bursts once a shaft turn (a rub, an imbalance-driven knock): a strong series at
    the shaft rate and its multiples, which the scan must not report as a bearing series."""
    rng = np.random.default_rng(2)
    n = int(4 * FS)
    t = np.arange(n) / FS
    gate = 1.0 + 3.0 * (np.mod(t * SHAFT_HZ, 1.0) < 0.1)
    r = scan_signal(rng.standard_normal(n) * gate, FS, SHAFT_HZ, GEOMETRY)
    multiple = r["f0"] / SHAFT_HZ
    assert abs(multiple - round(multiple)) > 0.02
    assert r["score"] < 40.0  # only background remains once the shaft lines are masked
