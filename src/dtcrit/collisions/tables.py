"""Error curves shipped as generated data: per engine scheme, law and restitution, the worst error
over sampled entry phases at each N of a geometric grid (``_generated/collision_tables.json``).

Written by ``python3 -m dtcrit.collisions.tables`` (run by ``python3 dev.py generate``); its header holds
a hash of the sources that produce it, and ``tests/collisions/test_collision_tables.py`` fails when the
sources changed without regenerating and recomputes entries to compare.  The curves are the sampled
worst case (``SAMPLE_PHASES`` phases); ``resolution_step`` always computes the guaranteed value
(optimised over the phase).  Its cost grows as N_res (measured on one core: under 1 s where N_res < 50,
about 10 s at a few hundred, minutes in the thousands), so the document also holds the resolution steps
of the standard cases that ``resolve`` gives (``resolution_table``: ``resolutions``), and ``lookup``
answers from them.
"""
from __future__ import annotations

import functools
import json
import sys
from pathlib import Path

import numpy as np

from dtcrit.collisions import resolution_table
from dtcrit.collisions.resolution import SAMPLE_PHASES, sampled_errors
from dtcrit.collisions.laws import scaled_law
from dtcrit.integrators.engines import ENGINES
from dtcrit.json_meta import sources_hash

TABLE_PATH = Path(__file__).resolve().parents[1] / "_generated" / "collision_tables.json"
SCHEMES: tuple[str, ...] = tuple(sorted({scheme for scheme, _, _ in ENGINES.values()}))
LAWS: tuple[tuple[str, str], ...] = (
    ("hooke", "liggghts"), ("hooke", "lammps-tsuji"),
    ("hertz", "liggghts"), ("hertz", "yade-mindlin"), ("hertz", "lammps-tsuji"), ("hertz", "lammps-tsuji-2021"),
)
RESTITUTIONS: tuple[float, ...] = (1.0, 0.9, 0.5, 0.1)
STEPS: tuple[float, ...] = tuple(float(x) for x in np.round(np.geomspace(4.0, 1024.0, 25), 6))
SOURCES = ("collisions/scaled.py", "collisions/laws.py", "collisions/reference.py", "collisions/stepping.py", "collisions/resolution.py",
           "collisions/tables.py", "collisions/resolution_table.py", "physics/collision_laws.py", "physics/damping_conventions.py",
           "integrators/schemes.py", "integrators/engines.py")


def source_hash() -> str:
    """SHA-256 (16 hex digits) of the sources that produce the tables (``json_meta.sources_hash``).

    Returns
    -------
    str
        The derivation hash.
    """
    return sources_hash(SOURCES)


def curve(scheme: str, normal: str, damping: str, e: float) -> dict:
    """The sampled worst relative errors over ``STEPS`` for one case.

    Parameters
    ----------
    scheme : str
        A scheme key.
    normal, damping : str
        The law.
    e : float
        Restitution.

    Returns
    -------
    dict
        quantity -> list of errors (rounded to 6 significant digits; null where not separated).
    """
    errs = sampled_errors(scheme, scaled_law(normal, damping, e), STEPS)
    return {k: [float(f"{x:.6g}") if np.isfinite(x) else None for x in v] for k, v in errs.items()}


def build() -> dict:
    """Every curve of the tables with the header.

    Returns
    -------
    dict
        The JSON document.
    """
    cases = []
    for scheme in SCHEMES:
        for normal, damping in LAWS:
            for e in RESTITUTIONS:
                cases.append({"scheme": scheme, "normal": normal, "damping": damping, "restitution": e,
                              "errors": curve(scheme, normal, damping, e)})
    return {"generated_by": "python3 dev.py generate (dtcrit.collisions.tables)", "derivation_hash": source_hash(),
            "sample_phases": SAMPLE_PHASES, "steps_per_collision": list(STEPS), "cases": cases,
            "resolutions": resolution_table.build(cases, STEPS)}


def load() -> dict:
    """The committed tables.

    Returns
    -------
    dict
        The JSON document.
    """
    return json.loads(TABLE_PATH.read_text())


@functools.lru_cache(maxsize=1)
def _resolutions() -> tuple:
    return tuple(load().get("resolutions", ())) if TABLE_PATH.exists() else ()


def lookup(scheme, normal, damping, restitution, tol, quantities, clip):
    """The tabulated resolution step of the request, or None (``resolution_table.find``).

    Parameters
    ----------
    scheme, normal, damping : str
        The case.
    restitution, tol : float
        Restitution and tolerance.
    quantities : tuple of str
        The quantities.
    clip : bool or None
        Clipping.

    Returns
    -------
    Resolution or None
        The stored resolution (what ``resolve`` gives, to ``resolution_table.DIGITS`` digits), or None.
    """
    try:
        e, t = float(restitution), float(tol)
    except (TypeError, ValueError):
        return None
    return resolution_table.find(list(_resolutions()), scheme, normal, damping, e, t, quantities, clip)


def main() -> int:
    """Write the tables when their text changed.

    Returns
    -------
    int
        Exit status 0.
    """
    text = json.dumps(build(), indent=1, sort_keys=True) + "\n"
    if not TABLE_PATH.exists() or TABLE_PATH.read_text() != text:
        TABLE_PATH.write_text(text)
        print(f"wrote src/dtcrit/_generated/{TABLE_PATH.name}")
    return 0


__all__ = ["TABLE_PATH", "SCHEMES", "LAWS", "RESTITUTIONS", "STEPS", "source_hash", "curve", "build", "load", "lookup"]

if __name__ == "__main__":
    sys.exit(main())
