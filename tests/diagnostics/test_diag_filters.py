"""Zero-phase notch, band-pass and low-pass filters."""

from __future__ import annotations

import numpy as np
import pytest

from diagnostics import bandpass_filter, envelope_spectrum, lowpass_filter, notch_filter

FS = 10_000.0
T = np.arange(int(2 * FS)) / FS  # 2 s
MIDDLE = slice(int(0.5 * FS), int(1.5 * FS))  # away from the edge transients


def _tone(f: float) -> np.ndarray:
    return np.sin(2 * np.pi * f * T)


def _gain_db(y: np.ndarray, x: np.ndarray) -> float:
    return 20 * np.log10(np.std(y[MIDDLE]) / np.std(x[MIDDLE]))


def _phase(y: np.ndarray, f: float) -> float:
    """Phase of the component at f over the middle second (a whole number of cycles)."""
    t, seg = T[MIDDLE], y[MIDDLE]
    return np.angle(np.sum(seg * np.exp(-2j * np.pi * f * t)))


def test_notch_removes_f0_and_spares_neighbours():
    f0 = 1000.0
    at_f0 = _tone(f0)
    assert _gain_db(notch_filter(at_f0, FS, f0), at_f0) <= -25.0
    for f in (0.8 * f0, 1.2 * f0):
        x = _tone(f)
        assert abs(_gain_db(notch_filter(x, FS, f0, Q=30.0), x)) < 0.5


def test_notch_is_zero_phase():
    x = _tone(700.0)
    y = notch_filter(x, FS, 1000.0, Q=5.0)  # a broad notch: strong phase if one-way
    assert abs(_phase(y, 700.0) - _phase(x, 700.0)) < 1e-3


def test_bandpass_passes_band_without_lag_and_rejects_outside():
    x = _tone(1000.0)
    y = bandpass_filter(x, FS, 700.0, 1400.0)
    assert abs(_gain_db(y, x)) < 0.1
    assert abs(_phase(y, 1000.0) - _phase(x, 1000.0)) < 1e-3
    # An impulse comes out centred on itself: the zero-phase response is symmetric.
    impulse = np.zeros(T.size)
    impulse[T.size // 2] = 1.0
    response = bandpass_filter(impulse, FS, 700.0, 1400.0)
    assert np.argmax(np.abs(response)) == T.size // 2
    half = 200
    centre = T.size // 2
    np.testing.assert_allclose(
        response[centre - half : centre], response[centre + half : centre : -1], atol=1e-9
    )
    for f in (150.0, 4000.0):
        out = _tone(f)
        assert _gain_db(bandpass_filter(out, FS, 700.0, 1400.0), out) < -40.0


def test_lowpass_cutoff_is_minus_6_db_after_forward_backward():
    # Butterworth |H(fc)|^2 = 1/2 per pass; two passes give 1/4, i.e. -6.02 dB.
    x = _tone(800.0)
    assert _gain_db(lowpass_filter(x, FS, 800.0), x) == pytest.approx(-6.02, abs=0.05)
    low = _tone(100.0)
    assert abs(_gain_db(lowpass_filter(low, FS, 800.0), low)) < 0.01
    high = _tone(3000.0)
    assert _gain_db(lowpass_filter(high, FS, 800.0), high) < -60.0


def test_bandpass_up_to_nyquist_is_a_highpass():
    x = _tone(3000.0)
    y = bandpass_filter(x, FS, 1000.0, FS / 2)
    assert abs(_gain_db(y, x)) < 0.01
    low = _tone(200.0)
    assert _gain_db(bandpass_filter(low, FS, 1000.0, FS / 2), low) < -60.0


@pytest.mark.parametrize(
    "call",
    [
        lambda x: notch_filter(x, FS, FS / 2),
        lambda x: notch_filter(x, FS, 0.0),
        lambda x: notch_filter(x, FS, 1000.0, Q=0.0),
        lambda x: bandpass_filter(x, FS, 2000.0, 1000.0),
        lambda x: bandpass_filter(x, FS, 100.0, 6000.0),
        lambda x: bandpass_filter(x, FS, 100.0, 1000.0, order=0),
        lambda x: lowpass_filter(x, FS, 6000.0),
        lambda x: lowpass_filter(x[:10], FS, 1000.0),
        lambda x: lowpass_filter(np.full(100, np.nan), FS, 1000.0),
    ],
)
def test_filters_reject_bad_arguments(call):
    with pytest.raises(ValueError):
        call(_tone(100.0))


def test_bandpass_edges_at_zero_and_nyquist_mean_lowpass_and_all_pass():
    rng = np.random.default_rng(3)
    fs = 8000.0
    x = rng.standard_normal(4000)
    # A band from 0 is the low-pass at its upper edge; the whole range leaves x unchanged.
    np.testing.assert_array_equal(
        bandpass_filter(x, fs, 0.0, 1000.0), lowpass_filter(x, fs, 1000.0)
    )
    np.testing.assert_array_equal(bandpass_filter(x, fs, 0.0, fs / 2), x)


def test_envelope_spectrum_accepts_the_kurtogram_level_0_band():
    # The fast kurtogram's best band can be level 0, (0, fs/2): the envelope of the whole band.
    fs = 8000.0
    t = np.arange(8000) / fs
    x = (1.0 + 0.5 * np.cos(2 * np.pi * 50.0 * t)) * np.cos(2 * np.pi * 1000.0 * t)
    f_all, a_all = envelope_spectrum(x, fs, band=(0.0, fs / 2))
    f_none, a_none = envelope_spectrum(x, fs)
    np.testing.assert_allclose(a_all, a_none)
    assert f_all[np.argmax(a_all[1:]) + 1] == pytest.approx(50.0)
