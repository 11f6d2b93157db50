"""`python -m taichi_bearing run CASE.yaml`: the full simulation (not built yet)."""

from __future__ import annotations

import argparse

from taichi_bearing.case import load_case_for_cli
from taichi_bearing.commands.common import add_case_arguments

PLAN = """\
The run will:
  1. read and validate the case file ({case});
  2. mesh the bearing (rings, adapter, rollers, line spall);
  3. preload it under the radial load by dynamic relaxation;
  4. spin it at the case speed and record sensor vibration and roller contact forces;
  5. write histories, frames, figures, summary.json and a report.
The explicit solver is not implemented yet, so no simulation was run."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument(
        "--arch", choices=["cpu", "cuda", "vulkan"], default=None, help="Taichi backend"
    )
    parser.add_argument("--resume", action="store_true", help="continue from the last checkpoint")


def main(args: argparse.Namespace) -> int:
    # Validate first, so a bad case file fails with one line and exit 2 (CaseError).
    case = load_case_for_cli(args.case, args.overrides)
    print(PLAN.format(case=f"{case.source}, case '{case.name}'"))
    return 1
