"""Sphinx configuration of tumble's site: ``make docs`` builds it into
``docs/_build/html``, a folder that works with no network (MathJax, the theme's
fonts and the search index are all local)."""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

import tumble  # noqa: E402

project = "tumble"
author = "the tumble authors"
copyright = "the tumble authors"
release = version = tumble.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "tumble_docs",
]
# No intersphinx: the site is built with no network, and every warning fails it.

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# The galleries' sources: sphinx-gallery reads them and writes the auto_* pages.
exclude_patterns = ["_build", "tutorials", "how-to", "examples", "**/*.ipynb", "**/*.zip"]
templates_path = ["_templates"]
nitpicky = True  # every reference resolves; tumble_docs shows internals' as text

html_theme = "pydata_sphinx_theme"
html_title = f"tumble {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "icon_links": [],
    "check_switcher": False,
    "footer_start": ["copyright"],
    "footer_end": [],
}
# Without search summaries the search page reads no page by fetch(), which a
# browser refuses for file:// addresses.
html_show_search_summary = False
html_context = {"default_mode": "auto"}  # light or dark as the reader's system prefers
html_show_sourcelink = False

# MathJax 3 from the sphinx-mathjax-offline wheel, copied into _static/mathjax
# (tumble_docs.copy_mathjax); a relative path is read below _static.
mathjax_path = "mathjax/tex-chtml.js"

autodoc_typehints = "none"  # the types are in the numpydoc Parameters sections
autodoc_preserve_defaults = True
autodoc_member_order = "bysource"
autosummary_generate = True
autosummary_imported_members = True
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
numpydoc_attributes_as_param_list = False  # attributes get targets of their own

myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

sphinx_gallery_conf = {
    "examples_dirs": ["tutorials", "how-to", "examples"],
    "gallery_dirs": ["auto_tutorials", "auto_how-to", "auto_examples"],
    "filename_pattern": r".*",
    "image_scrapers": ("matplotlib",),
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "show_signature": False,
    "run_stale_examples": True,
    "write_computation_times": False,
    "reference_url": {"tumble": None},
    "matplotlib_animations": False,
}
