"""Safe file writing: results are written to a temporary name, then renamed into place,
so a crash or Ctrl-C never leaves a half-written file; output folders are checked before
anything is written to them. Used by both ``diagnostics`` and ``taichi_bearing``."""

from __future__ import annotations

import errno
import json
import math
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

__all__ = [
    "atomic_path",
    "ensure_writable",
    "nonempty_path",
    "output_folder",
    "to_jsonable",
    "write_json",
]


@contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` on success.

    The parent folder is created. On an exception the temporary file is removed and
    ``path`` is left as it was.

    Examples
    --------
    >>> import tempfile
    >>> out = Path(tempfile.mkdtemp())
    >>> with atomic_path(out / "tables" / "table.csv") as tmp:
    ...     _ = tmp.write_text("f_hz,level_db")
    >>> (out / "tables" / "table.csv").read_text()
    'f_hz,level_db'
    >>> sorted(p.name for p in (out / "tables").iterdir())   # no temporary file left
    ['table.csv']
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(
        prefix=f".{path.name}.", suffix=".tmp" + path.suffix, dir=path.parent
    )
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        # mkstemp makes the file private (0600); give it the permissions of a normal file.
        os.chmod(tmp, 0o666 & ~_current_umask())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def to_jsonable(value):
    """Convert numpy scalars/arrays, paths and non-finite floats into plain JSON values.

    Non-finite floats become ``None`` (JSON has no NaN).
    """
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, np.generic):
        return to_jsonable(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


def write_json(path: str | os.PathLike, data: dict) -> Path:
    """Write ``data`` as indented JSON, atomically. Returns the path."""
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(to_jsonable(data), indent=2) + "\n", encoding="utf-8")
    return Path(path)


# What the user can do about the usual reasons a folder cannot be made or written in.
_OS_REASONS = {
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.EROFS: "read-only file system",
    errno.ENOSPC: "no space left on the device",
    errno.ENAMETOOLONG: "name too long",
    errno.ENOENT: "the file system does not allow new entries there",
}


def _reason(exc: OSError) -> str:
    return _OS_REASONS.get(exc.errno, (exc.strerror or str(exc)).lower())


def nonempty_path(value: str | os.PathLike, option: str) -> Path:
    """``value`` as a Path; an empty (or blank) value is refused, since ``Path("")`` is
    the current folder and a command would write there unasked.

    Raises
    ------
    ValueError
        One line naming ``option`` (the argument the value came from).
    """
    if not str(value).strip():
        example = f", e.g. {option} results" if option.startswith("--") else ""
        raise ValueError(f"{option}: empty path; give a folder{example}")
    return Path(value)


def ensure_writable(folder: str | os.PathLike, option: str) -> None:
    """Refuse a folder in which no file can be created (read-only, ``/proc``, permissions).

    A temporary file is made and removed at once: only trying tells, for the file
    systems (``/proc``, ``/sys``) where the permission bits do not.

    Raises
    ------
    ValueError
        One line naming ``option`` and the reason.
    """
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise ValueError(f"{option}: cannot write in {folder}: {_reason(exc)}") from None


def output_folder(value: str | os.PathLike, option: str = "--out") -> Path:
    """Check and create an output folder; return it.

    Refused, in one line naming ``option`` and with nothing left on disk: an empty path,
    an existing file (or a path through one), a folder that cannot be made (e.g. under
    ``/proc``) or written in.

    Parameters
    ----------
    value : str or path-like
        The folder as given (``--out DIR``, a case key or a command's default).
    option : str
        What a refusal names: the argument or key the folder came from.

    Returns
    -------
    Path
        The folder, which now exists.

    Raises
    ------
    ValueError
        If the folder cannot be used; any folder made here is removed again.

    Examples
    --------
    >>> import tempfile
    >>> base = Path(tempfile.mkdtemp())
    >>> output_folder(base / "runs" / "cwru130", "--out").is_dir()
    True
    >>> open(base / "notes.txt", "w").close()
    >>> output_folder(base / "notes.txt", "--out")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: --out: .../notes.txt exists and is not a folder
    """
    path = nonempty_path(value, option)
    try:
        if path.exists() and not path.is_dir():
            raise ValueError(f"{option}: {path} exists and is not a folder")
        missing = []  # the folders to make, innermost first
        parent = path
        while not parent.exists() and parent.parent != parent:
            missing.append(parent)
            parent = parent.parent
        if not parent.is_dir():
            raise ValueError(f"{option}: {path}: {parent} is a file, not a folder")
    except OSError as exc:  # e.g. a name too long to look up
        raise ValueError(f"{option}: {path}: {_reason(exc)}") from None
    made: list[Path] = []
    try:
        for folder in reversed(missing):
            try:
                folder.mkdir()
            except OSError as exc:
                raise ValueError(f"{option}: cannot create {folder}: {_reason(exc)}") from None
            made.append(folder)
        ensure_writable(path, option)
    except ValueError:
        for folder in reversed(made):  # nothing written on a refusal
            folder.rmdir()
        raise
    return path
