"""Sphinx configuration of dtcrit's documentation site (``python3 dev.py docs`` -> ``docs/_build/html``).

The site is built with warnings as errors.  Pages that come from the code are made at build time:
the teaching notebooks (``notebooks/*.py``, jupytext percent format) are copied into
``tutorials/notebooks/`` and executed by myst-nb with a jupyter-cache under
``docs/_build/.jupyter_cache`` (a second build re-executes only a changed notebook, or all of them
when the package changed); the derivation
records are included from ``derivations/records``; the gallery figures and the benchmarks page are
made by the steps in ``docs/_gen`` (written into gitignored ``_generated`` folders).  The reference
pages come from the extension ``dtcrit_docs`` in ``docs/_ext`` when it exists.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path[:0] = [str(DOCS / "_ext"), str(DOCS / "_gen"), str(ROOT / "src")]

import notebook_cache  # noqa: E402 - from docs/_gen, on the path just above

project = "dtcrit"
author = "the dtcrit authors"
copyright = "the dtcrit authors"  # noqa: A001 - Sphinx's name

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "numpydoc",
    "sphinxarg.ext",
    "sphinx.ext.mathjax",
]
if (DOCS / "_ext" / "dtcrit_docs.py").is_file():  # the generated reference pages
    extensions.append("dtcrit_docs")
if (DOCS / "_gen" / "dtcrit_site.py").is_file():  # notebooks, records, gallery, benchmarks
    extensions.append("dtcrit_site")

root_doc = "index"
exclude_patterns = ["_build", "_ext", "_gen", "_generated", "**/_generated", "**/_generated/*", "**/data",
                    "**.ipynb_checkpoints"]

html_theme = "alabaster"
html_title = "dtcrit"
html_static_path: list[str] = []

# MyST: $...$ maths, ::: fences, heading anchors for links like page.md#section
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# The notebooks: jupytext percent-format sources, executed once and cached, in a cache folder named
# by a hash of the package's sources (``_gen/notebook_cache.py``): a changed dtcrit re-executes them.
nb_custom_formats = {".nbpy": ["jupytext.reads", {"fmt": "py:percent"}]}
nb_execution_mode = "cache"
nb_execution_cache_path = str(notebook_cache.cache_path(prune=True))
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_output_stderr = "warn"  # a notebook writing to stderr fails the -W build
# the kernel draws inline so each figure is kept as a PNG output (as dtcrit.notebooks.render does)
os.environ["MPLBACKEND"] = "module://matplotlib_inline.backend_inline"
# the kernel (and every command the build runs) imports this checkout's dtcrit
os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), os.environ.get("PYTHONPATH")]))

# MathJax from Debian's libjs-mathjax (2.7, installed by `dev.py test` as root) when it is there, copied into
# the site so that formulas render offline and in the browser test; else Sphinx's default (a CDN).
MATHJAX_DIR = Path("/usr/share/javascript/mathjax")
if (MATHJAX_DIR / "MathJax.js").is_file():
    mathjax_path = "mathjax/MathJax.js?config=TeX-AMS_CHTML"


def _copy_mathjax(app, exception) -> None:
    """Copy the local MathJax (no test pages, no unpacked sources) into ``_static/mathjax``."""
    import shutil

    if exception is None and app.builder.format == "html" and (MATHJAX_DIR / "MathJax.js").is_file():
        shutil.copytree(MATHJAX_DIR, Path(app.outdir) / "_static" / "mathjax", dirs_exist_ok=True,
                        ignore=shutil.ignore_patterns("test", "unpacked"))


def setup(app) -> None:
    """Register the MathJax copy."""
    app.connect("build-finished", _copy_mathjax)


numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
autodoc_typehints = "none"
