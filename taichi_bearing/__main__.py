"""Command line: ``python -m taichi_bearing [run|mesh|analytic|sweep|post|compare] ...``.

A bare case file (``python -m taichi_bearing cases/line_spall.yaml``) means ``run``.
Each subcommand lives in ``taichi_bearing.commands.<name>`` and provides
``add_arguments(parser)`` and ``main(args) -> int``. Bad input is reported as one line on
stderr with exit status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Iterable

from taichi_bearing.errors import InputError, SimulationError

COMMANDS = {
    "run": "preload, spin and record the bearing (the main job)",
    "mesh": "build the finite element mesh, write mesh.vtu, pictures and statistics",
    "analytic": "quasi-static load distribution with the spall, tables and figures",
    "modes": "natural frequencies and mode shapes of the finite element model",
    "sweep": "run a grid of cases over any case keys (e.g. load x speed)",
    "passages": "the distribution of each passage quantity over runs from spread start angles",
    "convergence": "how each quantity changes over mesh or penalty levels, with its order",
    "post": "redo the checks, figures and report of a run folder (finished or not)",
    "compare": "a run's sensor acceleration against measured records, side by side",
    "animate": "a GIF or MP4 of the spall region from a run's field frames (von Mises)",
}


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (argparse prints its whole usage
    block); subcommand parsers are of this class too."""

    def error(self, message: str):  # noqa: D401 - argparse API
        self.exit(2, f"error: {self.prog}: {message} (see --help)\n")


def build_parser(commands: Iterable[str] | None = None) -> argparse.ArgumentParser:
    """The command line's parser.

    Parameters
    ----------
    commands : iterable of str, optional
        The subcommands whose arguments are added; default all of them. The others are
        listed by name and help only, so that ``--help`` and ``run --help`` import no
        other command's module. A command module imports only the standard library when
        loaded (numpy, Taichi and scipy in its ``main``), so that ``--help`` answers at once.
    """
    parser = _Parser(
        prog="python -m taichi_bearing",
        description="2-D explicit dynamics of a roller bearing with a line spall.",
        epilog="A case file alone, as in 'python -m taichi_bearing cases/line_spall.yaml', "
        "runs the simulation.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, help_text in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        if commands is None or name in commands:
            importlib.import_module(f"taichi_bearing.commands.{name}").add_arguments(p)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] not in COMMANDS and not argv[0].startswith("-"):
        argv.insert(0, "run")
    parser = build_parser(argv[:1] if argv and argv[0] in COMMANDS else ())
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    module = importlib.import_module(f"taichi_bearing.commands.{args.command}")
    try:
        return int(module.main(args) or 0)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except SimulationError as exc:
        print(f"simulation stopped: {exc}", file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print("interrupted: results written so far are kept", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
