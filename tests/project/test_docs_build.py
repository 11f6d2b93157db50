"""The documentation builds with Sphinx with warnings as errors (``-W --keep-going``).

Skipped where the docs extra is not installed (``pip install -e ".[docs]"``). The gallery
is not executed here (``-D plot_gallery=0``): tests/test_examples.py runs its scripts.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
NEEDED = ("sphinx", "myst_parser", "sphinx_gallery")

pytestmark = pytest.mark.skipif(
    any(importlib.util.find_spec(m) is None for m in NEEDED),
    reason='the docs extra is not installed (pip install -e ".[docs]")',
)


def test_docs_build_without_warnings(tmp_path):
    out = tmp_path / "html"
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
           "-D", "plot_gallery=0", "-d", str(tmp_path / "doctrees"), str(ROOT / "docs"),
           str(out)]  # fmt: skip
    env = dict(os.environ, MPLBACKEND="Agg", TI_LOG_LEVEL="error")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600, cwd=ROOT)
    assert proc.returncode == 0, f"sphinx failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-6000:]}"

    # the pages generated from the code hold what they are generated from
    cli = (out / "guide" / "cli.html").read_text(encoding="utf-8")
    for option in ("--scheduler", "--load-kN", "--resume", "--bearing", "--tacho"):
        assert option in cli, option
    for program, commands in (
        ("taichi-bearing", ("run", "mesh", "analytic", "modes", "sweep", "passages",
                            "convergence", "post", "compare")),
        ("diagnostics", ("analyze", "compare", "benchmark")),
    ):  # fmt: skip
        for command in commands:
            assert f'id="python-m-{program}-{command}"' in cli, (program, command)
    reference = (out / "guide" / "case_reference.html").read_text(encoding="utf-8")
    assert "pitch_diameter_mm" in reference and "surface_size_mm" in reference
    # the API: a summary table on the package page, a page for each public object
    package = (out / "api" / "diagnostics.html").read_text(encoding="utf-8")
    assert 'class="autosummary' in package and "generated/diagnostics.kurtogram.html" in package
    api = (out / "api" / "generated" / "diagnostics.kurtogram.html").read_text(encoding="utf-8")
    assert 'id="diagnostics.kurtogram"' in api
    module = (out / "api" / "generated" / "taichi_bearing.api.html").read_text(encoding="utf-8")
    assert "taichi_bearing.api.run.html" in module
    import diagnostics  # every public name of the namespace under a topic of its page

    missing = [n for n in diagnostics.__all__ if f"generated/diagnostics.{n}.html" not in package]
    assert not missing, f"add to a table of docs/api/diagnostics.rst: {missing}"
    assert (out / "auto_examples" / "plot_diagnose_record.html").is_file()
    assert "energy_balance_error" in (out / "guide" / "run_folder.html").read_text("utf-8")

    # results: one title a page, no tracker label or commit in a title, every committed
    # figure shown on a page (Sphinx copies each figure it shows into _images/)
    titles = {}
    for page in (out / "results").rglob("*.html"):
        title = re.search(r"<title>(.*?)</title>", page.read_text("utf-8"), re.S)[1]
        titles.setdefault(" ".join(title.split()), []).append(page.name)
        assert not re.search(r"issue \d|\b[0-9a-f]{7}\b", title), title
    assert all(len(pages) == 1 for pages in titles.values()), titles
    shown = {_digest(p) for p in (out / "_images").iterdir()}
    for figure in (ROOT / "docs" / "results").rglob("*.png"):
        assert _digest(figure) in shown, f"{figure.relative_to(ROOT)} is on no page"


def _digest(path: Path) -> str:
    return hashlib.sha1(path.read_bytes()).hexdigest()


def test_no_machine_path_in_a_committed_report():
    """The reports kept in docs/results/ name run folders as the commands write them
    (``runs/NAME``), not the temporary folder of the machine that ran them."""
    machine = re.compile(r"(?<![\w.])/(tmp|home|root|work|check)/")
    for path in (ROOT / "docs" / "results").rglob("*"):
        if path.suffix in (".md", ".html", ".json", ".csv", ".yaml"):
            found = machine.search(path.read_text(encoding="utf-8"))
            assert found is None, f"{path.relative_to(ROOT)}: {found[0]}"
