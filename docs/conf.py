"""Sphinx configuration of the slosh-fsi documentation.

Build (no network needed):

    .venv/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

While editing, ``-D nb_execution_mode=off`` skips running the notebooks.
"""
from __future__ import annotations

import sys
from datetime import date
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(ROOT))

project = "slosh-fsi"
author = "the slosh-fsi authors"
copyright = f"2014–{date.today().year}, {author}"
try:
    from importlib.metadata import version as _version

    release = _version("slosh-fsi")
except Exception:  # not installed: the source tree's pyproject
    release = "0.1.0"
version = release

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax 3 copied into _static/mathjax: equations render offline
    "sphinx.ext.viewcode",
    "generated",  # docs/_ext/generated.py: scene keys, output datasets, notebooks
    "docstrings",  # docs/_ext/docstrings.py: |x| in docstrings read as written
    "datatable",  # docs/_ext/datatable.py: tables and numbers read from docs/data/*.json
]

# -- sources ------------------------------------------------------------------------------
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "data", "Thumbs.db", ".DS_Store", "**.ipynb_checkpoints",
                    "jupyter_execute"]
templates_path: list[str] = []
html_static_path = ["_static"]
# Commands are copied from the pages: "--fills" must not become an en dash, nor ' a curly quote.
smartquotes = False

# -- MyST -------------------------------------------------------------------------------
myst_enable_extensions = [
    "amsmath",
    "colon_fence",
    "deflist",
    "dollarmath",
    "fieldlist",
    "substitution",
]
myst_heading_anchors = 3
myst_dmath_double_inline = True

# -- notebooks (MyST-NB) ------------------------------------------------------------------
nb_execution_mode = "force"  # every build runs them: a notebook that breaks fails the build
nb_execution_timeout = 900
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# -- API (autodoc + napoleon, numpy style) -----------------------------------------------
autodoc_default_options = {
    "members": True,
    "undoc-members": False,
    "show-inheritance": False,
    "member-order": "bysource",
}
autodoc_typehints = "none"
autodoc_preserve_defaults = True
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True

# -- HTML ---------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"slosh-fsi {release}"
html_theme_options = {
    "navigation_with_keys": True,
}
html_last_updated_fmt = None
# The site loads nothing from another host (tests/test_docs_build.py): MathJax is served from
# _static/mathjax, which sphinx-mathjax-offline fills on every build.
mathjax_path = "mathjax/tex-chtml.js"
nitpicky = False
