"""Spectral kurtosis and the fast kurtogram (checked against the straightforward port)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from benchmarks.diagnostics.kurtogram_reference import reference_kurtogram
from diagnostics import kurtogram, sk_threshold, spectral_kurtosis
from diagnostics._kurtosis import analysis_filters, kurtogram_levels

FS = 20_000.0
RESONANCE = 3500.0


def _impacts(n: int, rate: float, seed: int, noise: float = 1.0, amp: float = 2.0):
    """Decaying 3.5 kHz resonances at ``rate`` per second, buried in white noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / FS
    x = noise * rng.normal(size=n)
    ring = np.arange(int(0.02 * FS)) / FS
    burst = amp * np.exp(-1500.0 * ring) * np.sin(2 * np.pi * RESONANCE * ring)
    for start in np.arange(0.005, t[-1] - 0.02, 1.0 / rate):
        i = int(start * FS)
        x[i : i + burst.size] += burst
    return x


def test_sk_of_white_noise_stays_below_the_gaussian_threshold():
    x = np.random.default_rng(0).normal(size=200_000)
    result = spectral_kurtosis(x, FS, nw=128)
    f, sk = result
    inner = sk[1:-1]
    # The threshold rests on std(SK) = 2 / sqrt(frames) for Gaussian noise: check that basis.
    assert np.std(inner) == pytest.approx(2 / np.sqrt(result.n_frames), rel=0.2)
    # With a Bonferroni-corrected false-alarm rate no bin may exceed it.
    assert inner.max() < result.threshold(p=0.01 / inner.size)
    # No offset: a wrong Gaussian reference (e.g. - 3, the real-signal value) would give -1.
    assert abs(inner.mean()) < 2 / np.sqrt(result.n_frames)
    assert f[-1] == FS / 2 and f.size == 65


def test_sk_peaks_at_the_resonance_of_buried_impacts():
    x = _impacts(100_000, rate=23.0, seed=1, amp=3.0)
    result = spectral_kurtosis(x, FS, nw=64)
    f, sk = result
    assert abs(f[np.argmax(sk)] - RESONANCE) <= FS / 64
    assert sk.max() > 5 * result.threshold(p=0.01)
    far = (f > 500) & (f < 1500)
    assert np.all(sk[far] < result.threshold(p=0.001))


def test_sk_of_a_pure_tone_is_minus_one():
    # A stationary tone has a constant STFT modulus: <|X|^4> / <|X|^2>^2 = 1, SK = -1.
    t = np.arange(40_000) / FS
    f, sk = spectral_kurtosis(np.sin(2 * np.pi * 2500.0 * t), FS, nw=128)
    assert sk[np.argmin(np.abs(f - 2500.0))] == pytest.approx(-1.0, abs=1e-6)


def test_sk_threshold_is_the_normal_quantile_over_sqrt_frames():
    assert sk_threshold(400, p=0.025) == pytest.approx(1.959964 * 2 / 20, rel=1e-5)
    with pytest.raises(ValueError, match="p"):
        sk_threshold(100, p=1.5)


def test_analysis_filters_cover_their_bands():
    filters = analysis_filters()
    assert filters["h"].size == 17 and filters["g"].size == 16
    centres = {"h": 0.125, "g": 0.375, "h1": 1 / 12, "h2": 3 / 12, "h3": 5 / 12}
    for name, centre in centres.items():
        w, response = signal.freqz(filters[name], worN=4096, whole=True)
        gain = np.abs(response)
        f = w / (2 * np.pi)
        assert gain[np.argmin(np.abs(f - centre))] == pytest.approx(1.0, abs=0.02)
        # Quasi-analytic: the mirror frequency -centre (i.e. 1 - centre) is attenuated; with
        # the reference's short, wide prototypes (cut-off 0.4) by about 18 dB.
        assert gain[np.argmin(np.abs(f - (1 - centre)))] < 0.15


def test_kurtogram_layout_and_levels():
    x = _impacts(2**14, rate=20.0, seed=2)
    kg = kurtogram(x, FS, nlevel=5)
    assert kg.K.shape == (10, 96)
    np.testing.assert_allclose(kg.levels, kurtogram_levels(5))
    np.testing.assert_allclose(kg.levels[:5], [0, 1, np.log2(3), 2, 1 + np.log2(3)])
    assert kg.levels[-1] == 5
    np.testing.assert_allclose(np.diff(kg.freqs), FS / 2 / 96)
    assert kg.freqs[0] == pytest.approx(FS / 2 / 96 / 2)
    # Row r holds 2**level bands (3 * 2**(level - log2 3) for the 1/3 rows), each repeated.
    for row, level in enumerate(kg.levels):
        n_bands = round(2**level)
        bands = kg.K[row].reshape(n_bands, -1)
        assert np.all(bands == bands[:, :1])
    assert np.all(kg.K >= 0)
    assert kg.kurtosis == kg.K.max()
    assert kg.bw == pytest.approx(FS * 2.0 ** -(kg.level + 1))


def test_kurtogram_best_band_holds_the_resonance():
    x = _impacts(2**16, rate=15.0, seed=3, noise=1.0, amp=3.0)
    kg = kurtogram(x, FS, nlevel=6)
    lo, hi = kg.band
    assert lo <= RESONANCE <= hi
    assert kg.bw < FS / 16  # a narrow band around the resonance, not a wide one
    assert kg.kurtosis > 0.5


@pytest.mark.parametrize(
    ("n", "nlevel", "seed"), [(2**13 + 37, 4, 4), (3 * 2**12 + 5, 5, 5), (2**15 + 1, 7, 6)]
)
def test_fast_kurtogram_equals_the_straightforward_reference(n, nlevel, seed):
    x = _impacts(n, rate=31.0, seed=seed, noise=1.0, amp=1.0) + 0.3
    fast = kurtogram(x, FS, nlevel=nlevel)
    ref = reference_kurtogram(x, FS, nlevel=nlevel)
    np.testing.assert_allclose(fast.K, ref["K"], rtol=0, atol=1e-10)
    assert (fast.row, fast.column) == (ref["row"], ref["column"])
    assert fast.level == ref["level"]
    assert fast.fc == pytest.approx(ref["fc"], rel=1e-12)
    assert fast.bw == pytest.approx(ref["bw"], rel=1e-12)
    assert fast.kurtosis == pytest.approx(ref["kurtosis"], abs=1e-10)
    np.testing.assert_allclose(fast.freqs, ref["freqs"])


def _logistic_test_signal(n: int = 2**15) -> np.ndarray:
    """Logistic-map pseudo-noise (plain IEEE arithmetic, the same on every machine) plus
    decaying 3.1 kHz resonances 37 times a second."""
    value, noise = 0.3141592653589793, []
    for _ in range(n):
        value = 3.99 * value * (1.0 - value)
        noise.append(value)
    x = np.array(noise) - 0.5
    t = np.arange(n) / FS
    ring = t[:200]
    burst = 0.8 * np.exp(-900.0 * ring) * np.sin(2 * np.pi * 3100.0 * ring)
    for start in np.arange(0.004, t[-1] - 0.01, 1 / 37.0):
        i = int(round(start * FS))
        x[i : i + 200] += burst
    return x


# Antoni's own Fast_kurtogram.m (revision 12-2014), run in GNU Octave 7.3 on the signal
# above with nlevel = 6 and fir1 as MATLAB defines it (Hamming-windowed ideal response;
# Octave's fir1 samples the frequency response instead and differs by about 1e-3):
# best cell (I, J) = (9, 57), 1-based, and the maximum of every row of Kwav.
ANTONI_BEST_CELL = (9, 57)
ANTONI_FC, ANTONI_BW, ANTONI_KMAX = 3125.0, 416.66666666666669, 1.5714369037892317
ANTONI_ROW_MAX = [
    0.0, 0.07927944531731956, 0.2978342699173484, 0.1197366792955914,
    0.751002458483947, 0.7819294184292427, 1.358418525495122, 1.3848924360995438,
    1.5714369037892317, 1.2903900352748008, 1.0868631999472123, 0.8313152913105615,
]  # fmt: skip


def test_kurtogram_reproduces_antonis_matlab_code():
    kg = kurtogram(_logistic_test_signal(), FS, nlevel=6)
    assert (kg.row + 1, kg.column + 1) == ANTONI_BEST_CELL
    assert kg.fc == pytest.approx(ANTONI_FC, rel=1e-12)
    assert kg.bw == pytest.approx(ANTONI_BW, rel=1e-12)
    assert kg.kurtosis == pytest.approx(ANTONI_KMAX, abs=1e-10)
    np.testing.assert_allclose(kg.K.max(axis=1), ANTONI_ROW_MAX, rtol=0, atol=1e-10)


def test_reference_formula_for_best_band_centre():
    # fi = (J - 1)/3/2**(nlevel+1) + 2**(-2-level) with J the 1-based first column.
    x = _impacts(2**14, rate=20.0, seed=7)
    kg = kurtogram(x, FS, nlevel=5)
    expected = FS * (kg.column / 3 / 2**6 + 2.0 ** (-2 - kg.level))
    assert kg.fc == pytest.approx(expected)
    assert kg.K[kg.row, kg.column] == kg.kurtosis
    assert kg.column == 0 or kg.K[kg.row, kg.column - 1] != kg.kurtosis


@pytest.mark.parametrize(
    ("x", "nlevel", "fragment"),
    [
        (np.ones(2**11), 5, "too short"),
        (np.zeros(2**14), 4, "constant"),
        (np.random.default_rng(0).normal(size=2**14), 0, "nlevel"),
        (np.full(2**14, np.nan), 4, "NaN"),
    ],
)
def test_kurtogram_rejects_bad_input(x, nlevel, fragment):
    with pytest.raises(ValueError, match=fragment):
        kurtogram(x, FS, nlevel=nlevel)


def test_spectral_kurtosis_rejects_short_signal():
    with pytest.raises(ValueError, match="too short"):
        spectral_kurtosis(np.ones(100), FS, nw=256)
