"""Progress of the two long stages of a run: the preload and the transient.

On a terminal each shows a tqdm bar. When the output is not a terminal (a log file, a pipe,
CI) and a line interval is given, each prints a plain line every so many seconds of wall
time and a last line when it ends, so that a log shows how far a run got and how fast.

- :class:`RunProgress`, the transient: simulated time in ms, steps per second, time left.
- :class:`RelaxProgress`, the preload (dynamic relaxation), which has no known end: the
  steps taken and the kinetic-energy ratio against its tolerance, the bar on log10 of the
  ratio.

The solver calls ``update`` every few hundred steps; between redraws a call only stores a
few numbers and reads the clock, so it costs well under a microsecond or two.
"""

from __future__ import annotations

import math
import sys
import time
from typing import TYPE_CHECKING, TextIO

# One default and one terminal test for every progress display, the run's and the
# diagnostics benchmark's.
from bearing_io.progress import LOG_INTERVAL_S
from bearing_io.progress import is_terminal as _is_tty

if TYPE_CHECKING:
    from tqdm import tqdm

__all__ = ["LOG_INTERVAL_S", "RelaxProgress", "RunProgress", "format_duration"]

# Separate name so tests can drive the clock.
_clock = time.time

_BAR_FORMAT = (
    "{desc}: {percentage:3.0f}%|{bar}| {n:.3f}/{total:.3f} ms [{elapsed}<{remaining}{postfix}]"
)
# The preload's bar is on log10(peak KE / KE): no rate or time left, its pace is not steady.
_RELAX_BAR_FORMAT = "{desc}: {bar}| [{elapsed}{postfix}]"


def _tqdm() -> type[tqdm]:
    from tqdm import tqdm  # only for a bar: the command line imports this module for --help

    return tqdm


def format_duration(seconds: float) -> str:
    """Wall time for a log line: ``'8.2 s'``, ``'5 min 12 s'``, ``'1 h 05 min'``."""
    if not math.isfinite(seconds):
        return "?"
    if seconds < 60:
        return f"{seconds:.1f} s"
    minutes, secs = divmod(round(seconds), 60)
    if minutes < 60:
        return f"{minutes} min {secs:02d} s"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes:02d} min"


class _Progress:
    """What both progress displays share: the stream, the clock, the rate, and the choice
    between a bar (a terminal), plain lines (not a terminal) or nothing (quiet)."""

    def __init__(
        self,
        description: str,
        enabled: bool | None,
        quiet: bool,
        file: TextIO | None,
        min_interval_s: float,
        log_every_s: float | None,
        start_step: int,
    ) -> None:
        stream = sys.stderr if file is None else file
        self._stream = stream
        self._quiet = bool(quiet)
        self.description = description
        self.enabled = (not quiet) and (_is_tty(stream) if enabled is None else bool(enabled))
        # plain lines only where the bar is off for want of a terminal, not by request
        self.logging = not quiet and enabled is None and not self.enabled and bool(log_every_s)
        self.log_every_s = log_every_s
        self.min_interval_s = float(min_interval_s)
        self.step = self._start_step = int(start_step)
        self._t0 = self._last_draw = _clock()
        self._bar: tqdm | None = None
        self._closed = False

    def _start_lines(self) -> None:
        """Count the lines' pace from now (once the subclass holds its state)."""
        # wall time, step and progress at the last line: a line gives the pace since the
        # one before, which leaves out the kernels' compilation after the first
        self._mark = (self._t0, self.step, self._done())

    def _done(self) -> float:
        """The quantity whose pace gives the time left (the simulated time); 0: none."""
        return 0.0

    def _pace(self) -> tuple[float, float]:
        """Steps and progress (:meth:`_done`) per wall second since the previous line."""
        wall, step, done = self._mark
        elapsed = _clock() - wall
        if elapsed <= 0:
            return 0.0, 0.0
        return (self.step - step) / elapsed, (self._done() - done) / elapsed

    @property
    def wall_time_s(self) -> float:
        """Wall time since the start, s."""
        return _clock() - self._t0

    @property
    def steps_per_s(self) -> float:
        """Mean steps per second of wall time since the start (0 before any time passed)."""
        elapsed = self.wall_time_s
        return (self.step - self._start_step) / elapsed if elapsed > 0 else 0.0

    def _tick(self) -> None:
        """Redraw the bar, or print a line, if one is due."""
        if self._bar is None and not self.logging:
            return
        now = _clock()
        if self._bar is not None:
            if now - self._last_draw >= self.min_interval_s:
                self._last_draw = now
                self._draw()
        elif now - self._mark[0] >= self.log_every_s:
            self._print(self._line(final=False))
            self._mark = (now, self.step, self._done())

    def _print(self, line: str) -> None:
        print(line, file=self._stream, flush=True)

    def _draw(self) -> None:
        raise NotImplementedError

    def _line(self, final: bool) -> str:
        raise NotImplementedError

    def write(self, message: str) -> None:
        """Print a line to the bar's stream without breaking the bar (nothing when quiet)."""
        if self._bar is not None:
            self._bar.write(message, file=self._stream)
        elif not self._quiet:
            self._print(message)

    def close(self) -> None:
        """Draw the final state and release the bar, or print the last line. Idempotent."""
        if self._closed:
            return
        self._closed = True
        if self._bar is not None:
            self._draw()
            self._bar.close()
            self._bar = None
        elif self.logging:
            self._print(self._line(final=True))

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close()


class RunProgress(_Progress):
    """Progress over simulated time: a bar on a terminal, else lines if asked for.

    Parameters
    ----------
    total_time : float
        Simulated time at the end of the run, s.
    description : str
        Label in front of the bar or line.
    enabled : bool, optional
        Show the bar. By default it is shown only when the output stream is a terminal;
        True forces it, False shows nothing (no lines either).
    quiet : bool
        Show nothing (wins over ``enabled``).
    start_time : float
        Simulated time at the start, s (non-zero when resuming).
    start_step : int
        Step number at the start (non-zero when resuming).
    file : text stream, optional
        Where to draw; default ``sys.stderr``.
    min_interval_s : float
        Smallest wall time between redraws of the bar.
    log_every_s : float, optional
        When the stream is not a terminal (and ``enabled`` is None): print a line with the
        simulated time, steps per second and time left every this many seconds of wall
        time, and a last one at :meth:`close`. None: no lines.

    Examples
    --------
    Into a stream that is not a terminal: a line every 20 s of wall time and one at the end.

    >>> import sys
    >>> with RunProgress(1e-3, "transient", file=sys.stdout, log_every_s=20) as bar:
    ...     for step in range(0, 1001, 200):
    ...         bar.update(step, step * 1e-6)
    transient: 1.000/1.000 ms simulated (100%), step 1,000, ... steps/s, ... s in all
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
        log_every_s: float | None = None,
    ) -> None:
        if not total_time > 0:
            raise ValueError(f"total_time must be positive, got {total_time!r}")
        super().__init__(description, enabled, quiet, file, min_interval_s, log_every_s, start_step)
        self.total_time = float(total_time)
        self.sim_time = float(start_time)
        self._start_lines()
        if self.enabled:
            self._bar = _tqdm()(
                total=self.total_time * 1e3,
                initial=self.sim_time * 1e3,
                desc=description,
                unit="ms",
                bar_format=_BAR_FORMAT,
                file=self._stream,
                mininterval=0.0,  # throttled here, before any tqdm work
                miniters=0,
                smoothing=0.1,
                dynamic_ncols=True,
                leave=True,
            )

    def _done(self) -> float:
        return self.sim_time

    def update(self, step: int, sim_time: float) -> None:
        """Record that ``step`` (simulated time ``sim_time`` s) is done; redraw if due."""
        self.step = step
        self.sim_time = sim_time
        self._tick()

    def _draw(self) -> None:
        self._bar.set_postfix_str(f"{self.steps_per_s:,.0f} steps/s", refresh=False)
        self._bar.update(min(self.sim_time * 1e3, self._bar.total) - self._bar.n)

    def _line(self, final: bool) -> str:
        done = min(self.sim_time / self.total_time, 1.0)
        head = (
            f"{self.description}: {self.sim_time * 1e3:.3f}/{self.total_time * 1e3:.3f} ms "
            f"simulated ({100 * done:.0f}%), step {self.step:,}"
        )
        if final:
            return (
                f"{head}, {self.steps_per_s:,.0f} steps/s, "
                f"{format_duration(self.wall_time_s)} in all"
            )
        steps_rate, sim_rate = self._pace()  # the recent pace: the time left from it
        left = (self.total_time - self.sim_time) / sim_rate if sim_rate > 0 else math.inf
        return (
            f"{head}, {steps_rate:,.0f} steps/s, {format_duration(self.wall_time_s)} so far, "
            f"about {format_duration(max(left, 0.0))} left"
        )


class RelaxProgress(_Progress):
    """Progress of dynamic relaxation, which stops when the kinetic energy has fallen to
    ``tolerance`` of its peak: the steps and that ratio, a bar on ``log10`` of it.

    Parameters
    ----------
    tolerance : float
        The KE ratio at which relaxation stops (``preload.ke_ratio_tol``).
    max_steps : int
        Most steps it may take (``preload.max_steps``), shown in the lines.
    description : str
        Label in front of the bar or line.
    enabled, quiet, file, min_interval_s, log_every_s
        As for :class:`RunProgress`.

    Examples
    --------
    >>> import sys
    >>> with RelaxProgress(1e-5, 200_000, file=sys.stdout, log_every_s=20) as bar:
    ...     for steps, ratio in ((50, 1.0), (100, 1e-3), (150, 5e-6)):
    ...         bar.update(steps, ratio)
    preload: KE ratio 5e-06 (stops below 1e-05), step 150 of at most 200,000, ... s in all
    """

    def __init__(
        self,
        tolerance: float,
        max_steps: int,
        description: str = "preload",
        enabled: bool | None = None,
        quiet: bool = False,
        file: TextIO | None = None,
        min_interval_s: float = 0.5,
        log_every_s: float | None = None,
    ) -> None:
        if not 0 < tolerance < 1:
            raise ValueError(f"tolerance must be in (0, 1), got {tolerance!r}")
        super().__init__(description, enabled, quiet, file, min_interval_s, log_every_s, 0)
        self.tolerance = float(tolerance)
        self.max_steps = int(max_steps)
        self.ke_ratio = math.inf
        self._start_lines()
        if self.enabled:
            self._bar = _tqdm()(
                total=-math.log10(self.tolerance),
                desc=description,
                bar_format=_RELAX_BAR_FORMAT,
                postfix=self._state(0.0),
                file=self._stream,
                mininterval=0.0,
                miniters=0,
                dynamic_ncols=True,
                leave=True,
            )

    @property
    def fraction(self) -> float:
        """How far the ratio has fallen towards the tolerance on a log scale, 0 to 1."""
        if not self.ke_ratio > 0 or not math.isfinite(self.ke_ratio):
            return 1.0 if self.ke_ratio == 0 else 0.0
        return min(max(math.log10(self.ke_ratio) / math.log10(self.tolerance), 0.0), 1.0)

    def update(self, steps: int, ke_ratio: float) -> None:
        """Record ``steps`` taken and the current KE / peak KE; redraw if due."""
        self.step = steps
        self.ke_ratio = ke_ratio
        self._tick()

    def _state(self, steps_per_s: float) -> str:
        ratio = "-" if math.isinf(self.ke_ratio) else f"{self.ke_ratio:.2g}"
        return (
            f"KE ratio {ratio} (stops below {self.tolerance:g}), step {self.step:,} of at "
            f"most {self.max_steps:,}, {steps_per_s:,.0f} steps/s"
        )

    def _draw(self) -> None:
        self._bar.set_postfix_str(self._state(self.steps_per_s), refresh=False)
        self._bar.n = self.fraction * self._bar.total  # the ratio may rise again
        self._bar.refresh()

    def _line(self, final: bool) -> str:
        rate = self.steps_per_s if final else self._pace()[0]
        wall = f"{format_duration(self.wall_time_s)} {'in all' if final else 'so far'}"
        return f"{self.description}: {self._state(rate)}, {wall}"
