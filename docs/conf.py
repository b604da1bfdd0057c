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

import hashlib
import os
import shutil
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path[:0] = [str(DOCS / "_ext"), str(DOCS / "_gen"), str(ROOT / "src")]

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

# The notebooks: jupytext percent-format sources, executed once and cached.  jupyter-cache keys a
# notebook on its code cells only, so the cache lives in a folder named by a hash of the package's
# sources: changing dtcrit re-executes every notebook, and an unchanged tree reuses the outputs.
nb_custom_formats = {".nbpy": ["jupytext.reads", {"fmt": "py:percent"}]}
nb_execution_mode = "cache"


def _package_hash() -> str:
    digest = hashlib.sha256()
    for path in sorted((ROOT / "src" / "dtcrit").rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(path.relative_to(ROOT).as_posix().encode() + path.read_bytes())
    return digest.hexdigest()[:16]


_CACHES = DOCS / "_build" / ".jupyter_cache"
nb_execution_cache_path = str(_CACHES / _package_hash())
for _stale in (_CACHES.iterdir() if _CACHES.is_dir() else ()):
    if _stale.is_dir() and str(_stale) != nb_execution_cache_path:
        shutil.rmtree(_stale, ignore_errors=True)
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_output_stderr = "warn"  # a notebook writing to stderr fails the -W build
# the kernel draws inline so each figure is kept as a PNG output (as dtcrit.notebooks.render does)
os.environ["MPLBACKEND"] = "module://matplotlib_inline.backend_inline"
# the kernel (and every command the build runs) imports this checkout's dtcrit
os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), os.environ.get("PYTHONPATH")]))

numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
autodoc_typehints = "none"
