"""Checks of single values of a ``dtcrit-bodies/1`` file (``dtcrit.packing.readers.bodies_file``): each
problem is one ``InputError`` keyed by the file and the entry (``FILE: bodies[3].position``).
"""
from __future__ import annotations

import itertools
import math

import numpy as np

from dtcrit.errors import InputError


def _fail(where: str, reason: str) -> InputError:
    return InputError(where, reason)


def _keys(where: str, table: dict, allowed: tuple[str, ...]) -> None:
    for key in table:
        if key not in allowed:
            raise _fail(f"{where}.{key}" if where else str(key),
                        f"unknown key; valid keys here: {', '.join(allowed)}")


def _finite_number(v) -> bool:
    """A JSON number (not a boolean) that is finite as a double (a 400-digit integer is not)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool) and (
        math.isfinite(v) if isinstance(v, float) else abs(v) < 2**1000)


def _numbers(where: str, value, size: int) -> np.ndarray:
    ok = isinstance(value, list) and len(value) == size and all(_finite_number(v) for v in value)
    if not ok:
        raise _fail(where, f"expected an array of {size} finite numbers, found {_short(value)}")
    return np.array(value, dtype=float)


def _short(value, limit: int = 60) -> str:
    text = " ".join(repr(value).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _integer(where: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or abs(value) >= 2**63:
        raise _fail(where, f"expected an integer id, found {_short(value)}")
    return value


def _stiffness(where: str, value) -> float:
    if not _finite_number(value) or value < 0:
        raise _fail(where, f"expected a finite stiffness >= 0 [N/m], found {_short(value)}")
    return float(value) + 0.0  # -0.0 is 0


def _sphere_table(table):
    """``(radius, density, mass)`` (NaN for the one not given) of a plain sphere table -- ``shape``
    ``"sphere"``, a ``radius`` and one of ``density`` or ``mass``, each a JSON number -- else None:
    then the scenes' parser reads the table and names what is wrong with it.
    """
    if type(table) is not dict or len(table) != 3 or table.get("shape") != "sphere" or "radius" not in table:
        return None
    if "density" in table:
        values = (table["radius"], table["density"], math.nan)
    elif "mass" in table:
        values = (table["radius"], math.nan, table["mass"])
    else:
        return None
    for v in values[:2] if values[2] != values[2] else values[::2]:
        if type(v) is not float and not (type(v) is int and abs(v) < 2**1000):
            return None
    return values


def _array(path, name: str, values: list, size: int, default=None) -> np.ndarray:
    """``bodies[k].<name>`` of every body as an ``(n, size)`` array of finite numbers (``default``
    where absent); the first entry that is not one is named by ``_numbers``.
    """
    rows = [default if v is None else v for v in values]
    out = None
    try:
        out = np.array(rows, dtype=float)
        ok = (out.shape == (len(rows), size) and bool(np.isfinite(out).all())
              and set(map(type, itertools.chain.from_iterable(rows))) <= {float, int})
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        for k, row in enumerate(rows):
            _numbers(f"{path}: bodies[{k}].{name}", row, size)
    return out
