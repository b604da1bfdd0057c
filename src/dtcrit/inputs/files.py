"""Reading input files: bounded reads, UTF-8 lines numbered from 1, and errors located in a file.

A reader names the file in every error: :func:`located_in` turns the errors its body raises with a
key of the form ``FILE:LINE`` or ``FILE: entry`` into ones whose :class:`dtcrit.errors.Location`
holds the source, line and key apart (the message text is unchanged).
"""
from __future__ import annotations

import re
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from dtcrit.errors import InputError, Location

if TYPE_CHECKING:  # pathlib is not imported at run time: a path is opened as given (start-up)
    from pathlib import Path


def read_bounded(path: str | Path, limit: int) -> bytes:
    """At most ``limit + 1`` bytes of a file: more than ``limit`` tells the caller the file is too
    large without reading all of it (``/dev/zero`` is not an input file).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    limit : int
        The largest size [bytes] the caller accepts.

    Returns
    -------
    bytes
        The file's first ``limit + 1`` bytes (all of it when shorter).

    Raises
    ------
    OSError
        The file cannot be read.
    ValueError
        The path contains a NUL character.
    """
    with open(path, "rb") as handle:
        return handle.read(limit + 1)


def line_of(data: bytes, offset: int) -> int:
    """The 1-based line of byte ``offset`` in ``data`` (a newline ends a line).

    Parameters
    ----------
    data : bytes
        The file's content.
    offset : int
        A byte offset into ``data``.

    Returns
    -------
    int
        The line number.
    """
    return data[:offset].count(b"\n") + 1


def text_lines(path: str | Path) -> list[str]:
    """A text file's lines, each decoded as UTF-8: a newline ends one, a trailing carriage return and a leading
    byte-order mark are dropped; a byte that is not UTF-8 is an error located at its line.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    list of str
        The lines, without their ends.
    """
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as exc:
        raise InputError(None, f"cannot read: {exc.strerror or exc}", source=path) from None
    lines = []
    for n, raw in enumerate(data.removeprefix(b"\xef\xbb\xbf").split(b"\n")):
        try:
            lines.append(raw.decode("utf-8").rstrip("\r"))
        except UnicodeDecodeError as exc:
            raise InputError(None, f"byte {exc.start + 1} of the line is not UTF-8: not a text file",
                             source=path, line=n + 1) from None
    return lines


def relocate(exc: InputError, source: str | Path) -> InputError:
    """``exc`` with its location split into source, line and key when its key names ``source``.

    A key ``FILE`` becomes ``Location(FILE)``, ``FILE:7`` becomes ``Location(FILE, 7)`` and
    ``FILE: bodies[3].id`` becomes ``Location(FILE, key="bodies[3].id")``; an error already located,
    or keyed otherwise (a flag, a library key), is returned as it is.

    Parameters
    ----------
    exc : InputError
        The error raised while reading ``source``.
    source : str or pathlib.Path
        The file read.

    Returns
    -------
    InputError
        An error with the same message and a structured location.
    """
    name = str(source)
    where = exc.location
    if where.source is not None or where.line is not None or where.key is None or not where.key.startswith(name):
        return exc
    rest = where.key[len(name):]
    if not rest:
        return InputError.at(Location(name), exc.reason)
    found = re.fullmatch(r":(\d+)(?:: (.+))?", rest, re.S)
    if found:
        return InputError.at(Location(name, int(found.group(1)), found.group(2)), exc.reason)
    if rest.startswith(": "):
        return InputError.at(Location(name, None, rest[2:]), exc.reason)
    return exc


@contextmanager
def located_in(source: str | Path) -> Iterator[None]:
    """Re-raise the ``InputError`` of the body located in ``source`` (:func:`relocate`).

    Parameters
    ----------
    source : str or pathlib.Path
        The file the body reads.

    Yields
    ------
    None
        Nothing: the body runs inside the context.
    """
    try:
        yield
    except InputError as exc:
        moved = relocate(exc, source)
        if moved is exc:
            raise
        raise moved from None
