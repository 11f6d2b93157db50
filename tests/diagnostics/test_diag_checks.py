"""Input validation shared by the diagnostics functions."""

from __future__ import annotations

import numpy as np
import pytest

from diagnostics._checks import check_band, check_frequency, check_signal


def test_check_signal_returns_contiguous_float64_vector():
    x = check_signal([1, 2, 3], 10.0)
    assert x.dtype == np.float64 and x.ndim == 1
    np.testing.assert_array_equal(x, [1.0, 2.0, 3.0])
    column = np.arange(5, dtype=np.float32).reshape(5, 1)
    flat = check_signal(column, 10.0)
    assert flat.shape == (5,) and flat.dtype == np.float64


@pytest.mark.parametrize(
    ("x", "fs", "fragment"),
    [
        ([], 10.0, "empty"),
        ([1.0, np.nan, 2.0], 10.0, "NaN or inf"),
        ([1.0, np.inf], 10.0, "NaN or inf"),
        (np.ones((3, 4)), 10.0, "1-D"),
        ([1.0 + 1j, 2.0], 10.0, "real"),
        (["a", "b"], 10.0, "numeric"),
        ([1.0, 2.0], 0.0, "fs"),
        ([1.0, 2.0], -5.0, "fs"),
        ([1.0, 2.0], float("nan"), "fs"),
        ([1.0, 2.0], "48k", "fs"),
    ],
)
def test_check_signal_rejects_bad_input(x, fs, fragment):
    with pytest.raises(ValueError, match=fragment):
        check_signal(x, fs)


def test_check_signal_names_the_argument_and_length():
    with pytest.raises(ValueError, match=r"^accel .*8 samples, need at least 16"):
        check_signal(np.zeros(8), 100.0, name="accel", min_length=16)


def test_check_band_accepts_up_to_nyquist():
    assert check_band(10, 500, 1000.0) == (10.0, 500.0)


def test_check_band_accepts_edges_at_zero_and_nyquist():
    assert check_band(0.0, 100.0, 1000.0) == (0.0, 100.0)
    assert check_band(0, 500, 1000.0) == (0.0, 500.0)


@pytest.mark.parametrize(
    ("lo", "hi"), [(-1.0, 100.0), (200.0, 100.0), (100.0, 100.0), (10.0, 600.0)]
)
def test_check_band_rejects_bands_outside_0_to_nyquist(lo, hi):
    with pytest.raises(ValueError, match="band"):
        check_band(lo, hi, 1000.0)


def test_check_band_rejects_non_finite_edges():
    with pytest.raises(ValueError, match="finite"):
        check_band(10.0, float("nan"), 1000.0)


@pytest.mark.parametrize("f", [0.0, -3.0, 500.0, 750.0, float("inf")])
def test_check_frequency_requires_open_range(f):
    with pytest.raises(ValueError, match="f0"):
        check_frequency(f, 1000.0, "f0")
    assert check_frequency(499.0, 1000.0, "f0") == 499.0
