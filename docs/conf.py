"""Sphinx configuration of certkit's documentation (``make docs`` builds it).

Sphinx, because certkit's docstrings are numpydoc (Sphinx's numpydoc extension reads them
as written) and the scientific-Python projects a certkit user knows (NumPy, SciPy, pandas)
publish their documentation with the same tools and the PyData theme. Pages are MyST
Markdown, so that they read as plain text in the repository too.
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).parent / "_ext"))

from certkit.version import VERSION  # noqa: E402

project = "certkit"
author = "certkit's authors"
copyright = "2026, certkit's authors"
release = version = VERSION

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "numpydoc",
    "spec_reference",   # docs/_ext: the campaign spec reference, made from certkit's schema
    "cli_reference",    # docs/_ext: the command-line reference, made from the commands
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "examples/**/README.md"]
myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
# every heading gets an anchor, so that a link to a section that does not exist warns
myst_heading_anchors = 4

# the API reference: what a docstring says, in the order the source gives it
autodoc_member_order = "bysource"
autodoc_typehints = "none"          # numpydoc's Parameters sections say the types in words
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

html_theme = "pydata_sphinx_theme"
html_title = f"certkit {VERSION}"
html_static_path = ["_static"]
# every page is listed in the header; the left sidebar would be empty
html_sidebars = {"**": []}
html_theme_options = {
    "header_links_before_dropdown": 6,
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
# no request leaves the machine while the site builds or is read offline
html_theme_options["icon_links"] = []
