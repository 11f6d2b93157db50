"""Progress bar: simulated ms, steps/s and time left from a driven clock; TTY detection."""

from __future__ import annotations

import io

import pytest
import tqdm.std

from taichi_bearing.output import progress
from taichi_bearing.output.progress import RunProgress


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
