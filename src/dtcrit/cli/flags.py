"""Numeric command-line flags: one argparse type for all of them.

``number(...)`` gives the ``type=`` of a flag that takes an integer or a float with a lower bound
(and optionally an upper one): zero, a negative value, NaN, an infinity or text that is no number is
refused while the command line is parsed, in one line naming the flag
(``dtcrit notebooks: argument --timeout: must be a positive number of seconds (got '0')``), exit
status 2, before any work starts.  ``flag_errors`` reports a library's refusal of a flag's value
(``InputError('zeta', ...)``) under the flag's name (``--zeta: ...``).
"""
from __future__ import annotations

import argparse
import contextlib
import math

from dtcrit.errors import InputError


def number(kind: type = float, *, positive: bool = True, maximum: float | None = None, what: str = "number"):
    """An argparse ``type`` for a numeric flag, checked while the command line is parsed.

    Parameters
    ----------
    kind : type
        ``int`` or ``float``.
    positive : bool
        Above zero (True) or at least zero (False).
    maximum : float, optional
        The largest value allowed.
    what : str
        What the value is, for the message (``"number of seconds"``).

    Returns
    -------
    callable
        ``convert(text) -> kind``, raising ``argparse.ArgumentTypeError`` for NaN, an infinity, a
        value out of range or text that is no number.
    """
    adjective = "positive" if positive else "non-negative"
    bound = "" if maximum is None else f", at most {maximum}" if isinstance(maximum, int) else f", at most {maximum:g}"
    message = f"must be a {adjective} {'whole ' if kind is int and what == 'number' else ''}{what}{bound}"

    def convert(text: str):
        try:
            value = kind(text)
        except (TypeError, ValueError, OverflowError):
            value = None
        if value is None or (isinstance(value, float) and not math.isfinite(value)) or value < 0 \
                or (positive and value == 0) or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"{message} (got {text!r:.40})")
        return value

    convert.__name__ = f"{adjective} {kind.__name__}"
    return convert


@contextlib.contextmanager
def flag_errors(flags: dict[str, str]):
    """Re-raise an ``InputError`` whose key is in ``flags`` as ``--flag: reason``.

    Parameters
    ----------
    flags : dict of str to str
        Library key -> the flag that sets it.

    Yields
    ------
    None
        Runs the block inside.
    """
    try:
        yield
    except InputError as exc:
        if exc.key not in flags:
            raise
        raise InputError(flags[exc.key], exc.reason) from None


__all__ = ["flag_errors", "number"]
