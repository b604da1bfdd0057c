"""Number, formula and verdict text shared by the derivation records.

Every record prints its numbers through :func:`num` (Python's ``g`` format, so the text does not depend
on the type that carries the value), its SymPy expressions through :func:`latex`, and the comparison of
a printed entry with the derived one through :func:`entry_verdict`.
"""
from __future__ import annotations

import math

import sympy as sp


def num(x, digits: int = 6) -> str:
    """A number as text, to ``digits`` significant digits (``format(float(x), ".{digits}g")``).

    Parameters
    ----------
    x : float, int, numpy scalar, mpmath or SymPy real, or None
        The value; None is printed as ``-`` (no value), NaN as ``n/a``, an infinity as ``inf``/``-inf``.
    digits : int
        Significant digits.

    Returns
    -------
    str
        The text.
    """
    if x is None:
        return "-"
    x = float(x)
    if math.isnan(x):
        return "n/a"
    return f"{x:.{digits}g}"


def latex(e) -> str:
    """A SymPy expression as LaTeX, products written by juxtaposition (``sp.latex(e, mul_symbol=None)``).

    Parameters
    ----------
    e : sympy.Basic
        The expression.

    Returns
    -------
    str
        Its LaTeX text.
    """
    return sp.latex(e, mul_symbol=None)


def entry_verdict(k) -> str:
    """The verdict on a printed matrix entry against the derived one.

    Parameters
    ----------
    k : int or None
        The index of the first reading that matches the derived entry (>= 0), a negative number when
        none does, None when the printed entry cannot be read.

    Returns
    -------
    str
        ``**reproduced**``, ``**differs**`` or ``illegible``.
    """
    if k is None:
        return "illegible"
    return "**reproduced**" if k >= 0 else "**differs**"
