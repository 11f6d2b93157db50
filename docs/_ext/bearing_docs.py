"""Sphinx helpers of this project's documentation, generated from the code at build time.

* ``.. cli-options:: MODULE:FUNCTION`` renders an argparse parser (the one the command
  line itself builds) as ``program``/``option`` entries, one section per subcommand, so
  every command and option is indexed and searchable and cannot drift from the code.
* ``@REPOSITORY@`` and ``@REPOSITORY_LINK@`` in a page's source become the repository's
  address (``repository_url`` in conf.py), as text and as a link, also in code blocks
  (a substitution would not reach them).
* On ``builder-inited`` the case-file reference is written to ``_generated/`` by
  :func:`taichi_bearing.case.reference.render_reference`, the generator that also writes
  ``docs/case_reference.md`` (so the page follows the schema the loader validates with).
"""

from __future__ import annotations

import argparse
import importlib
import inspect
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
    text = render_reference()
    # the whole page, and its introduction and its sections apart (the guide's page puts
    # the bearing's pictures between them)
    title, _, rest = text.partition("\n")
    intro, units, body = rest.partition("\n## Units\n")
    if not units:
        intro, body = rest, ""
    parts = {"case_reference.md": text, "case_reference_intro.md": intro,
             "case_reference_body.md": units.lstrip("\n") + body}  # fmt: skip
    for name, content in parts.items():
        path = out / name
        if not path.exists() or path.read_text(encoding="utf-8") != content:
            path.write_text(content, encoding="utf-8")


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


def _import_dotted(name: str):
    """The object a dotted name reaches: its longest importable module, then attributes."""
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except Exception:  # noqa: BLE001 - any failure: try a shorter module
            continue
        try:
            for attr in parts[i:]:
                obj = getattr(obj, attr)
        except AttributeError:
            return None, None
        return obj, ".".join(parts[:i])
    return None, None


def _is_code(obj) -> bool:
    return inspect.isroutine(obj) or inspect.isclass(obj) or isinstance(obj, property)


def _documented(app, env) -> dict[int, str]:
    """Each documented function, class and method, by the object itself: id -> the name
    under which it has a page (computed once a build)."""
    cache = getattr(app, "_bearing_documented", None)
    if cache is None or cache[0] != len(env.get_domain("py").objects):
        objects = env.get_domain("py").objects
        by_id: dict[int, str] = {}
        for fullname, entry in objects.items():
            if entry.objtype == "module" or entry.aliased:
                continue
            obj, _ = _import_dotted(fullname)
            if obj is not None and _is_code(obj):
                by_id.setdefault(id(inspect.unwrap(obj)), fullname)
        cache = (len(objects), by_id)
        app._bearing_documented = cache
    return cache[1]


# Words a numpy-style type is written with; an attribute's first line whose text before a
# colon has others ("Time step, s: the stable one") is a sentence, not "type: text".
_TYPE_WORDS = {
    *("of", "or", "and", "to", "str", "int", "float", "bool", "bytes", "tuple", "list"),
    *("dict", "set", "frozenset", "mapping", "sequence", "iterable", "array", "array_like"),
    *("ndarray", "none", "optional", "callable", "path", "shape"),
}


def restore_attribute_sentences(app, what, name, obj, options, lines: list[str]) -> None:
    """autodoc-process-docstring, after napoleon: napoleon reads the text before the first
    colon of an attribute's or a property's docstring as its type. Where that text is a
    sentence, put it back at the head of the description."""
    if what not in ("attribute", "property", "data"):
        return
    for i, line in enumerate(lines):
        if not line.startswith(":type: "):
            continue
        text = line.removeprefix(":type: ")
        words = re.findall(r"[A-Za-z_]+", text)
        if len(text.split()) >= 2 and any(w.lower() not in _TYPE_WORDS for w in words):
            del lines[i]
            if i > 0 and not lines[i - 1].strip():
                del lines[i - 1]
            lines[0] = f"{text}: {lines[0]}" if lines and lines[0] else text
        return


def resolve_elsewhere(app, env, node, contnode):
    """missing-reference: a Python name written as the code reads it, linked to the page
    where the object is documented.

    * A name imported where it is used, or re-exported by a package (``taichi_bearing.run``,
      ``diagnostics._kurtosis.kurtogram``, ``run_cell`` in a module that imports it): the
      object is imported and looked up among the documented ones.
    * A short name (``Mesh``, ``Model.set_initial_velocities``) that ends exactly one
      documented name, or one in the package of the module that writes it.
    * An attribute without an entry of its own (a dataclass field, ``Setup.pair_table``):
      its class's page; a module's constant (``SUMMARY_FILE``, upper case): the page of
      the module that assigns it.
    """
    if node.get("refdomain") != "py":
        return None
    target = node.get("reftarget", "")
    if not target or " " in target:
        return None
    domain = env.get_domain("py")
    module = node.get("py:module") or ""
    klass = node.get("py:class") or ""

    def link(name, typ="obj"):
        log = os.environ.get("BEARING_DOCS_XREF_LOG")  # what was linked where, to review
        if log:
            with open(log, "a", encoding="utf-8") as f:
                f.write(f"{node.get('refdoc')}\t{module}\t{target}\t{name}\n")
        return domain.resolve_xref(
            env, node.get("refdoc", ""), app.builder, typ, name, node, contnode
        )

    documented = _documented(app, env)
    contexts = [f"{module}.{klass}", module, ""] if klass else [module, ""]
    for context in contexts:
        name = f"{context}.{target}" if context else target
        obj, owner = _import_dotted(name)
        if obj is None and "." in target:
            # a dataclass field or an attribute without an entry: its class's page
            obj, owner = _import_dotted(name.rsplit(".", 1)[0])
            if not inspect.isclass(obj):
                continue
        if obj is None or owner is None:
            continue
        if _is_code(obj):
            found = documented.get(id(inspect.unwrap(obj)))
            if found:
                return link(found)
            continue
        parent = name.rsplit(".", 1)[0]
        if inspect.ismodule(obj) or parent not in domain.objects:
            continue
        holder = _import_dotted(parent)[0]
        if inspect.isclass(holder):  # a class attribute without an entry: the class
            return link(parent)
        attr = name.rsplit(".", 1)[1]
        if _defines(holder, attr):  # a module's constant: the module
            return link(parent, "mod")
        # a constant imported there: the module that assigns that very object
        holders = _defining_modules(
            domain, attr, lambda m, attr=attr, obj=obj: getattr(m, attr, None) is obj
        )
        if len(holders) == 1:
            return link(holders[0], "mod")
    # a short name: the documented names it ends, nearest the writer's module first
    ends = [n for n in domain.objects if n.endswith("." + target)]
    parts = module.split(".")
    for i in range(0, len(parts) + 1):
        prefix = ".".join(parts[:i])
        pool = [n for n in ends if n.startswith(prefix + ".")] if prefix else ends
        if len(pool) == 1:
            return link(pool[0])
        if not pool:
            break
    # a constant (UPPER_CASE) of a module in the package it is written under (or the
    # writer's): the module that assigns it
    within, _, constant = target.rpartition(".")
    within = within or parts[0]
    if within and re.fullmatch(r"[A-Z][A-Z0-9_]*", constant):
        holders = _defining_modules(
            domain, constant, lambda m: m.__name__ == within or m.__name__.startswith(within + ".")
        )
        if len(holders) == 1:
            return link(holders[0], "mod")
    return None


def _defining_modules(domain, name: str, keep) -> list[str]:
    """The documented modules that assign ``name`` at their top level, as ``keep`` allows."""
    found = []
    for module, entry in domain.objects.items():
        if entry.objtype != "module":
            continue
        obj = _import_dotted(module)[0]
        if obj is not None and keep(obj) and _defines(obj, name):
            found.append(module)
    return found


def _defines(module, name: str) -> bool:
    """Whether a module's own source assigns ``name`` at its top level."""
    try:
        source = inspect.getsource(module)
    except (OSError, TypeError):
        return False
    return re.search(rf"^{re.escape(name)}\s*[:=]", source, re.MULTILINE) is not None


class ExamplesUsing(SphinxDirective):
    """``.. examples-using:: taichi_bearing.case.load.load_case``: the gallery's examples
    that use the object, under any name it is imported by: sphinx-gallery records a call
    under the shortest module path that has the name (``taichi_bearing.case.load_case``),
    the API page is under the module that defines it."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        fullname = self.arguments[0]
        obj, _ = _import_dotted(fullname)
        names = [fullname]
        parts = fullname.split(".")
        for i in range(1, len(parts) - 1):
            package, _ = _import_dotted(".".join(parts[:i]))
            if obj is not None and getattr(package, parts[-1], None) is obj:
                names.append(".".join(parts[:i] + parts[-1:]))
        lines = [f".. minigallery:: {' '.join(names)}",
                 f"   :add-heading: Examples using ``{parts[-1]}``",
                 "   :heading-level: -"]  # fmt: skip
        container = nodes.section()
        container.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source="examples-using"), container)
        return container.children


def drop_stale_stubs(app) -> None:
    """builder-inited, before autosummary writes its pages: remove the page of an object
    that is gone from the code (a renamed function would leave a page that fails)."""
    for stub in (Path(app.srcdir) / "api" / "generated").glob("*.rst"):
        if _import_dotted(stub.stem)[0] is None:
            stub.unlink()


def fill_repository(app, docname, source: list[str]) -> None:
    """source-read: the repository's address where a page writes ``@REPOSITORY@``."""
    url = app.config.repository_url
    link = f"`{url} <{url}>`_" if url.startswith("http") else f"``{url}``"
    source[0] = source[0].replace("@REPOSITORY_LINK@", link).replace("@REPOSITORY@", url)


def setup(app):
    app.add_config_value("repository_url", "<repository URL>", "html")
    app.connect("source-read", fill_repository)
    app.add_directive("cli-options", CliOptions)
    app.add_directive("examples-using", ExamplesUsing)
    app.connect("missing-reference", resolve_elsewhere)
    app.connect("autodoc-process-docstring", escape_absolute_values)
    app.connect("autodoc-process-docstring", restore_attribute_sentences, priority=600)
    app.connect("builder-inited", write_generated)
    app.connect("builder-inited", drop_stale_stubs, priority=400)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
