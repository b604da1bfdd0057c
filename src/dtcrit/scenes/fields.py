"""Checks of single scene values: numbers, strings, choices, vectors and vertex lists, and the keys of a
table (unknown keys name the nearest valid key).  Each problem is one :class:`dtcrit.errors.InputError`
whose key is the path of the value (``contact.kn``, ``particle[2].semi_axes``).
"""
from __future__ import annotations

import difflib
import json
import math
import re
from typing import Any

from dtcrit.errors import InputError


# ----------------------------------------------------------------------------------------------
# Value checks: each names its key
# ----------------------------------------------------------------------------------------------
def _type_name(value: Any) -> str:
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
    return f"a {type(value).__name__} value"  # dates and times


def _number(key: str, value: Any, *, allow_zero: bool = False, lo: float | None = None, hi: float | None = None,
            hi_open: bool = False) -> float:
    """A finite number; positive (or non-negative), optionally within [lo, hi] / [lo, hi)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(key, f"must be a number (got {_type_name(value)}: {_short(value)})")
    try:
        x = float(value)
    except OverflowError:
        raise InputError(key, f"must be a finite number (got an integer with {len(str(value))} digits)") from None
    if not math.isfinite(x):
        raise InputError(key, f"must be finite (got {x})")
    if lo is None:
        if x < 0 or (x == 0 and not allow_zero):
            raise InputError(key, f"must be {'non-negative' if allow_zero else 'positive'} (got {x:g})")
    else:
        if x <= lo:
            raise InputError(key, f"must be greater than {lo:g} (got {x:g})")
    if hi is not None and (x > hi or (hi_open and x == hi)):
        raise InputError(key, f"must be {'less than' if hi_open else 'at most'} {hi:g} (got {x:g})")
    return x


def _string(key: str, value: Any) -> str:
    if not isinstance(value, str):
        raise InputError(key, f"must be a string (got {_type_name(value)}: {_short(value)})")
    return value


def _choice(key: str, value: Any, choices: tuple[str, ...], what: str) -> str:
    text = _string(key, value)
    if text in choices:
        return text
    if text.lower() in choices:
        return text.lower()
    close = difflib.get_close_matches(text.lower(), choices, n=1, cutoff=0.5)
    hint = f" (did you mean '{close[0]}'?)" if close else ""
    raise InputError(key, f"unknown {what} {_short(text)}{hint}; choose one of {', '.join(choices)}")


def _vector(key: str, value: Any, length: int) -> list[float]:
    if not isinstance(value, list):
        raise InputError(key, f"must be an array of {length} numbers (got {_type_name(value)}: {_short(value)})")
    if len(value) != length:
        raise InputError(key, f"must have {length} entries (got {len(value)})")
    return [_number(f"{key}[{n + 1}]", v) for n, v in enumerate(value)]


def _vertices(key: str, value: Any) -> list[list[float]]:
    if not isinstance(value, list) or not value:
        raise InputError(key, f"must be an array of [x, y, z] points (got {_type_name(value)}: {_short(value)})")
    if len(value) < 4:
        raise InputError(key, f"needs at least 4 points (got {len(value)})")
    return [_finite_row(f"{key}[{n + 1}]", point, "[x, y, z]") for n, point in enumerate(value)]


def _finite_row(key: str, row: Any, form: str) -> list[float]:
    """A row of ``len(form)`` finite numbers (``form`` such as ``"[x, y, z]"``; entries counted from 1)."""
    width = form.count(",") + 1
    if not isinstance(row, list) or len(row) != width:
        raise InputError(key, f"must be an {form} array of {width} numbers (got {_short(row)})")
    nums = []
    for m, v in enumerate(row):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InputError(f"{key}[{m + 1}]", f"must be a number (got {_type_name(v)}: {_short(v)})")
        try:
            x = float(v)
        except OverflowError:
            raise InputError(f"{key}[{m + 1}]", "must be a finite number") from None
        if not math.isfinite(x):
            raise InputError(f"{key}[{m + 1}]", f"must be finite (got {x})")
        nums.append(x)
    return nums


def _clump_spheres(key: str, value: Any) -> list[list[float]]:
    """``[[x, y, z, r], ...]``: at least one sphere, finite coordinates, positive radii."""
    if not isinstance(value, list) or not value:
        raise InputError(key, f"a clump needs at least one sphere [x, y, z, r] (got {_type_name(value)}: {_short(value)})")
    out = []
    for n, row in enumerate(value):
        k = f"{key}[{n + 1}]"
        nums = _finite_row(k, row, "[x, y, z, r]")
        if nums[3] <= 0:
            raise InputError(f"{k}[4]", f"the radius must be positive (got {nums[3]:g})")
        out.append(nums)
    return out


def _short(value: Any, limit: int = 40) -> str:
    text = repr(value)
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _key_text(key: str) -> str:
    """A key as TOML would write it: bare when possible, else quoted with ASCII escapes."""
    return key if _BARE_KEY.match(key) else json.dumps(key)


TOP_LEVEL_KEYS = ("integrator", "omega_max", "safety", "pairs", "title", "coordination_max", "overlap_max", "isolated")
"""Keys that belong before the first table (``dtcrit.scenes.model.TOP_KEYS`` without the tables)."""


def _check_keys(prefix: str, table: dict, allowed: tuple[str, ...], vocabulary: tuple[str, ...], where: str) -> None:
    """Reject keys outside ``allowed``; suggest the nearest key (preferring the allowed ones)."""
    for key in table:
        if key in allowed:
            continue
        path = f"{prefix}{_key_text(key)}"
        if key in vocabulary:
            raise InputError(path, f"not used {where}; valid keys here: {', '.join(allowed)}")
        close = difflib.get_close_matches(str(key), allowed, n=1, cutoff=0.6) or difflib.get_close_matches(
            str(key).lower(), allowed, n=1, cutoff=0.5
        )
        hint = f" (did you mean '{close[0]}'?)" if close else ""
        if prefix and key in TOP_LEVEL_KEYS:
            hint = (f" ('{key}' is a top-level key: in TOML every key after a [table] header belongs to that table, "
                    "so write top-level keys before the first table)")
        raise InputError(path, f"unknown key{hint}; valid keys here: {', '.join(allowed)}")


def _required(prefix: str, table: dict, key: str, what: str) -> Any:
    if key not in table:
        raise InputError(f"{prefix}{key}", f"missing: {what}")
    return table[key]
