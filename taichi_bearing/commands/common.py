"""Arguments and checks shared by several subcommands.

Only the standard library is imported at load: ``python -m taichi_bearing --help`` builds
every subcommand's parser, and it should not wait for numpy, Taichi or scipy.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from taichi_bearing.errors import InputError


def add_case_arguments(parser: argparse.ArgumentParser) -> None:
    """The case file, ``--set`` overrides and ``--out``."""
    parser.add_argument("case", help="case file (YAML), e.g. cases/line_spall.yaml")
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY.PATH=VALUE",
        help="override one case value, e.g. --set operating.load_kN=80 (repeatable)",
    )
    parser.add_argument(
        "--out", default=None, metavar="DIR", help="output folder (default runs/<case name>/)"
    )


def _input_error(check, *args) -> Path | None:
    """Run one of the folder checks of :mod:`bearing_io.files` (their ValueError is the
    command line's InputError: one line, exit status 2)."""
    try:
        return check(*args)
    except ValueError as exc:
        raise InputError(str(exc)) from None


def check_empty(value: str | os.PathLike, option: str) -> Path:
    """``value`` as a Path; empty is refused (:func:`bearing_io.files.nonempty_path`)."""
    from bearing_io.files import nonempty_path  # numpy: not for --help

    return _input_error(nonempty_path, value, option)


def ensure_writable(folder: Path, option: str) -> None:
    """Refuse a folder no file can be written in (:func:`bearing_io.files.ensure_writable`)."""
    from bearing_io.files import ensure_writable as check

    _input_error(check, folder, option)


def output_folder(value: str | os.PathLike, option: str = "--out") -> Path:
    """Check and create an output folder (:func:`bearing_io.files.output_folder`): an
    empty path, a file, a folder that cannot be made or written in are refused in one
    line naming ``option``, with nothing left on disk."""
    from bearing_io.files import output_folder as make

    return _input_error(make, value, option)


def case_output_folder(out: str | None, case) -> Path:
    """:func:`output_folder` of a case command: ``--out`` if given, else the case's
    ``output.dir`` (named as such in a refusal), else ``runs/<case name>``.

    Parameters
    ----------
    out : str or None
        The ``--out`` argument.
    case : taichi_bearing.case.Case
        The loaded case.
    """
    if out is not None:
        return output_folder(out, "--out")
    return output_folder(case.out_dir, "output.dir" if case.output.dir else "--out")
