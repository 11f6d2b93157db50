"""bearing_io.progress: progress over many records, timed lines in a log and a bar on a
terminal."""

from __future__ import annotations

import numpy as np


def test_progress_lines_wait_for_their_interval(monkeypatch):
    """A line only once the interval has passed since the last (the clock is driven here:
    12 s a record, a 20 s interval), none for the last record, whose line is the summary."""
    import io

    from bearing_io import progress

    now = iter(np.arange(0.0, 1000.0, 12.0))
    monkeypatch.setattr(progress, "_clock", lambda: float(next(now)))
    log = io.StringIO()
    shown = progress.RecordProgress(6, file=log, log_every_s=20.0)
    for k in range(6):
        shown.update(f"r{k}.mat")
    shown.close()
    assert log.getvalue().splitlines() == [
        "benchmark: 2 of 6 records, 24 s, last r1.mat",
        "benchmark: 4 of 6 records, 48 s, last r3.mat",
        "benchmark: 6 records in 84 s",
    ]


def test_progress_is_a_bar_on_a_terminal():
    import io

    from bearing_io.progress import RecordProgress

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    screen = Terminal()
    shown = RecordProgress(3, file=screen)
    for k in range(3):
        shown.update(f"r{k}.mat")
    shown.close()
    last = screen.getvalue().split("\r")[-1]
    assert "benchmark: 100%" in last and "3/3" in last and "r2.mat" in last
