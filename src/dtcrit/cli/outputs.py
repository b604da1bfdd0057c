"""Check, before any work starts, that a command can write where it was told to (``--out``,
``--write-dump``): one line and exit 2 instead of a traceback after minutes of work.  Nothing is
created: the nearest existing folder on the path must be a folder that accepts a file.
"""
from __future__ import annotations

import tempfile
from pathlib import Path

from dtcrit.errors import InputError


def _nearest_existing(path: Path) -> Path:
    p = path
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


def _accepts_files(folder: Path, flag: str, target: Path) -> None:
    if not folder.is_dir():
        raise InputError(flag, f"cannot write {target}: {folder} is not a folder")
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise InputError(flag, f"cannot write into {folder}: {exc.strerror or exc}") from None


def _path(path, flag: str) -> Path:
    text = str(path)
    if not text:
        raise InputError(flag, "empty path")
    if "\x00" in text:
        raise InputError(flag, "the path contains a NUL character")
    return Path(text)


def check_output_dir(path, flag: str = "--out") -> Path:
    """Check that ``path`` is, or can become, a folder we can write into (nothing is created).

    Parameters
    ----------
    path : str or os.PathLike
        The folder as given.
    flag : str
        The flag that gave it, for the message.

    Returns
    -------
    pathlib.Path
        The path.
    """
    p = _path(path, flag)
    try:
        if p.exists() and not p.is_dir():
            raise InputError(flag, f"{p} exists and is not a folder")
        _accepts_files(_nearest_existing(p), flag, p)
    except OSError as exc:  # a name too long, a loop of links, ...
        raise InputError(flag, f"cannot write {_short(p)}: {exc.strerror or exc}") from None
    return p


def check_output_file(path, flag: str) -> Path:
    """Check that ``path`` can be written as a file (its folder exists or can be made, and accepts files).

    Parameters
    ----------
    path : str or os.PathLike
        The file as given.
    flag : str
        The flag that gave it, for the message.

    Returns
    -------
    pathlib.Path
        The path.
    """
    p = _path(path, flag)
    try:
        if p.is_dir():
            raise InputError(flag, f"{p} is a folder, not a file")
        _accepts_files(_nearest_existing(p.parent), flag, p)
    except OSError as exc:
        raise InputError(flag, f"cannot write {_short(p)}: {exc.strerror or exc}") from None
    return p


def _short(p: Path, limit: int = 80) -> str:
    text = str(p)
    return text if len(text) <= limit else text[: limit - 3] + "..."
