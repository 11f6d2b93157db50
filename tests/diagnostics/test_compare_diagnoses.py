"""benchmarks/diagnostics/compare_diagnoses.py: diagnoses reduced to plain data, and the first field
where two differ."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

from benchmarks.diagnostics.compare_diagnoses import first_difference, main, plain, verdict
from benchmarks.diagnostics.other_source_scenarios import scenario
from diagnostics import diagnose


@pytest.fixture(scope="module")
def diagnosis():
    *_, fs, geometry, shaft, x = scenario(1)  # an outer-race fault beside another source
    return diagnose(x, fs, geometry, shaft)


def test_a_diagnosis_reduces_to_plain_data_equal_to_itself(diagnosis):
    a = pickle.loads(pickle.dumps(plain(diagnosis)))
    assert a == plain(diagnosis) and first_difference(a, plain(diagnosis)) == ""
    name, fields = a
    assert name == "Diagnosis" and fields["fault"] == diagnosis.fault
    assert fields["confidence"] == float(diagnosis.confidence).hex()


def test_the_first_field_that_differs_is_named(diagnosis):
    """A last-bit change in one harmonic's normalised value, deep in the first band's
    outer-race score, is found and named by its path."""
    band = diagnosis.bands[0]
    score = band.families["BPFO"]
    z = score.z.copy()
    z[1] = np.nextafter(z[1], np.inf)
    families = dict(band.families, BPFO=dataclasses.replace(score, z=z))
    bands = (dataclasses.replace(band, families=families), *diagnosis.bands[1:])
    changed = dataclasses.replace(diagnosis, bands=bands)
    assert first_difference(plain(diagnosis), plain(changed)) == ".bands[0].families.BPFO.z"
    shorter = dataclasses.replace(diagnosis, bands=diagnosis.bands[:1])
    assert first_difference(plain(diagnosis), plain(shorter)) == ".bands (length)"


def test_the_verdict_moved_is_read_from_the_plain_data(diagnosis):
    """Which diagnoses a change moved: the verdict of each side, from its plain data."""
    moved = dataclasses.replace(diagnosis, fault="outer or ball", undecided=("outer", "ball"))
    assert verdict(plain(diagnosis)) == diagnosis.fault
    assert verdict(plain(moved)) == "outer or ball"
    assert verdict([1, 2]) == "?"


@pytest.mark.parametrize(
    ("argv", "message"),
    [([], "give folders of records"), (["/nonexistent/records"], "/nonexistent/records: no such")],
)
def test_bad_arguments_are_refused(argv, message, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err
