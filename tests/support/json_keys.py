"""Shared by the JSON schema tests: the names of every number in a document."""
from __future__ import annotations


def numeric_keys(x, name=None, out=None) -> set:
    """Names of the keys that hold numbers anywhere in ``x`` (a list item counts under its list's key),
    outside the envelope's ``units`` and ``derivation_hashes``."""
    out = set() if out is None else out
    if isinstance(x, dict):
        for k, v in x.items():
            if k not in ("units", "derivation_hashes"):
                numeric_keys(v, k, out)
    elif isinstance(x, list):
        for v in x:
            numeric_keys(v, name, out)
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        out.add(name)
    return out
