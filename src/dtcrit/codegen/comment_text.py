r"""Outside text (a scene's title, its file name, a command line) made safe for a comment of emitted code.

Every line of an emitted header passes through ``comment_lines`` (``dtcrit.codegen.render._comment``
is the one place where text enters a comment), so no title or path can end the comment or the line
and put code into the C, Fortran or NumPy output.  ``comment_safe`` returns printable ASCII in which

* every character outside printable ASCII (line terminators ``\n \r \x0b \x0c \x1c-\x1e \x85
  \u2028 \u2029``, tabs, controls, any non-ASCII letter) and the backslash itself is written as
  Python's escape ``\xHH``, ``\uHHHH`` or ``\UHHHHHHHH``: a backslash only ever starts an escape,
  so no line ends with one (C splices a line ending in ``\`` onto the next, before comments are
  removed; so does ``gfortran -cpp``);
* the C comment delimiters ``/*`` and ``*/`` never occur: the second character of such a pair is
  escaped (``*\x2f``), and so is the second ``?`` of ``??`` (a C99 trigraph, ``??/`` is a
  backslash);
* three double quotes in a row never occur (the third is escaped), nor ``coding:`` or ``coding=`` in any case
  (on the first two lines of a Python file that declares the source encoding, e.g. UTF-7, under which
  printable ASCII decodes to a newline).

In Fortran a comment runs to the end of its line, so only line terminators matter there (an ``&`` in
a comment does not continue anything).  Plain printable text without these pairs is unchanged.
"""
from __future__ import annotations

import re

WIDTH = 129
"""Longest comment line (before the language's comment prefix, at most 3 characters) left unwrapped:
Fortran allows 132 characters on a line, and every fixed header line is shorter."""

_PRINTABLE = frozenset(chr(c) for c in range(0x20, 0x7F)) - {"\\"}
_PAIRS = {("*", "/"), ("/", "*"), ("?", "?")}  # C comment delimiters, the trigraph introducer
_CODING = re.compile(r"coding$", re.IGNORECASE)
_ATOM = re.compile(r"\\(?:x[0-9a-f]{2}|u[0-9a-f]{4}|U[0-9a-f]{8})|.", re.DOTALL)


def _escape(ch: str) -> str:
    code = ord(ch)
    if code < 0x100:
        return f"\\x{code:02x}"
    return f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def comment_safe(text: str) -> str:
    """``text`` as one line of printable ASCII that cannot end a C, Fortran or Python comment.

    Escapes as described in the module docstring; any other character is kept, so the result
    reads like ``text``.

    Parameters
    ----------
    text : str
        Any text (a title, a path, a command line); converted with ``str`` first.

    Returns
    -------
    str
        The escaped text, printable ASCII on one line.
    """
    out: list[str] = []
    tail = ""  # the last characters written (escapes included), to see a forbidden pair form
    for ch in str(text):
        if ch not in _PRINTABLE:
            piece = _escape(ch)
        elif (tail[-1:], ch) in _PAIRS or (ch == '"' and tail.endswith('""')) \
                or (ch in ":=" and _CODING.search(tail)):
            piece = _escape(ch)
        else:
            piece = ch
        out.append(piece)
        tail = (tail + piece)[-8:]
    return "".join(out)


def comment_lines(text: str, width: int = WIDTH) -> list[str]:
    """``comment_safe(text)``, wrapped at spaces (or, in a longer word, between characters and whole
    escapes) into lines of at most ``width`` characters when it is longer; continuation lines are
    indented by two spaces.  The split never separates an escape's backslash from its digits.

    Parameters
    ----------
    text : str
        Any text; made safe with ``comment_safe`` first.
    width : int
        Largest number of characters of a line.

    Returns
    -------
    list of str
        The comment's lines, without the comment markers.
    """
    safe = comment_safe(text).rstrip(" ")
    if len(safe) <= width:
        return [safe]
    lines, line = [], ""
    for word in re.split(r"(?<= )", safe):  # words keep their trailing space
        if len(line) + len(word.rstrip(" ")) > width and line.strip():
            lines.append(line.rstrip(" "))
            line = "  "
        while len(line) + len(word.rstrip(" ")) > width:  # a word longer than a line: cut between atoms
            cut, used = 0, len(line)
            for atom in _ATOM.findall(word):
                if used + len(atom) > width:
                    break
                cut, used = cut + len(atom), used + len(atom)
            if cut == 0:  # the line is full (only its indent left no room): start a fresh one
                first = _ATOM.match(word)
                assert first is not None  # every character of a safe text is an atom
                cut = len(first.group())
            lines.append((line + word[:cut]).rstrip(" "))
            line, word = "  ", word[cut:]
        line += word
    if line.strip():
        lines.append(line.rstrip(" "))
    return lines


__all__ = ["WIDTH", "comment_lines", "comment_safe"]
