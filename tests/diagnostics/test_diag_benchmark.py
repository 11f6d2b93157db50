"""The benchmark over public record sets: names read as labels, the right channel, bearing and
speed for each record, the table, the command line; the development sets where present."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.io import savemat
from synthetic_records import cwru_file, impacts

from diagnostics import bearing_frequencies
from diagnostics.app.benchmark import find_records, run_benchmark, summary_table
from diagnostics.app.cli import main
from diagnostics.app.datasets import (
    CWRU_DRIVE_END,
    CWRU_FAN_END,
    MFPT_BEARING,
    label_from_name,
    read_labelled_record,
)

DATA = Path(__file__).resolve().parents[3] / "shared" / "data"

NAMES = {
    "12k_Drive_End_IR007_0_105.mat": ("CWRU", "inner", "drive", 0.007, "", "0", 12000.0),
    "48k_Drive_End_OR007@6_0_135.mat": ("CWRU", "outer", "drive", 0.007, "@6", "0", 48000.0),
    "12k_Fan_End_OR014@3_1_309.mat": ("CWRU", "outer", "fan", 0.014, "@3", "1", 12000.0),
    "12k_Fan_End_B021_3_293.mat": ("CWRU", "ball", "fan", 0.021, "", "3", 12000.0),
    "48k_Drive_End_IR014_0_174.mat": ("CWRU", "inner", "drive", 0.014, "", "0", 48000.0),
    "12k Fan End Bearing Fault Data/IR028_2.mat": ("CWRU", "inner", "fan", 0.028, "", "2", 12000.0),
    "normal_2_99.mat": ("CWRU", "none", "drive", None, "", "2", 48000.0),
    "mfpt/OuterRaceFault_vload_4.mat": ("MFPT", "outer", "-", None, "", "vload_4", None),
    "InnerRaceFault_vload_7.mat": ("MFPT", "inner", "-", None, "", "vload_7", None),
    "baseline_2.mat": ("MFPT", "none", "-", None, "", "2", None),
    # The data center's own names: the record number, looked up in its published table.
    "cwru/105.mat": ("CWRU", "inner", "drive", 0.007, "", "0", 12000.0),
    "215.mat": ("CWRU", "inner", "drive", 0.021, "", "2", 48000.0),
    "160.mat": ("CWRU", "outer", "drive", 0.007, "@12", "3", 12000.0),
    "318.mat": ("CWRU", "outer", "fan", 0.021, "@3", "3", 12000.0),
    "98.mat": ("CWRU", "none", "drive", None, "", "1", 48000.0),
    # The cwru Python package's downloads: experiment and speed folders, size-fault names.
    "CWRU/12DriveEndFault/1797/12DriveEndFault/1797/0.007-Ball.mat":
        ("CWRU", "ball", "drive", 0.007, "", "0", 12000.0),
    "CWRU/12FanEndFault/1772/12FanEndFault/1772/0.014-OuterRace3.mat":
        ("CWRU", "outer", "fan", 0.014, "@3", "1", 12000.0),
    "CWRU/48DriveEndFault/1730/48DriveEndFault/1730/0.021-InnerRace.mat":
        ("CWRU", "inner", "drive", 0.021, "", "3", 48000.0),
    "CWRU/12DriveEndFault/1750/NormalBaseline/1750/Normal.mat":
        ("CWRU", "none", "drive", None, "", "2", 48000.0),
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(NAMES))
def test_labels_from_public_names(name):
    label = label_from_name(name)
    source, fault, end, size, position, load, fs = NAMES[name]
    assert (label.source, label.fault, label.end, label.position, label.load, label.fs) == (
        source, fault, end, position, load, fs
    )  # fmt: skip
    assert label.size_in == (pytest.approx(size) if size else None)


@pytest.mark.parametrize("name", ["notes.mat", "run_7.mat", "X097_DE_time.csv", "157.mat"])
def test_other_names_are_not_records(name):
    assert label_from_name(name) is None


def test_bearings_reproduce_the_published_defect_frequencies():
    # CWRU documentation, as multiples of the shaft rate: drive end 6205 and fan end 6203;
    # MFPT: BPFO 81.1 Hz and BPFI 118.9 Hz at 25 Hz.
    published = {
        CWRU_DRIVE_END: (3.5848, 5.4152, 0.39828, 4.7135),
        CWRU_FAN_END: (3.0530, 4.9469, 0.3817, 3.9874),
    }
    for geometry, (bpfo, bpfi, ftf, two_bsf) in published.items():
        f = bearing_frequencies(geometry, 1.0)
        assert (f.bpfo, f.bpfi, f.ftf, 2 * f.bsf) == pytest.approx((bpfo, bpfi, ftf, two_bsf), 1e-3)
    f = bearing_frequencies(MFPT_BEARING, 25.0)
    assert (f.bpfo, f.bpfi) == pytest.approx((81.1, 118.9), abs=0.1)


@pytest.fixture
def synthetic_set(tmp_path):
    """A drive-end outer-race record, a fan-end inner-race record (fault only on the fan-end
    channel, no RPM variable: the nominal 1772 rpm at 1 hp) and a baseline of noise."""
    fs = 12000.0
    shaft = 1797 / 60.0
    noise = np.random.default_rng(5).standard_normal(int(2 * fs))
    bpfo = bearing_frequencies(CWRU_DRIVE_END, shaft).bpfo
    bpfi_fan = bearing_frequencies(CWRU_FAN_END, 1772 / 60.0).bpfi
    folder = tmp_path / "cwru"
    folder.mkdir()
    cwru_file(folder, "12k_Drive_End_OR007@6_0_130.mat", 130, impacts(fs, bpfo, 2.0, 1),
               noise, rpm=1797)  # fmt: skip
    cwru_file(folder, "12k_Fan_End_IR007_1_279.mat", 279, noise, impacts(fs, bpfi_fan, 2.0, 2))
    normal = np.random.default_rng(6).standard_normal(int(2 * 48000.0))
    cwru_file(folder, "normal_0_97.mat", 97, normal, normal, rpm=1797)
    (folder / "readme.mat").write_bytes(b"")  # not a record name: ignored
    return folder


def test_fan_end_record_reads_fan_channel_bearing_and_nominal_speed(synthetic_set):
    rec = read_labelled_record(synthetic_set / "12k_Fan_End_IR007_1_279.mat")
    assert rec.channel == "X279_FE_time" and rec.geometry == CWRU_FAN_END
    assert rec.shaft_hz == pytest.approx(1772 / 60.0) and rec.fs == 12000.0
    rec = read_labelled_record(synthetic_set / "normal_0_97.mat")
    assert rec.channel == "X097_DE_time" and rec.geometry == CWRU_DRIVE_END
    assert rec.fs == 48000.0 and rec.shaft_hz == pytest.approx(1797 / 60.0)


def test_the_cwru_package_layout_is_read(synthetic_set, tmp_path):
    """The same files laid out as the cwru Python package downloads them: experiment and
    speed folders, size-fault names without the record number."""
    root = tmp_path / "Datasets" / "CWRU"
    layout = {
        "12k_Drive_End_OR007@6_0_130.mat":
            "12DriveEndFault/1797/12DriveEndFault/1797/0.007-OuterRace6.mat",
        "12k_Fan_End_IR007_1_279.mat": "12FanEndFault/1772/12FanEndFault/1772/0.007-InnerRace.mat",
        "normal_0_97.mat": "12DriveEndFault/1797/NormalBaseline/1797/Normal.mat",
    }  # fmt: skip
    for source, target in layout.items():
        (root / target).parent.mkdir(parents=True)
        (root / target).write_bytes((synthetic_set / source).read_bytes())
    results = run_benchmark(find_records(root))
    verdicts = {
        r.path.relative_to(root).as_posix(): (r.group, r.expected, r.verdict) for r in results
    }
    assert verdicts == {
        layout["12k_Drive_End_OR007@6_0_130.mat"]: ("CWRU 12k drive end", "outer", "outer"),
        layout["12k_Fan_End_IR007_1_279.mat"]: ("CWRU 12k fan end", "inner", "inner"),
        layout["normal_0_97.mat"]: ("CWRU 48k drive end", "none", "none"),
    }
    fan = read_labelled_record(root / layout["12k_Fan_End_IR007_1_279.mat"])
    assert fan.channel == "X279_FE_time" and fan.shaft_hz == pytest.approx(1772 / 60.0)


def test_benchmark_names_every_synthetic_fault(synthetic_set):
    paths = find_records(synthetic_set)
    assert [p.name for p in paths] == [
        "12k_Drive_End_OR007@6_0_130.mat", "12k_Fan_End_IR007_1_279.mat", "normal_0_97.mat"
    ]  # fmt: skip
    results = run_benchmark(paths)
    assert [(r.expected, r.verdict) for r in results] == [
        ("outer", "outer"), ("inner", "inner"), ("none", "none")
    ]  # fmt: skip
    table = summary_table(results).splitlines()
    assert table[1].split()[:8] == ["CWRU", "12k", "drive", "end", "outer", "1", "1/1", "1"]
    assert "CWRU 12k fan end    inner        1      1/1      0      1" in table[2]
    assert table[-2].split() == ["all", "3", "3/3"]
    assert table[-1] == "wrong fault named: 0 of 3"


def test_benchmark_command_line(synthetic_set, tmp_path, capsys):
    csv = tmp_path / "verdicts.csv"
    assert main(["benchmark", str(synthetic_set), "--records", "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "12k_Fan_End_IR007_1_279.mat: inner -> inner" in out
    assert out.splitlines()[-3].split() == ["all", "3", "3/3"]
    assert csv.read_text().count("\n") == 4
    assert main(["benchmark", str(tmp_path / "absent")]) == 2
    assert "not a folder" in capsys.readouterr().err


def test_other_bearing_check_reads_the_healthy_end(synthetic_set, tmp_path, capsys):
    """The false-alarm check reads the other accelerometer with the other bearing; the
    right verdict is none, and a channel that copies the faulty one is flagged."""
    rec = read_labelled_record(synthetic_set / "12k_Fan_End_IR007_1_279.mat", end="drive")
    assert rec.channel == "X279_DE_time" and rec.geometry == CWRU_DRIVE_END
    rec = read_labelled_record(synthetic_set / "normal_0_97.mat", end="fan")
    assert rec.channel == "X097_FE_time" and rec.geometry == CWRU_FAN_END
    results = run_benchmark(find_records(synthetic_set), other_bearing=True)
    assert [(r.group, r.expected, r.verdict) for r in results] == [
        ("CWRU 12k drive end, fan-end channel and bearing", "none", "none"),
        ("CWRU 12k fan end, drive-end channel and bearing", "none", "none"),
        ("CWRU 48k drive end, fan-end channel and bearing", "none", "none"),
    ]
    # The baseline file was written with one noise array on both channels.
    assert ["copies" in r.detail for r in results] == [False, False, True]
    with pytest.raises(ValueError, match="end must be"):
        read_labelled_record(synthetic_set / "normal_0_97.mat", end="left")
    assert main(["benchmark", str(synthetic_set), "--other-bearing"]) == 0
    assert capsys.readouterr().out.splitlines()[-2].split() == ["all", "3", "3/3"]
    mfpt = tmp_path / "mfpt"
    mfpt.mkdir()
    x = np.random.default_rng(1).standard_normal(50000)
    savemat(mfpt / "OuterRaceFault_vload_1.mat",
            {"bearing": {"gs": x[:, None], "sr": 48828.0, "rate": 25.0, "load": 25.0}})  # fmt: skip
    assert main(["benchmark", str(mfpt), "--other-bearing"]) == 2
    assert "--other-bearing" in capsys.readouterr().err


def test_benchmark_shows_its_progress_on_stderr(synthetic_set, capsys):
    """In a log or a pipe, a line every --progress-interval seconds (0: each record) and a
    last one with the count; the table on stdout stays as it is. --quiet and --records
    (whose lines are the progress) show none; a negative interval is refused."""
    assert main(["benchmark", str(synthetic_set), "--progress-interval", "0"]) == 0
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert [line.split(",")[0] for line in lines[:-1]] == [
        "benchmark: 1 of 3 records", "benchmark: 2 of 3 records"
    ]  # fmt: skip
    assert lines[-1].startswith("benchmark: 3 records in ")
    assert out.splitlines()[-2].split() == ["all", "3", "3/3"]
    for flag in ("--quiet", "--records"):
        assert main(["benchmark", str(synthetic_set), "--progress-interval", "0", flag]) == 0
        assert capsys.readouterr().err == ""
    assert main(["benchmark", str(synthetic_set), "--progress-interval", "-1"]) == 2
    assert "--progress-interval -1" in capsys.readouterr().err


def test_a_csv_path_that_cannot_be_written_is_refused_before_the_records(synthetic_set, capsys):
    """A folder given as --csv, or a file under /proc, is one line and exit status 2 before
    any record is read (it was an OSError after the whole run, the verdicts lost)."""
    for bad in (str(synthetic_set), "/proc/verdicts.csv"):
        assert main(["benchmark", str(synthetic_set), "--csv", bad]) == 2
        out, err = capsys.readouterr()
        assert out == "" and err.startswith("error: --csv") and len(err.splitlines()) == 1


def test_other_bearing_progress_counts_the_cwru_records(synthetic_set, tmp_path, capsys):
    """With --other-bearing an MFPT record (one bearing) is not diagnosed, nor counted."""
    folder = tmp_path / "both"
    folder.mkdir()
    for path in find_records(synthetic_set):
        (folder / path.name).write_bytes(path.read_bytes())
    x = np.random.default_rng(2).standard_normal(50000)
    savemat(folder / "OuterRaceFault_vload_1.mat",
            {"bearing": {"gs": x[:, None], "sr": 48828.0, "rate": 25.0, "load": 25.0}})  # fmt: skip
    assert main(["benchmark", str(folder), "--other-bearing", "--progress-interval", "0"]) == 0
    lines = capsys.readouterr().err.splitlines()
    assert lines[0].startswith("benchmark: 1 of 3 records,")
    assert lines[-1].startswith("benchmark: 3 records in ")


# ------------------------------------------------------------- development sets (if present)
# The development sets these counts were measured on; cwru12k_fan_end (added for issue 44)
# has its own test below.
DEVELOPMENT = ("cwru", "cwru48k", "mfpt")


def development_records() -> list:
    if not DATA.is_dir():
        pytest.skip(f"development data not available at {DATA}")
    return [p for folder in DEVELOPMENT for p in find_records(DATA / folder)]


@pytest.fixture(scope="module")
def development_results():
    return run_benchmark(development_records())


def _count(results, group_prefix, fault):
    rows = [r for r in results if r.group.startswith(group_prefix) and r.expected == fault]
    return sum(r.correct for r in rows), len(rows)


def test_development_sets_read_completely(development_results):
    assert len(development_results) == 31
    assert not [r for r in development_results if r.verdict == "error"]


def test_development_mfpt_and_baseline(development_results):
    assert _count(development_results, "MFPT", "inner") == (7, 7)
    assert _count(development_results, "MFPT", "outer") == (7, 7)
    normal = [r for r in development_results if r.expected == "none"]
    assert [r.verdict for r in normal] == ["none"]
    # No record of a race fault is called a different race fault.
    swapped = [r for r in development_results if {r.expected, r.verdict} == {"inner", "outer"}]
    assert not swapped, [r.path.name for r in swapped]
    assert math.isfinite(sum(r.confidence for r in development_results))


def test_development_cwru_counts_do_not_fall_back(development_results):
    # Measured at the commit that added the cage-rate series (docs/results/diagnostics): a
    # change that names fewer of these records than that is a regression.
    assert _count(development_results, "CWRU 48k", "outer")[0] >= 6
    assert _count(development_results, "CWRU 48k", "inner")[0] >= 2
    assert _count(development_results, "CWRU 48k", "ball")[0] >= 1
    assert _count(development_results, "CWRU 12k", "outer") == (1, 1)
    assert _count(development_results, "CWRU 12k", "inner") == (1, 1)


def test_development_other_bearing_false_alarms_do_not_grow():
    """The healthy bearing's channel of every development CWRU record: when the check was added
    (docs/results/diagnostics), 3 of 17 named a fault, each where that channel carries a strong
    drive-end fault (a copy of its channel, or 135's). A family whose pair rests on the lines of
    a stronger series at no fault frequency of the bearing is not named (135), nor one whose
    in-between lines mark a slower period (238); 213 (inner, lines the drive-end series does not
    make) is left; the baseline and the 12 kHz records stay none."""
    results = run_benchmark(development_records(), other_bearing=True)
    assert len(results) == 17 and all(r.expected == "none" for r in results)
    alarms = [r for r in results if r.verdict != "none"]
    assert len(alarms) <= 1, [(r.path.name, r.verdict) for r in alarms]
    assert all(r.verdict == "none" for r in results if "12k" in r.group or "normal" in r.path.name)


def test_fan_end_counts_do_not_fall_back():
    """The 23 fan-end faults at motor loads 0 and 1 (cwru12k_fan_end, read on the fan-end
    channel with the 6203 bearing). When the set was added (issue 44): outer 8 of 11, inner
    6 of 6, ball 2 of 6, and 295 (outer race at 6 o'clock) named ball. With the candidates
    (issue 44): 295 named outer (the ball comb's lines are its BPFO + fr sidebands, weaker
    than their carriers), 299 undecided between outer and ball (two harmonics each, each
    explaining the other's), no wrong fault named. A change that names fewer, or names a
    wrong fault, is a regression."""
    folder = DATA / "cwru12k_fan_end"
    if not folder.is_dir():
        pytest.skip(f"fan-end development data not available at {folder}")
    results = run_benchmark(find_records(folder))
    assert len(results) == 23 and not [r for r in results if r.verdict == "error"]
    assert _count(results, "CWRU 12k fan end", "outer")[0] >= 8
    assert _count(results, "CWRU 12k fan end", "inner") == (6, 6)
    assert _count(results, "CWRU 12k fan end", "ball")[0] >= 2
    wrong = [r for r in results if r.wrong]
    assert not wrong, [(r.path.name, r.verdict) for r in wrong]
    verdicts = {r.path.name: r.verdict for r in results}
    assert verdicts["12k_Fan_End_OR007@6_1_295.mat"] == "outer"


def test_development_wrong_names_are_at_most_the_two_single_comb_records(development_results):
    """On the 12 and 48 kHz drive-end sets and MFPT, the only wrong names may be two ball
    faults whose records hold one race comb and no ball evidence at any level (issue 44,
    benchmarks/diagnostics/issue44_notes.md): 118 (BPFO, three harmonics, family-wise p
    5e-47) and 226 (BPFI, five harmonics and sidebands, 6e-35); a change that names any
    other wrong is a regression. No verdict there is undecided between a race fault and
    anything else."""
    wrong = {r.path.name for r in development_results if r.wrong}
    assert wrong <= {"12k_Drive_End_B007_0_118.mat", "48k_Drive_End_B021_0_226.mat"}, wrong
    assert not [r.path.name for r in development_results if r.undecided]


def test_detail_names_the_families_set_aside(synthetic_set):
    """Where diagnose set a family aside for another source's series, the record's detail
    says which and gives that series' rate in shaft orders."""
    from types import SimpleNamespace

    def stub(x, fs, geometry, shaft_hz):
        return SimpleNamespace(
            fault="none", confidence=0.9, dominated=("ball",), other_series=(3.5 * shaft_hz, 9.0)
        )

    results = run_benchmark(find_records(synthetic_set), diagnose_fn=stub)
    assert results[0].detail == "0.007 in@6 (set aside: ball; other series at 3.500 orders)"
    assert results[2].detail == "(set aside: ball; other series at 3.500 orders)"  # baseline


def test_detail_says_what_the_shaft_lines_did_to_the_speed(synthetic_set):
    """A speed moved to the record's shaft lines is given as its change; a record whose
    spectrum holds no shaft series near the file's speed (these synthetic records are
    impacts in noise) says so."""
    from types import SimpleNamespace

    from diagnostics import ShaftLines

    def moved(x, fs, geometry, shaft_hz):
        lines = ShaftLines(shaft_hz, 0.993 * shaft_hz, 20, 10, 50.0, 1e-10, 0.05)
        return SimpleNamespace(
            fault="none",
            confidence=1.0,
            frequencies=SimpleNamespace(shaft=lines.found_hz),
            shaft_lines=lines,
            speed_change=lines.offset,
        )

    results = run_benchmark(find_records(synthetic_set), diagnose_fn=moved)
    assert results[0].detail == "0.007 in@6 (speed -0.7 % from the shaft lines)"
    real = run_benchmark(find_records(synthetic_set)[:1])
    assert real[0].detail == "0.007 in@6 (no shaft lines within 5 % of the speed)"
