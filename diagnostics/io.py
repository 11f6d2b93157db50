"""Read one vibration channel from a measured or simulated file.

Formats, chosen by extension: CSV/TXT (a column by name or index), WAV (fs from the file),
MAT (a variable by name; CWRU bearing-data files default to the drive-end channel and report
the shaft speed), Parquet, NPY and NPZ. The sampling rate comes from the file where it holds
one (WAV header, a time column, an ``fs`` variable or key), else it must be given.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from diagnostics._checks import check_fs, check_signal

SUPPORTED_SUFFIXES = (".csv", ".txt", ".wav", ".mat", ".parquet", ".npy", ".npz")
# Names under which files commonly store their sampling rate (compared case-insensitively).
_FS_NAMES = ("fs", "fsamp", "sample_rate", "sampling_rate", "samplerate", "sample_rate_hz")
_TIME_NAMES = ("t", "time", "time_s", "times", "time [s]", "time(s)", "seconds")
# Two sampling rates closer than this are the same rate (time columns are printed rounded).
_FS_TOLERANCE = 0.01


@dataclass(frozen=True)
class Signal:
    """One channel read from a file.

    Attributes
    ----------
    x : numpy.ndarray
        Samples, 1-D float64, finite.
    fs : float
        Sampling rate in Hz.
    name : str
        Channel name (column, variable or key), or the file stem for single-channel files.
    meta : dict
        ``path``, ``format``, ``channel``, ``channels`` (all channels the file offers) and,
        where the file holds them, ``rpm`` (shaft speed) and ``fs_file``.
    """

    x: np.ndarray
    fs: float
    name: str
    meta: dict = field(default_factory=dict)

    @property
    def duration(self) -> float:
        """Length of the record in seconds."""
        return self.x.size / self.fs


def read_signal(path, channel=None, fs: float | None = None) -> Signal:
    """Read one channel of a vibration record.

    Parameters
    ----------
    path : str or path-like
        File to read: .csv, .txt, .wav, .mat, .parquet, .npy or .npz.
    channel : str or int, optional
        Column name or index (CSV/TXT/Parquet), channel index (WAV, NPY with 2-D data),
        variable name (MAT) or key (NPZ). By default: the only data channel; the first
        column that is not a time column; for CWRU .mat files the ``*_DE_time`` channel;
        WAV channel 0.
    fs : float, optional
        Sampling rate in Hz. Required where the file holds none; where it does, a given
        ``fs`` must agree with it within 1 %.

    Returns
    -------
    Signal
        The samples, the sampling rate, the channel name and metadata.

    Raises
    ------
    ValueError
        For a missing or unreadable file, an unsupported extension, an unknown channel (the
        message lists the available ones), empty or non-finite data, a missing sampling rate,
        or a given ``fs`` that contradicts the file.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"file not found: {path}")
    if fs is not None:
        fs = check_fs(fs)
    suffix = path.suffix.lower()
    readers = {
        ".csv": _read_table,
        ".txt": _read_table,
        ".parquet": _read_table,
        ".wav": _read_wav,
        ".mat": _read_mat,
        ".npy": _read_npy,
        ".npz": _read_npz,
    }
    if suffix not in readers:
        raise ValueError(
            f"{path}: unsupported file type {suffix or '(none)'}; "
            f"supported: {', '.join(SUPPORTED_SUFFIXES)}"
        )
    try:
        data, name, fs_file, meta = readers[suffix](path, channel)
    except Exception as exc:
        if isinstance(exc, ValueError) and str(exc).startswith(str(path)):
            raise  # our own message, already naming the file
        # Corrupt or foreign files: one line naming the file and what the parser said.
        raise ValueError(f"{path}: cannot read as {suffix[1:]} ({exc})") from None
    rate = _resolve_fs(path, fs, fs_file)
    x = check_signal(data, rate, name=f"{path.name}:{name}")
    meta = {"path": str(path), "format": suffix[1:], "channel": name, **meta}
    if fs_file is not None:
        meta["fs_file"] = fs_file
    return Signal(x=x, fs=rate, name=name, meta=meta)


def _resolve_fs(path: Path, fs: float | None, fs_file: float | None) -> float:
    if fs_file is None:
        if fs is None:
            raise ValueError(
                f"{path}: the file holds no sampling rate; give fs (Hz), e.g. fs=12000"
            )
        return fs
    if fs is not None and abs(fs - fs_file) > _FS_TOLERANCE * fs_file:
        raise ValueError(
            f"{path}: fs = {fs:g} Hz contradicts the file's sampling rate {fs_file:g} Hz"
        )
    return fs if fs is not None else fs_file


def _unknown_channel(path: Path, channel, available) -> ValueError:
    listed = ", ".join(str(c) for c in available) or "(none)"
    return ValueError(f"{path}: no channel {channel!r}; available: {listed}")


def _is_time_name(name) -> bool:
    return str(name).strip().lower() in _TIME_NAMES


def _is_fs_name(name) -> bool:
    return str(name).strip().lower() in _FS_NAMES


def _fs_from_time(path: Path, t: np.ndarray) -> float:
    """Sampling rate of a uniformly sampled time column."""
    t = np.asarray(t, dtype=float)
    if t.size < 2 or not np.all(np.isfinite(t)):
        raise ValueError(f"{path}: the time column must hold at least two finite values")
    step = np.diff(t)
    mean_step = (t[-1] - t[0]) / (t.size - 1)
    if mean_step <= 0 or np.max(np.abs(step - mean_step)) > _FS_TOLERANCE * mean_step + 1e-12:
        raise ValueError(f"{path}: the time column is not uniformly increasing")
    return 1.0 / mean_step


# --------------------------------------------------------------------------------- tables
def _read_table(path: Path, channel):
    import pandas as pd

    if path.suffix.lower() == ".parquet":
        frame = pd.read_parquet(path)
    else:
        frame = _read_text_table(path)
    if frame.shape[0] == 0 or frame.shape[1] == 0:
        raise ValueError(f"{path}: the file holds no data")
    columns = list(frame.columns)
    time_columns = [c for c in columns if _is_time_name(c)]
    data_columns = [c for c in columns if c not in time_columns]
    if channel is None:
        if not data_columns:
            raise ValueError(f"{path}: no data column besides time; columns: {columns}")
        name = data_columns[0]
    elif channel in columns:
        name = channel
    elif isinstance(channel, int | np.integer) and not isinstance(channel, bool):
        if not -len(columns) <= channel < len(columns):
            raise _unknown_channel(path, channel, range(len(columns)))
        name = columns[channel]
    else:
        raise _unknown_channel(path, channel, columns)
    values = pd.to_numeric(frame[name], errors="coerce").to_numpy(dtype=float)
    fs_file = _fs_from_time(path, frame[time_columns[0]]) if time_columns else None
    return values, str(name), fs_file, {"channels": [str(c) for c in columns]}


def _read_text_table(path: Path):
    """CSV or whitespace-separated text, with or without a header row."""
    import pandas as pd

    with path.open("r", encoding="utf-8", errors="replace") as handle:
        lines = [line for line in handle.readlines() if line.strip() and line[0] != "#"]
    if not lines:
        raise ValueError(f"{path}: the file holds no data")
    first = lines[0]
    sep = "," if "," in first else (";" if ";" in first else r"\s+")
    fields = [f for f in re.split(sep, first.strip()) if f != ""]
    header = None if all(_is_number(f) for f in fields) else 0
    frame = pd.read_csv(path, sep=sep, header=header, comment="#", engine="python")
    if header is None:
        frame.columns = list(range(frame.shape[1]))
    else:
        frame.columns = [str(c).strip() for c in frame.columns]
    return frame


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


# ------------------------------------------------------------------------------------ wav
def _read_wav(path: Path, channel):
    from scipy.io import wavfile

    rate, data = wavfile.read(path)
    data = np.asarray(data)
    if data.dtype.kind in "iu":
        # Integer PCM scaled to [-1, 1): unsigned 8-bit is offset by 128.
        info = np.iinfo(data.dtype)
        offset = 128.0 if data.dtype == np.uint8 else 0.0
        data = (data.astype(float) - offset) / (float(info.max) + 1.0 - offset)
    n_channels = 1 if data.ndim == 1 else data.shape[1]
    index = _channel_index(path, channel, n_channels)
    values = data if data.ndim == 1 else data[:, index]
    return values, f"channel{index}", float(rate), {"channels": list(range(n_channels))}


def _channel_index(path: Path, channel, n_channels: int) -> int:
    if channel is None:
        return 0
    if isinstance(channel, str) and channel.startswith("channel"):
        channel = channel[len("channel") :]
    try:
        index = int(channel)
    except (TypeError, ValueError):
        raise _unknown_channel(path, channel, range(n_channels)) from None
    if not 0 <= index < n_channels:
        raise _unknown_channel(path, channel, range(n_channels))
    return index


# ------------------------------------------------------------------------------------ mat
def _read_mat(path: Path, channel):
    from scipy.io import loadmat

    try:
        variables = loadmat(path)
    except NotImplementedError:
        raise ValueError(
            f"{path}: MATLAB v7.3 (HDF5) files are not supported; save with -v7"
        ) from None
    variables = {k: v for k, v in variables.items() if not k.startswith("__")}
    numeric = {
        k: np.asarray(v)
        for k, v in variables.items()
        if isinstance(v, np.ndarray) and v.dtype.kind in "biuf"
    }
    vectors = [k for k, v in numeric.items() if v.size > 1 and min(v.shape) == 1]
    meta: dict = {"channels": sorted(vectors)}
    if channel is None:
        name = _default_mat_channel(path, vectors)
    elif channel in numeric:
        name = channel
    else:
        raise _unknown_channel(path, channel, sorted(vectors))
    rpm = _cwru_rpm(name, numeric)
    if rpm is not None:
        meta["rpm"] = rpm
    fs_file = _scalar_named(numeric, _is_fs_name)
    return numeric[name].reshape(-1), name, fs_file, meta


def _default_mat_channel(path: Path, vectors: list[str]) -> str:
    """The drive-end channel of a CWRU file, or the only vector variable."""
    drive_end = sorted(k for k in vectors if k.endswith("_DE_time"))
    if drive_end:
        # Some CWRU files carry a second record's channels; prefer the file's own number.
        number = re.search(r"(\d+)$", path.stem)
        for name in drive_end:
            own = re.match(r"X0*(\d+)_DE_time$", name)
            if number and own and int(own.group(1)) == int(number.group(1)):
                return name
        return drive_end[0]
    if len(vectors) == 1:
        return vectors[0]
    listed = ", ".join(sorted(vectors)) or "(none)"
    raise ValueError(f"{path}: several variables, choose a channel; available: {listed}")


def _cwru_rpm(channel: str, numeric: dict) -> float | None:
    """Shaft speed from the ``XNNNRPM`` variable matching the channel, else the only one."""
    rpm_names = sorted(k for k in numeric if k.upper().endswith("RPM") and numeric[k].size == 1)
    prefix = channel.split("_")[0]
    for name in rpm_names:
        if name.startswith(prefix):
            return float(numeric[name].reshape(-1)[0])
    if len(rpm_names) == 1:
        return float(numeric[rpm_names[0]].reshape(-1)[0])
    return None


def _scalar_named(numeric: dict, wanted) -> float | None:
    for key, value in numeric.items():
        if wanted(key) and np.asarray(value).size == 1:
            rate = float(np.asarray(value).reshape(-1)[0])
            if math.isfinite(rate) and rate > 0:
                return rate
    return None


# -------------------------------------------------------------------------------- npy/npz
def _read_npy(path: Path, channel):
    data = np.load(path, allow_pickle=False)
    return _array_channel(path, data, channel, path.stem)


def _array_channel(path: Path, data: np.ndarray, channel, name: str):
    data = np.asarray(data)
    if data.ndim <= 1:
        if channel not in (None, 0, name):
            raise _unknown_channel(path, channel, [0])
        return data.reshape(-1), name, None, {"channels": [name]}
    if data.ndim != 2:
        raise ValueError(f"{path}: expected a 1-D or 2-D array, got shape {data.shape}")
    # Samples run along the longer axis; channels along the shorter one.
    columns = data if data.shape[0] >= data.shape[1] else data.T
    n_channels = columns.shape[1]
    index = _channel_index(path, channel, n_channels)
    return columns[:, index], f"{name}[{index}]", None, {"channels": list(range(n_channels))}


def _read_npz(path: Path, channel):
    with np.load(path, allow_pickle=False) as archive:
        arrays = {k: np.asarray(archive[k]) for k in archive.files}
    fs_file = _scalar_named(arrays, _is_fs_name)
    candidates = [k for k, v in arrays.items() if v.size > 1 and not _is_time_name(k)]
    if channel is None:
        if len(candidates) != 1:
            listed = ", ".join(candidates) or "(none)"
            raise ValueError(f"{path}: choose a channel; available: {listed}")
        name = candidates[0]
    elif channel in arrays:
        name = channel
    else:
        raise _unknown_channel(path, channel, candidates)
    times = [k for k in arrays if _is_time_name(k) and arrays[k].size > 1]
    if fs_file is None and times:
        fs_file = _fs_from_time(path, arrays[times[0]].reshape(-1))
    values = arrays[name]
    if values.ndim > 1 and min(values.shape) == 1:
        values = values.reshape(-1)
    if values.ndim != 1:
        raise ValueError(f"{path}: key {name!r} is not a 1-D array (shape {values.shape})")
    return values, name, fs_file, {"channels": candidates}
