"""Render the teaching notebooks: jupytext percent-format sources -> executed ``.ipynb``.

The sources live in ``notebooks/*.py`` (no outputs committed).  ``render`` converts each with
jupytext, executes it with nbclient and writes the executed notebook.  The kernel draws with
matplotlib's inline backend (``MPLBACKEND=module://matplotlib_inline.backend_inline``, whatever the
calling process uses), so every figure a cell makes is kept in the notebook as a PNG output.  On
POSIX the kernel talks over local IPC sockets in a private temporary folder rather than TCP.  A cell
whose assertion fails makes the render fail.  Needs the ``notebooks`` extra (jupytext, nbclient,
nbformat, ipykernel).
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

from dtcrit.errors import InputError

NOTEBOOK_DIR = Path(__file__).resolve().parents[3] / "notebooks"
INLINE_BACKEND = "module://matplotlib_inline.backend_inline"


def sources(directory: Path | None = None) -> list[Path]:
    """The notebook sources, ``NN_name.py`` files in jupytext percent format, in their numbered order.

    Parameters
    ----------
    directory : pathlib.Path, optional
        Folder to list; the repository's ``notebooks/`` when omitted.

    Returns
    -------
    list of pathlib.Path
        The sources, sorted by name (so by their two-digit number).
    """
    directory = Path(directory or NOTEBOOK_DIR)
    return sorted(p for p in directory.glob("[0-9][0-9]_*.py"))


def kernel_env() -> dict[str, str]:
    """The environment of the notebook kernel: this process's, with the inline matplotlib backend.

    Returns
    -------
    dict of str to str
        A copy of ``os.environ`` with ``MPLBACKEND`` set to ``INLINE_BACKEND``.
    """
    env = dict(os.environ)
    env["MPLBACKEND"] = INLINE_BACKEND
    return env


def render(source: Path, out_dir: Path | None = None, timeout: int = 120):
    """Execute one notebook source; write ``<out_dir>/<stem>.ipynb`` when ``out_dir`` is given.

    Parameters
    ----------
    source : pathlib.Path
        The jupytext percent-format source (``notebooks/NN_name.py``); it runs in its own folder.
    out_dir : pathlib.Path, optional
        Folder for the executed notebook (created if needed); nothing is written when omitted.
    timeout : int
        Seconds each cell may run before nbclient stops the notebook.

    Returns
    -------
    nbformat.NotebookNode
        The executed notebook, with every cell's outputs (figures as PNG).

    Raises
    ------
    InputError
        When the ``notebooks`` extra is not installed.
    """
    try:
        import jupytext
        from nbclient import NotebookClient
        from traitlets.config import Config
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise InputError("notebooks", f"needs the 'notebooks' extra ({exc.name} is missing)") from None
    source = Path(source)
    nb = jupytext.read(source)
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    with tempfile.TemporaryDirectory(prefix="dtcrit-nb-") as sockets:
        config = Config()
        if os.name == "posix":
            config.KernelManager.transport = "ipc"
            config.KernelManager.ip = os.path.join(sockets, "kernel")
        client = NotebookClient(nb, timeout=timeout, kernel_name="python3", config=config,
                                resources={"metadata": {"path": str(source.parent)}})
        client.execute(env=kernel_env())
    if out_dir is not None:
        import nbformat

        out_dir = Path(out_dir)
        out_dir.mkdir(parents=True, exist_ok=True)
        nbformat.write(nb, out_dir / f"{source.stem}.ipynb")
    return nb
