"""Long bearing-run checks (marked slow): two rollers through the spall of the coarse case,
re-stressing events one BPFO period apart."""

from __future__ import annotations

import numpy as np
import pytest

from taichi_bearing.analytic.bearing import fault_frequencies
from taichi_bearing.case import load_case

pytestmark = pytest.mark.slow


def test_restress_events_are_one_bpfo_period_apart(tmp_path):
    from taichi_bearing.pipeline import run_case

    # 9 ms at 1000 rpm: roller 0 and then roller 19 (one pitch behind) leave the spall
    case = load_case(
        "cases/validation/coarse_spall.yaml",
        ["run.duration_ms=9.0", "output.frames=false", "run.checkpoint_interval_ms=3.0"],
    )
    summary = run_case(case, tmp_path, threads=1, quiet=True, post=False)
    events = summary["events"]
    assert [e["roller"] for e in events] == [0, 19]
    bpfo = fault_frequencies(case.bearing, case.operating.shaft_hz).bpfo
    gap = np.diff(summary["restress_times_s"])[0]
    assert gap * bpfo == pytest.approx(1.0, abs=0.02)
    assert summary["checks"]["restress_interval"]["passed"]
    # and the entries too (de-stressing) are one period apart
    assert np.diff(summary["entry_times_s"])[0] * bpfo == pytest.approx(1.0, abs=0.02)
