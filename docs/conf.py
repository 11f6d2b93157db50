"""Sphinx configuration of the taichi-bearing documentation.

Build: ``python -m sphinx -W --keep-going docs docs/_build/html`` (``pip install -e
".[docs]"``). The gallery scripts in ``examples/`` run during the build; add
``-D plot_gallery=0`` to build the pages without running them (what
``tests/test_docs_build.py`` does; ``tests/test_examples.py`` runs the scripts).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(ROOT))
os.environ.setdefault("MPLBACKEND", "Agg")

import taichi_bearing  # noqa: E402

project = "taichi-bearing"
author = "the taichi-bearing authors"
copyright = "the taichi-bearing authors"  # noqa: A001
release = version = taichi_bearing.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    # MathJax copied into the built site (mathjax_path set to it): formulas render offline
    "sphinx-mathjax-offline",
    "sphinx.ext.viewcode",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "bearing_docs",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "Thumbs.db",
    ".DS_Store",
    # the committed copy of the case reference; the site builds its own from the schema
    "case_reference.md",
    # a table the impact README links as a file (no title of its own)
    "results/impact/table.md",
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "auto_examples/*.md5",
    "auto_examples/*.json",
]

# Markdown pages (architecture, results): MyST with heading anchors for in-page links.
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

# API reference: numpy-style docstrings through napoleon (it ships with Sphinx).
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_description_target = "documented"
# A module's own members only: names it re-exports (in its __all__) are documented where
# they are defined, so each object has one entry and one link target.
autodoc_default_options = {"members": True, "ignore-module-all": True}
autodoc_preserve_defaults = True
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True

# Gallery: examples/plot_*.py run at build time (a few minutes in all, on synthetic data).
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
    "show_memory": False,
    "capture_repr": ("__repr__",),
}

# Literal blocks without a language (docstring formulas, usage lines) are plain text.
highlight_language = "none"

# "--set" stays two hyphens in option help (no typographic dashes or quotes).
smartquotes = False

html_theme = "alabaster"
html_title = "taichi-bearing"
html_static_path = ["_static"]  # _static/custom.css: alabaster picks it up
html_theme_options = {
    "description": "Roller bearing with a line spall: simulation and diagnostics",
    "fixed_sidebar": True,
    "page_width": "1400px",
    "body_max_width": "none",
    "sidebar_width": "240px",
}
html_sidebars = {"**": ["about.html", "navigation.html", "relations.html", "searchbox.html"]}
