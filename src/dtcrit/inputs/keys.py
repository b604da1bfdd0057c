"""Checks of a table's keys: unknown keys (naming the nearest valid one) and missing keys, each a
one-line message naming the key.
"""
from __future__ import annotations

from typing import Any

from dtcrit.errors import InputError
from dtcrit.inputs.text import did_you_mean, key_text


def check_keys(prefix: str, table: dict, allowed: tuple[str, ...], vocabulary: tuple[str, ...], where: str,
               top_level: tuple[str, ...] = ()) -> None:
    """Refuse the first key of ``table`` outside ``allowed``, suggesting the nearest allowed key.

    Parameters
    ----------
    prefix : str
        The table's path with its trailing dot (``particle[2].``), empty at the top level.
    table : dict
        The table as read.
    allowed : tuple of str
        The keys accepted here.
    vocabulary : tuple of str
        Keys valid elsewhere in the format: one of them is "not used" here rather than unknown.
    where : str
        Where the keys are read (``"by a sphere"``), for the message.
    top_level : tuple of str
        Keys that belong at the top of a TOML document: found in a table, the message says that
        every key after a ``[table]`` header belongs to that table.
    """
    for key in table:
        if key in allowed:
            continue
        path = f"{prefix}{key_text(key)}"
        if key in vocabulary:
            raise InputError(path, f"not used {where}; valid keys here: {', '.join(allowed)}")
        hint = did_you_mean(str(key), allowed) or did_you_mean(str(key).lower(), allowed, 0.5)
        if prefix and key in top_level:
            hint = (f" ('{key}' is a top-level key: in TOML every key after a [table] header belongs to that table, "
                    "so write top-level keys before the first table)")
        raise InputError(path, f"unknown key{hint}; valid keys here: {', '.join(allowed)}")


def required(prefix: str, table: dict, key: str, what: str) -> Any:
    """The value of ``key`` in ``table``; missing, an error ``prefix+key: missing: what``.

    Parameters
    ----------
    prefix : str
        The table's path with its trailing dot, empty at the top level.
    table : dict
        The table as read.
    key : str
        The key required.
    what : str
        What the key gives, for the message.

    Returns
    -------
    Any
        The value as read.
    """
    if key not in table:
        raise InputError(f"{prefix}{key}", f"missing: {what}")
    return table[key]


def known_keys(where: str, table: dict, allowed: tuple[str, ...]) -> None:
    """Refuse the first key of a JSON object outside ``allowed`` (engine-file style, no suggestion).

    Parameters
    ----------
    where : str
        The object's location (``FILE: bodies[3]``); the key is appended as ``where.key``.
    table : dict
        The object as read.
    allowed : tuple of str
        The keys accepted.
    """
    for key in table:
        if key not in allowed:
            raise InputError(f"{where}.{key}" if where else str(key), f"unknown key; valid keys here: {', '.join(allowed)}")
