"""Checks of arrays: vectors of numbers, rows of fixed width, vertex and sphere lists, and the
``(n, size)`` arrays of engine files.  Entries of scene arrays are counted from 1 in messages
(``semi_axes[2]``), entries of engine files from 0, as JSON does (``pos[0]``).
"""
from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np

from dtcrit.errors import InputError
from dtcrit.inputs.text import short, show, type_name
from dtcrit.inputs.values import finite, is_finite_number, number


def vector(key: str, value: Any, length: int) -> list[float]:
    """An array of ``length`` positive finite numbers (:func:`dtcrit.inputs.values.number`).

    Parameters
    ----------
    key : str
        The array's key; entry ``n`` is named ``key[n]`` counted from 1.
    value : Any
        The value as read.
    length : int
        The number of entries required.

    Returns
    -------
    list of float
        The entries.
    """
    if not isinstance(value, list):
        raise InputError(key, f"must be an array of {length} numbers (got {type_name(value)}: {short(value)})")
    if len(value) != length:
        raise InputError(key, f"must have {length} entries (got {len(value)})")
    return [number(f"{key}[{n + 1}]", v) for n, v in enumerate(value)]


def finite_row(key: str, row: Any, form: str) -> list[float]:
    """A row of finite numbers of any sign, as many as ``form`` names (``"[x, y, z]"``).

    Parameters
    ----------
    key : str
        The row's key; entry ``m`` is named ``key[m]`` counted from 1.
    row : Any
        The value as read.
    form : str
        The row's form as messages show it; its width is its number of commas plus one.

    Returns
    -------
    list of float
        The entries.
    """
    width = form.count(",") + 1
    if not isinstance(row, list) or len(row) != width:
        raise InputError(key, f"must be an {form} array of {width} numbers (got {short(row)})")
    nums = []
    for m, v in enumerate(row):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InputError(f"{key}[{m + 1}]", f"must be a number (got {type_name(v)}: {short(v)})")
        try:
            x = float(v)
        except OverflowError:
            raise InputError(f"{key}[{m + 1}]", "must be a finite number") from None
        if not math.isfinite(x):
            raise InputError(f"{key}[{m + 1}]", f"must be finite (got {x})")
        nums.append(x)
    return nums


def vertices(key: str, value: Any) -> list[list[float]]:
    """At least 4 points ``[x, y, z]`` of finite coordinates (a convex polyhedron's vertices).

    Parameters
    ----------
    key : str
        The list's key; point ``n`` is named ``key[n]`` counted from 1.
    value : Any
        The value as read.

    Returns
    -------
    list of list of float
        The points.
    """
    if not isinstance(value, list) or not value:
        raise InputError(key, f"must be an array of [x, y, z] points (got {type_name(value)}: {short(value)})")
    if len(value) < 4:
        raise InputError(key, f"needs at least 4 points (got {len(value)})")
    return [finite_row(f"{key}[{n + 1}]", point, "[x, y, z]") for n, point in enumerate(value)]


def clump_spheres(key: str, value: Any) -> list[list[float]]:
    """At least one sphere ``[x, y, z, r]``: finite coordinates and a positive radius.

    Parameters
    ----------
    key : str
        The list's key; sphere ``n`` is named ``key[n]`` counted from 1.
    value : Any
        The value as read.

    Returns
    -------
    list of list of float
        The spheres' rows.
    """
    if not isinstance(value, list) or not value:
        raise InputError(key, f"a clump needs at least one sphere [x, y, z, r] (got {type_name(value)}: {short(value)})")
    out = []
    for n, row in enumerate(value):
        k = f"{key}[{n + 1}]"
        nums = finite_row(k, row, "[x, y, z, r]")
        if nums[3] <= 0:
            raise InputError(f"{k}[4]", f"the radius must be positive (got {nums[3]:g})")
        out.append(nums)
    return out


def numbers(where: str, value: Any, size: int) -> np.ndarray:
    """An array of ``size`` finite numbers of a JSON file (:func:`dtcrit.inputs.values.is_finite_number`).

    Parameters
    ----------
    where : str
        The array's location, named in the error.
    value : Any
        The value as read.
    size : int
        The number of entries required.

    Returns
    -------
    numpy.ndarray
        The entries as floats, shape ``(size,)``.
    """
    ok = isinstance(value, list) and len(value) == size and all(is_finite_number(v) for v in value)
    if not ok:
        raise InputError(where, f"expected an array of {size} finite numbers, found {short(value, 60)}")
    return np.array(value, dtype=float)


def triple(where: str, value: Any, size: int = 3, positive: bool = False) -> np.ndarray:
    """``size`` finite numbers of an engine file, of any sign (``positive``: each ``> 0``).

    Parameters
    ----------
    where : str
        The array's location; entry ``a`` is named ``where[a]`` counted from 0.
    value : Any
        The value as read.
    size : int
        The number of entries required.
    positive : bool
        Require every entry to be positive.

    Returns
    -------
    numpy.ndarray
        The entries as floats, shape ``(size,)``.
    """
    if not isinstance(value, list) or len(value) != size:
        raise InputError(where, f"expected {size} finite numbers, found {show(value)}")
    return np.array([finite(f"{where}[{a}]", v, positive=positive, signed=not positive) for a, v in enumerate(value)])


def rows(where_of, values: list, size: int, default: Any = None) -> np.ndarray:
    """Rows of ``size`` finite numbers, one per entry of ``values`` (``default`` where None), checked
    all at once; the first bad row is named by :func:`numbers` with ``where_of(k)``.

    Parameters
    ----------
    where_of : callable
        ``where_of(k)`` locates row ``k`` (``FILE: bodies[k].position``).
    values : list
        The rows as read.
    size : int
        The width of every row.
    default : Any
        The row used for an absent (None) entry.

    Returns
    -------
    numpy.ndarray
        The rows as floats, shape ``(len(values), size)``.
    """
    given = [default if v is None else v for v in values]
    out = None
    try:
        out = np.array(given, dtype=float)
        ok = (out.shape == (len(given), size) and bool(np.isfinite(out).all())
              and set(map(type, itertools.chain.from_iterable(given))) <= {float, int})
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok or out is None:
        for k, row in enumerate(given):
            numbers(where_of(k), row, size)
    assert out is not None  # every row passed ``numbers``: the array was built
    return out


def booleans(where: str, value: Any, size: int) -> tuple[bool, ...]:
    """An array of ``size`` JSON booleans.

    Parameters
    ----------
    where : str
        The array's location, named in the error.
    value : Any
        The value as read.
    size : int
        The number of entries required.

    Returns
    -------
    tuple of bool
        The entries.
    """
    if not (isinstance(value, list) and len(value) == size and all(isinstance(p, bool) for p in value)):
        raise InputError(where, f"expected {'three' if size == 3 else size} booleans, found {short(value, 60)}")
    return tuple(value)
