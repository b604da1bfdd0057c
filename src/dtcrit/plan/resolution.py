"""Which normal law and collision-damping model a snapshot's contacts follow, for the collision resolution.

``dtcrit.collisions.resolution_step`` time-steps one impact of a code's normal law and damping model
(``dtcrit.physics.collision_laws.DAMPING_MODELS``) at a restitution.  A snapshot's law maps onto one
where the engine's dashpot is a constant times ``m_eff`` (or a constant) on a linear spring -- the
restitution is then the linear oscillator's ``e = exp(-pi zeta / sqrt(1 - zeta^2))`` with ``zeta = c /
(2 sqrt(m_eff k))`` (``dtcrit.physics.damping_conventions.damping_ratio_from_restitution`` inverted):

* LAMMPS ``pair_style gran/hooke``, ``gran/hooke/history`` (``c_n = m_eff gamma_n``, constant in the
  overlap: ``lammps-mass-velocity`` on ``hooke``);
* ``pair_style granular hooke`` with ``damping mass_velocity`` or ``velocity`` (a constant dashpot: the
  same collision).

Every other damped law (Hertz, whose restitution depends on the impact speed; ``tsuji``; LIGGGHTS;
a YADE export or a table of unknown law) is *not assessed*: :func:`damping_model` returns None and the
plan says so.  :func:`is_hertz` decides Hertz from the parsed normal model, never from words.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["damping_model", "is_hertz", "linear_restitution"]


def _law(snapshot):
    from dtcrit.errors import InputError
    from dtcrit.plan.rederive import law_of

    if snapshot.convention.name == "yade" or snapshot.law.startswith(("per-contact table", "YADE")):
        return None
    try:
        return law_of(snapshot)[0]
    except InputError:
        return None


def is_hertz(snapshot) -> bool:
    """Whether the snapshot's normal law is Hertzian, from its parsed normal model.

    Parameters
    ----------
    snapshot : dtcrit.packing.audit.results.Snapshot
        The snapshot.

    Returns
    -------
    bool
        ``gran/hertz/history``; ``granular hertz``, ``hertz/material``, ``dmt``; LIGGGHTS ``hertz``.
        False for linear laws, a YADE export (FrictPhys: linear) and a table (its ``kn`` as given).
    """
    from dtcrit.packing.conventions.granular_style import GranularStyle
    from dtcrit.packing.conventions.pair_styles import GranPairStyle

    law = _law(snapshot)
    if isinstance(law, GranPairStyle):
        return law.style == "gran/hertz/history"
    if isinstance(law, GranularStyle):
        return law.normal in ("hertz", "hertz/material", "dmt")
    spec = getattr(law, "spec", None)
    return bool(spec is not None and spec.normal == "hertz")


def damping_model(snapshot) -> str | None:
    """The ``DAMPING_MODELS`` key of a damped snapshot's normal law on ``hooke``, None when not mapped (module docstring).

    Parameters
    ----------
    snapshot : dtcrit.packing.audit.results.Snapshot
        The snapshot.

    Returns
    -------
    str or None
        ``"none"`` for undamped contacts, ``"lammps-mass-velocity"`` for a constant linear dashpot, None otherwise.
    """
    from dtcrit.packing.conventions.granular_style import GranularStyle
    from dtcrit.packing.conventions.pair_styles import GranPairStyle

    if not snapshot.contacts.damped:
        return "none"
    law = _law(snapshot)
    if isinstance(law, GranPairStyle) and law.style in ("gran/hooke", "gran/hooke/history"):
        return "lammps-mass-velocity"
    if isinstance(law, GranularStyle) and law.normal == "hooke" and law.damping in ("mass_velocity", "velocity"):
        return "lammps-mass-velocity"
    return None


def linear_restitution(packing, contacts, factors=None) -> np.ndarray:
    """Each contact's restitution ``exp(-pi zeta / sqrt(1 - zeta^2))``, ``zeta = c_n / (2 sqrt(m_eff k_n))`` (0 when overdamped).

    Parameters
    ----------
    packing : dtcrit.packing.model.Packing
        The bodies (masses).
    contacts : dtcrit.packing.contact_set.Contacts
        The contacts (``kn``, ``cn``), at the masses ``factors`` give.
    factors : numpy.ndarray or None
        ``(N,)`` mass factors.

    Returns
    -------
    numpy.ndarray
        ``(C,)`` restitutions in [0, 1].
    """
    m = packing.masses if factors is None else packing.masses * factors
    mi, mj = m[contacts.i], m[contacts.j]
    m_eff = np.where(contacts.i == contacts.j, mi / 2.0, mi * mj / (mi + mj))
    cn = np.zeros(contacts.count) if contacts.cn is None else contacts.cn
    with np.errstate(divide="ignore", invalid="ignore"):
        zeta = cn / (2.0 * np.sqrt(m_eff * contacts.kn))
        e = np.exp(-math.pi * zeta / np.sqrt(1.0 - zeta**2))
    return np.where(zeta < 1.0, np.nan_to_num(e, nan=1.0), 0.0)
