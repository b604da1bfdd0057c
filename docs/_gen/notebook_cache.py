"""Where the site keeps the notebooks' executions, and how to read them back.

jupyter-cache keys a notebook on its code cells only, so the cache of ``conf.py`` lives in a folder
named by a hash of the package's sources (``docs/_build/.jupyter_cache/<hash>``): changing dtcrit
re-executes every notebook, and an unchanged tree reuses the outputs.  ``executed`` reads the
executed notebooks back (the tests check them instead of executing the notebooks a second time).
Standard library only at import time; ``executed`` needs jupyter-cache (a dependency of myst-nb).
"""
from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
CACHES = DOCS / "_build" / ".jupyter_cache"


def package_hash(root: Path = ROOT) -> str:
    """A hash of every file of ``src/dtcrit`` (bytecode caches left out).

    Parameters
    ----------
    root : pathlib.Path
        The repository.

    Returns
    -------
    str
        16 hexadecimal digits.
    """
    digest = hashlib.sha256()
    for path in sorted((root / "src" / "dtcrit").rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(path.relative_to(root).as_posix().encode() + path.read_bytes())
    return digest.hexdigest()[:16]


def cache_path(prune: bool = False) -> Path:
    """The jupyter-cache folder for the current sources; with ``prune``, delete the others.

    Parameters
    ----------
    prune : bool
        Remove the caches of other source trees (and files of an older layout).

    Returns
    -------
    pathlib.Path
        ``docs/_build/.jupyter_cache/<package_hash()>``.
    """
    path = CACHES / package_hash()
    if prune and CACHES.is_dir():
        for stale in CACHES.iterdir():
            if stale != path:
                shutil.rmtree(stale, ignore_errors=True) if stale.is_dir() else stale.unlink()
    return path


def executed(stem: str):
    """The executed notebook of ``tutorials/notebooks/<stem>`` from the current cache.

    Parameters
    ----------
    stem : str
        The notebook's name, e.g. ``01_quaternions_to_amax``.

    Returns
    -------
    nbformat.NotebookNode or None
        The notebook with its outputs; None when the cache holds no execution of it.
    """
    from jupyter_cache import get_cache

    path = cache_path()
    if not path.is_dir():
        return None
    cache = get_cache(path)
    records = [r for r in cache.list_cache_records() if Path(r.uri).stem == stem]
    if not records:
        return None
    latest = max(records, key=lambda r: r.pk)
    return cache.get_cache_bundle(latest.pk).nb
