"""Sphinx helpers of this project's documentation, generated from the code at build time.

* ``.. cli-options:: MODULE:FUNCTION`` renders an argparse parser (the one the command
  line itself builds) as ``program``/``option`` entries, one section per subcommand, so
  every command and option is indexed and searchable and cannot drift from the code.
* On ``builder-inited`` the case-file reference is written to ``_generated/`` by
  :func:`taichi_bearing.case.reference.render_reference`, the generator that also writes
  ``docs/case_reference.md`` (so the page follows the schema the loader validates with).
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import directives
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

GENERATED = "_generated"
_RST_SPECIAL = re.compile(r"([\\*`|_])")


def rst_text(text: str) -> str:
    """One line of plain text, with the characters reStructuredText would read escaped."""
    return _RST_SPECIAL.sub(r"\\\1", " ".join(text.split()))


def _help(parser: argparse.ArgumentParser, action: argparse.Action) -> str:
    """An action's help with ``%(default)s`` and the like filled in, as ``--help`` shows."""
    return parser._get_formatter()._expand_help(action)  # noqa: SLF001 - argparse's own way


def _option_signature(parser: argparse.ArgumentParser, action: argparse.Action) -> str:
    formatter = parser._get_formatter()  # noqa: SLF001
    if not action.option_strings:
        return formatter._metavar_formatter(action, action.dest.upper())(1)[0]  # noqa: SLF001
    if action.nargs == 0:
        return ", ".join(action.option_strings)
    args = formatter._format_args(action, action.dest.upper())  # noqa: SLF001
    return ", ".join(f"{o} {args}" for o in action.option_strings)


def _subparsers(parser: argparse.ArgumentParser):
    for action in parser._actions:  # noqa: SLF001
        if isinstance(action, argparse._SubParsersAction):  # noqa: SLF001
            helps = {a.dest: a.help for a in action._choices_actions}  # noqa: SLF001
            for name, sub in action.choices.items():
                yield name, sub, helps.get(name, "")


def parser_rst(parser: argparse.ArgumentParser, prog: str, underline: str) -> list[str]:
    """reStructuredText for one parser: usage, description and its options by group."""
    lines = [f".. program:: {prog}", ""]
    usage = parser.format_usage().strip()
    lines += ["::", "", *("   " + u for u in usage.splitlines()), ""]
    if parser.description:
        lines += [rst_text(parser.description), ""]
    for group in parser._action_groups:  # noqa: SLF001
        actions = [
            a
            for a in group._group_actions  # noqa: SLF001
            if a.help != argparse.SUPPRESS and not isinstance(a, argparse._SubParsersAction)  # noqa: SLF001
        ]
        if not actions:
            continue
        lines += [f"**{rst_text(group.title or 'options')}**", ""]
        for action in actions:
            lines += [f".. option:: {_option_signature(parser, action)}", ""]
            lines += ["   " + rst_text(_help(parser, action) or ""), ""]
    if parser.epilog:
        lines += [rst_text(parser.epilog), ""]
    return lines


class CliOptions(SphinxDirective):
    """``.. cli-options:: package.module:build_parser`` with ``:prog:`` (the name shown)."""

    required_arguments = 1
    option_spec = {"prog": directives.unchanged_required, "level": directives.unchanged}

    def run(self) -> list[nodes.Node]:
        module_name, func_name = self.arguments[0].split(":")
        old = os.environ.get("COLUMNS")
        os.environ["COLUMNS"] = "88"  # argparse wraps usage lines to the terminal's width
        try:
            parser = getattr(importlib.import_module(module_name), func_name)()
            prog = self.options.get("prog", parser.prog)
            parser.prog = prog
            underline = self.options.get("level", "-")
            lines = parser_rst(parser, prog, underline)
            for name, sub, help_text in _subparsers(parser):
                title = f"``{prog} {name}``"
                lines += [title, underline * len(title), ""]
                if help_text and not sub.description:
                    lines += [rst_text(help_text), ""]
                lines += parser_rst(sub, f"{prog} {name}", underline)
        finally:
            if old is None:
                os.environ.pop("COLUMNS", None)
            else:
                os.environ["COLUMNS"] = old
        container = nodes.section()
        container.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source="cli-options"), container)
        return container.children


def write_generated(app) -> None:
    """The pages made from the code: written only when they change (no needless rebuild)."""
    from taichi_bearing.case.reference import render_reference

    out = Path(app.srcdir) / GENERATED
    out.mkdir(exist_ok=True)
    path = out / "case_reference.md"
    text = render_reference()
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


# |x| written for an absolute value, outside a ``literal``: reStructuredText reads it as a
# substitution reference (an error). Where a docstring of the simulator's says |x| in
# plain text, the bars are escaped (display only; the docstrings stay as written).
_BARS = re.compile(r"(?<![\\|`])\|(?=\S)([^|`\n]*?\S)\|(?![|`])")


def _escape_bars(line: str) -> str:
    parts = line.split("``")
    for i in range(0, len(parts), 2):  # the parts outside ``literal`` spans
        parts[i] = _BARS.sub(r"\\|\1\\|", parts[i])
    return "``".join(parts)


def escape_absolute_values(app, what, name, obj, options, lines: list[str]) -> None:
    """autodoc-process-docstring: escape ``|x|`` in taichi_bearing's plain text (not in
    literal blocks, not in table rows)."""
    if not name.startswith("taichi_bearing"):
        return
    literal_indent = None
    for i, line in enumerate(lines):
        stripped = line.lstrip()
        indent = len(line) - len(stripped)
        if literal_indent is not None:
            if not stripped or indent > literal_indent:
                continue
            literal_indent = None
        if stripped.startswith("+") or (stripped.startswith("|") and stripped.endswith("|")):
            continue  # a grid table's rows
        lines[i] = _escape_bars(line)
        if stripped.endswith("::"):
            literal_indent = indent


def resolve_public_names(app, env, node, contnode):
    """missing-reference: ``diagnostics.kurtogram`` (the package's public name, as users
    write it) links to where it is documented, ``diagnostics.kurtosis.kurtogram``."""
    target = node.get("reftarget", "")
    if node.get("refdomain") != "py":
        return None
    if "." not in target and node.get("py:module") == "diagnostics":
        target = f"diagnostics.{target}"  # written in the package's own docstring
    if not target.startswith("diagnostics."):
        return None
    import diagnostics

    name = target.removeprefix("diagnostics.")
    module = diagnostics._MODULE_OF.get(name)  # noqa: SLF001
    if module is None:
        return None
    domain = env.get_domain("py")
    node["reftarget"] = f"diagnostics.{module}.{name}"
    return domain.resolve_xref(
        env,
        node.get("refdoc", ""),
        app.builder,
        node["reftype"],
        node["reftarget"],
        node,
        contnode,
    )


def setup(app):
    app.add_directive("cli-options", CliOptions)
    app.connect("missing-reference", resolve_public_names)
    app.connect("autodoc-process-docstring", escape_absolute_values)
    app.connect("builder-inited", write_generated)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
