"""Compare a rebuilt derivation record with the committed one (used by the records tests).

A record is the same when its text is identical, or when the only differences are numbers printed
with at least ``MIN_DIGITS`` significant digits that agree to the relative ``RTOL``: such numbers
(12-digit quadratures, closed forms) carry the last bits of floating point, which change with the
processor's SIMD loops.  Every other number and every word must be identical.
"""
from __future__ import annotations

import difflib
import re

RTOL = 1e-9
MIN_DIGITS = 10
_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def _digits(token: str) -> int:
    mantissa = re.split(r"[eE]", token)[0].lstrip("+-").replace(".", "").lstrip("0")
    return len(mantissa)


def _same_line(old: str, new: str) -> bool:
    if _NUMBER.sub("#", old) != _NUMBER.sub("#", new):
        return False
    for a, b in zip(_NUMBER.findall(old), _NUMBER.findall(new)):
        if a == b:
            continue
        if min(_digits(a), _digits(b)) < MIN_DIGITS:
            return False
        x, y = float(a), float(b)
        if abs(x - y) > RTOL * max(abs(x), abs(y)):
            return False
    return True


def differences(committed: str, rebuilt: str, name: str) -> str:
    """Empty when the two texts are the same record (module docstring), else a unified diff."""
    if committed == rebuilt:
        return ""
    old, new = committed.splitlines(), rebuilt.splitlines()
    if len(old) == len(new) and all(_same_line(a, b) for a, b in zip(old, new)):
        return ""
    return "\n".join(difflib.unified_diff(old, new, f"committed {name}", f"rebuilt {name}", lineterm="", n=0))
