"""STFT, Welch PSD and IEC 61260 one-third-octave bands."""

from __future__ import annotations

import numpy as np
import pytest

from diagnostics import psd, stft, third_octave, third_octave_centres

FS = 48_000.0


def _noise(seconds: float = 4.0, seed: int = 3) -> np.ndarray:
    return np.random.default_rng(seed).normal(size=int(seconds * FS))


def test_third_octave_centres_follow_iec_base_ten_series():
    fc = third_octave_centres(20.0, 20_000.0)
    assert fc[0] == pytest.approx(19.9526, rel=1e-5)  # nominal 20 Hz
    assert fc[-1] == pytest.approx(19952.6, rel=1e-5)  # nominal 20 kHz
    assert 1000.0 in fc
    np.testing.assert_allclose(fc[1:] / fc[:-1], 10**0.1)
    # Nominal labels 25, 31.5, 40, 50, 63, 80, 100 Hz round from the exact centres.
    np.testing.assert_allclose(fc[1:8], [25, 31.5, 40, 50, 63, 80, 100], rtol=0.02)


def test_third_octave_band_powers_add_up_to_total_power_in_range():
    x = _noise()
    fc, level = third_octave(x, FS, f_min=20.0)
    band_sum = np.sum(10 ** (level / 10))
    lo, hi = fc[0] * 10**-0.05, fc[-1] * 10**0.05
    # Independent estimate of the power between the outer edges: Welch PSD integrated.
    f, pxx = psd(x, FS, nperseg=8192)
    inside = (f >= lo) & (f < hi)
    total_in_range = np.sum(pxx[inside]) * (f[1] - f[0])
    assert band_sum == pytest.approx(total_in_range, rel=0.01)


def test_third_octave_tones_land_in_their_bands_at_their_level():
    t = np.arange(int(FS)) / FS
    amplitudes = {100.0: 1.0, 1000.0: 0.1, 8000.0: 2.0}
    x = sum(a * np.sin(2 * np.pi * f * t) for f, a in amplitudes.items())
    fc, level = third_octave(x, FS, f_min=50.0, f_max=10_000.0)
    for f, a in amplitudes.items():
        band = np.argmin(np.abs(fc - f))
        assert level[band] == pytest.approx(10 * np.log10(a**2 / 2), abs=0.01)
    others = np.ones(fc.size, bool)
    others[[np.argmin(np.abs(fc - f)) for f in amplitudes]] = False
    assert np.all(level[others] < -100.0)
    # The first band holds f_min, the last holds f_max.
    assert fc[0] * 10**-0.05 <= 50.0 < fc[0] * 10**0.05
    assert fc[-1] * 10**-0.05 <= 10_000.0 < fc[-1] * 10**0.05


def test_third_octave_drops_bands_above_nyquist():
    fc, _ = third_octave(_noise(1.0), 8000.0)
    assert fc[-1] * 10**0.05 <= 4000.0
    with pytest.raises(ValueError, match="f_max"):
        third_octave(_noise(1.0), 8000.0, f_max=5000.0)


def test_psd_integrates_to_variance_and_finds_a_tone():
    x = _noise()
    f, pxx = psd(x, FS)
    assert np.sum(pxx) * (f[1] - f[0]) == pytest.approx(np.var(x), rel=0.02)
    t = np.arange(x.size) / FS
    f, pxx = psd(0.01 * x + np.sin(2 * np.pi * 5000.0 * t), FS)
    assert f[np.argmax(pxx)] == pytest.approx(5000.0, abs=FS / 4096)


def test_stft_reads_a_tones_amplitude_in_its_bin():
    t = np.arange(int(FS / 4)) / FS
    amplitude, f0 = 3.0, 1500.0  # bins are 48000/256 = 187.5 Hz apart: 1500 Hz is bin 8
    x = amplitude * np.sin(2 * np.pi * f0 * t)
    f, frames, Z = stft(x, FS, nperseg=256)
    assert Z.shape == (129, frames.size)
    assert frames.size == 1 + (x.size - 256) // 128
    k = np.argmin(np.abs(f - f0))
    assert f[k] == pytest.approx(f0)
    np.testing.assert_allclose(np.abs(Z[k]), amplitude / 2, rtol=1e-6)
    assert frames[0] == pytest.approx(128 / FS)


@pytest.mark.parametrize(
    "call",
    [
        lambda x: stft(x[:100], FS, nperseg=256),
        lambda x: stft(x, FS, nperseg=256, noverlap=256),
        lambda x: stft(x, FS, window="no-such-window"),
        lambda x: psd(x[:1000], FS, nperseg=4096),
        lambda x: third_octave(x, FS, f_min=-1.0),
        lambda x: third_octave(x, FS, f_min=30_000.0, f_max=24_000.0),
        lambda x: psd(x, -1.0),
    ],
)
def test_spectral_functions_reject_bad_arguments(call):
    with pytest.raises(ValueError):
        call(_noise(0.5))
