"""diagnostics stands alone: importing any of its modules (or of bearing_io, the file and
progress helpers it shares with the simulator) never imports taichi."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = """
import importlib, pkgutil, sys
import bearing_io, diagnostics
names = sorted(m.name for pkg in (diagnostics, bearing_io)
               for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + ".")
               if not m.name.rsplit(".", 1)[-1].startswith("__"))
for name in names:
    importlib.import_module(name)
loaded = sorted(m for m in sys.modules if m.split(".")[0] in ("taichi", "taichi_bearing"))
assert not loaded, loaded
print(",".join(names))
"""


def test_importing_every_diagnostics_module_leaves_taichi_unloaded():
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT))
    result = subprocess.run(
        [sys.executable, "-c", SCRIPT],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    imported = set(result.stdout.strip().split(","))
    expected = {
        f"diagnostics.{m}"
        for m in ("_checks", "_filters", "_envelope", "_spectral", "_kurtosis", "_io",
                  "_frequencies", "_diagnose", "plots", "app.cli", "app.compare")
    } | {"bearing_io.files", "bearing_io.progress"}  # fmt: skip
    assert expected <= imported
    # ... and every module file of the two packages, subpackages too, was among them
    files = {
        ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
        for pkg in ("diagnostics", "bearing_io")
        for path in (ROOT / pkg).rglob("*.py")
        if not path.name.startswith("__")
    }
    assert files <= imported, files - imported
