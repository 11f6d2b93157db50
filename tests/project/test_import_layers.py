"""The packages' one-way flow: no import circle anywhere, and no module reaching up from an
earlier stage of the pipeline into a later one.

Every import statement counts, those inside functions too: an import deferred to the call
(to keep ``--help`` from loading Taichi or scipy) is still a dependency, so deferring one
cannot hide a circle.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("taichi_bearing", "diagnostics", "bearing_io")

# The simulator's stages in pipeline order; a module may import its own stage and earlier
# ones. ``output`` (the run folder's format) comes before the simulation that writes it.
STAGES = (
    ("errors", "blas"),
    ("geometry",),
    ("case",),
    ("analytic",),
    ("mesh",),
    ("solver",),
    ("output",),
    ("modes",),
    ("simulation",),
    ("checks",),
    ("post",),
    ("studies",),
    ("validation",),
    ("pipeline",),
    ("commands", "api", "__init__", "__main__"),
)
RANK = {name: i for i, names in enumerate(STAGES) for name in names}


def module_names() -> dict[str, Path]:
    """Dotted name -> file, for every module of the three packages."""
    out = {}
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            if parts[-1] == "__init__":
                parts = parts[:-1]
            out[".".join(parts)] = path
    return out


def imports_of(name: str, path: Path, known: set[str]) -> set[str]:
    """The known modules ``name`` imports anywhere in its file (a ``from m import x``
    counts as importing ``m.x`` where that is a module, else ``m``)."""
    is_pkg = path.name == "__init__.py"
    package = name if is_pkg else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module
            targets = [f"{mod}.{a.name}" if f"{mod}.{a.name}" in known else mod for a in node.names]
        else:
            continue
        for t in targets:
            while t and t not in known:  # `import a.b.c` of a non-module: its module
                t = t.rpartition(".")[0]
            if t and t != name:
                found.add(t)
    return found


def import_graph() -> dict[str, set[str]]:
    mods = module_names()
    known = set(mods)
    return {name: imports_of(name, path, known) for name, path in mods.items()}


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def stage(module: str) -> str | None:
    """The simulator stage of a taichi_bearing module, None for the other packages."""
    parts = module.split(".")
    if parts[0] != "taichi_bearing":
        return None
    return parts[1] if len(parts) > 1 else "__init__"


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    bad = []
    for a, targets in graph.items():
        sa = stage(a)
        for b in targets:
            sb = stage(b)
            if sa is not None and sb is not None and RANK[sb] > RANK[sa]:
                bad.append(f"{a} ({sa}) imports {b} ({sb})")
            if a.startswith(("diagnostics", "bearing_io")) and b.startswith("taichi_bearing"):
                bad.append(f"{a} imports the simulator's {b}")
            if a.startswith("bearing_io") and b.startswith("diagnostics"):
                bad.append(f"{a} imports {b}")
    return sorted(bad)


def test_every_stage_is_ranked():
    stages = {stage(m) for m in import_graph()} - {None}
    assert stages <= set(RANK), sorted(stages - set(RANK))


def test_no_import_circle():
    assert circles(import_graph()) == []


def test_no_stage_imports_a_later_one():
    assert upward_imports(import_graph()) == []


def test_the_checks_find_a_circle_and_an_upward_import():
    """The two checks have teeth: a made-up graph with both faults."""
    graph = {
        "taichi_bearing.mesh.a": {"taichi_bearing.solver.b"},
        "taichi_bearing.solver.b": {"taichi_bearing.mesh.a"},
        "diagnostics.x": {"taichi_bearing.case"},
        "taichi_bearing.case": set(),
    }
    assert circles(graph) == [["taichi_bearing.mesh.a", "taichi_bearing.solver.b"]]
    assert upward_imports(graph) == [
        "diagnostics.x imports the simulator's taichi_bearing.case",
        "taichi_bearing.mesh.a (mesh) imports taichi_bearing.solver.b (solver)",
    ]


@pytest.mark.parametrize(
    "code, expected",
    [
        ("from taichi_bearing.case import load_case", {"taichi_bearing.case"}),
        ("def f():\n    from taichi_bearing.mesh import types", {"taichi_bearing.mesh.types"}),
        ("from . import types", {"taichi_bearing.mesh.types"}),
        ("import taichi_bearing.mesh.types.Mesh", {"taichi_bearing.mesh.types"}),
    ],
)
def test_imports_are_read_inside_functions_and_relative(tmp_path, code, expected):
    path = tmp_path / "quality.py"
    path.write_text(code)
    known = {"taichi_bearing.case", "taichi_bearing.mesh", "taichi_bearing.mesh.types"}
    assert imports_of("taichi_bearing.mesh.quality", path, known) == expected
