"""Hilbert envelope and squared envelope spectrum on amplitude-modulated carriers."""

from __future__ import annotations

import numpy as np
import pytest

from diagnostics import envelope, envelope_spectrum

FS = 20_000.0
T = np.arange(int(FS)) / FS  # 1 s: every frequency below is a whole number of cycles
CARRIER = 3000.0
FM = 37.0
DEPTH = 0.5


def _am(depth: float = DEPTH) -> np.ndarray:
    return (1 + depth * np.cos(2 * np.pi * FM * T)) * np.cos(2 * np.pi * CARRIER * T)


def _amplitude_at(f: np.ndarray, a: np.ndarray, freq: float) -> float:
    return float(a[np.argmin(np.abs(f - freq))])


def test_envelope_of_am_tone_is_the_modulating_law():
    env = envelope(_am(), FS)
    expected = 1 + DEPTH * np.cos(2 * np.pi * FM * T)
    inner = slice(200, -200)  # the Hilbert transform is exact only away from the ends
    np.testing.assert_allclose(env[inner], expected[inner], atol=2e-3)


def test_squared_envelope_spectrum_peaks_at_modulation_frequency():
    f, a = envelope_spectrum(_am(), FS)
    assert f[np.argmax(a)] == pytest.approx(FM)
    # (1 + m cos)^2 = 1 + m^2/2 + 2 m cos + (m^2/2) cos(2 .): lines of 2m at FM, m^2/2 at 2 FM.
    assert _amplitude_at(f, a, FM) == pytest.approx(2 * DEPTH, rel=0.01)
    assert _amplitude_at(f, a, 2 * FM) == pytest.approx(DEPTH**2 / 2, rel=0.02)
    assert a[0] == pytest.approx(0.0, abs=1e-9)  # mean removed
    assert f[1] == pytest.approx(FS / T.size)


def test_plain_envelope_spectrum_has_no_second_harmonic():
    f, a = envelope_spectrum(_am(), FS, squared=False)
    assert _amplitude_at(f, a, FM) == pytest.approx(DEPTH, rel=0.01)
    assert _amplitude_at(f, a, 2 * FM) < 0.01 * DEPTH


def test_band_isolates_the_modulated_carrier_from_a_strong_tone():
    # A strong 120 Hz line beating with the carrier would put 120 Hz (and its products) in
    # the envelope; band-passing around the carrier first removes it.
    x = _am() + 5.0 * np.sin(2 * np.pi * 120.0 * T)
    f, a = envelope_spectrum(x, FS, band=(2000.0, 4000.0))
    assert f[np.argmax(a)] == pytest.approx(FM)
    assert _amplitude_at(f, a, 120.0) < 0.02 * _amplitude_at(f, a, FM)
    f_raw, a_raw = envelope_spectrum(x, FS)
    assert f_raw[np.argmax(a_raw)] != pytest.approx(FM)


@pytest.mark.parametrize("band", [(4000.0, 2000.0), (100.0, 20_000.0), 3000.0, (1.0, 2.0, 3.0)])
def test_bad_band_raises(band):
    with pytest.raises(ValueError, match="band"):
        envelope_spectrum(_am(), FS, band=band)


def test_bad_signal_raises():
    with pytest.raises(ValueError, match="NaN"):
        envelope(np.array([1.0, np.nan, 0.0]), FS)
