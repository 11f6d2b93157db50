"""`python -m taichi_bearing mesh`: not built yet."""

from __future__ import annotations

import argparse

from taichi_bearing.commands.common import add_case_arguments


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)


def main(args: argparse.Namespace) -> int:
    print("'mesh' is not implemented yet; nothing was computed.")
    return 1
