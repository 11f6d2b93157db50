"""The look of the HTML reports both packages write: one self-contained page (CSS inline,
figures as base64 PNG data URIs), readable offline. The simulator's run and study reports
(:mod:`taichi_bearing.post.document`) and the diagnostics' ``analyze`` and ``benchmark``
pages (:mod:`diagnostics.app.report`) are built from these pieces, so they look alike.
Standard library only."""

from __future__ import annotations

import base64
import html
from collections.abc import Callable, Iterable, Sequence

__all__ = ["REPORT_CSS", "escape_text", "html_page", "html_table", "png_figure"]

REPORT_CSS = (
    "body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}"
    "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;"
    "padding:2px 8px;text-align:left}th{background:#eee}img{max-width:100%}"
    "figcaption{font-style:italic;margin-bottom:1.5em}"
)


def escape_text(text: str) -> str:
    """``text`` escaped for an element's content (quotes left as they are)."""
    return html.escape(text, quote=False)


def html_page(title: str, body: Iterable[str], css: str = REPORT_CSS) -> str:
    """A whole page: ``body`` (HTML fragments, one a line) under ``title``, ``css`` inline.

    Examples
    --------
    >>> print(html_page("A & B", ["<p>hi</p>"], css="p{}"))
    <!DOCTYPE html>
    <html><head><meta charset="utf-8">
    <title>A &amp; B</title><style>p{}</style></head><body>
    <p>hi</p>
    </body></html>
    """
    head = [
        "<!DOCTYPE html>",
        '<html><head><meta charset="utf-8">',
        f"<title>{html.escape(title)}</title><style>{css}</style></head><body>",
    ]
    return "\n".join([*head, *body, "</body></html>"])


def html_table(
    header: Sequence[str],
    rows: Iterable[Sequence[str]],
    cell: Callable[[str], str] = escape_text,
) -> str:
    """A table: ``header`` escaped, each cell of ``rows`` through ``cell`` (escaping by
    default; a caller that formats its cells, e.g. inline code, passes its own).

    Examples
    --------
    >>> html_table(["a"], [["<1"]])
    '<table><tr><th>a</th></tr><tr><td>&lt;1</td></tr></table>'
    """
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{cell(c)}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def png_figure(png: bytes, alt: str, caption: str) -> str:
    """A PNG inline as a base64 data URI, with its caption: the page needs no other file."""
    data = base64.b64encode(png).decode("ascii")
    return (
        f'<figure><img alt="{html.escape(alt)}" src="data:image/png;base64,{data}">'
        f"<figcaption>{html.escape(caption)}</figcaption></figure>"
    )
