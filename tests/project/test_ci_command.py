"""`.ci/run` runs exactly README's test command, and the getting-started page gives the same
two commands as README (the guide's rule: one command for the tests, the one CI runs)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def commands(path: Path) -> list[str]:
    """The one-line commands of the page's ```bash blocks that install the package."""
    blocks = re.findall(r"```bash\n(.*?)```", path.read_text(encoding="utf-8"), flags=re.S)
    return [line for b in blocks for line in b.splitlines() if "pip install -e" in line]


def test_ci_runs_the_readme_test_command():
    readme = [c for c in commands(ROOT / "README.md") if "pytest" in c]
    assert len(readme) == 1, readme
    script = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert readme[0] in script


def test_getting_started_gives_readme_commands():
    readme = commands(ROOT / "README.md")[:2]
    assert len(readme) == 2
    assert commands(ROOT / "docs" / "getting_started.md")[:2] == readme
