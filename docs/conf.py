"""Sphinx configuration of the taichi-bearing documentation.

Build: ``python -m sphinx -W --keep-going docs docs/_build/html`` (``pip install -e
".[docs]"``). The gallery scripts in ``examples/`` run during the build; add
``-D plot_gallery=0`` to build the pages without running them (what
``tests/project/test_docs_build.py`` does; ``tests/project/test_examples.py`` runs them).
``python docs/_ext/screenshots.py`` builds the site and takes screenshots of it in headless
Chromium; ``python docs/_ext/front_figures.py`` redraws the pictures of the bearing.
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
# Where the code is published: the front page's clone step (``@REPOSITORY@`` in a page,
# docs/_ext/bearing_docs.py) and, for an http address, a link in the top bar.
repository_url = REPOSITORY = os.environ.get("TAICHI_BEARING_REPOSITORY", "<repository URL>")
author = "the taichi-bearing authors"
copyright = "the taichi-bearing authors"  # noqa: A001
release = version = taichi_bearing.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    # MathJax copied into the built site (mathjax_path set to it): formulas render offline
    "sphinx-mathjax-offline",
    "sphinx.ext.viewcode",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    # grids and cards (the front page), tabs: the pydata theme styles them
    "sphinx_design",
    "bearing_docs",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "Thumbs.db",
    ".DS_Store",
    # the committed copy of the case reference; the site builds its own from the schema,
    # in _generated/, which the guide's page includes
    "case_reference.md",
    "_generated",
    # tables the impact READMEs link as files or copy (no title of their own)
    "results/impact/table.md",
    "results/cylinder_impact/*/table.md",
    "results/contact_convergence/static*/table.md",
    # the gallery's downloads and notebooks, and the API pages' templates, are not pages
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "auto_examples/*.md5",
    "auto_examples/*.json",
    "_templates",
]

# Markdown pages (architecture, results): MyST with heading anchors for in-page links.
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

# API reference: numpy-style docstrings through napoleon (it ships with Sphinx); autosummary
# writes a page per module and per public function and class into api/generated/ (from
# the templates in _templates/autosummary/), each with the gallery examples that use it.
templates_path = ["_templates"]
autosummary_generate = True
autosummary_imported_members = False
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
    # "Examples using this": each API page lists the examples that call it
    "doc_module": ("taichi_bearing", "diagnostics", "bearing_io"),
    "backreferences_dir": "api/backreferences",
    "reference_url": {"taichi_bearing": None, "diagnostics": None, "bearing_io": None},
}

# Every cross-reference must resolve: a name that links nowhere is an error (-W). Project
# names written as the code reads them (imported, re-exported, short) are linked by
# bearing_docs.resolve_elsewhere; what stays plain text, and why:
nitpicky = True
nitpick_ignore_regex = [
    # Other projects' names: the build is offline, without their intersphinx inventories.
    (
        r"py:.*",
        r"(numpy|np|scipy|pandas|pd|matplotlib|mpl|taichi|ti|pyvista|meshio|yaml"
        r"|dask|distributed|tqdm|threadpoolctl|pyarrow|argparse|collections|concurrent"
        r"|contextlib|dataclasses|datetime|enum|io|json|logging|multiprocessing|os"
        r"|pathlib|subprocess|types|typing)(\..+)?",
    ),  # fmt: skip
    # ... and their short names, as the docstrings' types write them.
    (
        r"py:.*",
        r"(ndarray|array|DataFrame|Series|Axes|Figure|Path|PathLike|Sequence|Mapping"
        r"|Iterable|Iterator|Callable|Any|Literal|Self|TextIO|Namespace|ArgumentParser"
        r"|Future|Client|csr_matrix|Generator|Hashable)",
    ),  # fmt: skip
    # numpy-style type descriptions, which Sphinx cuts into words and looks each up: shapes
    # and sizes ("ndarray, shape (n_nodes, 2)"), "array_like", "sequence of", choices
    # ("{'outer', 'inner'}"): a word without a dot that no class name here has (not
    # capitalised: lower case, a number, a brace), or words with spaces. Dotted names and
    # capitalised words are always looked up.
    (r"py:class", r"[^A-Z][^.]*|.* .*"),
]

# Literal blocks without a language (docstring formulas, usage lines) are plain text.
highlight_language = "none"

# "--set" stays two hyphens in option help (no typographic dashes or quotes).
smartquotes = False

# The pydata theme (numpy, scipy, pandas, scikit-learn, pyvista): a top bar of the site's
# parts, the part's pages on the left, the page's own contents on the right; below 960 px
# both side panels fold away behind buttons, so the text comes first on any screen.
html_theme = "pydata_sphinx_theme"
html_title = "taichi-bearing"
html_short_title = "taichi-bearing"
html_static_path = ["_static"]
html_css_files = ["custom.css"]
html_theme_options = {
    "logo": {"text": "taichi-bearing"},
    "navbar_align": "left",
    # one row of the top bar at 1366 px: the search as a button, the rest under "More"
    "navbar_persistent": ["search-button"],
    "navbar_end": ["theme-switcher", "navbar-icon-links"],
    "header_links_before_dropdown": 6,
    # the left panel says where a page is; no breadcrumb line above its title
    "article_header_start": [],
    "show_toc_level": 2,
    # the left panel: a section's pages, their own pages folded (with some 800 API pages,
    # an unfolded tree would be rendered into every page: slow to build, long to read)
    "navigation_depth": 2,
    "show_nav_level": 1,
    "collapse_navigation": True,
    "secondary_sidebar_items": ["page-toc", "sourcelink"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version", "theme-version"],
    "show_prev_next": True,
    "icon_links": (
        [{"name": "Repository", "url": REPOSITORY, "icon": "fa-brands fa-git-alt"}]
        if REPOSITORY.startswith("http")
        else []
    ),
}
# The front page is a page of its own: no side panels. A single API object's page lists
# the API's parts (_templates/api-sidebar.html); its module's page, linked from it, has
# the module's table.
html_sidebars = {
    "index": [],
    # pages without pages of their own: no empty left panel
    "getting_started": [],
    "architecture": [],
    "api/generated/*": ["api-sidebar.html"],
}
html_context = {"default_mode": "light"}
