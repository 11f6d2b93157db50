"""The documentation builds with Sphinx with warnings as errors (``-W --keep-going``).

Skipped where the docs extra is not installed (``pip install -e ".[docs]"``). The gallery
is not executed here (``-D plot_gallery=0``): tests/test_examples.py runs its scripts.
"""

from __future__ import annotations

import importlib.util
import os
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
    api = (out / "api" / "diagnostics.html").read_text(encoding="utf-8")
    assert 'id="diagnostics.kurtogram"' in api
    assert (out / "auto_examples" / "plot_diagnose_record.html").is_file()
    assert "energy_balance_error" in (out / "guide" / "run_folder.html").read_text("utf-8")
