"""Discrete/random separation: periodic lines to the discrete part, impacts and noise to the
random part."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from diagnostics import discrete_random_separation

FS = 12000.0


def _line_level(y: np.ndarray, f0: float) -> float:
    spectrum = np.abs(np.fft.rfft(y * np.hanning(y.size)))
    f = np.fft.rfftfreq(y.size, 1.0 / FS)
    return float(spectrum[np.argmin(np.abs(f - f0))])


def test_tones_go_to_the_discrete_part_and_impacts_stay_random():
    rng = np.random.default_rng(0)
    n = int(8 * FS)
    t = np.arange(n) / FS
    tones = 2.0 * np.sin(2 * np.pi * 29.95 * 7 * t) + np.sin(2 * np.pi * 1234.5 * t)
    impacts = np.zeros(n)
    tail = np.arange(48) / FS
    ring = 6.0 * np.exp(-900.0 * tail) * np.sin(2 * np.pi * 3000.0 * tail)
    for start in np.cumsum(rng.uniform(0.008, 0.012, 1000)):  # irregular: not periodic
        i = int(start * FS)
        if i + ring.size < n:
            impacts[i : i + ring.size] += ring
    x = tones + impacts + 0.3 * rng.standard_normal(n)
    parts = discrete_random_separation(x, FS)
    inner = slice(4096, -4096)
    for f0 in (29.95 * 7, 1234.5):  # each tone at least 30 dB down in the random part
        assert _line_level(parts.random[inner], f0) < 0.03 * _line_level(x[inner], f0)
    # The impacts are all in the random part: its kurtosis is the impacts', not the tones'.
    assert stats.kurtosis(parts.random[inner]) > 3.0 * stats.kurtosis(x[inner])
    np.testing.assert_allclose(parts.discrete + parts.random, x, atol=1e-12)
    assert np.interp(1234.5, parts.f, parts.coherence) > 0.9
    assert np.median(parts.coherence) < 0.2


def test_separation_refuses_bad_blocks():
    x = np.random.default_rng(1).standard_normal(4000)
    with pytest.raises(ValueError, match="too short for discrete/random separation"):
        discrete_random_separation(x, FS, nfft=1024)
    with pytest.raises(ValueError, match=r"delay \(100\) must be at least a block"):
        discrete_random_separation(x, FS, nfft=256, delay=100)
