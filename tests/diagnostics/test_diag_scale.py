"""A record's unit does not change what ``diagnostics`` finds (issue 46, item 2).

Every public function that takes a record gives, for ``x`` and ``c * x`` (c from 1e-300 to
1e300, and powers of two from 2**-990 to 2**990), the same result without a warning: the
same numbers where they have no unit (kurtosis, p-values, frequencies, verdicts), ``c``
times them where they are amplitudes, ``c**2`` times them where they are powers (or one
clear ``ValueError`` where that leaves the range of float64), and ``20 log10 c`` more in
dB. For a power of two ``c`` the rescaling is exact: everything but the record's shaft-line
fit (a parabola through log powers) comes out bit for bit. ``diagnostics analyze`` on the
CWRU record 130 scaled by 1e-300 ... 1e300 gives the record's own verdict.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import warnings
from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.io import loadmat, savemat
from synthetic_records import FREQS, GEOMETRY, SHAFT_HZ, fault_signal, spall_record

import diagnostics as dg
from diagnostics.app.cli import main

FS = 12000.0
_T = np.arange(int(0.6 * FS)) / FS
# Outer-race impacts ringing a 3 kHz resonance, in noise, over five shaft harmonics.
RECORD = fault_signal(FS, FREQS.bpfo, 3000.0, duration_s=0.6, seed=1) + sum(
    0.3 / k * np.cos(2 * np.pi * k * SHAFT_HZ * _T) for k in range(1, 6)
)
# Two channels, each rescaled on its own where it needs to be.
CHANNELS = np.stack([RECORD, -0.25 * RECORD[::-1]])
TACHO = (np.sin(2 * np.pi * SHAFT_HZ * _T) > 0.9).astype(float)
SPALL_FS = 48000.0
SPALL = spall_record(SPALL_FS, 1.5e-3 / dg.contact_speed(GEOMETRY, SHAFT_HZ), 0.15)[0]

# What a result part carries of the record's unit: 0 none, 1 amplitude, 2 power, DB a level.
DB = "dB"


def _parts(result, *units) -> list[tuple[object, object]]:
    return list(zip(result, units, strict=True))


# name -> (record, call giving [(part, unit), ...]) for every public function of a record.
CASES: dict[str, tuple[np.ndarray, Callable]] = {
    "bandpass_filter": (CHANNELS, lambda v: [(dg.bandpass_filter(v, FS, 2000.0, 4000.0), 1)]),
    "lowpass_filter": (RECORD, lambda v: [(dg.lowpass_filter(v, FS, 1000.0), 1)]),
    "notch_filter": (CHANNELS, lambda v: [(dg.notch_filter(v, FS, 2 * SHAFT_HZ), 1)]),
    "envelope": (RECORD, lambda v: [(dg.envelope(v, FS, band=(2000.0, 4000.0)), 1)]),
    "envelope_spectrum": (CHANNELS, lambda v: _parts(dg.envelope_spectrum(v, FS), 0, 2)),
    "stft": (CHANNELS, lambda v: _parts(dg.stft(v, FS, nperseg=128), 0, 0, 1)),
    "psd": (CHANNELS, lambda v: _parts(dg.psd(v, FS, nperseg=512), 0, 2)),
    "third_octave": (CHANNELS, lambda v: _parts(dg.third_octave(v, FS), 0, DB)),
    "spectral_kurtosis": (CHANNELS, lambda v: [(dg.spectral_kurtosis(v, FS, nw=128), 0)]),
    "kurtogram": (RECORD, lambda v: [(dg.kurtogram(v, FS, nlevel=4), 0)]),
    "infogram": (RECORD, lambda v: [(dg.infogram(v, FS, nlevel=4, shaft_hz=SHAFT_HZ), 0)]),
    "kurtogram_and_infogram": (RECORD, lambda v: [(dg.kurtogram_and_infogram(v, FS, 4), 0)]),
    "kurtogram_band": (
        RECORD,
        lambda v: [(dg.kurtogram_band(dg.kurtogram(v, FS, nlevel=4), min_low_hz=750.0), 0)],
    ),
    "prewhiten": (CHANNELS, lambda v: [(dg.prewhiten(v, FS), 0)]),
    "normalised_envelope_spectrum": (
        RECORD,
        lambda v: [(dg.normalised_envelope_spectrum(v, FS, (2000.0, 4000.0), 600.0, 10.0), 0)],
    ),
    "discrete_random_separation": (
        RECORD,
        lambda v: _parts(
            dataclasses.astuple(dg.discrete_random_separation(v, FS, 256)), 1, 1, 0, 0
        ),
    ),
    "order_track": (
        CHANNELS,
        lambda v: _parts(dataclasses.astuple(dg.order_track(v, FS, SHAFT_HZ, 64)), 1, 0, 0, 0, 0),
    ),
    "speed_from_tacho": (
        TACHO,
        lambda v: [
            (dg.speed_from_tacho(v, FS), 0),
            (dg.speed_from_tacho(v, FS, threshold=0.375 * v.max()), 0),  # in v's unit
        ],
    ),
    "shaft_lines": (RECORD, lambda v: [(dg.shaft_lines(v, FS, 1.01 * SHAFT_HZ), 0)]),
    "speed_check": (RECORD, lambda v: [(dg.speed_check(v, FS, 1.01 * SHAFT_HZ), 0)]),
    "estimate_speed": (RECORD, lambda v: [(dg.estimate_speed(v, FS, 20.0, 40.0), 0)]),
    "diagnose": (RECORD, lambda v: [(dg.diagnose(v, FS, GEOMETRY, SHAFT_HZ, nlevel=4), 0)]),
    "estimate_defect_size": (
        SPALL,
        lambda v: [(dg.estimate_defect_size(v, SPALL_FS, GEOMETRY, SHAFT_HZ), 0)],
    ),
}
# Public names that take no record (geometry, kinematics, resolutions, files) or are results.
NO_RECORD = {
    "BearingGeometry", "FaultFrequencies", "bearing_frequencies", "contact_speed",
    "spall_length_from_travel", "record_requirements", "sk_threshold", "choose_nlevel",
    "choose_nperseg", "choose_sk_windows", "third_octave_f_min", "third_octave_centres",
    "shaft_angle", "read_signal", "read_speed_profile",
}  # fmt: skip
RESULTS = {
    "BandScore", "Candidate", "DefectSize", "Diagnosis", "FamilyScore", "Infogram", "Kurtogram",
    "OrderTrack", "Separation", "ShaftLines", "Signal", "SpectralKurtosis", "SpeedEstimate",
}  # fmt: skip
# Results computed through the record's shaft-line fit (log powers): equal to rounding only.
ROUNDED = {"shaft_lines", "speed_check", "diagnose"}
RTOL = 1e-9


def _call(name: str, c: float):
    """``CASES[name]`` on its record times ``c``, any warning raised as an error."""
    record, call = CASES[name]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return call(c * record)


@functools.cache
def _reference(name: str):
    return _call(name, 1.0)


def _assert_same(a, b, exact: bool, where: str = "") -> None:
    """``a`` (from ``c * x``, its unit taken out) against ``b`` (from ``x``): equal types,
    shapes, strings and integers; floats within RTOL of the largest (bit for bit where
    ``exact``)."""
    assert type(a) is type(b), where
    if dataclasses.is_dataclass(b):
        for f in dataclasses.fields(b):
            _assert_same(getattr(a, f.name), getattr(b, f.name), exact, f"{where}.{f.name}")
    elif isinstance(b, dict):
        assert a.keys() == b.keys(), where
        for key in b:
            _assert_same(a[key], b[key], exact, f"{where}[{key!r}]")
    elif isinstance(b, tuple | list):
        assert len(a) == len(b), where
        for i, (u, v) in enumerate(zip(a, b, strict=True)):
            _assert_same(u, v, exact, f"{where}[{i}]")
        if hasattr(b, "n_frames"):  # SpectralKurtosis
            assert a.n_frames == b.n_frames, where
    elif isinstance(b, np.ndarray) and b.dtype.kind in "fc":
        assert a.shape == b.shape, where
        if exact:
            assert np.array_equal(a, b, equal_nan=True), where
            return
        finite = np.isfinite(b)
        assert np.array_equal(finite, np.isfinite(a)), where
        assert np.array_equal(a[~finite], b[~finite], equal_nan=True), where
        scale = np.max(np.abs(b[finite]), initial=0.0)
        assert np.all(np.abs(a[finite] - b[finite]) <= RTOL * scale), where
    elif isinstance(b, np.ndarray):
        assert np.array_equal(a, b), where
    elif isinstance(b, float):
        if exact or not math.isfinite(b):
            assert a == b or (math.isnan(a) and math.isnan(b)), where
        else:
            assert math.isclose(a, b, rel_tol=RTOL, abs_tol=1e-12), where
    else:
        assert a == b, where


def _in_unit_of_x(part, unit, c: float):
    """A part of the result for ``c * x`` expressed as the result for ``x``."""
    if unit == DB:
        return part - 20.0 * math.log10(c)
    for _ in range(unit):
        part = part / c  # one factor at a time: c**2 itself can overflow
    return part


def _normal(part) -> bool:
    """Whether no value of an array is subnormal: rescaling it by a power of two is then
    exact (a record's power near 1e-300 has bins below 1e-308)."""
    if not isinstance(part, np.ndarray):
        return True
    values = np.abs(np.stack([part.real, part.imag]) if np.iscomplexobj(part) else part)
    return not np.any((values > 0.0) & (values < np.finfo(float).tiny))


def _decade(part, unit, c: float) -> float:
    """log10 of the largest magnitude a part reaches for ``c * x``."""
    peak = float(np.max(np.abs(part)))
    return math.log10(peak) + unit * math.log10(c) if peak > 0 else 0.0


SCALES = st.one_of(
    st.integers(-300, 300).map(lambda k: 10.0**k),
    st.integers(-990, 990).map(lambda k: 2.0**k),
)


@pytest.mark.parametrize("name", sorted(CASES))
@settings(max_examples=5, deadline=None, database=None)
@given(c=SCALES)
@example(c=1e-300)
@example(c=1e300)
@example(c=2.0**-990)
@example(c=2.0**990)
def test_same_result_in_any_unit(name, c):
    reference = _reference(name)
    power_of_two = math.frexp(c)[0] == 0.5
    exact = power_of_two and name not in ROUNDED
    # A power (unit 2) of a record near 1e300 or 1e-300 leaves float64: refused plainly.
    decades = [_decade(p, u, c) for p, u in reference if u in (1, 2)]
    if any(not -306.0 < d < 307.0 for d in decades):
        if all(-309.0 < d < 310.0 for d in decades):
            return  # at the very edge of the range: either outcome is fine
        with pytest.raises(ValueError, match="out of the range of float64 numbers"):
            _call(name, c)
        return
    result = _call(name, c)
    assert len(result) == len(reference)
    for (part, unit), (ref, _) in zip(result, reference, strict=True):
        if unit == 0:
            _assert_same(part, ref, exact, name)
        else:
            # Amplitudes and powers come back bit for bit too (their rescaling is exact),
            # but for values below the normal range, and levels in dB.
            bits = exact and unit != DB and _normal(part)
            _assert_same(_in_unit_of_x(part, unit, c), ref, bits, name)


def test_every_public_function_of_a_record_is_checked():
    assert set(CASES) | NO_RECORD | RESULTS == set(dg.__all__)
    assert not (set(CASES) & (NO_RECORD | RESULTS))


def test_a_record_near_the_largest_float_is_analysed_not_refused():
    # 1e308: its squares overflow; rescaled first, its verdict is the record's own.
    x = RECORD / np.max(np.abs(RECORD)) * 1.7e308
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = dg.diagnose(x, FS, GEOMETRY, SHAFT_HZ, nlevel=4)
        kg = dg.kurtogram(x, FS, nlevel=4)
    reference = _reference("diagnose")[0][0]
    assert (d.fault, d.band, d.dominated) == (reference.fault, reference.band, reference.dominated)
    assert kg.band == _reference("kurtogram")[0][0].band


def test_a_power_out_of_range_is_one_clear_line():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError) as err:
            dg.psd(1e300 * RECORD, FS, nperseg=512)
    message = str(err.value)
    assert "\n" not in message and "give x in a larger unit" in message


def test_figures_of_a_record_out_of_range_name_their_unit():
    from diagnostics import plots

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        psd = plots.plot_psd_notch(1e300 * RECORD, FS, [60.0]).axes[0]
        trace = plots.plot_time_trace(1e-300 * RECORD, FS, unit="g").axes[0]
    # Drawn in a unit 1e301 (1e-299) times the record's, which the label names.
    peak = np.max(np.abs(RECORD))
    assert psd.get_ylabel() == f"PSD ((1e{round(math.log10(1e300 * peak))} unit)^2/Hz)"
    decade = round(math.log10(1e-300 * peak))
    assert trace.get_ylabel() == f"signal (1e{decade} g)"
    shown = np.max(np.abs(trace.lines[0].get_ydata()))
    assert shown == pytest.approx(1e-300 * peak / 10.0**decade, rel=1e-9)


# -------------------------------------------------------- the command line on a CWRU record
RECORD_130 = "12k_Drive_End_OR007@6_0_130.mat"
BEARING = "n=9,d=7.94mm,D=39.04mm,angle=0"


@pytest.fixture(scope="module")
def summary_130(cwru_dir, tmp_path_factory) -> dict:
    """``summary.json`` of ``analyze`` on record 130 as it is."""
    return _analyze(cwru_dir / RECORD_130, tmp_path_factory.mktemp("record-130"))


def _analyze(path, out) -> dict:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code = main(["analyze", str(path), "--fs", "12000", "--bearing", BEARING,
                     "--out", str(out)])  # fmt: skip
    assert code == 0
    return json.loads((out / "summary.json").read_text())


@pytest.mark.parametrize("c", [1e-300, 1e-6, 1e6, 1e300])
def test_analyze_cwru_record_in_any_unit(cwru_dir, summary_130, tmp_path, c):
    variables = loadmat(cwru_dir / RECORD_130)
    channels = [k for k in variables if k.endswith("_time")]
    assert channels
    for key in channels:
        variables[key] = c * variables[key]
    path = tmp_path / RECORD_130
    savemat(path, {k: v for k, v in variables.items() if not k.startswith("__")})
    summary, reference = _analyze(path, tmp_path / "out"), summary_130
    for key in ("verdict", "band_hz", "dominated", "rpm"):
        assert summary[key] == reference[key], key
    assert summary["confidence"] == pytest.approx(reference["confidence"], rel=1e-9)
    for family, score in reference["scores"].items():
        assert summary["scores"][family] == pytest.approx(score, rel=1e-9)
