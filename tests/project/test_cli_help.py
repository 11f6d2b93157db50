"""``--help`` answers at once: building the command line's parsers imports neither Taichi
nor scipy (nor pandas or matplotlib), in a fresh interpreter. Timing is not asserted
(shared machines); what would make it slow is. ``import diagnostics`` loads its private
modules on first use, and each public name is the function or class, never a module."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HEAVY = ("taichi", "scipy", "pandas", "matplotlib")

LOADED = """
import json, sys
{code}
print(json.dumps(sorted({{m.split(".")[0] for m in sys.modules}} & set({heavy!r}))))
"""


def _loaded_after(code: str) -> list[str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run(
        [sys.executable, "-c", LOADED.format(code=code, heavy=HEAVY)],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
        cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _commands() -> list:
    from taichi_bearing.__main__ import COMMANDS

    slow = {
        "modes": "commands/modes.py imports taichi_bearing.modes.model (scipy) at load "
        "for its --part/--support choices"
    }
    return [
        pytest.param(name, marks=pytest.mark.xfail(reason=slow[name], strict=True))
        if name in slow
        else name
        for name in COMMANDS
    ]


@pytest.mark.parametrize("command", _commands())
def test_building_a_commands_parser_imports_no_heavy_module(command):
    code = f"import taichi_bearing.__main__ as m\nm.build_parser([{command!r}])"
    assert _loaded_after(code) == []


@pytest.mark.parametrize("argv", [["--help"], ["run", "--help"], ["post", "--help"]])
def test_help_of_the_command_line_imports_no_heavy_module(argv):
    code = (
        "import contextlib, io\nimport taichi_bearing.__main__ as m\n"
        "with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):\n"
        f"    m.main({argv!r})"
    )
    assert _loaded_after(code) == []


def test_diagnostics_help_imports_no_heavy_module():
    code = "import diagnostics.app.cli as c\nc.build_parser()"
    assert _loaded_after(code) == []


def test_diagnostics_loads_its_functions_on_first_use():
    code = """
import types
import diagnostics as dg
assert "scipy" not in sys.modules
import diagnostics._diagnose, diagnostics._envelope  # binds the private modules on the package
assert isinstance(dg.diagnose, types.FunctionType), dg.diagnose
assert isinstance(dg.envelope, types.FunctionType), dg.envelope
from diagnostics import BearingGeometry, diagnose, plots
assert diagnose is dg.diagnose and BearingGeometry.__module__ == "diagnostics._frequencies"
assert plots.__name__ == "diagnostics.plots"
assert set(dg.__all__) <= set(dir(dg))
# Every public name is a function or class of a private module, none a module itself.
for name in dg.__all__:
    value = getattr(dg, name)
    assert not isinstance(value, types.ModuleType), name
    assert value.__module__.startswith("diagnostics._"), (name, value.__module__)
"""
    assert "scipy" in _loaded_after(code)  # loaded by use, not at import
