"""Checkpoints of a run's state: one ``.npz`` per checkpoint, written then renamed.

A checkpoint holds the step number, the simulated time, named numpy arrays (the solver
state, bit for bit) and a JSON metadata dict. The metadata must carry a ``fingerprint`` of
what the run was built from (case dict, mesh arrays; see :func:`fingerprint`) so that
``--resume`` refuses a checkpoint from a different case or mesh.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import re
import struct
import zipfile
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from bearing_io.files import atomic_path, to_jsonable
from taichi_bearing.errors import InputError

__all__ = [
    "fingerprint",
    "latest_checkpoint",
    "list_checkpoints",
    "load_checkpoint",
    "save_checkpoint",
]

_NAME = re.compile(r"^checkpoint_(\d+)\.npz$")
_RESERVED = ("__step__", "__time__", "__meta__")


# --------------------------------------------------------------------------- fingerprint


def _feed(h, obj) -> None:
    """Hash ``obj`` with a type tag before each value, so that e.g. 1, 1.0, "1" and [1]
    differ, and dict key order does not matter."""
    if obj is None:
        h.update(b"N")
    elif isinstance(obj, (bool, np.bool_)):
        h.update(b"B1" if obj else b"B0")
    elif isinstance(obj, (int, np.integer)):
        h.update(b"I" + str(int(obj)).encode() + b";")
    elif isinstance(obj, (float, np.floating)):
        h.update(b"F" + struct.pack("<d", float(obj)))
    elif isinstance(obj, str):
        data = obj.encode()
        h.update(b"S" + str(len(data)).encode() + b":" + data)
    elif isinstance(obj, bytes):
        h.update(b"Y" + str(len(obj)).encode() + b":" + obj)
    elif isinstance(obj, os.PathLike):
        _feed(h, os.fspath(obj))
    elif isinstance(obj, np.ndarray):
        if obj.dtype.hasobject:
            raise TypeError("fingerprint: object arrays are not supported")
        a = np.ascontiguousarray(obj)
        h.update(b"A" + a.dtype.str.encode() + repr(a.shape).encode())
        h.update(a.tobytes())
    elif isinstance(obj, Mapping):
        items = sorted(obj.items(), key=lambda kv: str(kv[0]))
        h.update(b"D" + str(len(items)).encode() + b"{")
        for k, v in items:
            _feed(h, str(k))
            _feed(h, v)
        h.update(b"}")
    elif isinstance(obj, (list, tuple)):
        h.update(b"L" + str(len(obj)).encode() + b"[")
        for v in obj:
            _feed(h, v)
        h.update(b"]")
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        h.update(b"C" + type(obj).__name__.encode())
        _feed(h, {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)})
    else:
        raise TypeError(f"fingerprint: cannot hash a {type(obj).__name__}")


def fingerprint(*items) -> str:
    """A short, stable hash of what a run is built from.

    Parameters
    ----------
    *items
        numpy arrays (dtype, shape and bytes count), dicts (key order ignored), lists,
        scalars, strings, paths and dataclass instances (e.g. a ``Mesh``), nested freely.

    Returns
    -------
    str
        32 hexadecimal characters (SHA-256, truncated).

    Examples
    --------
    >>> import numpy as np
    >>> a = fingerprint({"load_kN": 50.0, "speed_rpm": 500.0}, np.zeros((4, 2)))
    >>> a == fingerprint({"speed_rpm": 500.0, "load_kN": 50.0}, np.zeros((4, 2)))
    True
    >>> a == fingerprint({"load_kN": 50.0, "speed_rpm": 500.0}, np.ones((4, 2))), len(a)
    (False, 32)
    """
    h = hashlib.sha256()
    _feed(h, list(items))
    return h.hexdigest()[:32]


# --------------------------------------------------------------------------- save / load


def list_checkpoints(folder: str | os.PathLike) -> list[Path]:
    """The complete checkpoints in ``folder``, oldest (lowest step) first."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    found = [(int(m.group(1)), p) for p in folder.iterdir() if (m := _NAME.match(p.name))]
    return [p for _, p in sorted(found)]


def latest_checkpoint(folder: str | os.PathLike) -> Path | None:
    """The checkpoint with the highest step in ``folder``, or None if there is none."""
    found = list_checkpoints(folder)
    return found[-1] if found else None


def save_checkpoint(
    folder: str | os.PathLike,
    step: int,
    time: float,
    arrays: Mapping[str, np.ndarray],
    meta: Mapping,
    keep: int = 3,
) -> Path:
    """Write ``folder/checkpoint_<step>.npz`` atomically and keep only the last ``keep``.

    Parameters
    ----------
    folder : str or path-like
        Checkpoint folder (created).
    step : int
        Step number of the state.
    time : float
        Simulated time of the state, s.
    arrays : mapping of str to ndarray
        The state; stored uncompressed and bit-exact. Names must not start with ``__``.
    meta : mapping
        JSON-able metadata; must contain ``"fingerprint"`` (see :func:`fingerprint`).
    keep : int
        How many checkpoints to keep in the folder (the newest by step).

    Returns
    -------
    pathlib.Path
        The checkpoint written.
    """
    if "fingerprint" not in meta:
        raise ValueError("checkpoint meta must contain a 'fingerprint' of the case and mesh")
    if keep < 1:
        raise ValueError(f"keep must be at least 1, got {keep!r}")
    if int(step) != step or step < 0:
        raise ValueError(f"step must be a non-negative integer, got {step!r}")
    payload = {}
    for name, value in arrays.items():
        if name.startswith("__"):
            raise ValueError(f"checkpoint array name {name!r} must not start with '__'")
        a = np.asarray(value)
        if a.dtype.hasobject:
            raise ValueError(f"checkpoint array {name!r} has object dtype")
        payload[name] = a
    payload["__step__"] = np.int64(step)
    payload["__time__"] = np.float64(time)
    payload["__meta__"] = np.array(json.dumps(to_jsonable(dict(meta)), sort_keys=True))
    path = Path(folder) / f"checkpoint_{int(step):010d}.npz"
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, **payload)
    for old in list_checkpoints(folder)[:-keep]:
        old.unlink(missing_ok=True)
    return path


def load_checkpoint(
    path: str | os.PathLike, expected_fingerprint: str | None = None
) -> tuple[int, float, dict[str, np.ndarray], dict]:
    """Read a checkpoint written by :func:`save_checkpoint`.

    Parameters
    ----------
    path : str or path-like
        The ``.npz`` file.
    expected_fingerprint : str, optional
        Fingerprint of the case and mesh of the run being resumed; a checkpoint with
        another one is refused.

    Returns
    -------
    step : int
    time : float
    arrays : dict of str to ndarray
    meta : dict

    Raises
    ------
    InputError
        If the file is missing or unreadable, or its fingerprint differs from
        ``expected_fingerprint``.
    """
    path = Path(path)
    try:
        # Open the file here: np.load leaks its handle when the zip is corrupt.
        with open(path, "rb") as f, np.load(f, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:
        raise InputError(f"{path}: not a readable checkpoint ({exc})") from None
    if any(k not in data for k in _RESERVED):
        raise InputError(f"{path}: not a taichi-bearing checkpoint")
    step = int(data.pop("__step__"))
    time = float(data.pop("__time__"))
    meta = json.loads(str(data.pop("__meta__")))
    if expected_fingerprint is not None and meta.get("fingerprint") != expected_fingerprint:
        raise InputError(
            f"{path}: checkpoint is from a different case or mesh "
            f"(fingerprint {meta.get('fingerprint')}, this run {expected_fingerprint}); "
            "run without --resume or use the matching case"
        )
    return step, time, data, meta
