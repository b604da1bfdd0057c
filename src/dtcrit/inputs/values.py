"""Checks of single values: finite numbers (positive, bounded), strings, choices and integer ids.

Two message styles exist and are kept: the scene style (``must be a number (got a string: 'x')``,
:func:`number`, :func:`string`, :func:`choice`) and the engine-file style (``expected a finite number,
found 'x'``, :func:`finite`, :func:`whole`, :func:`integer_id`, :func:`stiffness`).
"""
from __future__ import annotations

import math
from typing import Any, Literal, overload

from dtcrit.errors import InputError
from dtcrit.inputs.text import did_you_mean, short, show, type_name


def number(key: str, value: Any, *, allow_zero: bool = False, lo: float | None = None, hi: float | None = None,
           hi_open: bool = False) -> float:
    """A finite number: positive (or non-negative), or above ``lo``; at most (below) ``hi``.

    Parameters
    ----------
    key : str
        The value's key, named in the error.
    value : Any
        The value as read (a bool is not a number).
    allow_zero : bool
        Accept zero (non-negative instead of positive); ignored when ``lo`` is given.
    lo : float or None
        Exclusive lower bound replacing the sign check.
    hi : float or None
        Upper bound, inclusive unless ``hi_open``.
    hi_open : bool
        Make ``hi`` exclusive.

    Returns
    -------
    float
        The value as a float.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(key, f"must be a number (got {type_name(value)}: {short(value)})")
    try:
        x = float(value)
    except OverflowError:
        raise InputError(key, f"must be a finite number (got an integer with {len(str(value))} digits)") from None
    if not math.isfinite(x):
        raise InputError(key, f"must be finite (got {x})")
    if lo is None:
        if x < 0 or (x == 0 and not allow_zero):
            raise InputError(key, f"must be {'non-negative' if allow_zero else 'positive'} (got {x:g})")
    elif x <= lo:
        raise InputError(key, f"must be greater than {lo:g} (got {x:g})")
    if hi is not None and (x > hi or (hi_open and x == hi)):
        raise InputError(key, f"must be {'less than' if hi_open else 'at most'} {hi:g} (got {x:g})")
    return x


def string(key: str, value: Any) -> str:
    """A string.

    Parameters
    ----------
    key : str
        The value's key, named in the error.
    value : Any
        The value as read.

    Returns
    -------
    str
        The value.
    """
    if not isinstance(value, str):
        raise InputError(key, f"must be a string (got {type_name(value)}: {short(value)})")
    return value


def choice(key: str, value: Any, choices: tuple[str, ...], what: str) -> str:
    """One of ``choices`` (matched as given, then in lower case); an unknown one names the nearest.

    Parameters
    ----------
    key : str
        The value's key, named in the error.
    value : Any
        The value as read.
    choices : tuple of str
        The accepted values, in lower case.
    what : str
        What the value chooses (``"shape"``, ``"contact model"``), for the message.

    Returns
    -------
    str
        The chosen entry of ``choices``.
    """
    text = string(key, value)
    if text in choices:
        return text
    if text.lower() in choices:
        return text.lower()
    hint = did_you_mean(text.lower(), choices, 0.5)
    raise InputError(key, f"unknown {what} {short(text)}{hint}; choose one of {', '.join(choices)}")


def is_finite_number(value: Any) -> bool:
    """Whether ``value`` is a JSON number (not a boolean) finite as a double (a 400-digit integer is not).

    Parameters
    ----------
    value : Any
        The value as read.

    Returns
    -------
    bool
        True for a finite float or an integer of magnitude below ``2**1000``.
    """
    return isinstance(value, (int, float)) and not isinstance(value, bool) and (
        math.isfinite(value) if isinstance(value, float) else abs(value) < 2**1000)


@overload
def finite(where: str, value: Any, *, positive: bool = ..., allow_none: Literal[False] = ...,
           signed: bool = ...) -> float: ...
@overload
def finite(where: str, value: Any, *, positive: bool = ..., allow_none: bool = ..., signed: bool = ...) -> float | None: ...


def finite(where: str, value: Any, *, positive: bool = False, allow_none: bool = False,
           signed: bool = False) -> float | None:
    """A finite number of an engine file: ``>= 0`` (``> 0`` when ``positive``, any sign when ``signed``).

    Parameters
    ----------
    where : str
        The value's location, named in the error (``FILE: bodies[3].mass``).
    value : Any
        The value as read.
    positive : bool
        Refuse zero.
    allow_none : bool
        Accept an absent value (``None``), returned as ``None``.
    signed : bool
        Accept negative values.

    Returns
    -------
    float or None
        The value as a float (``-0.0`` becomes ``0.0``), or None when absent and allowed.
    """
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(where, f"expected a finite number, found {show(value)}")
    try:
        x = float(value)
    except OverflowError:
        raise InputError(where, f"expected a finite number, found an integer of {len(str(value))} digits") from None
    if not math.isfinite(x):
        raise InputError(where, f"expected a finite number, found {show(x)}")
    if not signed and (x < 0 or (positive and x == 0)):
        raise InputError(where, f"must be {'positive' if positive else '>= 0'}, found {show(x)}")
    return x + 0.0  # -0.0 is 0


def whole(where: str, value: Any) -> int:
    """An engine id: a whole number within 64 bits (a float with an integer value is accepted).

    Parameters
    ----------
    where : str
        The value's location, named in the error.
    value : Any
        The value as read.

    Returns
    -------
    int
        The id.
    """
    if isinstance(value, float) and math.isfinite(value) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int) or abs(value) >= 2**63:
        raise InputError(where, f"expected an integer id, found {show(value)}")
    return value


def integer_id(where: str, value: Any) -> int:
    """A body id of a JSON file: an integer (not a float, not a boolean) within 64 bits.

    Parameters
    ----------
    where : str
        The value's location, named in the error.
    value : Any
        The value as read.

    Returns
    -------
    int
        The id.
    """
    if isinstance(value, bool) or not isinstance(value, int) or abs(value) >= 2**63:
        raise InputError(where, f"expected an integer id, found {short(value, 60)}")
    return value


def stiffness(where: str, value: Any) -> float:
    """A spring stiffness [N/m] of a JSON file: a finite number ``>= 0``.

    Parameters
    ----------
    where : str
        The value's location, named in the error.
    value : Any
        The value as read.

    Returns
    -------
    float
        The stiffness (``-0.0`` becomes ``0.0``).
    """
    if not is_finite_number(value) or value < 0:
        raise InputError(where, f"expected a finite stiffness >= 0 [N/m], found {short(value, 60)}")
    return float(value) + 0.0  # -0.0 is 0


def boolean(key: str, value: Any) -> bool:
    """``true`` or ``false``.

    Parameters
    ----------
    key : str
        The value's key, named in the error.
    value : Any
        The value as read.

    Returns
    -------
    bool
        The value.
    """
    if not isinstance(value, bool):
        raise InputError(key, f"must be true or false (got {short(value)})")
    return value
