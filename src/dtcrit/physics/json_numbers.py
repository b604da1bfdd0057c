"""Numbers for JSON documents: a non-finite float (inf, nan) is written as ``null``.

``json.dumps`` would write ``Infinity``/``NaN`` (not JSON) or refuse them (``allow_nan=False``);
every dtcrit document instead writes ``null`` where a quantity does not exist (no stable step, no
mode).  One home for that rule, used by ``dtcrit step``, ``dtcrit packing`` and ``dtcrit audit``.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["finite_or_none", "json_safe"]


def finite_or_none(x: Any) -> float | None:
    """``float(x)``, or None when ``x`` is None or not finite.

    Parameters
    ----------
    x : float, numpy.floating or None
        A number for a JSON document.

    Returns
    -------
    float or None
        The number, or None (JSON ``null``) for None, inf and nan.
    """
    if x is None:
        return None
    value = float(x)
    return value if math.isfinite(value) else None


def json_safe(value: Any) -> Any:
    """``value`` with every float made finite or None and NumPy scalars made Python ones, recursively.

    Parameters
    ----------
    value : Any
        A dict, list, tuple or scalar (NumPy scalars included).

    Returns
    -------
    Any
        The same structure (tuples become lists) ready for ``json.dumps``.
    """
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return finite_or_none(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value
