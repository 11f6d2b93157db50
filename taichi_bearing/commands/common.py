"""Arguments shared by several subcommands."""

from __future__ import annotations

import argparse


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
