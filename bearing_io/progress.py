"""Progress of long work: a command over many records (``python -m diagnostics benchmark``),
and the terminal test the simulator's bars share.

On a terminal a tqdm bar counts the records done, with the one in hand; in a log or a pipe
a plain line every ``log_every_s`` seconds of wall time, and a last line with the count and
the time taken, so that a log shows how far a long benchmark got.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["LOG_INTERVAL_S", "RecordProgress", "is_terminal"]

LOG_INTERVAL_S = 20.0
"""Default wall seconds between progress lines when the output is not a terminal."""

# Separate name so tests can drive the clock.
_clock = time.monotonic


def is_terminal(stream) -> bool:
    """Whether ``stream`` is a terminal (a bar there; plain lines in a log or a pipe)."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False


class RecordProgress:
    """Records done out of ``total``, shown on ``file`` (default stderr).

    Parameters
    ----------
    total : int
        Records the command will diagnose.
    description : str
        The line's or bar's first word.
    file : text stream, optional
        Where progress goes; default ``sys.stderr``.
    log_every_s : float
        Wall seconds between plain lines when ``file`` is not a terminal (0: one a record).
    enabled : bool
        False shows nothing (``--quiet``).
    """

    def __init__(
        self,
        total: int,
        description: str = "benchmark",
        file: TextIO | None = None,
        log_every_s: float = LOG_INTERVAL_S,
        enabled: bool = True,
    ) -> None:
        self.total, self.description = int(total), description
        self.file = file if file is not None else sys.stderr
        self.log_every_s = float(log_every_s)
        self.enabled = enabled and self.total > 0
        self.done = 0
        self._start = self._last_line = _clock()
        self._bar = None
        if self.enabled and is_terminal(self.file):
            from tqdm import tqdm  # only for a bar

            self._bar = tqdm(total=self.total, desc=description, unit="record", file=self.file)

    def update(self, name: str) -> None:
        """One more record done; ``name`` is the record's (file) name."""
        self.done += 1
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.set_postfix_str(name, refresh=False)
            self._bar.update(1)
            return
        now = _clock()
        if now - self._last_line >= self.log_every_s and self.done < self.total:
            self._last_line = now
            print(
                f"{self.description}: {self.done} of {self.total} records, "
                f"{now - self._start:.0f} s, last {name}",
                file=self.file,
                flush=True,
            )

    def close(self) -> None:
        """The last line (or the bar's end): records done and the time they took."""
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.close()
            return
        print(
            f"{self.description}: {self.done} records in {_clock() - self._start:.0f} s",
            file=self.file,
            flush=True,
        )
