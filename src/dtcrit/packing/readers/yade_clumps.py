"""YADE clumps (and spheres) in a ``dtcrit-yade-export/1`` file as rigid bodies, and the kinematics of
their contacts as YADE integrates them.

**Bodies.**  A clump (``is_clump``) is one rigid body with its exported ``mass``, principal ``inertia``
and orientation ``ori`` ``[w, x, y, z]`` (body to global: YADE places a member at
``pos + ori * relPos``, ``Clump::moveMembers``).  Its members (``clump_id``) are not bodies of their
own: each is a sphere at ``d = x_member - x_clump`` from the clump's centre of mass.  A free sphere is
a body whose only "member" is itself (``d = 0``).  The packing's ``radii`` are bounding radii,
``max |d| + r`` over the members.

**Contacts** (YADE sources, ``pkg/dem/``).  YADE's interactions join two member spheres; one inside
a clump is dropped (the collider makes none).  With ``R_1``, ``R_2`` the members' radii, ``n`` their
centre line, ``delta`` the overlap:

* force side: ``Ig2_Sphere_Sphere_ScGeom`` puts the contact point at ``x_m1 + (R_1 - delta/2) n``;
  the Law2 functors apply the force there on the member, and ``Clump::addForceTorqueFromMembers``
  adds ``(x_m - x_clump) x f`` to the clump's torque: the torque arms are
  ``a_1 = d_1 + (R_1 - delta/2) n``, ``a_2 = d_2 - (R_2 - delta/2) n``;
* velocity side: a member moves with ``v_m = V + Omega x d``, ``omega_m = Omega``
  (``Clump::moveMembers``), and ``ScGeom::getIncidentVel`` with ``avoidGranularRatcheting`` (the
  default) takes ``alpha (v_m2 - v_m1) - R_2 omega_m2 x n - R_1 omega_m1 x n``,
  ``alpha = (R_1 + R_2)/(R_1 + R_2 - delta)``: that is ``alpha`` times the relative velocity of the
  points ``b_1 = d_1 + (R_1/alpha) n`` and ``b_2 = d_2 - (R_2/alpha) n``.  Without the ratcheting
  correction the velocity is taken at the contact point (``b = a``, ``alpha = 1``);
* the normal spring acts on the members' centre distance, ``n . (u_m2 - u_m1)``: any arm
  ``d + s n`` gives it, so only the shear spring sees the difference between ``a`` and ``b``.

Linearised, the shear element is ``alpha k_s B_a^T (1 - n n^T) B_b`` -- not symmetric when
``a != b``.  dtcrit takes its symmetric equivalent, arms ``e_i = d_i +- m_i n`` with
``m_i = sqrt((R_i - delta/2) R_i/alpha)`` and shear stiffness ``alpha k_s`` (for a free sphere,
``d = 0``, this is ``dtcrit.packing.conventions.engines``' ``"yade"`` convention).  Its error: ``a_i - b_i =
c n`` on both bodies with ``c = delta (R_1 - R_2)/(2 (R_1 + R_2))``, and ``e_i`` lies halfway
between them up to ``O(c^2/R)``.  It is **exact when the two touching members have equal radii**
(``c = 0``: ``a = b = e``).  Otherwise YADE's element equals the symmetric one plus an
antisymmetric part of relative order ``c/R``, which moves no eigenvalue at first order, and a
symmetric part of order ``(c/R)^2``: for ``delta/R = 1e-2`` and radii differing by a factor two,
``(c/R)^2 < 1e-5``.

**Pre-load.**  A pre-loaded contact between two free spheres keeps its geometric stiffness
``-(F/r)(1 - n n^T)`` (``dtcrit.packing.operators.assembly``).  For a contact with a clump the normal force
also turns with the member arms (torque terms ``F ((n . d) 1 - d n^T)`` not carried by the
assembly); those contacts enter without pre-load.  The terms dropped are of the relative size of
the overlap strain ``delta/(R_1 + R_2)`` times ``(1 + |d|/R)^2``, and are not signed: on a YADE packing
of 24 dumbbells at a mean overlap of 9e-4 R (``tests/engines/test_engine_yade_clumps_springs_bonds.py``) the step lies
2.1e-4 to 2.8e-4 *above* YADE's bisected threshold, while the clump pair, whose preload cancels
the geometric stiffness, lands inside its 1.3e-3 bracket.  Until the assembly carries the clump
pre-load, keep a safety factor of at least 0.99 on clump packings.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.inputs.arrays import triple as _triple
from dtcrit.inputs.text import show
from dtcrit.inputs.values import finite as _finite
from dtcrit.inputs.values import whole
from dtcrit.numerics.rotations import unit_body_to_world_matrix
from dtcrit.packing.model import Box, Contacts
from dtcrit.packing.periodic_cell import fractional, image_of, nearest_image
from dtcrit.packing.readers.limits import check_inertia, check_lengths, check_rates, contact_rates

TERMS = ("kn", "ks", "kr", "ktw", "cn", "cs", "fn")


def rotation_from_quaternion(where: str, wxyz) -> np.ndarray:
    """Body-to-global rotation matrix of a quaternion ``[w, x, y, z]`` (normalised here).

    ``v_global = R v_body`` (YADE's ``Quaternion`` ``ori``; ``docs/explanation/conventions.md``,
    "One rotation convention").

    Parameters
    ----------
    where : str
        The quaternion's location, named in errors.
    wxyz : Any
        The quaternion as read: four finite numbers, not all zero.

    Returns
    -------
    numpy.ndarray
        The ``3 x 3`` rotation matrix.
    """
    q = _triple(where, wxyz, 4)
    with np.errstate(over="ignore"):
        norm = float(np.linalg.norm(q))
    if norm == 0.0:
        raise InputError(where, "a zero quaternion is no orientation")
    if not math.isfinite(norm):
        raise InputError(where, "the quaternion's length overflows double precision; give [w, x, y, z] near unit length")
    return unit_body_to_world_matrix(q / norm)


@dataclass(frozen=True)
class RigidBodies:
    """The rigid bodies of an export (module docstring).

    Parameters
    ----------
    ids : numpy.ndarray
        The engine ids.
    positions : numpy.ndarray
        The centres of mass [m], as exported.
    masses : numpy.ndarray
        The masses [kg].
    inertia : numpy.ndarray
        The principal moments [kg m^2], ``(bodies, 3)``.
    rotations : numpy.ndarray
        The body-to-global rotations, ``(bodies, 3, 3)``.
    radii : numpy.ndarray
        The bounding radii [m], ``max |d| + r`` over the members.
    fixed : numpy.ndarray
        Whether each body is fixed (all degrees of freedom blocked).
    members : dict
        Every sphere's export id -> ``(body index, centre, radius)``.
    is_clump : numpy.ndarray
        Whether each body is a clump.
    """

    ids: np.ndarray
    positions: np.ndarray
    masses: np.ndarray
    inertia: np.ndarray
    rotations: np.ndarray
    radii: np.ndarray
    fixed: np.ndarray
    members: dict
    is_clump: np.ndarray

    @property
    def clumps(self) -> int:
        """The number of clumps among the bodies."""
        return int(self.is_clump.sum())


def _one_body(where: str, b, rows: list, members: dict, clump_index: dict, pending: list) -> int:
    """Read one exported body into ``rows`` (bodies), ``members`` (spheres) or ``pending`` (members);
    returns its id.
    """
    if not isinstance(b, dict):
        raise InputError(where, f"expected an object, found {show(b)}")
    bid = whole(f"{where}.id", b.get("id"))
    pos = _triple(f"{where}.pos", b.get("pos"))
    check_lengths(pos[None], lambda k: f"{where}.pos", "a coordinate")
    if isinstance(b.get("radius"), (int, float)) and not isinstance(b.get("radius"), bool):
        check_lengths([_finite(f"{where}.radius", b["radius"], positive=True)], lambda k: f"{where}.radius", "the radius")
    if b.get("is_clump"):
        rot = rotation_from_quaternion(f"{where}.ori", b.get("ori"))
    elif b.get("clump_id") is not None:
        pending.append((where, bid, whole(f"{where}.clump_id", b["clump_id"]), pos,
                        _finite(f"{where}.radius", b.get("radius"), positive=True)))
        return bid
    elif b.get("radius") is None:
        raise InputError(where, "only spheres and clumps of spheres are analysed (this body has no radius)")
    else:
        rot = np.eye(3)
        members[bid] = (len(rows), pos, _finite(f"{where}.radius", b["radius"], positive=True))
    inertia = _triple(f"{where}.inertia", b.get("inertia"), positive=True)
    check_inertia(inertia[None], lambda k: f"{where}.inertia", "a principal moment of inertia [kg m^2]")
    check_inertia([_finite(f"{where}.mass", b.get("mass"), positive=True)], lambda k: f"{where}.mass", "the mass [kg]")
    if b.get("is_clump"):
        clump_index[bid] = len(rows)
    rows.append((bid, pos, _finite(f"{where}.mass", b.get("mass"), positive=True), inertia, rot,
                 0.0 if b.get("is_clump") else members[bid][2], bool(b.get("fixed"))))
    return bid


def rigid_bodies(bodies: list, path) -> RigidBodies:
    """Clumps and free spheres of the export's ``bodies`` list; members become part of their clump.

    Parameters
    ----------
    bodies : list
        The export's ``bodies`` entries as read.
    path : str or pathlib.Path
        The export, naming it in errors.

    Returns
    -------
    RigidBodies
        The rigid bodies.
    """
    rows: list[tuple] = []
    members: dict[int, tuple] = {}
    clump_index: dict[int, int] = {}
    pending: list[tuple] = []
    seen: dict[int, int] = {}
    for k, b in enumerate(bodies):
        where = f"{path}: bodies[{k}]"
        bid = _one_body(where, b, rows, members, clump_index, pending)
        if bid in seen:
            raise InputError(f"{where}.id", f"id {bid} is already used by bodies[{seen[bid]}]")
        seen[bid] = k
    if not rows:
        raise InputError(f"{path}: bodies", "no free sphere or clump: every body is a member of a missing clump")
    reach = [row[5] for row in rows]
    for where, bid, cid, pos, radius in pending:
        if cid not in clump_index:
            raise InputError(f"{where}.clump_id", f"clump {cid} is not an exported clump body")
        body = clump_index[cid]
        members[bid] = (body, pos, radius)
        with np.errstate(over="ignore", invalid="ignore"):
            reach[body] = max(reach[body], float(np.linalg.norm(pos - rows[body][1])) + radius)
    empty = [cid for cid, body in clump_index.items() if reach[body] == 0.0]
    if empty:
        raise InputError(f"{path}: bodies", f"clump {empty[0]} has no exported member spheres")
    bad = [k for k, r in enumerate(reach) if not math.isfinite(r)]
    if bad:
        raise InputError(f"{path}: bodies", f"the members of clump {rows[bad[0]][0]} reach beyond double precision")
    ids, x, m, inertia, rot, _, fixed = (list(c) for c in zip(*rows))
    is_clump = np.zeros(len(rows), dtype=np.bool_)
    is_clump[list(clump_index.values())] = True
    return RigidBodies(np.array(ids), np.array(x), np.array(m), np.array(inertia), np.array(rot), np.array(reach),
                       np.array(fixed), members, is_clump)


def _terms(where: str, it: dict) -> dict:
    out: dict[str, float | None] = {}
    for key in TERMS:
        value = it.get(key)
        if key == "fn" and isinstance(value, (int, float)) and not isinstance(value, bool) and value < 0:
            out[key] = -_finite(f"{where}.fn", -value)  # a bond in tension: negative normal force
        else:
            out[key] = _finite(f"{where}.{key}", value, allow_none=key not in ("kn", "ks"))
    kn = out["kn"]
    if out["fn"] is None and kn is not None:  # linear law: the normal force is kn times the penetration (kn is required)
        out["fn"] = kn * _finite(f"{where}.penetration", it.get("penetration", 0.0), signed=True)
    return out


def _whole_cells(where: str, box: Box | None, shift: np.ndarray) -> None:
    """Refuse a ``shift2`` that is not ``hSize cellDist`` (whole cell vectors) of the export's cell."""
    if box is None:
        return
    n = fractional(box, shift)
    if np.abs(n - np.rint(n)).max() > 1e-6:
        raise InputError(f"{where}.shift2", f"{shift.tolist()} is not a whole number of cell vectors of cell_hsize "
                                            f"(hSize^-1 shift2 = {n.tolist()})")


def yade_contacts(bodies: RigidBodies, interactions: list, path, *, box: Box | None, wrapped: np.ndarray,
                  ratcheting: bool = True) -> Contacts:
    """Contacts between the rigid bodies with YADE's kinematics (module docstring).

    Parameters
    ----------
    bodies : RigidBodies
        The bodies (:func:`rigid_bodies`).
    interactions : list
        The export's ``interactions`` entries as read.
    path : str or pathlib.Path
        The export, naming it in errors.
    box : Box or None
        The periodic cell, if any.
    wrapped : numpy.ndarray
        The packing's positions (the exported ones mapped into the periodic cell).
    ratcheting : bool
        YADE's ``avoidGranularRatcheting`` (its default: on).

    Returns
    -------
    Contacts
        The contacts: arms, ``alpha k_s``, per-contact ``kr``, ``ktw``, ``cn``, ``cs`` and the pre-load
        of sphere-sphere contacts.
    """
    rows = []
    for k, it in enumerate(interactions):
        where = f"{path}: interactions[{k}]"
        if not isinstance(it, dict):
            raise InputError(where, f"expected an object, found {show(it)}")
        a, b = whole(f"{where}.id1", it.get("id1")), whole(f"{where}.id2", it.get("id2"))
        for key, bid in (("id1", a), ("id2", b)):
            if bid not in bodies.members:
                raise InputError(where, f"{key} {bid} is not the id of an exported sphere (free or clump member)")
        (p, x1, r1), (q, x2, r2) = bodies.members[a], bodies.members[b]
        if p == q:
            continue  # inside one clump: no spring between parts of one rigid body
        sep = x2 - x1
        if it.get("shift2") is not None:
            shift = _triple(f"{where}.shift2", it["shift2"])
            _whole_cells(where, box, shift)
        elif box is not None:
            shift = box.shift(nearest_image(box, sep[None]))[0]
        else:
            shift = np.zeros(3)
        sep = sep + shift
        with np.errstate(over="ignore", invalid="ignore"):
            dist = float(np.linalg.norm(sep))
        if dist == 0.0:
            raise InputError(where, f"spheres {a} and {b} have coincident centres")
        if not math.isfinite(dist):
            raise InputError(where, f"spheres {a} and {b} are further apart than double precision holds")
        if dist > 2.0 * (r1 + r2):  # a bond stretched beyond its spheres' size: no contact geometry left
            raise InputError(where, f"spheres {a} and {b} are {dist:g} m apart, more than twice the sum of their "
                                    "radii: not a contact or bond of touching spheres")
        if r1 + r2 - dist >= 2.0 * min(r1, r2):  # then R - delta/2 < 0: the arm points backwards
            raise InputError(where, f"spheres {a} and {b} overlap by {r1 + r2 - dist:g} m, at least the smaller "
                                    "diameter (one lies inside the other): not a contact")
        rows.append((p, q, sep / dist, r1 + r2 - dist, r1, r2, x1 - bodies.positions[p], x2 - bodies.positions[q],
                     shift, _terms(where, it), k))
    if not rows:
        raise InputError(f"{path}: interactions", "no interactions between bodies: no contact limits the step")
    p, q = np.array([r[0] for r in rows], np.int64), np.array([r[1] for r in rows], np.int64)
    n = np.array([r[2] for r in rows])
    delta, r1, r2 = (np.array([r[c] for r in rows]) for c in (3, 4, 5))
    d1, d2, shift = (np.array([r[c] for r in rows]) for c in (6, 7, 8))
    col = {key: np.array([0.0 if r[9][key] is None else r[9][key] for r in rows]) for key in TERMS}
    alpha = (r1 + r2) / (r1 + r2 - delta) if ratcheting else np.ones_like(delta)
    force_side1, force_side2 = r1 - 0.5 * delta, r2 - 0.5 * delta
    m1 = np.sqrt(force_side1 * (r1 / alpha if ratcheting else force_side1))
    m2 = np.sqrt(force_side2 * (r2 / alpha if ratcheting else force_side2))
    image = np.zeros((len(rows), 3), np.int64)
    if box is not None:  # x_q + shift - x_p in the packing's wrapped positions
        moved = wrapped - bodies.positions
        image = image_of(box, shift + moved[p] - moved[q])
    contacts = Contacts(i=p, j=q, normal=n, arm_i=d1 + m1[:, None] * n, arm_j=d2 - m2[:, None] * n,
                        overlap=np.maximum(delta, 0.0), image=image, radius_eff=r1 * r2 / (r1 + r2))
    ks = alpha * col["ks"]
    contacts = contacts.with_stiffness(col["kn"], ks, col["kr"], col["ktw"])
    free = ~bodies.fixed
    with np.errstate(over="ignore"):  # an overflowing F/d is refused below
        preload = np.abs(col["fn"]) / (r1 + r2 - delta)
    rate = contact_rates(np.where(free, bodies.masses, np.inf), np.where(free[:, None], bodies.inertia, np.inf), p, q,
                         contacts.arm_i, contacts.arm_j, np.maximum(np.maximum(col["kn"], ks), preload),
                         np.maximum(np.abs(col["kr"]), np.abs(col["ktw"])), np.maximum(col["cn"], col["cs"]))
    check_rates(rate, lambda c: f"{path}: interactions[{rows[c][10]}]")
    both_free = ~bodies.is_clump[p] & ~bodies.is_clump[q]
    return contacts.with_damping(col["cn"], col["cs"]).with_normal_force(np.where(both_free, col["fn"], 0.0))
