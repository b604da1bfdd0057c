"""Fixed walls in the packing model: each wall contact joins a particle to an immobile body.

A wall has infinite mass.  The packing model gives every body six degrees of freedom, so a wall
enters as an extra body whose mass and moments of inertia are ``FIXED_FACTOR`` (1e150) times the
largest free ones, as fixed YADE bodies enter (``dtcrit.packing.readers.yade_export``): its coupling
entries of ``M^-1/2 K M^-1/2`` are ``1e-75`` of the particles' own, so the free bodies' frequencies
move by ~1e-150 relative, and the block-diagonal and Gershgorin bounds and the codes' estimators
(``m_eff = m M/(m + M) = m`` exactly in floating point, ``m M`` far from overflow) are those of a
particle on an immovable wall.  The wall bodies come after the particles, so particle indices do not
change; they carry the ids ``max id + 1, max id + 2, ...``.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, replace

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.contact_set import Contacts
from dtcrit.packing.model import Packing

FIXED_FACTOR = 1e150
"""Mass and inertia of a wall body relative to the largest free ones."""

__all__ = ["FIXED_FACTOR", "WallContacts", "concatenate", "count_particles_only", "merge", "with_wall_bodies"]


@dataclass(frozen=True)
class WallContacts:
    """Contacts of particles with fixed walls, before the wall bodies exist.

    Parameters
    ----------
    i : numpy.ndarray
        (C,) index of the particle of each contact.
    normal : numpy.ndarray
        (C, 3) unit normals from the particle towards the wall.
    arm : numpy.ndarray
        (C,) the particle's arm length [m] along ``normal`` (the engine's).
    overlap : numpy.ndarray
        (C,) overlap with the wall [m].
    radius_eff : numpy.ndarray
        (C,) the effective radius [m] the engine's Hertz factor uses.
    anchor : numpy.ndarray
        (C, 3) where each contact's wall body sits [m] (its centre distance to the particle is the
        lever of the pre-load's geometric stiffness).
    wall : numpy.ndarray
        (C,) number of the wall each contact belongs to (counted from 1).
    """

    i: np.ndarray
    normal: np.ndarray
    arm: np.ndarray
    overlap: np.ndarray
    radius_eff: np.ndarray
    anchor: np.ndarray
    wall: np.ndarray

    @property
    def count(self) -> int:
        """Number of wall contacts."""
        return int(self.i.shape[0])


def with_wall_bodies(packing: Packing, walls: WallContacts) -> tuple[Packing, Contacts]:
    """The packing with one fixed body per wall contact, and those contacts (no springs yet).

    Parameters
    ----------
    packing : Packing
        The particles (spheres).
    walls : WallContacts
        The wall contacts.

    Returns
    -------
    tuple
        ``(packing with the wall bodies appended, contacts particle -> wall body)``; each contact's
        arm on the particle is ``arm * normal``, on the wall body the same contact point.
    """
    c = walls.count
    n = packing.n
    big_m = FIXED_FACTOR * float(packing.masses.max())
    big_i = FIXED_FACTOR * float(packing.inertia.max())
    if not (np.isfinite(big_m) and np.isfinite(big_i)):
        raise InputError("--wall", f"a wall enters as a body {FIXED_FACTOR:g} times heavier than the heaviest "
                                   "particle, which overflows for these masses")
    ids = packing.ids if packing.ids is not None else np.arange(1, n + 1)
    wall_ids = int(ids.max()) + 1 + np.arange(c)
    radii = packing.radii[walls.i]
    half = None if packing.half_lengths is None else np.concatenate([packing.half_lengths, np.repeat(radii[:, None], 3, 1)])
    grown = replace(packing, positions=np.concatenate([packing.positions, walls.anchor]),
                    masses=np.concatenate([packing.masses, np.full(c, big_m)]),
                    inertia=np.concatenate([packing.inertia, np.full((c, 3), big_i)]),
                    radii=np.concatenate([packing.radii, radii]), half_lengths=half,
                    ids=np.concatenate([ids, wall_ids]),
                    orientations=None if packing.orientations is None
                    else np.concatenate([packing.orientations, np.repeat(np.eye(3)[None], c, 0)]))
    arm_i = walls.arm[:, None] * walls.normal
    point = packing.positions[walls.i] + arm_i
    contacts = Contacts(i=walls.i.astype(np.int64), j=n + np.arange(c, dtype=np.int64), normal=walls.normal,
                        arm_i=arm_i, arm_j=point - walls.anchor, overlap=walls.overlap,
                        image=np.zeros((c, 3), np.int64), radius_eff=walls.radius_eff)
    return grown, contacts


_TERMS = ("kn", "ks", "cn", "cs", "kr", "ktw", "force_n", "cr", "ctw")


def concatenate(first: Contacts, second: Contacts) -> Contacts:
    """One contact list of two, every per-contact term kept (a term one list lacks is 0 there).

    Parameters
    ----------
    first, second : Contacts
        The two lists.

    Returns
    -------
    Contacts
        ``first`` followed by ``second``.
    """
    i, j, normal, arm_i, arm_j, overlap, image, radius_eff = (
        np.concatenate([getattr(first, key), getattr(second, key)])
        for key in ("i", "j", "normal", "arm_i", "arm_j", "overlap", "image", "radius_eff"))
    terms: dict[str, np.ndarray | None] = {}
    for key in _TERMS:
        a, b = getattr(first, key), getattr(second, key)
        terms[key] = None if a is None and b is None else np.concatenate(
            [np.zeros(first.count) if a is None else a, np.zeros(second.count) if b is None else b])
    return Contacts(i, j, normal, arm_i, arm_j, overlap, image, radius_eff, kn=terms["kn"], ks=terms["ks"], cn=terms["cn"], cs=terms["cs"], kr=terms["kr"],
                    ktw=terms["ktw"], force_n=terms["force_n"], cr=terms["cr"], ctw=terms["ctw"])


def merge(parts: list[WallContacts]) -> WallContacts:
    """The wall contacts of several walls as one list, in order.

    Parameters
    ----------
    parts : list of WallContacts
        The contacts of each wall.

    Returns
    -------
    WallContacts
        All of them.
    """
    return WallContacts(*(np.concatenate([getattr(p, key) for p in parts]) for key in
                          ("i", "normal", "arm", "overlap", "radius_eff", "anchor", "wall")))


def count_particles_only(report, packing: Packing, contacts: Contacts, n_free: int) -> None:
    """Report the particles alone when the last bodies of ``packing`` are walls (in place).

    The particle count, the mean coordination (a wall contact counts once, on its particle), the
    limiting ids (a wall body is never named), the participation ratio (over the particles: the
    walls hold no energy) and an estimator's "contact of particles i and w" (then "of particle i and a
    wall") of an ``AuditReport`` (``dtcrit.packing.audit.snapshot``).

    Parameters
    ----------
    report : AuditReport
        The audit of the packing with its wall bodies.
    packing : Packing
        That packing.
    contacts : Contacts
        Its contacts.
    n_free : int
        The number of particles (the bodies before the walls).
    """
    n_all = packing.n
    if n_free >= n_all:
        return
    walls = {packing.particle_id(k) for k in range(n_free, n_all)}
    per = contacts.coordination(n_all)[:n_free]
    report.n_particles = n_free
    report.coordination_mean = float(per.mean())
    report.limiting = [pid for pid in report.limiting if pid not in walls]
    report.estimators = [_name_walls(e, walls) for e in report.estimators]
    if np.isfinite(report.participation):
        report.participation = min(1.0, report.participation * n_all / n_free)
    mode = getattr(report, "governing_mode", None)
    if mode is not None:  # the same ratio over the particles, and their shares (the walls hold none)
        ratio = mode.participation_ratio
        report.governing_mode = replace(mode, participation_ratio=min(1.0, ratio * n_all / n_free)
                                        if np.isfinite(ratio) else ratio, particle_share=mode.particle_share[:n_free])


_PAIR = re.compile(r"contact of particles (\d+) and (\d+)")


def _name_walls(rated, walls: set):
    """The rated estimate with a wall body's id in its detail replaced by "a wall"."""
    found = _PAIR.search(rated.estimate.detail)
    if not found or int(found.group(2)) not in walls:
        return rated
    detail = _PAIR.sub(f"contact of particle {found.group(1)} and a wall", rated.estimate.detail)
    return replace(rated, estimate=replace(rated.estimate, detail=detail))
