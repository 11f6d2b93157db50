"""The gallery's scripts (examples/plot_*.py) run to the end on synthetic data, as the
documentation build runs them, and print what their text says they find.
(plot_coarse_run.py and plot_compare_measured.py run the coarse case: about a minute
each; they are marked slow and the documentation build runs them.)"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EXPECTED = {
    "plot_coarse_run.py": ["status finished", "impulses at the exit"],
    "plot_compare_measured.py": [
        "status finished: 3 roller passages recorded",
        "simulated: coarse_spall",
        "BPFO x1..5 / median",
    ],
    "plot_diagnose_record.py": ["fault: outer, confidence 1.00"],
    "plot_kurtogram_envelope.py": ["kurtogram band: strongest line 146.7 Hz"],
    "plot_mesh.py": ["14748 elements", "'race': 'outer'"],
}

SIMULATING = {"plot_coarse_run.py", "plot_compare_measured.py"}


def test_every_example_is_listed():
    assert sorted(p.name for p in EXAMPLES.glob("plot_*.py")) == sorted(EXPECTED)


@pytest.mark.parametrize(
    "name",
    # the coarse runs take ~1 min each: slow (the docs build runs them with the gallery)
    [pytest.param(n, marks=pytest.mark.slow) if n in SIMULATING else n
     for n in sorted(EXPECTED)],
)  # fmt: skip
def test_example_runs(name, tmp_path):
    path = os.pathsep.join(p for p in (str(EXAMPLES.parent), os.environ.get("PYTHONPATH")) if p)
    env = dict(os.environ, MPLBACKEND="Agg", TI_LOG_LEVEL="error", PYTHONPATH=path)
    proc = subprocess.run([sys.executable, str(EXAMPLES / name)], capture_output=True,
                          text=True, env=env, timeout=600, cwd=tmp_path)  # fmt: skip
    assert proc.returncode == 0, proc.stderr[-4000:]
    for text in EXPECTED[name]:
        assert text in proc.stdout, f"{text!r} not in the output of {name}:\n{proc.stdout}"
