"""Progress bar of a run: simulated time in ms, steps per second and time left (tqdm).

The engine calls :meth:`RunProgress.update` every few hundred steps; between redraws a call
only stores two numbers and reads the clock, so it costs well under a microsecond or two.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

from tqdm import tqdm

__all__ = ["RunProgress"]

# Separate name so tests can drive the clock.
_clock = time.time

_BAR_FORMAT = (
    "{desc}: {percentage:3.0f}%|{bar}| {n:.3f}/{total:.3f} ms [{elapsed}<{remaining}{postfix}]"
)


def _is_tty(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False


class RunProgress:
    """A progress bar over simulated time.

    Parameters
    ----------
    total_time : float
        Simulated time at the end of the run, s.
    description : str
        Label in front of the bar.
    enabled : bool, optional
        Show the bar. By default it is shown only when the output stream is a terminal
        (so logs and CI output stay clean); True forces it.
    quiet : bool
        Never show the bar (wins over ``enabled``).
    start_time : float
        Simulated time at the start, s (non-zero when resuming).
    start_step : int
        Step number at the start (non-zero when resuming).
    file : text stream, optional
        Where to draw; default ``sys.stderr``.
    min_interval_s : float
        Smallest wall time between redraws.

    Examples
    --------
    >>> with RunProgress(duration_s, "transient") as bar:        # doctest: +SKIP
    ...     for step in range(n_steps):
    ...         ...
    ...         if step % 200 == 0:
    ...             bar.update(step, t)
    """

    def __init__(
        self,
        total_time: float,
        description: str = "run",
        enabled: bool | None = None,
        quiet: bool = False,
        start_time: float = 0.0,
        start_step: int = 0,
        file: TextIO | None = None,
        min_interval_s: float = 0.5,
    ) -> None:
        if not total_time > 0:
            raise ValueError(f"total_time must be positive, got {total_time!r}")
        stream = sys.stderr if file is None else file
        self._stream = stream
        self._quiet = bool(quiet)
        self.enabled = (not quiet) and (_is_tty(stream) if enabled is None else bool(enabled))
        self.total_time = float(total_time)
        self.min_interval_s = float(min_interval_s)
        self.step = self._start_step = int(start_step)
        self.sim_time = float(start_time)
        self._t0 = self._last_draw = _clock()
        self._bar = None
        if self.enabled:
            self._bar = tqdm(
                total=self.total_time * 1e3,
                initial=self.sim_time * 1e3,
                desc=description,
                unit="ms",
                bar_format=_BAR_FORMAT,
                file=stream,
                mininterval=0.0,  # throttled here, before any tqdm work
                miniters=0,
                smoothing=0.1,
                dynamic_ncols=True,
                leave=True,
            )

    @property
    def wall_time_s(self) -> float:
        """Wall time since the start, s."""
        return _clock() - self._t0

    @property
    def steps_per_s(self) -> float:
        """Mean steps per second of wall time since the start (0 before any time passed)."""
        elapsed = self.wall_time_s
        return (self.step - self._start_step) / elapsed if elapsed > 0 else 0.0

    def update(self, step: int, sim_time: float) -> None:
        """Record that ``step`` (simulated time ``sim_time`` s) is done; redraw if due."""
        self.step = step
        self.sim_time = sim_time
        if self._bar is None:
            return
        now = _clock()
        if now - self._last_draw < self.min_interval_s:
            return
        self._last_draw = now
        self._draw()

    def _draw(self) -> None:
        self._bar.set_postfix_str(f"{self.steps_per_s:,.0f} steps/s", refresh=False)
        self._bar.update(min(self.sim_time * 1e3, self._bar.total) - self._bar.n)

    def write(self, message: str) -> None:
        """Print a line to the bar's stream without breaking the bar (nothing when quiet)."""
        if self._bar is not None:
            self._bar.write(message, file=self._stream)
        elif not self._quiet:
            print(message, file=self._stream, flush=True)

    def close(self) -> None:
        """Draw the final state and release the bar. Idempotent."""
        if self._bar is not None:
            self._draw()
            self._bar.close()
            self._bar = None

    def __enter__(self) -> RunProgress:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close()
