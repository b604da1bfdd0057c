"""The envelope every ``--json`` output of dtcrit carries (``docs/explanation/conventions.md``,
section "The JSON envelope").

Each document starts with ``schema`` (``dtcrit-<command>/<major>``: a key keeps its meaning within a
major version, new keys may be added), ``dtcrit_version``, ``units`` (the unit of every dimensional
key, SI throughout) and ``derivation_hashes``: for each committed generated module
(``dtcrit._generated``) the hash of the derivation that produced it, read from the module's header
line ``# Derivation hash: …``, so an output can be traced to the exact formulas behind it.  The
headers are read as text: nothing here imports the generated code.
"""
from __future__ import annotations

from functools import lru_cache

_HASH_PREFIX = "# Derivation hash:"


def sources_hash(sources: tuple[str, ...]) -> str:
    """SHA-256 (16 hex digits) of the package's source files ``sources`` (paths below ``dtcrit/``): the
    derivation hash a committed generated table records and its drift test checks.

    Parameters
    ----------
    sources : tuple of str
        The sources that compute the table, relative to the package directory.

    Returns
    -------
    str
        The hash.
    """
    import hashlib  # here, not at import: a plain ``dtcrit step`` starts without them
    from pathlib import Path

    root = Path(__file__).resolve().parent
    h = hashlib.sha256()
    for rel in sources:
        h.update((root / rel).read_bytes())
    return h.hexdigest()[:16]


@lru_cache(maxsize=1)
def derivation_hashes() -> dict[str, str]:
    """``{generated module name: derivation hash}`` from the headers of ``dtcrit/_generated/*.py``."""
    from importlib import resources  # here, not at import (as ``hashlib`` above)

    out: dict[str, str] = {}
    for entry in sorted(resources.files("dtcrit._generated").iterdir(), key=lambda e: e.name):
        if not entry.name.endswith(".py") or entry.name.startswith("__"):
            continue
        with entry.open("r", encoding="utf-8") as fh:
            for _, line in zip(range(8), fh):
                if line.startswith(_HASH_PREFIX):
                    out[entry.name[:-3]] = line[len(_HASH_PREFIX):].strip()
                    break
    return out


def envelope(schema: str, units: dict[str, str]) -> dict:
    """The leading keys of a JSON document of a given schema (module docstring).

    Parameters
    ----------
    schema : str
        ``dtcrit-<command>/<major>``, e.g. ``"dtcrit-packing/1"``.
    units : dict of str to str
        Unit of every dimensional key of the document (SI), e.g. ``{"dt_crit": "s"}``.

    Returns
    -------
    dict
        ``schema``, ``dtcrit_version``, ``units`` (a copy) and ``derivation_hashes``.
    """
    from dtcrit import __version__

    return {"schema": schema, "dtcrit_version": __version__, "units": dict(units),
            "derivation_hashes": derivation_hashes()}

