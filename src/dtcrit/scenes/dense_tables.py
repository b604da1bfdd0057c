"""The dense-packing bound's branch-and-bound values shipped as generated data
(``_generated/dense_phi_nodes.json``), so that ``dtcrit step`` on a scene seen before answers in
milliseconds instead of a second of branch and bound.

Each entry is one call of :func:`dtcrit.scenes.dense_phi._phi_bound`: its arguments (coordination
``z_eff``, half-angle ``psi``, the end parameters ``pars``, ``rtol``, ``n_theta``) and its rigorous
upper bound ``phi``.  :func:`phi_upper` answers a call from an entry with the same ``z_eff``,
``psi``, ``rtol``, ``n_theta`` and end parameters proportional to the entry's: ``Phi`` is linear in
the five stiffness parameters at a fixed arm ratio (``dense_phi._f_coefficients``), and
``dense_spheres._domination`` (passed in) gives the rigorous factor ``c`` with ``Phi(pars) <= c Phi(entry)`` for
parameters proportional to rounding; otherwise it runs the branch and bound.  The entries are those
the example scenes need (recorded while ``dtcrit step`` runs on each of ``examples/*.toml``).

Written by ``python3 -m dtcrit.bench.dense_table_writer`` (run by ``python3 dev.py generate``); the file's
``derivation_hash`` is a hash of the sources that compute ``phi`` (``SOURCES``), checked when the
table is loaded: after an edit of those sources without regenerating, the table is ignored (every
value recomputed), and ``tests/scenes/test_dense_tables.py`` fails.
"""
from __future__ import annotations

import functools
import json
import os
from pathlib import Path

from dtcrit.json_meta import sources_hash

__all__ = ["DISABLE", "SOURCES", "TABLE_PATH", "load", "phi_upper", "source_hash"]

TABLE_PATH = Path(__file__).resolve().parents[1] / "_generated" / "dense_phi_nodes.json"
SOURCES = ("scenes/dense_phi.py", "scenes/dense_cells.py", "scenes/dense_tables.py")
DISABLE = "DTCRIT_NO_DENSE_TABLE"
"""An environment variable: set (non-empty), the table is not used (every value computed)."""
PROPORTIONAL = 1e-12
"""Relative difference below which end parameters count as proportional to an entry's."""


def source_hash() -> str:
    """SHA-256 (16 hex digits) of the sources that compute the tabulated values (``json_meta.sources_hash``).

    Returns
    -------
    str
        The derivation hash.
    """
    return sources_hash(SOURCES)


@functools.lru_cache(maxsize=1)
def load() -> tuple:
    """The table's entries, or none when it is missing, disabled (``DISABLE``) or stale (hash).

    Returns
    -------
    tuple of dict
        Entries with keys ``z_eff``, ``psi``, ``rtol``, ``n_theta``, ``pars``, ``phi``.
    """
    if os.environ.get(DISABLE) or not TABLE_PATH.exists():
        return ()
    doc = json.loads(TABLE_PATH.read_text())
    if doc.get("derivation_hash") != source_hash():
        return ()
    return tuple(doc["entries"])


def _from_table(z_eff: int, psi: float, pars: tuple, rtol: float, n_theta: int, dominate) -> float | None:
    for e in load():
        if (e["z_eff"], e["psi"], e["rtol"], e["n_theta"]) != (z_eff, psi, rtol, n_theta) or len(e["pars"]) != len(pars):
            continue
        node = [float(t) for t in e["pars"]]
        k = next((a / b for a, b in zip(pars[:5], node[:5]) if b > 0), None)
        if k is None or pars[5:] != tuple(node[5:]):
            continue
        if any(abs(a - k * b) > PROPORTIONAL * abs(a) for a, b in zip(pars[:5], node[:5])):
            continue
        c = dominate(pars, node)
        if c is not None:
            return c * float(e["phi"])
    return None


def phi_upper(z_eff: int, psi: float, pars: tuple, rtol: float, n_theta: int, dominate) -> float:
    """``_phi_bound(z_eff, psi, pars, rtol, n_theta)[0]``: from the table when it holds the case, else computed.

    Parameters
    ----------
    z_eff : int
        Effective coordination.
    psi : float
        Half the smallest angle between contact normals [rad].
    pars : tuple of float
        End parameters ``(alpha, beta, gamma, gamma_r, gamma_w, t0)`` (``dense_spheres._pars``).
    rtol : float
        Branch-and-bound stopping tolerance.
    n_theta : int
        Sphere grid resolution.
    dominate : callable
        ``dominate(pars, node)``: the factor ``c`` with ``Phi(pars) <= c Phi(node)``, or None
        (``dense_spheres._domination``).

    Returns
    -------
    float
        A rigorous upper bound on ``Phi`` [1/s^2].
    """
    key = (int(z_eff), float(psi), tuple(float(t) for t in pars), float(rtol), int(n_theta))
    found = _from_table(*key, dominate)
    if found is not None:
        return found
    from dtcrit.scenes.dense_phi import _phi_bound

    return _phi_bound(*key)[0]
