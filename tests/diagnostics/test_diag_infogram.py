"""The infogram of the squared envelope spectrum and the band diagnose takes from it."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from benchmarks.diagnostics.aperiodic_impulse_scenarios import main as scenarios_main
from benchmarks.diagnostics.aperiodic_impulse_scenarios import scenario, weak_scenario
from diagnostics import Infogram, diagnose, infogram, kurtogram, kurtogram_and_infogram

FS = 12000.0
DATA = Path(__file__).resolve().parents[3] / "shared" / "data"


def _rings(n: int, times: np.ndarray, resonance: float, size) -> np.ndarray:
    tail = np.arange(240) / FS
    ring = np.exp(-300.0 * tail) * np.sin(2 * np.pi * resonance * tail)
    x = np.zeros(n)
    for i, a in zip(times, np.broadcast_to(size, times.shape), strict=True):
        x[i : i + ring.size] += a * ring[: n - i]
    return x


def test_random_noise_reads_the_exponential_negentropy():
    """White noise: every band's envelope spectrum is a set of exponential values, whose
    E[X ln X] is 1 - Euler's constant (0.423); the filters' passbands tilt the spectrum a
    little (a few percent more). The level-0 band's envelope spectrum falls linearly to
    fs/2, which gives 0.423 + ln 2 - 1/2 = 0.616."""
    x = np.random.default_rng(3).standard_normal(2**17)
    ig = infogram(x, FS, nlevel=5)
    assert isinstance(ig, Infogram) and ig.quantity == "SES negentropy"
    inner_rows = ig.K[1:]
    assert np.median(inner_rows) == pytest.approx(1.0 - np.euler_gamma, rel=0.06)
    assert inner_rows.max() < 0.55
    assert ig.K[0, 0] == pytest.approx(1.0 - np.euler_gamma + math.log(2.0) - 0.5, rel=0.02)


def test_the_train_wins_the_infogram_and_random_impacts_the_kurtogram():
    """A 100 Hz train ringing 3 kHz beside eight impacts 8 times stronger at random times
    ringing 1 kHz: the kurtogram's band holds the random ones, the infogram's the train."""
    rng = np.random.default_rng(1)
    n = 2**15
    train = _rings(n, np.arange(0, n - 240, 120), 3000.0, 1.0)
    spikes = _rings(n, np.sort(rng.choice(n - 300, 8, replace=False)), 1000.0, 8.0)
    x = train + spikes + 0.2 * rng.standard_normal(n)
    kg, ig = kurtogram(x, FS, nlevel=4), infogram(x, FS, nlevel=4)
    assert kg.band[1] <= 1500.0
    assert ig.band[0] <= 3000.0 <= ig.band[1]
    assert ig.kurtosis > 3.0


def test_shaft_harmonics_are_left_out():
    """White noise in 3-4.5 kHz modulated 90 % at the shaft rate: without the shaft rate its
    band wins the infogram by far; with it the shaft harmonics are left out and the map's
    maximum falls to less than half (what is left sits at the band's filter edges, where
    the modulated noise is narrow-band and its lines spread beyond the +-2.5 bins)."""
    rng = np.random.default_rng(5)
    n = 2**16
    t = np.arange(n) / FS
    spectrum = np.fft.rfft(rng.standard_normal(n))
    f = np.fft.rfftfreq(n, 1.0 / FS)
    spectrum[(f < 3000.0) | (f > 4500.0)] = 0.0
    hum = np.fft.irfft(spectrum, n)
    hum *= 3.0 / hum.std() * (1.0 + 0.9 * np.cos(2 * np.pi * 30.0 * t))
    x = hum + rng.standard_normal(n)
    with_shaft = infogram(x, FS, nlevel=4, cyclic_range=(10.0, 600.0), shaft_hz=30.0)
    without = infogram(x, FS, nlevel=4, cyclic_range=(10.0, 600.0))
    assert without.band[0] <= 3000.0 and without.band[1] >= 4500.0 and without.kurtosis > 2.0
    assert with_shaft.kurtosis < 0.5 * without.kurtosis


def test_one_pass_gives_both_maps_exactly():
    x = np.random.default_rng(7).standard_normal(2**14)
    kg, ig = kurtogram_and_infogram(x, FS, 4, (10.0, 900.0), 29.0)
    assert np.array_equal(kg.K, kurtogram(x, FS, nlevel=4).K)
    assert np.array_equal(ig.K, infogram(x, FS, 4, (10.0, 900.0), 29.0).K)
    assert (ig.fc, ig.bw) == (infogram(x, FS, 4, (10.0, 900.0), 29.0).fc, ig.bw)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"cyclic_range": (500.0, 100.0)}, "cyclic_range"),
        ({"cyclic_range": 5.0}, "cyclic_range"),
        ({"shaft_hz": -1.0}, "shaft_hz"),
        ({"nlevel": 9}, "too short for an infogram"),
    ],
)
def test_bad_inputs_are_named(kwargs, match):
    x = np.random.default_rng(0).standard_normal(2**14)
    with pytest.raises(ValueError, match=match):
        infogram(x, FS, **kwargs)


def test_diagnose_names_faults_beside_randomimpacts():
    """benchmarks/diagnostics/aperiodic_impulse_scenarios.py, its first 12 scenarios: faults beside
    impacts at random times up to 20 times as strong, ringing another resonance. With the
    kurtogram's band the random impacts hide every fault; the infogram's band names most, and no
    healthy record is called faulty either way."""
    named = {"kurtogram": 0, "infogram": 0}
    for seed in range(12):
        fault, _, fs, geometry, shaft, x = scenario(seed)
        for selector in named:
            verdict = diagnose(x, fs, geometry, shaft, band_selector=selector).fault
            assert verdict in (fault, "none")
            named[selector] += fault != "none" and verdict == fault
    assert named["infogram"] >= named["kurtogram"] + 3
    assert named["infogram"] >= 4


def test_scenario_script_prints_both_selectors(capsys):
    assert scenarios_main(["--scenarios", "2", "--seed", "1", "--weak", "0"]) == 0
    out = capsys.readouterr().out
    assert "| kurtogram | 1 | 0 |" in out and "| infogram | 1 | 1 |" in out
    assert "weak faults" not in out
    for bad in (["--scenarios", "0"], ["--weak", "-1"]):
        with pytest.raises(SystemExit):
            scenarios_main(bad)


def test_scenario_script_weak_tables_count_each_fault_type():
    """The weak tables: one fault per draw, so the per-type row of each size and selector
    counts one record in all, and names it where the first table does."""
    from benchmarks.diagnostics import aperiodic_impulse_scenarios

    lines = aperiodic_impulse_scenarios.weak_table(1)
    fault = weak_scenario(0, 1.0)[0]
    assert lines[lines.index("by fault type") + 1].startswith("| impacts / noise | band chosen")
    rows = [line for line in lines if line.startswith("| 1.3 |")]
    named = [int(cell.split()[0]) for cell in rows[0].split("|")[2:4]]  # kurtogram, infogram
    for selector, count in zip(("kurtogram", "infogram"), named, strict=True):
        row = next(r for r in rows if f"| {selector} |" in r)
        cells = dict(zip(("outer", "inner", "ball"), row.split("|")[3:6], strict=True))
        assert cells[fault].strip() == f"{count} of 1"
        assert all(cells[f].strip() == "0 of 0" for f in cells if f != fault)


def test_weak_faults_are_named_more_often_from_the_infograms_band():
    """Faults alone, impacts as strong as the noise (the script's weak table, its first 8
    draws: both bearings, 12 and 48 kHz, outer, inner, ball): the infogram's band holds the
    fault's train wherever the kurtogram's does and where the kurtogram takes a band of
    noise; neither names a wrong fault."""
    named = {"kurtogram": 0, "infogram": 0}
    for seed in range(8):
        fault, fs, geometry, shaft, x = weak_scenario(seed, 1.0)
        for selector in named:
            verdict = diagnose(x, fs, geometry, shaft, band_selector=selector).fault
            assert verdict in (fault, "none")
            named[selector] += verdict == fault
    assert named["infogram"] >= named["kurtogram"] + 2
    assert named["infogram"] >= 7


def test_band_selector_is_checked():
    x = np.random.default_rng(0).standard_normal(24000)
    from diagnostics.app.datasets import CWRU_DRIVE_END

    with pytest.raises(ValueError, match="band_selector"):
        diagnose(x, FS, CWRU_DRIVE_END, 29.95, band_selector="spectral")
    d = diagnose(x, FS, CWRU_DRIVE_END, 29.95)
    assert isinstance(d.infogram, Infogram)
    assert [b.name for b in d.bands] == ["prewhitened", "infogram", "infogram, second"]
    kurtogram_bands = diagnose(x, FS, CWRU_DRIVE_END, 29.95, band_selector="kurtogram").bands
    assert [b.name for b in kurtogram_bands] == ["prewhitened", "kurtogram"]


def test_best_band_apart_from_another():
    """kurtogram_band(..., apart_from=band): the best of the bands that do not overlap the
    one given, under the same width and low-edge limits (below the best of all)."""
    from diagnostics import kurtogram_band

    rng = np.random.default_rng(4)
    n = 2**15
    x = _rings(n, np.arange(0, n - 240, 97), 2600.0, 1.0) + _rings(
        n, np.arange(0, n - 240, 131), 4300.0, 0.8
    )
    ig = infogram(x + 0.3 * rng.standard_normal(n), FS, nlevel=4, cyclic_range=(20.0, 600.0))
    first, _ = kurtogram_band(ig, 300.0, 500.0)
    second, value = kurtogram_band(ig, 300.0, 500.0, apart_from=first)
    assert second[1] <= first[0] or second[0] >= first[1]
    bws = FS / 2.0 / 2.0 ** np.asarray(ig.levels)
    lows = np.floor(np.asarray(ig.freqs)[None, :] / bws[:, None]) * bws[:, None]
    eligible = (bws[:, None] >= 300.0) & (lows >= 500.0)
    apart = (lows + bws[:, None] <= first[0]) | (lows >= first[1])
    assert value == pytest.approx(ig.K[eligible & apart].max())
    assert value < ig.K[eligible].max()


@pytest.mark.parametrize("seed", [13, 39])
def test_the_infograms_second_band_holds_the_fault(seed):
    """Aperiodic scenarios 13 (an inner-race fault beside impacts at random times 18 times
    as strong) and 39 (a ball fault beside 25 such impacts a second): the random impacts
    take the infogram's best band by a little, and neither it nor the whole band shows any
    fault; the fault is named from the infogram's best band apart from that one."""
    fault, _, fs, geometry, shaft, x = scenario(seed)
    d = diagnose(x, fs, geometry, shaft)
    bands = {b.name: b for b in d.bands}
    first, second = bands["infogram"].band, bands["infogram, second"].band
    assert second[1] <= first[0] or second[0] >= first[1]
    assert d.fault == fault and d.band == second
    for name in ("prewhitened", "infogram"):
        assert not any(s is not None and s.detected for s in bands[name].families.values())


def test_records_with_random_impacts_script(tmp_path, capsys):
    """benchmarks/diagnostics/records_with_random_impacts.py on a folder of one CWRU-named synthetic
    outer-race record, two draws of random impacts 5-15 times its standard deviation: the infogram's
    band names the fault at least once and as often as the kurtogram's, neither names another; a
    folder without records is refused."""
    from synthetic_records import cwru_file, impacts

    from benchmarks.diagnostics.records_with_random_impacts import main as records_main
    from diagnostics import bearing_frequencies
    from diagnostics.app.datasets import CWRU_DRIVE_END

    folder = tmp_path / "cwru"
    folder.mkdir()
    shaft, n = 1797 / 60.0, int(2 * FS)
    x = impacts(FS, bearing_frequencies(CWRU_DRIVE_END, shaft).bpfo, 2.0, 1)
    noise = np.random.default_rng(5).standard_normal(n)
    cwru_file(folder, "12k_Drive_End_OR007@6_0_130.mat", 130, x, noise, rpm=1797)
    assert records_main([str(folder), "--draws", "2"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert "labelled fault named (2)" in out[-4]
    rows = {r.split("|")[1].strip(): [int(v) for v in r.split("|")[2:4]] for r in out[-2:]}
    assert rows["infogram"][0] >= max(1, rows["kurtogram"][0])
    assert rows["infogram"][1] == rows["kurtogram"][1] == 0
    for bad in ([str(tmp_path / "nothing")], [str(folder), "--draws", "0"]):
        with pytest.raises(SystemExit):
            records_main(bad)


@pytest.mark.skipif(not (DATA / "cwru").is_dir(), reason="../shared/data not present")
def test_faults_on_measured_backgrounds_script(capsys):
    """benchmarks/diagnostics/faults_on_measured_backgrounds.py on the five CWRU development records
    of cwru/: six healthy bearings' channels (the fan-end channel of each drive-end fault record,
    both channels of the baseline), at 12 kHz; each reads none as measured, and a fault of each type
    with impacts as strong as the channel's standard deviation is named on every one. Of cwru48k/,
    the five fan-end channels that copy the drive end's are left out."""
    from benchmarks.diagnostics.faults_on_measured_backgrounds import backgrounds
    from benchmarks.diagnostics.faults_on_measured_backgrounds import main as backgrounds_main

    found = list(backgrounds([DATA / "cwru"], 12000.0))
    assert sorted(end for _, end, *_ in found) == ["drive"] + ["fan"] * 5
    assert {fs for _, _, fs, *_ in found} == {12000.0}
    assert backgrounds_main([str(DATA / "cwru"), "--sizes", "1", "--draws", "1"]) == 0
    out = capsys.readouterr().out
    assert "drive-end bearing, 1 backgrounds: 1 read none" in out
    assert "fan-end bearing, 5 backgrounds: 5 read none" in out
    assert "| 1 | 1 of 1 (0) | 1 of 1 (0) | 1 of 1 (0) |" in out
    assert "| 1 | 5 of 5 (0) | 5 of 5 (0) | 5 of 5 (0) |" in out
    if (DATA / "cwru48k").is_dir():
        assert len(list(backgrounds([DATA / "cwru48k"], 0.0))) == 12 - 5
