"""``summary.json`` of a run: its numbers in SI units, with the keys every finished run
must have.

The file name and the required keys are those of :mod:`taichi_bearing.output.layout`.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Mapping
from pathlib import Path

from bearing_io.files import write_json
from taichi_bearing.output.layout import REQUIRED_SUMMARY_KEYS, SUMMARY_FILE

__all__ = [
    "missing_summary_keys",
    "required_summary_keys",
    "write_partial_summary",
    "write_summary",
]


def required_summary_keys() -> tuple[str, ...]:
    """The keys every finished run's ``summary.json`` has
    (:data:`~taichi_bearing.output.layout.REQUIRED_SUMMARY_KEYS`)."""
    return REQUIRED_SUMMARY_KEYS


def missing_summary_keys(summary: Mapping) -> list[str]:
    """The required keys absent from ``summary``, in the order of :func:`required_summary_keys`."""
    return [k for k in REQUIRED_SUMMARY_KEYS if k not in summary]


def write_summary(path: str | os.PathLike, summary: Mapping, strict: bool = False) -> Path:
    """Write ``summary.json`` atomically; flag required keys that are missing.

    Parameters
    ----------
    path : str or path-like
        The file, or a folder (then ``summary.json`` in it).
    summary : mapping
        Values may be numpy scalars/arrays; non-finite floats are written as ``null``.
    strict : bool
        Raise instead of warning when required keys are missing.

    Returns
    -------
    pathlib.Path
        The file written. When keys are missing (and not ``strict``), a ``UserWarning``
        names them and the file lists them under ``"missing_keys"``, so a partial run
        (stopped early, Ctrl-C) still leaves a summary that says what it lacks.

    Raises
    ------
    ValueError
        With ``strict=True``, if required keys are missing.
    """
    path = Path(path)
    if path.suffix != ".json":
        path = path / SUMMARY_FILE
    data = dict(summary)
    missing = missing_summary_keys(data)
    if missing:
        message = f"{path}: summary lacks required keys {missing}"
        if strict:
            raise ValueError(message)
        warnings.warn(message, UserWarning, stacklevel=2)
        data["missing_keys"] = missing
    else:
        data.pop("missing_keys", None)
    return write_json(path, data)


def write_partial_summary(path: str | os.PathLike, summary: Mapping) -> Path:
    """:func:`write_summary` for a run that did not finish: its missing keys are listed in
    the file, with no warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the missing keys are listed in the file
        return write_summary(path, summary)
