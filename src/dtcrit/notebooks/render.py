"""Render the teaching notebooks: jupytext percent-format sources -> executed ``.ipynb``.

The sources live in ``notebooks/*.py`` (no outputs committed).  ``render`` converts each with
jupytext, executes it with nbclient (``MPLBACKEND=Agg``, a per-notebook timeout) and writes the
executed notebook.  A cell whose assertion fails makes the render fail.  Needs the ``notebooks``
extra (jupytext, nbclient, nbformat, ipykernel).
"""
from __future__ import annotations

import os
from pathlib import Path

from dtcrit.errors import InputError

NOTEBOOK_DIR = Path(__file__).resolve().parents[3] / "notebooks"


def sources(directory: Path | None = None) -> list[Path]:
    directory = Path(directory or NOTEBOOK_DIR)
    return sorted(p for p in directory.glob("[0-9][0-9]_*.py"))


def render(source: Path, out_dir: Path | None = None, timeout: int = 120):
    """Execute one notebook source; write ``<out_dir>/<stem>.ipynb`` when ``out_dir`` is given."""
    try:
        import jupytext
        from nbclient import NotebookClient
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise InputError("notebooks", f"needs the 'notebooks' extra ({exc.name} is missing)") from None
    os.environ.setdefault("MPLBACKEND", "Agg")
    nb = jupytext.read(source)
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    client = NotebookClient(nb, timeout=timeout, kernel_name="python3", resources={"metadata": {"path": str(source.parent)}})
    client.execute()
    if out_dir is not None:
        import nbformat

        out_dir = Path(out_dir)
        out_dir.mkdir(parents=True, exist_ok=True)
        nbformat.write(nb, out_dir / f"{source.stem}.ipynb")
    return nb
