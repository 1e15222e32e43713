"""Sphinx configuration of the wake documentation site.

Build (from a clean clone; README.md, "Documentation"):

    pip install ".[docs]"
    sphinx-build -W --keep-going -b html docs docs/_build/html

Warnings are errors: a broken cross-reference, a missing heading anchor in a Markdown link, an unknown
object in a docstring's "See Also" and a page outside every table of contents all fail the build.
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# The package documented is the one importable here: an installed copy (pip install ".[docs]") or, from a
# checkout that is not installed, the source tree beside this folder.
try:
    import wake
except ImportError:
    sys.path.insert(0, str(ROOT))
    import wake

project = "wake"
author = "the wake-tremor authors"
copyright = "2026, the wake-tremor authors"
release = wake.__version__  # the package metadata's (pyproject.toml), the one place it is set
version = ".".join(release.split(".")[:2])

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
]

# Markdown sources (MyST).  Heading anchors down to level 4 so that a page links to a study's section
# as ../studies/design.md#missing-samples; a link to a missing page or anchor is a warning, so an error.
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 4
root_doc = "index"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]
templates_path = ["_templates"]

# The API reference: one page per object, its text the object's own numpydoc docstring, so the page and
# help(obj) say the same.
autosummary_generate = True
autodoc_default_options = {"members": False}
autodoc_typehints = "none"          # the numpydoc "Parameters" section states the types
numpydoc_show_class_members = False  # the class page lists its methods through the autosummary template
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
nitpicky = False  # numpydoc's free-text types ("int or None", "(n,) array") are not cross-reference targets

html_theme = "pydata_sphinx_theme"
html_title = f"wake {release}"
html_logo = None
html_static_path = []
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "navbar_align": "left",
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_context = {"default_mode": "light"}
html_show_sourcelink = False

# linkcheck (CI has no internet): external URLs are not fetched; the internal references and anchors are
# resolved by the html build above, where a missing one is an error.
linkcheck_ignore = [r"https?://.*"]
linkcheck_anchors = True

