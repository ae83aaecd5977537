"""Sphinx configuration of stickslip's documentation site.

Built by ``bash .ci/docs`` (warnings are errors; the tutorials are executed).
Sphinx with MyST-NB: the pages stay the Markdown files they were, the tutorials
are Markdown notebooks executed at every build (a stale example fails the build),
and the API reference comes from the numpydoc docstrings, as in SciPy and xarray.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
# the tutorials' kernels run from the docs folder: they import the same source
os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), os.environ.get("PYTHONPATH")]))
# figures of the tutorials are embedded by the kernel's inline backend, whatever the shell has set
os.environ["MPLBACKEND"] = "module://matplotlib_inline.backend_inline"

import stickslip  # noqa: E402

project = "stickslip"
author = "the stickslip developers"
copyright = "2026, the stickslip developers"  # noqa: A001
release = stickslip.__version__
version = release

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
]

source_suffix = {".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = ["_build", "jupyter_execute", "**/.ipynb_checkpoints"]
root_doc = "index"

# ---- MyST and notebook execution ------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
nb_execution_mode = "force"  # every build runs every tutorial
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# ---- API reference ---------------------------------------------------------------------
autosummary_generate = True
autodoc_typehints = "none"  # the numpydoc sections say it, with units
autodoc_default_options = {"members": True, "member-order": "bysource"}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
suppress_warnings = ["myst.header"]

# ---- HTML ------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"stickslip {release}"
html_static_path: list[str] = []
