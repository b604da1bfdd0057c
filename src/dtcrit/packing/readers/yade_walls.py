"""YADE ``Wall`` and ``Facet`` bodies of a ``dtcrit-yade-export/1`` file and their contacts with spheres.

The export (``dtcrit/engine_scripts/yade_export.py``) writes each body's ``shape`` (``Wall`` with
``axis``, ``sense``; ``Facet`` with its global ``vertices``) and, at the top level, ``wall_no_ratch``
(``Ig2_Wall_Sphere_ScGeom.noRatch``, on by default).  A wall or facet is a fixed body of infinite
mass (``dtcrit.packing.wall_bodies``); one that YADE integrates (``dynamic``) is refused.

A sphere-wall interaction keeps YADE's own ``kn``, ``ks`` (and ``cn``, ``cs``, ``kr``, ``ktw``) and takes
YADE's kinematics (:func:`dtcrit.physics.walls.yade_wall_arm`): the force acts at the exported
contact point (``R - delta`` from the centre on a Wall, ``R - delta/2`` on a Facet), the slip
velocity of a Wall contact carries the ratcheting correction with ``refR1``, ``refR2``; the symmetric
equivalent arm ``sqrt(force side x velocity side)`` and ``alpha k_s`` enter.  A Wall's normal is
fixed and so is a facet face's: their contacts carry no geometric stiffness.  On a facet's edge or
vertex the normal turns with the sphere (a destabilising ``-F/(R - delta)``), which is left out: the
step is then the smaller (safe) one of the two.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.errors import InputError
from dtcrit.inputs.arrays import triple as _triple
from dtcrit.inputs.text import show
from dtcrit.inputs.values import finite as _finite
from dtcrit.inputs.values import whole
from dtcrit.packing.contact_set import Contacts
from dtcrit.packing.model import Packing
from dtcrit.packing.wall_bodies import FIXED_FACTOR, concatenate
from dtcrit.physics.walls import yade_wall_arm

SHAPES = ("Wall", "Facet")
TERMS = ("kn", "ks", "kr", "ktw", "cn", "cs")

__all__ = ["SHAPES", "split_walls", "add_yade_walls"]


def split_walls(bodies: list, interactions: list, path) -> tuple[list, list, dict, list]:
    """Separate the Wall and Facet bodies, and their interactions, from the rest of an export.

    Parameters
    ----------
    bodies, interactions : list
        The export's entries as read.
    path : str or pathlib.Path
        The export, naming it in errors.

    Returns
    -------
    tuple
        ``(other bodies, other interactions, walls {id: (entry index, body)}, wall interactions
        [(entry index, interaction)])``.
    """
    walls: dict[int, tuple[int, dict]] = {}
    rest = []
    for k, b in enumerate(bodies):
        if isinstance(b, dict) and b.get("shape") in SHAPES:
            where = f"{path}: bodies[{k}]"
            if not b.get("fixed"):
                raise InputError(where, f"a {b['shape']} that YADE moves as a free body: a moving wall is not modelled")
            walls[whole(f"{where}.id", b.get("id"))] = (k, b)
        else:
            rest.append(b)
    if not walls:
        return bodies, interactions, walls, []
    other, touching = [], []
    for k, it in enumerate(interactions):
        ids = (it.get("id1"), it.get("id2")) if isinstance(it, dict) else ()
        if any(isinstance(v, int) and not isinstance(v, bool) and v in walls for v in ids):
            touching.append((k, it))
        else:
            other.append(it)
    return rest, other, walls, touching


def _one(where: str, it: dict, walls: dict, members: dict) -> tuple:
    a, b = whole(f"{where}.id1", it.get("id1")), whole(f"{where}.id2", it.get("id2"))
    if (a in walls) == (b in walls):
        raise InputError(where, "an interaction between two walls or facets: not a sphere contact")
    sphere, wall, sign = (b, a, -1.0) if a in walls else (a, b, 1.0)  # sign turns the normal towards the wall
    if sphere not in members:
        raise InputError(where, f"body {sphere} is not an exported sphere (free or clump member)")
    body, centre, radius = members[sphere]
    n = _triple(f"{where}.normal", it.get("normal"))
    norm = float(np.linalg.norm(n))
    if not norm > 0:
        raise InputError(f"{where}.normal", "a zero normal")
    n = sign * n / norm
    point = _triple(f"{where}.point", it.get("point"))
    delta = _finite(f"{where}.penetration", it.get("penetration"), signed=True)
    if delta is None or not delta < radius:
        raise InputError(f"{where}.penetration", f"expected an overlap below the sphere's radius, found {show(delta)}")
    opening = delta < 0.0  # real until YADE erases it: kept with its springs at zero overlap, as sphere pairs are
    delta = max(delta, 0.0)
    refs = [_finite(f"{where}.radius{s}", it.get(f"radius{s}"), positive=True) for s in (1, 2)]
    terms = {key: _finite(f"{where}.{key}", it.get(key), allow_none=key not in ("kn", "ks")) for key in TERMS}
    shape = walls[wall][1].get("shape")
    force_side = float(np.linalg.norm(point - centre))
    if not (0.0 < force_side <= radius * (1 + 1e-9) or (opening and force_side > 0.0)):
        raise InputError(f"{where}.point", f"the contact point lies {force_side:g} m from the sphere's centre, "
                                           f"not within its radius {radius:g} m")
    force_side = min(force_side, radius)
    return body, centre, radius, wall, shape, n, delta, refs, force_side, terms


def add_yade_walls(packing: Packing, contacts: Contacts, members: dict, walls: dict, touching: list, path,
                   no_ratch: bool, origins: np.ndarray, free: np.ndarray) -> tuple[Packing, Contacts, int]:
    """The packing with the walls and facets appended as fixed bodies, and their contacts added.

    Parameters
    ----------
    packing : Packing
        The export's rigid bodies (spheres, clumps).
    contacts : Contacts
        Their contacts with one another.
    members : dict
        Every sphere's id -> ``(body index, centre, radius)`` (``yade_clumps.RigidBodies.members``).
    walls : dict
        The wall bodies of :func:`split_walls`.
    touching : list
        Their interactions (:func:`split_walls`).
    path : str or pathlib.Path
        The export, naming it in errors.
    no_ratch : bool
        ``Ig2_Wall_Sphere_ScGeom.noRatch``.
    origins : numpy.ndarray
        The bodies' exported centres of mass (unwrapped), from which members sit.
    free : numpy.ndarray
        Which bodies are free (the walls are as heavy as ``FIXED_FACTOR`` times the heaviest of them).

    Returns
    -------
    tuple
        ``(packing, contacts, number of wall bodies)``.
    """
    order = sorted(walls)
    index = {bid: packing.n + k for k, bid in enumerate(order)}
    positions = np.array([_triple(f"{path}: bodies[{walls[b][0]}].pos", walls[b][1].get("pos")) for b in order])
    rows = [_one(f"{path}: interactions[{k}]", it, walls, members) for k, it in touching]
    big_m, big_i = FIXED_FACTOR * float(packing.masses[free].max()), FIXED_FACTOR * float(packing.inertia[free].max())
    if not (math.isfinite(big_m) and math.isfinite(big_i)):
        raise InputError(f"{path}: bodies", "a wall enters 1e150 times heavier than the heaviest body, which overflows")
    c, w = len(rows), len(order)
    grown = Packing(np.concatenate([packing.positions, positions]), np.concatenate([packing.masses, np.full(w, big_m)]),
                    np.concatenate([packing.inertia, np.full((w, 3), big_i)]),
                    np.concatenate([packing.radii, np.full(w, float(packing.radii.max()))]), box=packing.box,
                    orientations=None if packing.orientations is None
                    else np.concatenate([packing.orientations, np.repeat(np.eye(3)[None], w, 0)]),
                    half_lengths=None if packing.half_lengths is None
                    else np.concatenate([packing.half_lengths, np.full((w, 3), float(packing.radii.max()))]),
                    label=packing.label, ids=None if packing.ids is None else np.concatenate([packing.ids, order]))
    if not c:
        return grown, contacts, w
    body = np.array([r[0] for r in rows], np.int64)
    n = np.array([r[5] for r in rows])
    radius, delta, force_side = (np.array([r[k] for r in rows]) for k in (2, 6, 8))
    ref1, ref2 = (np.array([r[7][s] for r in rows]) for s in (0, 1))
    ratchet = np.array([r[4] == "Wall" and no_ratch for r in rows])
    arm, alpha = yade_wall_arm(radius, delta, ref1, ref2, force_side, ratchet)
    offset = np.array([r[1] for r in rows]) - origins[body]  # a clump member's place in its clump
    arm_i = offset + arm[:, None] * n
    j = np.array([index[r[3]] for r in rows], np.int64)
    point = packing.positions[body] + arm_i
    col = {key: np.array([0.0 if r[9][key] is None else r[9][key] for r in rows]) for key in TERMS}
    mine = Contacts(i=body, j=j, normal=n, arm_i=arm_i, arm_j=point - grown.positions[j], overlap=delta,
                    image=np.zeros((c, 3), np.int64), radius_eff=radius)
    mine = mine.with_stiffness(col["kn"], alpha * col["ks"], col["kr"], col["ktw"]).with_damping(col["cn"], col["cs"])
    mine = mine.with_normal_force(0.0)
    return grown, concatenate(contacts, mine), w
