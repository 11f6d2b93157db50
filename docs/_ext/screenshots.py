"""Look at the built site as its readers do: headless Chromium at laptop and desktop widths.

Builds the site (without running the gallery, unless ``--gallery``), then for each page of
``PAGES`` and each window of ``WINDOWS`` writes a screenshot of the first screen and one
of the page's top 2,400 px, and measures where the content, the first picture and the
first code block start. It fails (exit status 1) where a page opens with something other
than its content (a navigation block, say) above the first 200 px, or where the front page
at 1366 px does not show a picture and code in its first screen::

    python docs/_ext/screenshots.py              # build, then shoot: docs/_build/screenshots/
    python docs/_ext/screenshots.py --html OUT   # shoot an already built site

``tests/project/test_docs_screenshots.py`` runs it (marked slow); without a headless Chromium
(``chromium-headless-shell``, ``chromium``, ``google-chrome``) it says so and does nothing.
Look at the PNGs before committing a change to the docs.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
BROWSERS = ("chromium-headless-shell", "chromium", "chromium-browser", "google-chrome")

# front page, getting started, one results page, one API page
PAGES = {
    "front": "index.html",
    "getting_started": "getting_started.html",
    "results": "results/line_spall/report.html",
    "api": "api/generated/diagnostics.diagnose.html",
}
WINDOWS = {"1366": (1366, 768), "1920": (1920, 1080)}
FULL_HEIGHT = 2400
CONTENT_TOP_MAX = 200  # px: below the top bar and the page's title margin, nothing else

# Appended to a copy of the page: on load, the title becomes the layout's measures (the
# browser's --dump-dom prints the title back).
PROBE = """<script>addEventListener("load", () => {
  const top = (sel) => { const e = document.querySelector(sel);
    return e ? Math.round(e.getBoundingClientRect().top + scrollY) : null; };
  const visible = (sel) => [...document.querySelectorAll(sel)].filter(
    e => e.getBoundingClientRect().height > 0 && getComputedStyle(e).display !== "none");
  const side = visible(".bd-sidebar-primary")[0];
  document.title = "PROBE" + JSON.stringify({
    content: top("article.bd-article"),
    heading: top("article.bd-article h1"),
    image: top("article.bd-article img"),
    code: top("article.bd-article div.highlight pre"),
    sidebar_top: side ? Math.round(side.getBoundingClientRect().top) : null,
    sidebar_left: side ? Math.round(side.getBoundingClientRect().left) : null,
    width: innerWidth, height: innerHeight,
  }) + "PROBE";
});</script></body>"""


def browser() -> str | None:
    return next((b for b in BROWSERS if shutil.which(b)), None)


def build(out: Path, gallery: bool = False) -> None:
    """The site, as the documentation test builds it (warnings are errors)."""
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
           "-d", str(out.parent / "doctrees"), str(DOCS), str(out)]  # fmt: skip
    if not gallery:
        cmd[4:4] = ["-D", "plot_gallery=0"]
    env = dict(os.environ, MPLBACKEND="Agg", TI_LOG_LEVEL="error")
    subprocess.run(cmd, check=True, env=env, cwd=ROOT)


def _chromium(exe: str, size: tuple[int, int], *args: str) -> subprocess.CompletedProcess:
    cmd = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
           f"--window-size={size[0]},{size[1]}", "--virtual-time-budget=4000", *args]  # fmt: skip
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=True)


def measure(exe: str, page: Path, size: tuple[int, int]) -> dict:
    """Where the content, the first image and the first code block start on ``page``."""
    probe = page.with_name(page.stem + ".probe.html")
    probe.write_text(page.read_text(encoding="utf-8").replace("</body>", PROBE), "utf-8")
    try:
        dom = _chromium(exe, size, "--dump-dom", probe.as_uri()).stdout
    finally:
        probe.unlink()
    found = re.search(r"PROBE(\{.*?\})PROBE", dom)
    if found is None:
        raise RuntimeError(f"{page}: the probe did not report")
    return json.loads(found[1].replace("&quot;", '"'))


def shoot(exe: str, html: Path, out: Path) -> tuple[dict, list[str]]:
    """Screenshots and measures of every page at every window; the problems found."""
    out.mkdir(parents=True, exist_ok=True)
    measures, problems = {}, []
    for name, rel in PAGES.items():
        page = html / rel
        if not page.is_file():
            problems.append(f"{rel}: not built")
            continue
        for label, (width, height) in WINDOWS.items():
            _chromium(exe, (width, height), f"--screenshot={out / f'{name}_{label}.png'}",
                      page.as_uri())  # fmt: skip
            long = out / f"{name}_{label}_long.png"
            _chromium(exe, (width, FULL_HEIGHT), f"--screenshot={long}", page.as_uri())
            m = measure(exe, page, (width, height))
            measures[f"{name}_{label}"] = m
            content = m["heading"] if m["heading"] is not None else m["content"]
            if content is None or content > CONTENT_TOP_MAX:
                problems.append(f"{rel} at {width} px: content starts at {content} px")
            if m["sidebar_top"] is not None and m["sidebar_top"] > CONTENT_TOP_MAX:
                problems.append(f"{rel} at {width} px: navigation below the content")
            if name == "front" and label == "1366":
                for what in ("image", "code"):
                    if m[what] is None or m[what] > height - 40:
                        problems.append(f"front page at {width} px: no {what} on the first "
                                        f"screen ({m[what]} px)")  # fmt: skip
    (out / "measures.json").write_text(json.dumps(measures, indent=1) + "\n")
    return measures, problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--html", type=Path, help="a built site (default: build one)")
    parser.add_argument("--out", type=Path, default=DOCS / "_build" / "screenshots")
    parser.add_argument("--gallery", action="store_true", help="run the gallery in the build")
    args = parser.parse_args(argv)
    exe = browser()
    if exe is None:
        print("no headless Chromium installed: no screenshots")
        return 0
    html = args.html
    if html is None:
        html = DOCS / "_build" / "screenshots_html"
        build(html, gallery=args.gallery)
    measures, problems = shoot(exe, html, args.out)
    for key, m in measures.items():
        print(f"{key:24s} content {m['heading']} image {m['image']} code {m['code']} "
              f"sidebar top {m['sidebar_top']} left {m['sidebar_left']}")  # fmt: skip
    print(f"screenshots in {args.out}")
    for p in problems:
        print("PROBLEM:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
