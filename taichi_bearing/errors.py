"""Exceptions that the command line turns into a one-line message and exit status 2."""

from __future__ import annotations


class InputError(ValueError):
    """Bad user input: a file, an argument or a value. The message is one line."""


class _AtKey:
    """A message about one key of a case: ``SOURCE: KEY: MESSAGE``.

    Parameters
    ----------
    key : str
        Dotted key path in the case file, e.g. ``bearing.roller_diameter_mm``.
    message : str
        What is wrong and what was expected.
    source : str, optional
        Where the key came from: the case file, or the ``--set`` argument.
    """

    def __init__(self, key: str, message: str, source: str | None = None) -> None:
        self.key = key
        self.message = message
        self.source = source
        where = f"{source}: " if source else ""
        super().__init__(f"{where}{key}: {message}")


class CaseError(_AtKey, InputError):
    """An invalid case file: the message names the key path and what was expected."""


class CaseWarning(_AtKey, UserWarning):
    """A case that loads but may not do what was meant (the CLI prints it as one line)."""


class SimulationError(RuntimeError):
    """A run stopped for a physical or numerical reason (NaN, energy runaway, inverted
    element). The message names the step, time and worst element or node."""
