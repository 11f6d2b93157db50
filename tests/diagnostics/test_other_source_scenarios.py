"""benchmarks/diagnostics/other_source_scenarios.py: records beside another source of impacts."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks.diagnostics.other_source_scenarios import KINDS, main, other_rate, scenario
from diagnostics import bearing_frequencies
from diagnostics.app.datasets import CWRU_DRIVE_END, CWRU_FAN_END


def test_scenarios_are_reproducible_and_cycle_the_kinds():
    first, again = scenario(5), scenario(5)
    np.testing.assert_array_equal(first[-1], again[-1])
    assert [scenario(s)[2] for s in range(0, 12, 2)] == [*KINDS, *KINDS]
    assert [scenario(s)[1] == "none" for s in range(4)] == [True, False, True, False]


@pytest.mark.parametrize("kind", KINDS)
def test_other_rate_is_what_its_kind_says(kind):
    rng = np.random.default_rng(0)
    own = bearing_frequencies(CWRU_DRIVE_END, 29.0)
    other = bearing_frequencies(CWRU_FAN_END, 29.0)
    for _ in range(20):
        rate = other_rate(rng, kind, 29.0, own, other)
        if kind == "other bearing":
            assert min(abs(rate / other.bpfo - 1), abs(rate / other.bpfi - 1)) <= 0.005
        elif kind == "sub-multiple":
            assert any(abs(rate * q / f - 1) < 1e-12 for f in (own.bpfo, own.bpfi) for q in (2, 3))
        else:
            assert 1.2 * 29.0 <= rate <= 8.0 * 29.0
            assert abs(rate / own.bpfo - 1) > 0.03 and abs(rate / (2 * own.bsf) - 1) > 0.03


def test_table_beside_another_source(capsys):
    """18 records: none of the 9 healthy ones called faulty (before the other-source checks,
    at d8aefea, 4 of them were), the table printed."""
    assert main(["--scenarios", "18"]) == 0
    rows = [r for r in capsys.readouterr().out.splitlines() if r.startswith("| ")][1:]
    assert [r.split("|")[1].strip() for r in rows] == list(KINDS)
    assert all(r.split("|")[3].strip() == "3 of 3" for r in rows)
