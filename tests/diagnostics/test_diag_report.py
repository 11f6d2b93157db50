"""report.html of ``analyze`` and the page of ``benchmark --html``: self-contained pages
(no file or network fetched), the verdict and the evidence first, then the figures as
inline PNGs. The pages are read with html.parser, as a browser would take them apart;
where a headless Chromium is installed (not a dependency of the project), it also loads
the page and decodes every figure."""

from __future__ import annotations

import base64
import json
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from synthetic_records import FREQS, cwru_file, fault_signal, impacts

from bearing_io.report_html import REPORT_CSS
from diagnostics import bearing_frequencies
from diagnostics.app.benchmark import BenchmarkResult, record_rows
from diagnostics.app.cli import main
from diagnostics.app.datasets import CWRU_DRIVE_END
from diagnostics.app.report import analyze_report, benchmark_html

BEARING = "n=9,d=7.94mm,D=39.04mm,angle=0"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
VOID = {"img", "meta", "br", "hr", "link", "input"}  # elements without an end tag


class Page(HTMLParser):
    """What a browser would take from a page: headings in order, images, the text of the
    verdict box, table rows, and anything that would fetch another file."""

    def __init__(self, text: str):
        super().__init__()
        self.headings: list[tuple[str, str]] = []
        self.images: list[dict] = []
        self.fetches: list[str] = []
        self.rows: list[list[str]] = []
        self.verdict = ""
        self.style = ""
        self._open: list[str] = []
        self._in_verdict = 0
        self.feed(text)
        self.close()

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag not in VOID:
            self._open.append(tag)
        if tag == "img":
            self.images.append(attrs)
        for key in ("src", "href"):
            value = attrs.get(key) or ""
            if value and not value.startswith(("data:", "#")):
                self.fetches.append(f"{tag} {key}={value}")
        if tag == "div" and "verdict" in (attrs.get("class") or ""):
            self._in_verdict = 1
        elif self._in_verdict and tag == "div":
            self._in_verdict += 1
        if tag == "tr":
            self.rows.append([])

    def handle_endtag(self, tag):
        if self._open and self._open[-1] == tag:
            self._open.pop()
        if tag == "div" and self._in_verdict:
            self._in_verdict -= 1

    def handle_data(self, data):
        tag = self._open[-1] if self._open else ""
        if tag in ("h1", "h2", "h3"):
            self.headings.append((tag, data.strip()))
        if tag == "style":
            self.style += data
        if tag in ("td", "th") and self.rows:
            self.rows[-1].append(data)
        if self._in_verdict:
            self.verdict += data


@pytest.fixture(scope="module")
def analysed(tmp_path_factory):
    """``analyze`` on a synthetic inner-race record (impacts at BPFI, modulated at the shaft
    rate), run once for the module: the folder and its summary."""
    folder = tmp_path_factory.mktemp("report")
    path = folder / "inner.npz"
    x = fault_signal(12000.0, FREQS.bpfi, 3500.0, mod_hz=FREQS.shaft, mod_depth=0.8, seed=2)
    np.savez(path, x=x, fs=12000.0)
    out = folder / "out"
    rpm = f"{FREQS.shaft * 60:.6g}"
    assert main(["analyze", str(path), "--rpm", rpm, "--bearing", BEARING, "--out", str(out)]) == 0
    return out, json.loads((out / "summary.json").read_text())


def test_analyze_writes_report_beside_summary(analysed):
    out, summary = analysed
    assert (out / "report.html").is_file()
    assert not [p.name for p in out.iterdir() if p.name.startswith(".")]  # no temporary file
    assert summary["verdict"] == "inner" and summary["band_name"]
    assert summary["families"]["inner"]["comb"] == "BPFI"


def test_report_leads_with_the_verdict_then_evidence_then_figures(analysed):
    out, summary = analysed
    page = Page((out / "report.html").read_text(encoding="utf-8"))
    sections = [text for tag, text in page.headings if tag == "h2"]
    assert sections == [
        "Verdict",
        "Evidence for and against each fault family",
        "Envelope spectrum",
        "Band selection",
        "Time trace",
        "Power spectral density",
    ]
    assert page.headings[0] == ("h1", "Diagnosis: inner.npz")
    assert "Inner race fault" in page.verdict
    assert f"confidence {summary['confidence']:.2f}" in page.verdict
    band = summary["band_hz"]
    assert f"{band[0]:.4g}-{band[1]:.4g} Hz" in page.verdict
    # One evidence row per family, its detection as summary.json has it.
    evidence = [r for r in page.rows if len(r) == 9]  # the table of families
    assert [r[0] for r in evidence] == ["family", "outer race", "inner race",
                                        "rolling element (ball)"]  # fmt: skip
    rows = {r[0]: r for r in evidence}
    assert rows["inner race"][3] == "yes" and rows["inner race"][1] == "BPFI"
    assert "+-" in rows["inner race"][7]  # its shaft-rate sidebands, tested
    assert rows["outer race"][3] == ("yes" if summary["families"]["outer"]["detected"] else "no")


def test_report_is_self_contained_with_the_figures_inline(analysed):
    out, _ = analysed
    page = Page((out / "report.html").read_text(encoding="utf-8"))
    assert page.fetches == []  # readable offline: nothing to fetch
    assert page.style.startswith(REPORT_CSS)  # the simulator's report's look
    alts = [img["alt"] for img in page.images]
    assert alts == ["envelope spectrum", "infogram", "time trace", "power spectral density"]
    for img, name in zip(page.images, ("envelope_spectrum", "infogram", "trace", "psd_notch"),
                         strict=True):  # fmt: skip
        prefix = "data:image/png;base64,"
        assert img["src"].startswith(prefix)
        png = base64.b64decode(img["src"][len(prefix) :], validate=True)
        assert png.startswith(PNG_SIGNATURE)
        assert png == (out / f"{name}.png").read_bytes()


BROWSERS = ("chromium-headless-shell", "chromium", "chromium-browser", "google-chrome")
BROWSER = next((b for b in BROWSERS if shutil.which(b)), None)


@pytest.mark.skipif(BROWSER is None, reason="no headless Chromium installed")
def test_report_renders_in_a_headless_browser(analysed, tmp_path):
    """The page as a browser loads it from a file: every figure decoded, at its size."""
    out, _ = analysed
    # On load, the page's title becomes the figures' decoded sizes, which --dump-dom prints.
    probe = (
        '<script>addEventListener("load", () => {document.title = [...document.images]'
        '.map(i => i.naturalWidth + "x" + i.naturalHeight).join(" ")})</script></body>'
    )
    page = tmp_path / "probe.html"
    page.write_text((out / "report.html").read_text().replace("</body>", probe))
    command = [BROWSER, "--headless", "--no-sandbox", "--disable-gpu",
               "--virtual-time-budget=5000", "--dump-dom", page.as_uri()]  # fmt: skip
    dom = subprocess.run(command, capture_output=True, text=True, timeout=60, check=True).stdout
    sizes = re.search(r"<title>([^<]*)</title>", dom)[1].split()
    assert len(sizes) == 4
    for size in sizes:
        width, height = map(int, size.split("x"))
        assert width > 400 and height > 300


def test_printed_notes_stand_under_the_verdict_and_the_evidence(analysed, tmp_path):
    """What analyze printed about the speed goes under the verdict, about a family set aside
    under the evidence table; a figure missing from the folder is said, not broken."""
    out, summary = analysed
    text = analyze_report(summary, tmp_path, ["speed: moved <1 %"], ["not named: ball (x)"])
    verdict_at, evidence_at = text.index("<h2>Verdict"), text.index("<h2>Evidence")
    assert verdict_at < text.index("speed: moved &lt;1 %") < evidence_at
    assert evidence_at < text.index("not named: ball (x)") < text.index("<h2>Envelope")
    assert "envelope_spectrum.png was not drawn." in text and "<img" not in text


def test_benchmark_html_has_one_row_per_record():
    results = [
        BenchmarkResult(Path("a/105.mat"), "CWRU 12k drive end", "inner", "inner", 1.0),
        BenchmarkResult(Path("a/130.mat"), "CWRU 12k drive end", "outer", "none", 0.4,
                        "0.007 in@6 (speed -0.2 % from the shaft lines)", -0.002, True),
    ]  # fmt: skip
    page = Page(benchmark_html(record_rows(results), "table <as printed>", "Benchmark: a"))
    assert page.fetches == [] and page.style.startswith(REPORT_CSS)
    header, *rows = page.rows
    assert header[:6] == ["record", "set", "expected", "verdict", "confidence", "ok"]
    assert [r[0] for r in rows] == ["a/105.mat", "a/130.mat"]
    assert rows[1][3:6] == ["none", "0.40", "NO"] and rows[1][7] == "-0.20 %"


def test_benchmark_command_writes_html(tmp_path, capsys):
    """One CWRU-named record through the command line: the page's row is its verdict."""
    folder = tmp_path / "cwru"
    folder.mkdir()
    bpfo = bearing_frequencies(CWRU_DRIVE_END, 1797 / 60.0).bpfo
    noise = np.random.default_rng(5).standard_normal(24000)
    cwru_file(folder, "12k_Drive_End_OR007@6_0_130.mat", 130, impacts(12000.0, bpfo, 2.0, 1),
              noise, rpm=1797)  # fmt: skip
    html_path = tmp_path / "pages" / "verdicts.html"
    assert main(["benchmark", str(folder), "--quiet", "--html", str(html_path)]) == 0
    assert f"wrote {html_path}" in capsys.readouterr().out
    page = Page(html_path.read_text(encoding="utf-8"))
    header, *rows = page.rows
    assert len(rows) == 1 and rows[0][2:4] == ["outer", "outer"] and rows[0][5] == "yes"
    # A folder given as the file is refused in one line before any record is read.
    assert main(["benchmark", str(folder), "--html", str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith("error: --html")
