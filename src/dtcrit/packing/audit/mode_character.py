"""What governs: the character of the governing mode of an audit (which springs hold its energy).

The audit's solver returns the governing mode ``v`` in mass-scaled coordinates (``v = M^(1/2) phi``,
``dtcrit.packing.solvers.damped_step``: the top eigenvector of ``K~``, or the null vector of
``4M - 2hC - h^2 K`` with dashpots).  With ``phi = M^(-1/2) v`` its strain energy ``phi^T K phi``
is the sum, contact by contact, of the terms of the element ``[B_i B_j]^T K_c [B_i B_j]``
(``dtcrit.packing.operators.assembly``, module docstring; Otsubo et al. 2017, Section 3):

* normal ``k_n (n . delta)^2`` and tangential ``k_s |delta - n (n . delta)|^2``, with ``delta`` the
  relative displacement of the contact point (``slip_jacobians``);
* twisting ``k_tw (n . rho)^2`` and rolling ``k_r |rho - n (n . rho)|^2``, with ``rho`` the relative
  rotation (``rotation_jacobians``; YADE's CohFrictPhys moment law, LAMMPS ``granular`` rolling and
  twisting springs, linearised);
* the pre-load (initial-stress) term ``-(F/r) |c - n (n . c)|^2`` of the centre motion ``c``, not a
  spring: negative for a compressive force, reported apart as a signed fraction of the springs' energy.

The four spring shares are fractions of the springs' energy (they sum to 1).  The kinetic side is
``v^T v = phi^T M phi``: ``rotational_kinetic`` is the share of the rotation DOFs, and the
per-particle energies ``e_p = sum of v^2 over p's six DOFs`` give the participation ratio
``(sum e_p)^2 / (N sum e_p^2)`` (1: every particle alike; 1/N: one particle), the one definition the
audit's ``limiting`` uses too.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.operators.assembly import contact_kinematics, mass_diagonal, preload_coefficient
from dtcrit.packing.operators.element_matrices import rotation_jacobians

__all__ = ["SPRINGS", "ModeCharacter", "contact_energies", "describe", "mode_character", "participation_ratio",
           "particle_energies"]

SPRINGS = ("normal", "tangential", "rolling", "twisting")
"""The spring terms whose shares of the governing mode's strain energy are reported."""
CHUNK = 1 << 16
"""Contacts per vectorised chunk of ``contact_energies``."""


@dataclass(frozen=True)
class ModeCharacter:
    """The character of the governing mode (module docstring); shares are fractions (0-1).

    Parameters
    ----------
    normal, tangential, rolling, twisting : float
        Shares of the springs' strain energy ``phi^T K_springs phi`` in each kind of spring (sum 1).
    rotational_kinetic : float
        Share of the mode's kinetic energy ``phi^T M phi`` in the rotation DOFs.
    participation_ratio : float
        ``(sum e_p)^2 / (N sum e_p^2)`` of the per-particle kinetic energies ``e_p``.
    preload : float
        Energy of the pre-load term over the springs' energy (signed; 0 without pre-load).
    particle_share : numpy.ndarray
        Share of the mode's kinetic energy on each particle, shape (N,) (sums to 1).
    """

    normal: float
    tangential: float
    rolling: float
    twisting: float
    rotational_kinetic: float
    participation_ratio: float
    preload: float = 0.0
    particle_share: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False, compare=False)

    def to_json(self) -> dict:
        """The ``governing_mode`` object of schema ``dtcrit-audit/1``.

        Returns
        -------
        dict
            ``normal``, ``tangential``, ``rolling``, ``twisting``, ``rotational_kinetic``,
            ``participation_ratio`` and ``preload``, floats.
        """
        keys = SPRINGS + ("rotational_kinetic", "participation_ratio", "preload")
        return {k: float(getattr(self, k)) for k in keys}


def particle_energies(vector: np.ndarray) -> np.ndarray:
    """Per-particle kinetic energy of a mass-scaled mode ``v``: the sum of ``v^2`` over each particle's
    six DOFs (``v^T v = phi^T M phi``).

    Parameters
    ----------
    vector : numpy.ndarray
        The mode in mass-scaled coordinates, length 6N.

    Returns
    -------
    numpy.ndarray
        ``e_p``, shape (N,).
    """
    return (np.asarray(vector, dtype=float).reshape(-1, 6) ** 2).sum(axis=1)


def participation_ratio(energies: np.ndarray) -> float:
    """``(sum e_p)^2 / (N sum e_p^2)``: 1 when every particle holds the same energy, 1/N for one.

    Parameters
    ----------
    energies : numpy.ndarray
        Per-particle energies ``e_p >= 0``.

    Returns
    -------
    float
        The ratio (NaN when every ``e_p`` is zero).
    """
    e = np.asarray(energies, dtype=float)
    total = float(e.sum())
    if total <= 0:
        return math.nan
    return float(total**2 / (e.size * np.sum(e**2)))


def _split(vectors: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``((n . x)^2, |x - n (n . x)|^2)`` of each row of ``vectors``."""
    along = np.einsum("ij,ij->i", vectors, normal) ** 2
    return along, np.maximum(np.einsum("ij,ij->i", vectors, vectors) - along, 0.0)


def _rotations(packing: Packing, contacts: Contacts, sl) -> tuple[np.ndarray | None, np.ndarray | None]:
    q = packing.orientations
    return (None, None) if q is None else (q[contacts.i[sl]], q[contacts.j[sl]])


def contact_energies(packing: Packing, contacts: Contacts, phi: np.ndarray) -> dict[str, np.ndarray]:
    """Each contact's terms of ``phi^T K phi`` (twice the strain energy) for a displacement ``phi``.

    Parameters
    ----------
    packing : Packing
        The bodies (orientations give the axes of their rotation DOFs).
    contacts : Contacts
        The contacts with their springs ``kn``, ``ks`` [N/m], ``kr``, ``ktw`` [N m/rad] and
        optional normal force ``force_n`` [N].
    phi : numpy.ndarray
        Displacements and small rotations, length 6N (``dtcrit.packing.operators.assembly`` order).

    Returns
    -------
    dict of str to numpy.ndarray
        ``normal``, ``tangential``, ``rolling``, ``twisting`` and ``preload``, each (nc,) [J x 2].
    """
    q = np.asarray(phi, dtype=float).reshape(-1, 6)
    nc = contacts.count
    out = {k: np.zeros(nc) for k in SPRINGS + ("preload",)}
    assert contacts.kn is not None and contacts.ks is not None  # the audit checks its terms first
    for start in range(0, nc, CHUNK):
        sl = slice(start, min(start + CHUNK, nc))
        qi, qj, n = q[contacts.i[sl]], q[contacts.j[sl]], contacts.normal[sl]
        b_i, b_j = contact_kinematics(packing, contacts, sl)
        delta = np.einsum("cak,ck->ca", b_i, qi) + np.einsum("cak,ck->ca", b_j, qj)
        along, across = _split(delta, n)
        out["normal"][sl] = contacts.kn[sl] * along
        out["tangential"][sl] = contacts.ks[sl] * across
        if contacts.kr is not None or contacts.ktw is not None:
            r_i, r_j = rotation_jacobians(sl.stop - sl.start, *_rotations(packing, contacts, sl))
            rho = np.einsum("cak,ck->ca", r_i, qi) + np.einsum("cak,ck->ca", r_j, qj)
            twist, roll = _split(rho, n)
            if contacts.ktw is not None:
                out["twisting"][sl] = contacts.ktw[sl] * twist
            if contacts.kr is not None:
                out["rolling"][sl] = contacts.kr[sl] * roll
        g = preload_coefficient(packing, contacts, sl)
        if g is not None:
            out["preload"][sl] = -g * _split(qj[:, :3] - qi[:, :3], n)[1]
    return out


def mode_character(packing: Packing, contacts: Contacts, vector: np.ndarray | None) -> ModeCharacter | None:
    """The character of the governing mode ``vector`` (mass-scaled, as the audit's solver returns it).

    Parameters
    ----------
    packing : Packing
        The bodies.
    contacts : Contacts
        The contacts with every spring and the pre-load the audit solved with.
    vector : numpy.ndarray or None
        The mode ``v = M^(1/2) phi``, length 6N; ``None`` (the spectral-radius route returns none).

    Returns
    -------
    ModeCharacter or None
        The shares (module docstring), ``None`` without a mode or when it strains no spring.
    """
    if vector is None:
        return None
    v = np.asarray(vector, dtype=float).reshape(-1)
    e_p = particle_energies(v)
    kinetic = float(e_p.sum())
    terms = {k: float(np.sum(e)) for k, e in contact_energies(packing, contacts, v / np.sqrt(mass_diagonal(packing))).items()}
    springs = sum(terms[k] for k in SPRINGS)
    if kinetic <= 0 or springs <= 0:
        return None
    rotational = float(np.sum(v.reshape(-1, 6)[:, 3:] ** 2)) / kinetic
    return ModeCharacter(normal=terms["normal"] / springs, tangential=terms["tangential"] / springs,
                         rolling=terms["rolling"] / springs, twisting=terms["twisting"] / springs,
                         rotational_kinetic=rotational, participation_ratio=participation_ratio(e_p),
                         preload=terms["preload"] / springs, particle_share=e_p / kinetic)


def _pct(x: float) -> str:
    return f"{100 * x:.3g} %"


def describe(c: ModeCharacter) -> str:
    """Text on the governing mode's character (what ``dtcrit audit`` prints).

    Parameters
    ----------
    c : ModeCharacter
        The character.

    Returns
    -------
    str
        Two lines: the springs' shares, then the kinetic side.
    """
    springs = ", ".join(f"{_pct(getattr(c, k))} {k}" for k in SPRINGS)
    preload = f" (pre-load term {_pct(c.preload)} of it)" if c.preload != 0 else ""
    return (f"governing mode: springs' strain energy {springs}{preload}\n"
            f"  kinetic energy {_pct(c.rotational_kinetic)} in rotation, {_pct(1 - c.rotational_kinetic)} in "
            f"translation; participation ratio {c.participation_ratio:.3g}")
