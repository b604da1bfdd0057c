"""Values as error messages show them: shortened, on one line, with their JSON/TOML type named."""
from __future__ import annotations

import re
from typing import Any


def short(value: Any, limit: int = 40) -> str:
    """``repr(value)`` on one line (whitespace runs become one space), cut to ``limit`` characters.

    Parameters
    ----------
    value : Any
        The value to show.
    limit : int
        The most characters returned; a longer text ends with ``...``.

    Returns
    -------
    str
        The shortened text.
    """
    text = " ".join(repr(value).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def show(value: Any, limit: int = 60) -> str:
    """A value as the engine-file readers show it: a float by ``%g``, anything else by :func:`short`.

    Parameters
    ----------
    value : Any
        The value to show.
    limit : int
        The most characters of a non-float value's text.

    Returns
    -------
    str
        The text.
    """
    if isinstance(value, float):
        return f"{value:g}"
    return short(value, limit)


def type_name(value: Any) -> str:
    """The kind of a parsed TOML/JSON value with its article: ``a number``, ``a table``, ...

    Parameters
    ----------
    value : Any
        A value as ``tomllib`` or ``json`` returns it.

    Returns
    -------
    str
        ``a boolean``, ``a string``, ``a table``, ``an array``, ``a number`` or ``a <type> value``
        (dates and times).
    """
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, (int, float)):
        return "a number"
    return f"a {type(value).__name__} value"


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def key_text(key: str) -> str:
    """A key as TOML writes it: bare when it can be, else quoted with ASCII escapes.

    Parameters
    ----------
    key : str
        A table key as read.

    Returns
    -------
    str
        The key, bare (``semi_axes``) or JSON-quoted (``"a b"``) so that messages show it safely.
    """
    if _BARE_KEY.match(key):
        return key
    import json  # only for a key that needs quotes

    return json.dumps(key)


def did_you_mean(word: str, choices, cutoff: float = 0.6) -> str:
    """The hint `` (did you mean 'x'?)`` naming the entry of ``choices`` closest to ``word``, or ``""``.

    ``difflib.get_close_matches`` with one match; ``difflib`` is imported here, only when a message
    needs it, not at every start.

    Parameters
    ----------
    word : str
        The word as given.
    choices : sequence of str
        The valid words (the hint only ever shows one of them).
    cutoff : float
        The least similarity ratio of a match, in [0, 1].

    Returns
    -------
    str
        The hint with its leading space, or an empty string when nothing is close.

    Examples
    --------
    >>> did_you_mean("velocity-verlett", ("velocity-verlet", "leapfrog"))
    " (did you mean 'velocity-verlet'?)"
    """
    import difflib

    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=cutoff)
    return f" (did you mean '{close[0]}'?)" if close else ""
