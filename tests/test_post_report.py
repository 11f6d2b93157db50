"""report.md / report.html of a synthetic run folder: every section, numbers from the run."""

from __future__ import annotations

import base64
import json
import re

import pytest
from synthetic_run import make_synthetic_run

from taichi_bearing.post.report import SECTIONS, fmt, write_report
from taichi_bearing.post.run_figures import FIGURE_NAMES


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    run_dir = tmp_path_factory.mktemp("run")
    make_synthetic_run(run_dir)
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


def test_every_section_in_order(report):
    _, md, _, _ = report
    positions = [md.index(f"\n## {title}\n") for title in SECTIONS]
    assert positions == sorted(positions)


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
        cells = _row(md, str(j))
        assert cells[1] == fmt(sim[j]) and cells[2] == fmt(ana[j])
        assert float(cells[3].rstrip(" %")) == pytest.approx(
            100 * (sim[j] - ana[j]) / ana[j], abs=0.006
        )
        # the flexible-ring reference beside it
        ref = summary["reference_roller_forces_N"][j]
        assert cells[4] == fmt(ref)
        assert float(cells[5].rstrip(" %")) == pytest.approx(100 * (sim[j] - ref) / ref, abs=0.006)
    assert _row(md, "10")[3] == "unloaded"


def test_checks_table(report):
    _, md, summary, _ = report
    for name, c in summary["checks"].items():
        cells = _row(md, name)
        assert cells[1:4] == [fmt(c["value"]), fmt(c["limit"]), "PASS" if c["passed"] else "FAIL"]
    n_pass = sum(c["passed"] for c in summary["checks"].values())
    assert f"{n_pass} of {len(summary['checks'])} checks pass." in md


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
