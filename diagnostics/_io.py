"""Read a vibration record, every channel with its name, from a measured or simulated file.

Formats, chosen by extension: CSV/TXT (columns by name or index), WAV (fs from the file),
MAT (variables by name, MATLAB structs flattened to ``struct.field``; CWRU bearing-data files
default to the drive-end channel and report the shaft speed, MFPT files hold a struct
``bearing`` with ``gs``, ``sr`` and the shaft ``rate``), Parquet, NPY and NPZ. The sampling
rate comes from the file where it holds one (WAV header, a time column, an ``fs`` or ``sr``
variable or key), else it must be given.
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
_FS_NAMES = ("fs", "sr", "fsamp", "sample_rate", "sampling_rate", "samplerate", "sample_rate_hz")
_TIME_NAMES = ("t", "time", "time_s", "times", "time [s]", "time(s)", "seconds")
# Two sampling rates closer than this are the same rate (time columns are printed rounded).
_FS_TOLERANCE = 0.01


@dataclass(frozen=True)
class Signal:
    """A record read from a file: the chosen channel, and every channel with its name.

    Attributes
    ----------
    x : numpy.ndarray
        Samples of the chosen channel, 1-D float64, finite.
    fs : float
        Sampling rate in Hz.
    name : str
        Name of the chosen channel (column, variable or key), or the file stem for a
        single-channel file.
    meta : dict
        ``path``, ``format``, ``channel``, ``channels`` (the names of all channels the file
        offers) and, where the file holds them, ``rpm`` (shaft speed) and ``fs_file``.
    channels : dict of str to numpy.ndarray
        Every finite numeric channel of the file with the chosen channel's length, by name,
        in the file's order (the chosen one included): a multi-channel record sampled at
        ``fs``, e.g. a tachometer beside the accelerometer.
    """

    x: np.ndarray
    fs: float
    name: str
    meta: dict = field(default_factory=dict)
    channels: dict = field(default_factory=dict, repr=False)

    @property
    def duration(self) -> float:
        """Length of the record in seconds."""
        return self.x.size / self.fs

    @property
    def data(self) -> np.ndarray:
        """All channels stacked, shape ``(n_channels, n_samples)`` (``channel_names`` order),
        for the functions that take ``axis=-1``."""
        if not self.channels:
            return self.x[None, :]
        return np.stack(list(self.channels.values()))

    @property
    def channel_names(self) -> list[str]:
        """Names of the rows of :attr:`data`."""
        return list(self.channels) if self.channels else [self.name]

    def channel(self, name) -> np.ndarray:
        """Samples of one channel, by name or by index in :attr:`channel_names`.

        Raises
        ------
        ValueError
            If the record has no such channel (the message lists the available ones).
        """
        names = self.channel_names
        key = resolve_channel(self.meta.get("path", "record"), name, names)
        return self.x if key == self.name else np.asarray(self.channels[key])


def read_signal(path, channel=None, fs: float | None = None) -> Signal:
    """Read a vibration record: one chosen channel, and every channel with its name.

    Parameters
    ----------
    path : str or path-like
        File to read: .csv, .txt, .wav, .mat, .parquet, .npy or .npz.
    channel : str or int, optional
        Channel to return as ``x``: a column name (CSV/TXT/Parquet), variable name (MAT,
        ``struct.field`` inside a MATLAB struct), key (NPZ) or ``channelN`` (WAV), or an
        index into ``meta["channels"]``; a string of digits that is not a name is taken as
        an index, as the command line passes it. By default: the only data channel; the
        first column that is not a time column; for CWRU .mat files the ``*_DE_time``
        channel; WAV channel 0.
    fs : float, optional
        Sampling rate in Hz. Required where the file holds none; where it does, a given
        ``fs`` must agree with it within 1 %.

    Returns
    -------
    Signal
        The chosen channel ``x``, the sampling rate, its name, metadata, and ``channels``:
        every finite numeric channel of the same length by name.

    Raises
    ------
    ValueError
        For a missing or unreadable file, a folder, an unsupported extension, an unknown
        channel (the message lists the available ones), a file with no numeric data, empty
        or non-finite data, a missing sampling rate, or a given ``fs`` that contradicts the
        file.

    Examples
    --------
    A file laid out as the CWRU data center's (a drive-end and a fan-end channel and the
    speed in rpm; CWRU files hold no sampling rate, so ``fs`` is given):

    >>> import os, tempfile
    >>> import scipy.io
    >>> path = os.path.join(tempfile.mkdtemp(), "48k_Drive_End_IR007_0_109.mat")
    >>> noise = np.random.default_rng(0).standard_normal((4800, 2))
    >>> scipy.io.savemat(path, {"X109_DE_time": noise[:, :1], "X109_FE_time": noise[:, 1:],
    ...                         "X109RPM": 1797.0})
    >>> sig = read_signal(path, fs=48000)
    >>> sig.name, sig.fs, sig.meta["rpm"], sig.channel_names
    ('X109_DE_time', 48000.0, 1797.0, ['X109_DE_time', 'X109_FE_time'])
    >>> sig.x.shape, sig.data.shape, sig.channel("X109_FE_time").shape
    ((4800,), (2, 4800), (4800,))
    """
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{path}: is a folder, not a file; give one record file")
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
        columns, name, fs_file, meta = readers[suffix](path, channel)
    except Exception as exc:
        if isinstance(exc, ValueError) and str(exc).startswith(str(path)):
            raise  # our own message, already naming the file
        # Corrupt or foreign files: one line naming the file and what the parser said.
        raise ValueError(f"{path}: cannot read as {suffix[1:]} ({exc})") from None
    rate = _resolve_fs(path, fs, fs_file)
    x = check_signal(columns[name], rate, name=f"{path.name}:{name}")
    channels = {}
    for key, values in columns.items():
        if key == name:
            channels[key] = x
            continue
        values = np.asarray(values)
        if values.dtype.kind in "biuf" and values.shape == x.shape:
            values = values.astype(np.float64)
            if np.all(np.isfinite(values)):
                channels[key] = values
    meta = {"path": str(path), "format": suffix[1:], "channel": name, **meta}
    if fs_file is not None:
        meta["fs_file"] = fs_file
    return Signal(x=x, fs=rate, name=name, meta=meta, channels=channels)


_RPM_NAMES = ("rpm", "speed_rpm", "shaft_rpm")
_HZ_NAMES = ("shaft_hz", "speed_hz", "hz", "rate_hz", "frequency_hz")


def read_speed_profile(path, fs: float, n_samples: int) -> np.ndarray:
    """Shaft rate at every sample of a record, from a speed-profile table.

    Parameters
    ----------
    path : str or path-like
        CSV or TXT table with a time column (``time_s``, ``t``, ``time``, ...) and a speed
        column, ``rpm`` (rev/min) or ``shaft_hz`` (Hz), at any increasing times.
    fs : float
        Sampling rate of the record, Hz.
    n_samples : int
        Length of the record.

    Returns
    -------
    numpy.ndarray
        Shaft rate (Hz) at each sample time :math:`k / f_s`: linear between the table's rows,
        held before the first and after the last.

    Raises
    ------
    ValueError
        For a missing or unreadable file, a missing time or speed column, times not
        increasing, speeds not finite and positive, or a table that ends before a tenth of
        the record has passed.
    """
    import pandas as pd

    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{path}: is a folder, not a speed-profile file")
    if not path.is_file():
        raise ValueError(f"file not found: {path}")
    fs = check_fs(fs)
    try:
        frame = _read_text_table(path)
    except ValueError:
        raise
    except Exception as exc:
        raise ValueError(f"{path}: cannot read as a table ({exc})") from None
    names = {str(c).strip().lower(): c for c in frame.columns}
    time_key = next((names[k] for k in names if _is_time_name(k)), None)
    rpm_key = next((names[k] for k in _RPM_NAMES if k in names), None)
    hz_key = next((names[k] for k in _HZ_NAMES if k in names), None)
    if time_key is None or (rpm_key is None and hz_key is None):
        raise ValueError(
            f"{path}: a speed profile needs a time column (time_s) and a speed column (rpm or "
            f"shaft_hz); columns: {', '.join(map(str, frame.columns))}"
        )
    t = pd.to_numeric(frame[time_key], errors="coerce").to_numpy(dtype=float)
    speed = pd.to_numeric(frame[rpm_key if rpm_key is not None else hz_key], errors="coerce")
    rate = speed.to_numpy(dtype=float) / (60.0 if rpm_key is not None else 1.0)
    if t.size < 2 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
        raise ValueError(f"{path}: the time column must hold two or more increasing values")
    if not np.all(np.isfinite(rate) & (rate > 0)):
        raise ValueError(f"{path}: every speed must be finite and positive")
    duration = n_samples / fs
    if t[-1] < 0.1 * duration or t[0] > 0.9 * duration:
        raise ValueError(
            f"{path}: the profile spans {t[0]:g}..{t[-1]:g} s, the record 0..{duration:g} s"
        )
    return np.interp(np.arange(n_samples) / fs, t, rate)


def resolve_channel(path, channel, names) -> str:
    """Name of the channel ``channel`` picks among ``names``.

    A channel is matched by name first (compared as text, so a headerless table's column
    ``1`` is ``"1"`` or ``1``), then as an index into ``names``: an int, or a string of
    digits, as a command line passes it.

    Raises
    ------
    ValueError
        If neither matches; the message lists the available names.
    """
    names = [str(n) for n in names]
    if channel is None:
        raise ValueError(f"{path}: choose a channel; available: {', '.join(names) or '(none)'}")
    if str(channel) in names and not isinstance(channel, bool):
        return str(channel)
    index = None
    if isinstance(channel, int | np.integer) and not isinstance(channel, bool):
        index = int(channel)
    elif isinstance(channel, str) and re.fullmatch(r"\s*-?\d+\s*", channel):
        index = int(channel)
    if index is not None and -len(names) <= index < len(names):
        return names[index]
    listed = ", ".join(names) or "(none)"
    hint = f" (or an index 0..{len(names) - 1})" if names else ""
    raise ValueError(f"{path}: no channel {channel!r}; available: {listed}{hint}")


def _resolve_fs(path: Path, fs: float | None, fs_file: float | None) -> float:
    if fs_file is None:
        if fs is None:
            raise ValueError(
                f"{path}: the file holds no sampling rate; give fs (Hz; --fs on the command line), "
                "e.g. fs=12000"
            )
        return fs
    if fs is not None and abs(fs - fs_file) > _FS_TOLERANCE * fs_file:
        raise ValueError(
            f"{path}: fs = {fs:g} Hz contradicts the file's sampling rate {fs_file:g} Hz"
        )
    return fs if fs is not None else fs_file


def _is_time_name(name) -> bool:
    return str(name).strip().lower() in _TIME_NAMES


def _is_fs_name(name) -> bool:
    # A struct field ``bearing.sr`` is named by its last part.
    return str(name).strip().lower().split(".")[-1] in _FS_NAMES


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
    names = [str(c) for c in frame.columns]
    frame.columns = names
    time_columns = [c for c in names if _is_time_name(c)]
    data_columns = [c for c in names if c not in time_columns]
    if channel is None:
        if not data_columns:
            raise ValueError(f"{path}: no data column besides time; columns: {names}")
        name = data_columns[0]
    else:
        name = resolve_channel(path, channel, names)
    columns = {
        c: pd.to_numeric(frame[c], errors="coerce").to_numpy(dtype=float)
        for c in data_columns + ([name] if name in time_columns else [])
    }
    fs_file = _fs_from_time(path, frame[time_columns[0]]) if time_columns else None
    return columns, name, fs_file, {"channels": names}


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
        frame.columns = [str(i) for i in range(frame.shape[1])]
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
    data = data.reshape(data.shape[0], -1)
    names = [f"channel{i}" for i in range(data.shape[1])]
    if isinstance(channel, str) and re.fullmatch(r"\d+", channel.strip()):
        channel = int(channel)
    name = names[0] if channel is None else resolve_channel(path, channel, names)
    columns = {n: data[:, i] for i, n in enumerate(names)}
    return columns, name, float(rate), {"channels": names}


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
    numeric = dict(_numeric_variables(variables))
    vectors = [k for k, v in numeric.items() if v.size > 1 and min(v.shape) == 1]
    if not vectors:
        held = ", ".join(sorted(variables)) or "nothing"
        raise ValueError(f"{path}: holds no numeric signal (a vector variable); it holds: {held}")
    meta: dict = {"channels": sorted(vectors)}
    if channel is None:
        name = _default_mat_channel(path, vectors)
    elif str(channel) in numeric and numeric[str(channel)].size > 1:
        name = str(channel)
    else:
        name = resolve_channel(path, channel, sorted(vectors))
    rpm = _cwru_rpm(name, numeric)
    if rpm is None:
        rpm = _mfpt_rpm(name, numeric)
    if rpm is not None:
        meta["rpm"] = rpm
    fs_file = _scalar_named(numeric, _is_fs_name, prefix=name.rpartition(".")[0])
    columns = {k: numeric[k].reshape(-1) for k in sorted(vectors)}
    columns.setdefault(name, numeric[name].reshape(-1))
    return columns, name, fs_file, meta


def _numeric_variables(variables: dict, prefix: str = ""):
    """(name, array) of every numeric variable; the fields of a 1x1 struct as ``s.field``."""
    for key, value in variables.items():
        if not isinstance(value, np.ndarray):
            continue
        if value.dtype.names and value.size == 1:
            fields = {f: value[f].reshape(-1)[0] for f in value.dtype.names}
            yield from _numeric_variables(fields, f"{prefix}{key}.")
        elif value.dtype.kind in "biuf":
            yield f"{prefix}{key}", np.asarray(value)


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
    listed = ", ".join(sorted(vectors))
    raise ValueError(f"{path}: several signals, choose a channel; available: {listed}")


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


def _mfpt_rpm(channel: str, numeric: dict) -> float | None:
    """Shaft speed of an MFPT record: struct ``S`` with ``S.gs``, ``S.sr`` and ``S.rate``
    (shaft rate in Hz)."""
    struct, _, field_name = channel.rpartition(".")
    if not struct or field_name != "gs" or f"{struct}.sr" not in numeric:
        return None
    rate = numeric.get(f"{struct}.rate")
    if rate is None or rate.size != 1:
        return None
    value = float(rate.reshape(-1)[0])
    return 60.0 * value if math.isfinite(value) and value > 0 else None


def _scalar_named(numeric: dict, wanted, prefix: str = "") -> float | None:
    # A scalar beside the channel (in the same struct) first, then anywhere.
    keys = sorted(numeric, key=lambda k: k.rpartition(".")[0] != prefix)
    for key in keys:
        value = numeric[key]
        if wanted(key) and np.asarray(value).size == 1:
            rate = float(np.asarray(value).reshape(-1)[0])
            if math.isfinite(rate) and rate > 0:
                return rate
    return None


# -------------------------------------------------------------------------------- npy/npz
def _read_npy(path: Path, channel):
    data = np.load(path, allow_pickle=False)
    return _array_channels(path, data, channel, path.stem)


def _array_channels(path: Path, data: np.ndarray, channel, name: str):
    data = np.asarray(data)
    if data.ndim <= 1:
        names = [name]
        columns = {name: data.reshape(-1)}
    elif data.ndim == 2:
        # Samples run along the longer axis; channels along the shorter one.
        rows = data.T if data.shape[0] >= data.shape[1] else data
        names = [f"{name}[{i}]" for i in range(rows.shape[0])]
        columns = dict(zip(names, rows, strict=True))
    else:
        raise ValueError(f"{path}: expected a 1-D or 2-D array, got shape {data.shape}")
    if isinstance(channel, str) and re.fullmatch(r"\d+", channel.strip()):
        channel = int(channel)
    chosen = names[0] if channel is None else resolve_channel(path, channel, names)
    return columns, chosen, None, {"channels": names}


def _read_npz(path: Path, channel):
    with np.load(path, allow_pickle=False) as archive:
        arrays = {k: np.asarray(archive[k]) for k in archive.files}
    fs_file = _scalar_named(arrays, _is_fs_name)
    candidates = [
        k
        for k, v in arrays.items()
        if v.size > 1 and not _is_time_name(k) and v.dtype.kind in "biuf"
    ]
    if channel is None:
        if not candidates:
            held = ", ".join(arrays) or "nothing"
            raise ValueError(f"{path}: holds no numeric signal; it holds: {held}")
        if len(candidates) != 1:
            raise ValueError(f"{path}: choose a channel; available: {', '.join(candidates)}")
        name = candidates[0]
    elif str(channel) in arrays:
        name = str(channel)
    else:
        name = resolve_channel(path, channel, candidates)
    times = [k for k in arrays if _is_time_name(k) and arrays[k].size > 1]
    if fs_file is None and times:
        fs_file = _fs_from_time(path, arrays[times[0]].reshape(-1))
    columns = {}
    for key in dict.fromkeys([name, *candidates]):
        values = arrays[key]
        if values.ndim > 1 and min(values.shape) == 1:
            values = values.reshape(-1)
        if values.ndim == 1:
            columns[key] = values
    if name not in columns:
        raise ValueError(f"{path}: key {name!r} is not a 1-D array (shape {arrays[name].shape})")
    ordered = {k: columns[k] for k in dict.fromkeys([*candidates, name]) if k in columns}
    return ordered, name, fs_file, {"channels": candidates}
