"""Progress: the bar (simulated ms, steps/s, time left) on a terminal, plain lines in a log,
the preload's KE ratio; from a driven clock."""

from __future__ import annotations

import io
import math

import pytest
import tqdm.std

from taichi_bearing.output import progress
from taichi_bearing.output.progress import RelaxProgress, RunProgress, format_duration


class FakeClock:
    def __init__(self) -> None:
        self.t = 1000.0

    def __call__(self) -> float:
        return self.t


class TTY(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.fixture
def clock(monkeypatch):
    c = FakeClock()
    monkeypatch.setattr(progress, "_clock", c)
    monkeypatch.setattr(tqdm.std, "time", c)  # tqdm's own clock (elapsed, remaining)
    return c


def test_bar_shows_sim_time_rate_and_time_left(clock):
    out = io.StringIO()
    # 3 ms simulated in total; 1 ms per 2 s of wall time at 500 steps/s.
    with RunProgress(3e-3, "transient", enabled=True, file=out, min_interval_s=0.5) as bar:
        for k in range(1, 5):
            clock.t += 0.5
            bar.update(250 * k, 0.25e-3 * k)
        text = out.getvalue().split("\r")[-1]
        assert "transient" in text
        assert "1.000/3.000 ms" in text
        assert "500 steps/s" in text
        assert "<00:04" in text  # 2 ms left at 1 ms per 2 s
        assert bar.steps_per_s == pytest.approx(500.0)
        assert bar.wall_time_s == pytest.approx(2.0)
        # Calls closer together than min_interval_s store the state but do not redraw.
        before = out.getvalue()
        clock.t += 0.1
        bar.update(1050, 1.05e-3)
        assert out.getvalue() == before and bar.step == 1050
    assert "1.050/3.000 ms" in out.getvalue().split("\r")[-1]


def test_resume_starts_from_checkpoint(clock):
    out = io.StringIO()
    with RunProgress(
        4e-3, "resume", enabled=True, file=out, start_time=2e-3, start_step=8000
    ) as bar:
        clock.t += 4.0
        bar.update(10000, 3e-3)
        text = out.getvalue().split("\r")[-1]
        assert "3.000/4.000 ms" in text
        assert "500 steps/s" in text  # 2000 steps since the resume in 4 s
        assert "<00:04" in text  # 1 ms left at 1 ms per 4 s


def test_disabled_without_tty_and_when_quiet(clock):
    piped = io.StringIO()
    bar = RunProgress(1e-3, "run", file=piped)
    assert not bar.enabled
    clock.t += 1.0
    bar.update(100, 0.5e-3)
    bar.close()
    assert piped.getvalue() == ""
    assert bar.steps_per_s == pytest.approx(100.0)  # still measured

    shown = RunProgress(1e-3, "run", file=TTY())
    assert shown.enabled
    shown.close()
    tty = TTY()
    quiet = RunProgress(1e-3, "run", enabled=True, quiet=True, file=tty)
    assert not quiet.enabled
    quiet.update(1, 1e-4)
    quiet.write("hello")
    quiet.close()
    assert tty.getvalue() == ""


def test_write_goes_to_the_stream(clock):
    tty = TTY()
    with RunProgress(1e-3, "run", file=tty) as bar:
        bar.write("preload converged")
    assert "preload converged" in tty.getvalue()
    piped = io.StringIO()
    RunProgress(1e-3, "run", file=piped).write("stopped at step 12")
    assert piped.getvalue() == "stopped at step 12\n"


def test_bad_total_is_refused():
    with pytest.raises(ValueError, match="total_time"):
        RunProgress(0.0)


def _lines(stream: io.StringIO) -> list[str]:
    return stream.getvalue().splitlines()


def test_piped_run_prints_a_line_per_interval_with_the_recent_pace_and_a_last_line(clock):
    out = io.StringIO()
    with RunProgress(4e-3, "transient", file=out, log_every_s=10.0) as bar:
        assert not bar.enabled and bar.logging
        clock.t += 5.0
        bar.update(500, 0.5e-3)
        assert out.getvalue() == ""  # not yet 10 s
        clock.t += 5.0
        bar.update(1000, 1e-3)  # 1 ms in 10 s: 100 steps/s
        clock.t += 10.0
        bar.update(3000, 2e-3)  # then 1 ms in 10 s at 200 steps/s: 2 ms left, 20 s
    first, second, last = _lines(out)
    assert first == (
        "transient: 1.000/4.000 ms simulated (25%), step 1,000, 100 steps/s, "
        "10.0 s so far, about 30.0 s left"
    )
    assert second == (
        "transient: 2.000/4.000 ms simulated (50%), step 3,000, 200 steps/s, "
        "20.0 s so far, about 20.0 s left"
    )
    # the last line: the mean rate over the whole run, no time left
    assert (
        last == "transient: 2.000/4.000 ms simulated (50%), step 3,000, 150 steps/s, 20.0 s in all"
    )


def test_lines_only_when_piped_and_asked_for(clock):
    def shown(**kwargs) -> str:
        stream = kwargs.pop("file", None) or io.StringIO()
        with RunProgress(1e-3, "run", file=stream, **kwargs) as bar:
            clock.t += 5.0
            bar.update(100, 0.5e-3)
        return stream.getvalue()

    assert "0.500/1.000 ms simulated" in shown(log_every_s=1.0)
    assert shown(log_every_s=1.0, quiet=True) == ""
    assert shown(log_every_s=1.0, enabled=False) == ""
    assert shown() == ""  # no interval: no lines
    bar = shown(log_every_s=1.0, file=TTY())  # a terminal: the bar, not lines
    assert "0.500/1.000 ms" in bar and "so far" not in bar and "in all" not in bar


def test_relaxation_lines_show_steps_and_ke_ratio_against_the_tolerance(clock):
    out = io.StringIO()
    with RelaxProgress(1e-5, 200_000, file=out, log_every_s=10.0) as bar:
        clock.t += 10.0
        bar.update(4000, 3.2e-3)
        clock.t += 4.0
        bar.update(5000, 1.5e-5)  # not yet 10 s since the last line
        clock.t += 1.0
        bar.update(5050, 9.0e-6)
    first, last = _lines(out)
    assert first == (
        "preload: KE ratio 0.0032 (stops below 1e-05), step 4,000 of at most 200,000, "
        "400 steps/s, 10.0 s so far"
    )
    assert last == (
        "preload: KE ratio 9e-06 (stops below 1e-05), step 5,050 of at most 200,000, "
        "337 steps/s, 15.0 s in all"
    )
    quiet = io.StringIO()
    with RelaxProgress(1e-5, 200_000, file=quiet, log_every_s=1.0, quiet=True) as bar:
        clock.t += 5.0
        bar.update(100, 0.5)
    assert quiet.getvalue() == ""


def test_relaxation_bar_is_on_log10_of_the_ke_ratio(clock):
    tty = TTY()
    bar = RelaxProgress(1e-4, 1000, file=tty)
    assert bar.enabled and bar.fraction == 0.0  # no ratio yet
    for ratio, fraction in ((1.0, 0.0), (1e-2, 0.5), (1e-3, 0.75), (1e-1, 0.25), (1e-6, 1.0)):
        clock.t += 1.0
        bar.update(100, ratio)
        assert bar.fraction == pytest.approx(fraction)  # it may go back
    assert "KE ratio 1e-06 (stops below 0.0001), step 100 of at most 1,000" in tty.getvalue()
    bar.close()
    bar.close()  # idempotent


@pytest.mark.parametrize(
    ("seconds", "text"),
    [(8.24, "8.2 s"), (59.9, "59.9 s"), (312.0, "5 min 12 s"), (3725.0, "1 h 02 min")],
)
def test_format_duration(seconds, text):
    assert format_duration(seconds) == text
    assert format_duration(math.inf) == "?"
