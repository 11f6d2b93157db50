"""The docstring examples run, on small data, with their printed output checked (none is
skipped): ``doctest`` on every module of ``diagnostics`` (its private modules and its
``app`` subpackage too) and on the simulator's modules that hold examples (the Python
API's three calls on the coarse case; pure functions:
kinematics, Hertz, the load distribution, studies)."""

from __future__ import annotations

import doctest
import importlib
import pkgutil
from pathlib import Path

import numpy as np
import pytest

import diagnostics

ROOT = Path(__file__).resolve().parents[2]

SIMULATOR = [
    "taichi_bearing.api",
    "taichi_bearing.analytic.bearing",
    "taichi_bearing.studies.convergence",
    "taichi_bearing.output.checkpoint",
    "taichi_bearing.output.histories",
    "taichi_bearing.output.progress",
    "taichi_bearing.analytic.quasistatic",
    "taichi_bearing.studies.cells",
]
MODULES = (
    ["diagnostics"]
    + sorted(m.name for m in pkgutil.walk_packages(diagnostics.__path__, "diagnostics."))
    + SIMULATOR
)
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


@pytest.fixture(autouse=True)
def _stable_printing():
    """numpy's default print options, whatever an earlier test set; matplotlib off-screen."""
    import matplotlib

    matplotlib.use("Agg")
    saved = np.get_printoptions()
    np.set_printoptions(legacy=False, precision=8, suppress=False, linewidth=75)
    yield
    np.set_printoptions(**saved)


def _tests(name: str) -> list[doctest.DocTest]:
    module = importlib.import_module(name)
    return [t for t in doctest.DocTestFinder().find(module, name) if t.examples]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # an example that writes a file writes it here
    (tmp_path / "cases").symlink_to(ROOT / "cases")  # as from the repository's root
    if name == "taichi_bearing.api":
        # Taichi's start-up lines are printed once per process: before the examples
        from taichi_bearing.solver import init_taichi

        init_taichi("cpu", threads=1)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    for test in _tests(name):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name}"


def test_no_example_is_skipped():
    """Every example runs: no ``+SKIP``, and the public modules have examples."""
    skipped, counted = [], {}
    for name in MODULES:
        for test in _tests(name):
            counted[name] = counted.get(name, 0) + len(test.examples)
            skipped += [
                f"{test.name}:{ex.lineno}" for ex in test.examples if ex.options.get(doctest.SKIP)
            ]
    assert not skipped, f"skipped examples: {skipped}"
    documented = (
        "diagnostics",
        "diagnostics._diagnose",
        "diagnostics._kurtosis",
        "diagnostics._envelope",
        "diagnostics._io",
        "diagnostics._defect_size",
        "diagnostics._frequencies",
        "diagnostics._speed",
        "diagnostics._spectral",
        *SIMULATOR,
    )
    for name in documented:
        assert counted.get(name, 0) > 0, f"{name} has no docstring example"
