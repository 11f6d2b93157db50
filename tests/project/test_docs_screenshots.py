"""The site as its readers see it: built, then loaded in a headless Chromium at 1366 and
1920 px (``docs/_ext/screenshots.py``). No page opens with anything but its content under
the top bar, and the front page shows a picture and code in its first screen at 1366 px.

Slow (a whole build); skipped where the docs extra or a headless Chromium is missing.
The screenshots are left in ``docs/_build/screenshots/``: look at them.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "docs" / "_ext"))
screenshots = pytest.importorskip("screenshots")

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        any(importlib.util.find_spec(m) is None for m in ("sphinx", "pydata_sphinx_theme")),
        reason='the docs extra is not installed (pip install -e ".[docs]")',
    ),
    pytest.mark.skipif(screenshots.browser() is None, reason="no headless Chromium installed"),
]


def test_pages_open_on_their_content(tmp_path):
    html = tmp_path / "html"
    screenshots.build(html)
    out = ROOT / "docs" / "_build" / "screenshots"
    measures, problems = screenshots.shoot(screenshots.browser(), html, out)
    assert not problems, problems
    assert set(measures) == {f"{p}_{w}" for p in screenshots.PAGES for w in screenshots.WINDOWS}
    for name in measures:
        assert (out / f"{name}.png").stat().st_size > 10_000, name
