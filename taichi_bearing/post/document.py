"""The document model of the reports: blocks (:class:`Heading`, :class:`Para`,
:class:`Table`, :class:`Image`) built once and rendered twice, as Markdown with linked
pictures and as a self-contained HTML page with the pictures inline (standard library
only). The run report (:mod:`taichi_bearing.post.report`) and the study reports
(:mod:`taichi_bearing.studies`) are lists of these blocks."""

from __future__ import annotations

import html
import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from bearing_io.files import atomic_path
from bearing_io.report_html import html_page, html_table, png_figure
from taichi_bearing.output.layout import FIGURES_DIR

__all__ = [
    "Heading",
    "Image",
    "Para",
    "Table",
    "figure_block",
    "fmt",
    "pct",
    "to_html",
    "to_markdown",
    "write_documents",
]


def fmt(value, digits: int = 4) -> str:
    """A number as the report prints it: ``digits`` significant figures; '-' for none."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return "-"
        return f"{value:.{digits}g}"
    return str(value)


def pct(a, b) -> str:
    """Relative difference (a - b) / b in percent."""
    if a is None or b is None or not b:
        return "-"
    return f"{100.0 * (float(a) - float(b)) / float(b):+.2f} %"


@dataclass
class Heading:
    text: str
    level: int = 2


@dataclass
class Para:
    text: str


@dataclass
class Table:
    header: list[str]
    rows: list[list[str]]


@dataclass
class Image:
    path: Path
    caption: str


def figure_block(figs: Mapping, run_dir: Path, name: str) -> list:
    """The figure ``name`` of a run's figure index (``figures/figures.json``) as an
    :class:`Image` block, or a line saying it was not drawn."""
    entry = figs.get(name)
    if not entry:
        return [Para(f"figure {name} was not drawn.")]
    return [Image(run_dir / FIGURES_DIR / entry["file"], entry.get("caption", ""))]


def _md_cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def to_markdown(blocks: list, run_dir: Path) -> str:
    """The blocks as Markdown, pictures linked relative to ``run_dir``."""
    lines: list[str] = []
    for b in blocks:
        if isinstance(b, Heading):
            lines += ["#" * b.level + " " + b.text, ""]
        elif isinstance(b, Para):
            lines += [b.text, ""]
        elif isinstance(b, Table):
            lines.append("| " + " | ".join(_md_cell(h) for h in b.header) + " |")
            lines.append("|" + "---|" * len(b.header))
            lines += ["| " + " | ".join(_md_cell(c) for c in row) + " |" for row in b.rows]
            lines.append("")
        elif isinstance(b, Image):
            rel = os.path.relpath(b.path, run_dir)
            lines += [f"![{_md_cell(b.path.stem)}]({rel})", "", f"*{b.caption}*", ""]
    return "\n".join(lines)


def _inline(text: str) -> str:
    """Escaped text with Markdown's inline code and links as HTML (``[text](href)`` as
    an ``<a>``)."""
    out = re.sub(r"`([^`]*)`", r"<code>\1</code>", html.escape(text, quote=False))
    return re.sub(
        r"\[([^\]]+)\]\(([^)\s]+)\)",
        lambda m: f'<a href="{m[2].replace(chr(34), "&quot;")}">{m[1]}</a>',
        out,
    )


def to_html(blocks: list) -> str:
    """The blocks as one self-contained HTML page (pictures inline as base64 data URIs)."""
    title = next((b.text for b in blocks if isinstance(b, Heading)), "Run report")
    parts = []
    for b in blocks:
        if isinstance(b, Heading):
            parts.append(f"<h{b.level}>{html.escape(b.text)}</h{b.level}>")
        elif isinstance(b, Para):
            parts.append(f"<p>{_inline(b.text)}</p>")
        elif isinstance(b, Table):
            parts.append(html_table(b.header, b.rows, _inline))
        elif isinstance(b, Image):
            parts.append(png_figure(b.path.read_bytes(), b.path.stem, b.caption))
    return html_page(title, parts)


def write_documents(blocks: list, md_path: Path) -> tuple[Path, Path]:
    """Write ``md_path`` and the same document as a self-contained ``.html`` beside it
    (each to a temporary name, then renamed); returns both paths."""
    md_path = Path(md_path)
    html_path = md_path.with_suffix(".html")
    with atomic_path(md_path) as tmp:
        tmp.write_text(to_markdown(blocks, md_path.parent), encoding="utf-8")
    with atomic_path(html_path) as tmp:
        tmp.write_text(to_html(blocks), encoding="utf-8")
    return md_path, html_path
