"""Checks of single values of a ``dtcrit-bodies/1`` file (``dtcrit.packing.readers.bodies_file``) under
the names that reader uses: each is the one check of :mod:`dtcrit.inputs`, and each problem is one
``InputError`` keyed by the file and the entry (``FILE: bodies[3].position``).
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from dtcrit.errors import InputError
from dtcrit.inputs.arrays import numbers as _numbers
from dtcrit.inputs.arrays import rows
from dtcrit.inputs.keys import known_keys as _keys
from dtcrit.inputs.text import short
from dtcrit.inputs.values import integer_id as _integer
from dtcrit.inputs.values import stiffness as _stiffness

__all__ = ["_array", "_fail", "_integer", "_keys", "_numbers", "_short", "_sphere_table", "_stiffness"]


def _fail(where: str, reason: str) -> InputError:
    return InputError(where, reason)


def _short(value: Any, limit: int = 60) -> str:
    return short(value, limit)


def _sphere_table(table):
    """``(radius, density, mass)`` (NaN for the one not given) of a plain sphere table -- ``shape``
    ``"sphere"``, a ``radius`` and one of ``density`` or ``mass``, each a JSON number -- else None:
    then the shape parser (``dtcrit.bodies.spec.shape_from_table``) reads the table and names what is
    wrong with it.
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
    where absent); the first entry that is not one is named (``dtcrit.inputs.arrays.rows``).
    """
    return rows(lambda k: f"{path}: bodies[{k}].{name}", values, size, default)
