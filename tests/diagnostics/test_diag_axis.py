"""``axis`` on the array functions, as scipy.signal has it: a multi-channel array gives, for
each channel, exactly what the 1-D call gives; ``axis=0`` is the transpose; a bad axis is a
clear ValueError."""

from __future__ import annotations

import numpy as np
import pytest

import diagnostics as dg

FS = 12000.0
RNG = np.random.default_rng(4)
# Three channels of 1 s: noise, a tone in noise, and noise with impacts.
CHANNELS = RNG.standard_normal((3, int(FS)))
CHANNELS[1] += 3.0 * np.sin(2 * np.pi * 1500.0 * np.arange(int(FS)) / FS)
CHANNELS[2, ::997] += 25.0

# name -> call taking (x, axis) and returning the array compared (time or frequency axis
# where the time axis was)
CALLS = {
    "notch_filter": lambda x, axis: dg.notch_filter(x, FS, 1500.0, axis=axis),
    "bandpass_filter": lambda x, axis: dg.bandpass_filter(x, FS, 1000.0, 3000.0, axis=axis),
    "lowpass_filter": lambda x, axis: dg.lowpass_filter(x, FS, 800.0, axis=axis),
    "envelope": lambda x, axis: dg.envelope(x, FS, band=(1000.0, 3000.0), axis=axis),
    "envelope_spectrum": lambda x, axis: dg.envelope_spectrum(x, FS, axis=axis)[1],
    "psd": lambda x, axis: dg.psd(x, FS, nperseg=1024, axis=axis)[1],
    "third_octave": lambda x, axis: dg.third_octave(x, FS, f_min=50.0, axis=axis)[1],
    "spectral_kurtosis": lambda x, axis: dg.spectral_kurtosis(x, FS, nw=128, axis=axis)[1],
    "order_track": lambda x, axis: dg.order_track(x, FS, 20.0, 256, axis=axis).x,
    "prewhiten": lambda x, axis: dg.prewhiten(x, FS, axis=axis),
    "discrete_random_separation": lambda x, axis: (
        dg.discrete_random_separation(x, FS, nfft=256, axis=axis).random
    ),
}


@pytest.mark.parametrize("name", sorted(CALLS))
def test_each_channel_equals_the_one_channel_call(name):
    call = CALLS[name]
    together = call(CHANNELS, -1)
    for i, channel in enumerate(CHANNELS):
        np.testing.assert_allclose(together[i], call(channel, -1), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(call(CHANNELS.T, 0), together.T, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("name", sorted(CALLS))
def test_bad_axis_is_named(name):
    with pytest.raises(ValueError, match=r"axis 2 is out of range for x of shape \(3, 12000\)"):
        CALLS[name](CHANNELS, 2)


def test_column_vector_is_one_record_as_before():
    column = CHANNELS[1][:, None]
    np.testing.assert_allclose(
        dg.bandpass_filter(column, FS, 1000.0, 3000.0),
        dg.bandpass_filter(CHANNELS[1], FS, 1000.0, 3000.0),
    )


def test_stft_puts_channels_first_as_scipy_does():
    f, t, Z = dg.stft(CHANNELS, FS, nperseg=256)
    _, _, single = dg.stft(CHANNELS[1], FS, nperseg=256)
    assert Z.shape == (3, f.size, t.size)
    np.testing.assert_allclose(Z[1], single)
    # The tone of channel 1 reads half its amplitude in its bin.
    assert np.abs(Z[1, np.argmin(np.abs(f - 1500.0))]).mean() == pytest.approx(1.5, rel=0.05)


def test_nan_in_one_channel_is_located():
    bad = CHANNELS.copy()
    bad[2, 17] = np.nan
    with pytest.raises(ValueError, match=r"NaN or inf \(first at sample 17 of channel 2\)"):
        dg.psd(bad, FS, nperseg=256)


def test_signal_data_feeds_the_axis_functions(tmp_path):
    path = tmp_path / "three.npz"
    np.savez(path, de=CHANNELS[0], fe=CHANNELS[1], ba=CHANNELS[2], fs=FS)
    sig = dg.read_signal(path, channel="fe")
    assert sig.channel_names == ["de", "fe", "ba"]
    f, p = dg.psd(sig.data, sig.fs, nperseg=1024)
    np.testing.assert_allclose(p[1], dg.psd(sig.x, sig.fs, nperseg=1024)[1])
    np.testing.assert_array_equal(sig.channel("ba"), CHANNELS[2])
    np.testing.assert_array_equal(sig.channel(0), CHANNELS[0])
    with pytest.raises(ValueError, match="no channel 'tacho'; available: de, fe, ba"):
        sig.channel("tacho")


def test_separation_keeps_one_coherence_per_channel():
    parts = dg.discrete_random_separation(CHANNELS, FS, nfft=256)
    assert parts.discrete.shape == CHANNELS.shape and parts.coherence.shape == (3, 129)
    one = dg.discrete_random_separation(CHANNELS[1], FS, nfft=256)
    np.testing.assert_array_equal(parts.coherence[1], one.coherence)
    # The 1500 Hz tone of channel 1 is discrete; channel 0 (noise) has no coherent bin.
    assert np.interp(1500.0, one.f, one.coherence) > 0.9
    assert parts.coherence[0].max() < 0.5
