"""read_signal: round trips through every supported format, and clear errors."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from scipy.io import savemat, wavfile

from diagnostics import read_signal

FS = 12_000.0


@pytest.fixture
def samples() -> np.ndarray:
    return np.random.default_rng(11).normal(size=600)


def test_csv_with_header_time_column_and_named_channel(tmp_path, samples):
    t = np.arange(samples.size) / FS
    path = tmp_path / "record.csv"
    pd.DataFrame({"time_s": t, "accel": samples, "speed": 2 * samples}).to_csv(path, index=False)
    sig = read_signal(path, channel="speed")
    np.testing.assert_allclose(sig.x, 2 * samples, rtol=1e-12)
    assert sig.fs == pytest.approx(FS, rel=1e-9)  # from the time column
    assert sig.name == "speed"
    default = read_signal(path)  # first column that is not time
    assert default.name == "accel"
    np.testing.assert_allclose(default.x, samples, rtol=1e-12)
    assert read_signal(path, channel=2).name == "speed"
    assert default.meta["channels"] == ["time_s", "accel", "speed"]


def test_headerless_whitespace_txt_by_index(tmp_path, samples):
    path = tmp_path / "record.txt"
    np.savetxt(path, np.column_stack([samples, -samples]), fmt="%.17g")
    sig = read_signal(path, channel=1, fs=FS)
    np.testing.assert_array_equal(sig.x, -samples)
    assert sig.fs == FS


def test_wav_int16_scaled_and_fs_from_file(tmp_path, samples):
    path = tmp_path / "record.wav"
    pcm = np.round(np.clip(samples / 4, -1, 1) * 32767).astype(np.int16)
    stereo = np.column_stack([pcm, -pcm])
    wavfile.write(path, int(FS), stereo)
    sig = read_signal(path, channel=1)
    assert sig.fs == FS
    np.testing.assert_allclose(sig.x, -pcm / 32768.0)
    assert read_signal(path).name == "channel0"


def test_wav_float32(tmp_path, samples):
    path = tmp_path / "float.wav"
    wavfile.write(path, 48_000, samples.astype(np.float32))
    sig = read_signal(path)
    np.testing.assert_allclose(sig.x, samples.astype(np.float32))
    assert sig.fs == 48_000.0


def test_mat_variable_and_fs_variable(tmp_path, samples):
    path = tmp_path / "record.mat"
    savemat(path, {"vib": samples[:, None], "other": samples[:10], "fs": FS})
    sig = read_signal(path, channel="vib")
    np.testing.assert_array_equal(sig.x, samples)
    assert sig.fs == FS and sig.meta["fs_file"] == FS


def test_cwru_style_mat_defaults_to_drive_end_and_reports_rpm(tmp_path, samples):
    path = tmp_path / "12k_Drive_End_OR007@6_0_130.mat"
    savemat(
        path,
        {
            "X130_DE_time": samples[:, None],
            "X130_FE_time": -samples[:, None],
            "X130_BA_time": 0.5 * samples[:, None],
            "X130RPM": np.array([[1796]], dtype=np.uint16),
        },
    )
    sig = read_signal(path, fs=FS)
    assert sig.name == "X130_DE_time"
    np.testing.assert_array_equal(sig.x, samples)
    assert sig.meta["rpm"] == 1796.0
    fan_end = read_signal(path, channel="X130_FE_time", fs=FS)
    np.testing.assert_array_equal(fan_end.x, -samples)


def test_parquet_with_time_column(tmp_path, samples):
    path = tmp_path / "histories.parquet"
    t = np.arange(samples.size) / FS
    pd.DataFrame({"time_s": t, "s0_ay": samples}).to_parquet(path)
    sig = read_signal(path, channel="s0_ay")
    np.testing.assert_array_equal(sig.x, samples)
    assert sig.fs == pytest.approx(FS, rel=1e-9)


def test_npy_1d_and_2d(tmp_path, samples):
    path = tmp_path / "x.npy"
    np.save(path, samples)
    sig = read_signal(path, fs=FS)
    np.testing.assert_array_equal(sig.x, samples)
    path2 = tmp_path / "xy.npy"
    np.save(path2, np.column_stack([samples, 3 * samples]))
    np.testing.assert_array_equal(read_signal(path2, channel=1, fs=FS).x, 3 * samples)


def test_npz_with_fs_key(tmp_path, samples):
    path = tmp_path / "x.npz"
    np.savez(path, accel=samples, fs=np.float64(FS))
    sig = read_signal(path)
    np.testing.assert_array_equal(sig.x, samples)
    assert sig.fs == FS and sig.name == "accel"


def test_measured_cwru_record(cwru_dir):
    sig = read_signal(cwru_dir / "normal_0_97.mat", fs=48_000.0)
    assert sig.name == "X097_DE_time"
    assert sig.x.size == 243_938
    assert sig.meta["rpm"] == 1796.0
    # Accelerometer in g on a healthy bearing: zero-mean vibration of order 0.01-1 g.
    assert abs(sig.x.mean()) < 0.1 and 0.01 < sig.x.std() < 1.0
    inner = read_signal(cwru_dir / "12k_Drive_End_IR007_0_105.mat", fs=12_000.0)
    assert inner.name == "X105_DE_time" and inner.meta["rpm"] == 1797.0


def test_missing_file(tmp_path):
    with pytest.raises(ValueError, match="file not found"):
        read_signal(tmp_path / "nope.csv", fs=FS)


def test_unknown_channel_lists_available(tmp_path, samples):
    path = tmp_path / "record.csv"
    pd.DataFrame({"a": samples, "b": samples}).to_csv(path, index=False)
    with pytest.raises(ValueError, match=r"no channel 'c'; available: a, b"):
        read_signal(path, channel="c", fs=FS)
    mat = tmp_path / "record.mat"
    savemat(mat, {"vib": samples})
    with pytest.raises(ValueError, match="available: vib"):
        read_signal(mat, channel="acc", fs=FS)


def test_missing_fs(tmp_path, samples):
    path = tmp_path / "x.npy"
    np.save(path, samples)
    with pytest.raises(ValueError, match="no sampling rate; give fs"):
        read_signal(path)


def test_fs_contradicting_the_file(tmp_path, samples):
    path = tmp_path / "record.wav"
    wavfile.write(path, int(FS), samples.astype(np.float32))
    with pytest.raises(ValueError, match="contradicts"):
        read_signal(path, fs=48_000.0)


def test_non_finite_and_empty_data(tmp_path, samples):
    bad = samples.copy()
    bad[5] = np.nan
    path = tmp_path / "bad.npy"
    np.save(path, bad)
    with pytest.raises(ValueError, match="NaN or inf"):
        read_signal(path, fs=FS)
    empty = tmp_path / "empty.csv"
    empty.write_text("accel\n")
    with pytest.raises(ValueError, match="empty|no data"):
        read_signal(empty, fs=FS)


def test_unsupported_extension(tmp_path):
    path = tmp_path / "x.xlsx"
    path.write_bytes(b"\x00")
    with pytest.raises(ValueError, match="unsupported file type"):
        read_signal(path, fs=FS)


def test_corrupt_file_is_one_line_value_error(tmp_path):
    path = tmp_path / "x.wav"
    path.write_bytes(b"not a wave file")
    with pytest.raises(ValueError, match="cannot read as wav"):
        read_signal(path)
