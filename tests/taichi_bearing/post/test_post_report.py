"""report.md / report.html of a synthetic run folder: every section, numbers from the run.

The report leads with what happened: the verdict (its numbers computed here from the
summary, a failed check named), then the checks, the key figures, the analyses and the
case last; a partial run, an inner-race run and an extended spall's get their own verdict.
"""

from __future__ import annotations

import base64
import json
import re

import numpy as np
import pytest
from synthetic_run import make_synthetic_run

from bearing_io.files import write_json
from taichi_bearing.checks.passages import passage_statistics
from taichi_bearing.output.layout import ANIMATION_FILES
from taichi_bearing.post.document import Heading, Para, fmt
from taichi_bearing.post.report import (
    APPENDIX,
    APPENDIX_TITLE,
    SECTIONS,
    report_blocks,
    write_report,
)
from taichi_bearing.post.run_figures import FIGURE_NAMES

# per-passage signatures of the synthetic run's three passages (roller 0, 1, 2)
SIGNATURES = {
    "entry_destress_time_s": (3.4e-4, 2.1e-4, 4.4e-4),
    "exit_force_peak_ratio": (1.23, 2.6, 1.9),
    "exit_impulses": (12, 7, 9),
    "exit_entry_accel_ratio": (3.37, 0.9, 5.2),
}


def _add_signatures(run_dir, **summary_changes) -> dict:
    """Give the synthetic run's events their signatures and summary.json the statistics
    the checks write from them; returns the summary."""
    path = run_dir / "summary.json"
    summary = json.loads(path.read_text())
    for k, e in enumerate(summary["events"]):
        e.update({name: values[k] for name, values in SIGNATURES.items()})
    summary["passage_statistics"] = passage_statistics(summary["events"], list(SIGNATURES))
    summary.update(summary_changes)
    path.write_text(json.dumps(summary))
    return summary


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    run_dir = tmp_path_factory.mktemp("run")
    make_synthetic_run(run_dir)
    _add_signatures(run_dir)
    (run_dir / ANIMATION_FILES["gif"]).write_bytes(b"GIF89a")  # a folder with an animation
    md_path = write_report(run_dir)  # draws the figures itself (no figures.json yet)
    summary = json.loads((run_dir / "summary.json").read_text())
    figures = json.loads((run_dir / "figures" / "figures.json").read_text())["figures"]
    return run_dir, md_path.read_text(), summary, figures


def _row(md: str, first_cell: str, n_cells: int | None = None) -> list[str]:
    """Cells of the first table row starting with ``first_cell`` (and ``n_cells`` long)."""
    for line in md.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and cells[0] == first_cell:
            if n_cells is None or len(cells) == n_cells:
                return cells
    raise AssertionError(f"no table row {first_cell!r}")


def _verdict(md: str) -> str:
    return md[md.index("\n## Verdict\n") : md.index("\n## Checks\n")]


def test_verdict_checks_figures_analyses_then_the_case(report):
    _, md, _, _ = report
    positions = [md.index(f"\n## {title}\n") for title in SECTIONS]
    positions.append(md.index(f"\n## {APPENDIX_TITLE}\n"))
    positions += [md.index(f"\n### {title}\n") for title in APPENDIX]
    assert positions == sorted(positions)
    assert SECTIONS[:3] == ("Verdict", "Checks", "Key figures") and APPENDIX[-1] == "Case"
    # the first table after the verdict is the checks', the first picture the contact
    # forces through the spall, then the acceleration; the case table is the last table
    assert md.index("| check | value |") < md.index("![contact_forces]")
    assert md.index("![contact_forces]") < md.index("![acceleration]")
    assert md.index("![acceleration]") < md.index("\n## Spall passages\n")
    assert md.rindex("| key | value |") > md.index("\n### Case\n")
    assert md.index("| operating.load_kN |") > md.index("\n### Stages and times\n")


def test_verdict_numbers_are_the_summarys(report):
    _, md, summary, _ = report
    verdict = _verdict(md)
    events, stats = summary["events"], summary["passage_statistics"]
    assert f"passed through the spall: {len(events)} passages" in verdict
    words = {"entry_destress_time_s": (1e3, " ms"), "exit_impulses": (1, " impulses"),
             "exit_force_peak_ratio": (1, " F0"), "exit_entry_accel_ratio": (1, "")}  # fmt: skip
    for name, (scale, unit) in words.items():
        values = [e[name] for e in events]
        assert stats[name]["median"] == pytest.approx(np.median(values))
        med, lo, hi = (fmt(scale * v, 3) for v in (stats[name]["median"], min(values), max(values)))
        assert f"a median {med}{unit} (range {lo} to {hi}{unit})" in verdict, name


def test_the_verdict_names_each_failed_check_with_value_and_limit(report):
    _, md, summary, _ = report
    verdict = _verdict(md)
    checks = summary["checks"]
    failed = [n for n, c in checks.items() if c["passed"] is False]
    assert failed  # the synthetic run's energy balance fails
    for name in failed:
        c = checks[name]
        assert f"{name} {fmt(c['value'])} (limit {fmt(c['limit'])})" in verdict
    n_pass = sum(c["passed"] is True for c in checks.values())
    assert f"{n_pass} of {len(checks)} checks pass." in verdict
    for name in (n for n, c in checks.items() if c["passed"]):
        assert name not in verdict


def test_the_animation_is_linked_beside_the_key_figures(report):
    run_dir, md, _, _ = report
    gif = ANIMATION_FILES["gif"]
    key = md[md.index("\n## Key figures\n") : md.index("\n## Spall passages\n")]
    assert f"[{gif}]({gif})" in key
    html = (run_dir / "report.html").read_text()
    assert f'<a href="{gif}">{gif}</a>' in html and f"[{gif}]" not in html


def test_no_temporary_files_left(report):
    run_dir, _, _, _ = report
    assert (run_dir / "report.md").is_file() and (run_dir / "report.html").is_file()
    assert not [p for p in run_dir.iterdir() if p.name.startswith(".")]


def test_case_table_comes_from_case_yaml(report):
    _, md, _, _ = report
    assert _row(md, "operating.load_kN")[1] == "50"
    assert _row(md, "defect.length_mm")[1] == "10"
    assert _row(md, "mesh.surface_size_mm")[1] == "3"  # the synthetic run's override


def test_static_forces_and_errors_equal_the_summary(report):
    _, md, summary, _ = report
    sim, ana = summary["static_roller_forces_N"], summary["analytical_roller_forces_N"]
    for j in (0, 3, 18):
        cells = _row(md, str(j), n_cells=6)  # the static table's row
        assert cells[1] == fmt(sim[j]) and cells[2] == fmt(ana[j])
        assert float(cells[3].rstrip(" %")) == pytest.approx(
            100 * (sim[j] - ana[j]) / ana[j], abs=0.006
        )
        # the flexible-ring reference beside it
        ref = summary["reference_roller_forces_N"][j]
        assert cells[4] == fmt(ref)
        assert float(cells[5].rstrip(" %")) == pytest.approx(100 * (sim[j] - ref) / ref, abs=0.006)
    assert _row(md, "10", n_cells=6)[3] == "unloaded"


def test_checks_table(report):
    _, md, summary, _ = report
    for name, c in summary["checks"].items():
        cells = _row(md, name)
        assert cells[1:4] == [fmt(c["value"]), fmt(c["limit"]), "PASS" if c["passed"] else "FAIL"]


def test_stage_times_and_run_numbers(report):
    _, md, summary, _ = report
    for stage, t in summary["stage_times_s"].items():
        assert _row(md, stage)[1] == fmt(t)
    assert _row(md, "total")[1] == fmt(sum(summary["stage_times_s"].values()))
    assert _row(md, "time step dt (s)")[1] == fmt(summary["dt_s"])
    assert _row(md, "elements")[1] == fmt(summary["n_elements"])


def test_passages_and_bpfo_interval(report):
    _, md, summary, _ = report
    for e in summary["events"]:
        cells = _row(md, str(e["roller"]))  # first table with that roller is static forces
        assert cells  # present
    ms = [fmt(1e3 * e["exit_time_s"]) for e in summary["events"]]
    assert all(f"| {v} |" in md for v in ms)
    assert f"1/BPFO = {fmt(1e3 / summary['bpfo_hz'])} ms" in md


def test_notch_table_and_defect_size(report):
    _, md, summary, figures = report
    for r in figures["psd_notch"]["values"]["notches"]:
        cells = _row(md, fmt(r["frequency_hz"]), n_cells=5)
        assert cells[-1] == fmt(r["attenuation_db"], 3)
        assert r["attenuation_db"] >= 25.0
    est, true = summary["defect_size_estimate_m"], summary["defect_size_true_m"]
    assert _row(md, "estimated from the simulated signal (mm)")[1] == fmt(1e3 * est)
    assert _row(md, "true spall length (mm)")[1] == fmt(1e3 * true)
    assert _row(md, "difference")[1] == f"{100 * (est - true) / true:+.2f} %"


def test_markdown_links_and_html_embeds_every_figure(report):
    run_dir, md, _, figures = report
    html = (run_dir / "report.html").read_text()
    images = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', html)
    assert len(images) == len(FIGURE_NAMES)
    embedded = {base64.b64decode(data) for data in images}
    for name in FIGURE_NAMES:
        png = (run_dir / "figures" / f"{name}.png").read_bytes()
        assert png in embedded, name
        assert f"](figures/{name}.png)" in md
        assert figures[name]["caption"] in md


# ------------------------------------------------------------------ verdicts of other runs


def _light_run(run_dir, figures: dict | None = None, **summary_changes) -> list:
    """A short synthetic run without frames or drawn figures; returns its report blocks."""
    make_synthetic_run(run_dir, frames=False, duration_ms=10.0)
    summary = _add_signatures(run_dir, **summary_changes)
    write_json(run_dir / "figures" / "figures.json", {"figures": figures or {}})
    return summary, report_blocks(run_dir)


def _verdict_text(blocks: list) -> str:
    start = blocks.index(next(b for b in blocks if isinstance(b, Heading) and b.text == "Verdict"))
    end = next(i for i, b in enumerate(blocks) if i > start and isinstance(b, Heading))
    return " ".join(b.text for b in blocks[start:end] if isinstance(b, Para))


def test_a_partial_run_without_a_complete_passage_still_gets_a_report(tmp_path):
    """A run killed with kill -9 in its first passage: the verdict says partial, names
    the roller still inside, says what is unknown; the report files are written."""
    partial = {"status": "running", "recorded_until_s": 2.5e-3, "duration_s": 10e-3,
               "histories": "histories.parts/ only", "note": "killed"}  # fmt: skip
    events = [{"roller": 0, "entry_time_s": 1.3e-3, "exit_time_s": None}]
    checks = {"energy_balance": {"value": None, "limit": 0.02, "passed": None, "note": ""}}
    _, blocks = _light_run(tmp_path, partial=partial, events=events, checks=checks,
                           passage_statistics=None)  # fmt: skip
    verdict = _verdict_text(blocks)
    assert verdict.startswith("Partial run (status running): 2.5 ms of 10 ms recorded")
    assert "No roller passed through the spall in the 2.5 ms recorded" in verdict
    assert "is unknown" in verdict
    assert "Roller 0 entered the spall at 1.3 ms and had not left it" in verdict
    assert (
        "0 of 1 checks pass. None failed. Not applied or not computable: energy_balance" in verdict
    )
    md = write_report(tmp_path).read_text()
    assert md.index("## Verdict") < md.index("## Checks") < md.index("### Case")


def test_a_run_without_events_or_checks_says_what_is_unknown(tmp_path):
    _, blocks = _light_run(tmp_path, events=[], entry_times_s=[], restress_times_s=[],
                           checks={}, passage_statistics=None)  # fmt: skip
    verdict = _verdict_text(blocks)
    assert "No roller passed through the spall" in verdict and "unknown" in verdict
    assert "holds no checks" in verdict


def test_inner_race_verdict_counts_the_passages_with_an_event(tmp_path):
    """Passages of an inner-race spall: those under load gave the events, the others
    (outside the load zone) none; counted from summary.json passages and events."""
    bpfi = 373.3
    entries = [3e-3, 3e-3 + 2 / bpfi]
    passages = [
        {"roller": j, "time_s": t0 + 2e-4, "spall_angle_deg": a, "force_before_N": f}
        for j, t0, a, f in ((0, entries[0], -16.0, 13.5e3), (5, entries[0] + 1 / bpfi, 16.0, 0.0),
                            (1, entries[1], 48.0, 2.07e3))
    ]  # fmt: skip
    events = [{"roller": j, "entry_time_s": t, "exit_time_s": t + 4e-4} for j, t in
              zip((0, 1), entries, strict=True)]  # fmt: skip
    summary, blocks = _light_run(tmp_path / "inner", spall_race="inner", bpfi_hz=bpfi,
                                 passages=passages, events=events)  # fmt: skip
    verdict = _verdict_text(blocks)
    n_event = 2  # passages 0 and 2: their roller's event entered 0.2 ms before
    assert (
        f"met a roller {len(passages)} times, once every 1/BPFI = {fmt(1e3 / bpfi, 3)} ms"
        in verdict
    )
    assert f"{n_event} of these passages gave an event" in verdict
    assert "2.07 to 13.5 kN before it (the load zone)" in verdict
    assert "the other 1, the roller carrying no load (outside the load zone), none" in verdict
    assert "Rollers 0 and 1 passed through the spall: 2 passages" in verdict


def test_extended_spall_verdict_gives_the_load_sharing(tmp_path):
    rows = [
        {"roller": 0, "angle_deg": -9.0, "fe_N": 400.0, "quasi_static_spall_N": 0.0,
         "quasi_static_healthy_N": 9.8e3},
        {"roller": 19, "angle_deg": 9.0, "fe_N": 350.0, "quasi_static_spall_N": 0.0,
         "quasi_static_healthy_N": 9.6e3},
        {"roller": 1, "angle_deg": -27.0, "fe_N": 17.1e3, "quasi_static_spall_N": 14e3,
         "quasi_static_healthy_N": 8e3},
        {"roller": 2, "angle_deg": -45.0, "fe_N": 6e3, "quasi_static_spall_N": 6.5e3,
         "quasi_static_healthy_N": 5.9e3},
    ]  # fmt: skip
    values = {"window_s": [4.1e-3, 5.2e-3], "rollers_inside": [0, 19], "rollers": rows}
    figures = {"load_sharing": {"file": "load_sharing.png", "caption": "", "values": values}}
    _, blocks = _light_run(tmp_path, figures=figures)
    verdict = _verdict_text(blocks)
    assert "rollers 0 and 19 were both inside it from 4.1 to 5.2 ms" in verdict
    assert "carrying 0.4 and 0.35 kN (9.8 and 9.6 kN in a healthy bearing)" in verdict
    # the neighbour that took the most load first
    assert verdict.index("roller 1 with 17.1 kN") < verdict.index("roller 2 with 6 kN")
