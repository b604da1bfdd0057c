"""Packings of non-spherical bodies from a JSON file, schema ``dtcrit-bodies/1``.

The file (UTF-8 JSON, one object)::

    {"schema": "dtcrit-bodies/1",
     "box": {"lo": [x, y, z], "hi": [x, y, z], "periodic": [true, true, false]},   (or null: no box)
     "bodies": [
       {"id": 1,
        "shape": {"shape": "ellipsoid", "semi_axes": [a, b, c], "density": 2650.0},
        "position": [x, y, z],
        "orientation": [qw, qx, qy, qz]},
       ...],
     "contacts": [{"id1": 1, "id2": 2, "kn": 1e5, "ks": 8e4}, ...]}               (optional)

* ``shape`` holds the keys of a scene's ``[[particle]]`` table (``docs/howto/step.md``, section
  "The scene format") and is read by
  the one shape parser of scenes and bodies files (``dtcrit.bodies.spec.shape_from_table``): ``shape`` is one of ``sphere`` (``radius``), ``ellipsoid`` (``semi_axes``,
  largest first), ``superquadric`` (``semi_axes``, ``exponents``), ``box`` (``half_lengths``),
  ``polyhedron`` (``vertices``), ``clump`` (``spheres`` ``[[x, y, z, r], ...]``), with exactly one
  of ``density`` [kg/m^3] or ``mass`` [kg].  A body is one particle: size distributions (``radii``,
  ``lognormal``) and the elastic constants (the contact law comes from ``contacts`` or the command
  line) are refused.
* ``position`` [m] places the origin of the frame the shape's dimensions are given in: the centre
  of a sphere, ellipsoid, superquadric or box; the origin of a polyhedron's ``vertices`` or a
  clump's ``spheres``, whose centre of mass is then at ``position + R(q) c`` (``c`` the centroid in
  that frame, ``ConvexPolyhedron.centroid``, ``Clump.centre_of_mass``).
* ``orientation`` (optional, default ``[1, 0, 0, 0]``) is the unit quaternion of the body's
  orientation, body to world, ``v_world = R(q) v_body`` (``docs/explanation/conventions.md``, "One
  rotation convention"; Peng et al. 2020, Eq. (7)); it must have unit length to 1e-6 and is then
  normalised.  Polyhedra and clumps are analysed in their principal frame, ``R(q)`` times the shape's own frame rotation.
* ``id`` distinct integers, the names bodies carry in messages and contacts.
* ``contacts`` (optional) gives each touching pair its springs ``kn``, ``ks`` [N/m].  Contact
  points and normals always come from the geometry (below); every listed pair must touch, and
  every touching pair must be listed (``kn = ks = 0`` leaves one out).  Without the list the
  command line's ``--kn/--ks`` (or ``--youngs`` for sphere and clump-member contacts) applies.

Contacts (:func:`find_body_contacts`): convex bodies by their support-function penetration
(``dtcrit.packing.detection.overlaps.find_convex_contacts``: normal along the minimum-translation
direction, contact point halfway between the two deepest support points).  A clump is its member
spheres: members of different bodies meet like convex bodies, the arms are measured from the
clump's centre of mass (contacts sit at member surfaces), and members of one clump never
touch each other.  Periodic axes use the box's images as for spheres.

Bad input raises one ``InputError`` whose key names the file and the entry,
``FILE: bodies[3].shape.semi_axes`` (its ``location`` holds the two apart): arrays of the file count from 0, as JSON does; entries inside
a shape table count from 1, as in scene files.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
import numpy as np

from dtcrit.errors import InputError
from dtcrit.inputs.arrays import booleans
from dtcrit.inputs.files import located_in, read_bounded
from dtcrit.packing.readers.bodies_values import (_fail, _integer, _keys, _numbers, _short, _stiffness)
from dtcrit.packing.detection.body_contacts import find_body_contacts
from dtcrit.packing.model import Box, Contacts, Packing
from dtcrit.packing.readers.bodies_array import read_bodies
from dtcrit.packing.readers.limits import check_inertia, check_lengths, check_rates, contact_rates

SCHEMA = "dtcrit-bodies/1"
TOP_KEYS = ("schema", "box", "bodies", "contacts")
BOX_KEYS = ("lo", "hi", "periodic")
CONTACT_KEYS = ("id1", "id2", "kn", "ks")
MAX_BYTES = 64 << 20

@dataclass(frozen=True)
class BodiesFile:
    """A read ``dtcrit-bodies/1`` file.

    Parameters
    ----------
    packing : Packing
        The bodies (``Packing.from_shapes``, or a sphere packing) with the file's ids.
    contacts : Contacts
        The geometric contacts, with the file's ``kn``/``ks`` [N/m] when ``stiffness_given``.
    stiffness_given : bool
        Whether the file lists each contact's springs.
    kinds : dict
        Shape name -> number of bodies of that shape.
    """

    packing: Packing
    contacts: Contacts
    stiffness_given: bool
    kinds: dict


def is_bodies_file(path) -> bool:
    """Whether a file is a bodies file: it starts (after blanks and a byte-order mark) with ``{``.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    bool
        True when its first character is ``{``; False otherwise or when it cannot be read.
    """
    try:
        with open(path, "rb") as handle:
            head = handle.read(4096)
    except (OSError, ValueError):
        return False
    return head.removeprefix(b"\xef\xbb\xbf").lstrip().startswith(b"{")


def _load(path: Path) -> dict:
    try:
        data = read_bounded(path, MAX_BYTES)
    except OSError as exc:
        raise _fail(str(path), f"cannot read: {exc.strerror or exc}") from None
    if len(data) > MAX_BYTES:
        raise _fail(f"{path}: bodies", f"more than {MAX_BYTES >> 20} MiB of JSON (some 450,000 spheres), more than a "
                    "bodies file holds; give a larger sphere packing as a LAMMPS dump")
    try:
        doc = json.loads(data.decode("utf-8-sig"))
    except UnicodeDecodeError as exc:
        line = data[:exc.start].count(b"\n") + 1
        raise _fail(f"{path}:{line}", f"not UTF-8 text (byte {exc.start}); a bodies file is JSON") from None
    except json.JSONDecodeError as exc:
        raise _fail(f"{path}:{exc.lineno}", f"not valid JSON: {exc.msg}") from None
    except RecursionError:
        raise _fail(f"{path}: bodies", "arrays nested too deeply: not a bodies file") from None
    if not isinstance(doc, dict):
        raise _fail(f"{path}:1", f"a {SCHEMA} file is one JSON object, found {_short(type(doc).__name__)}")
    return doc


def _box(where: str, value) -> Box | None:
    if value is None:
        return None
    if not isinstance(value, dict):
        raise _fail(where, f"expected an object with lo, hi and periodic, or null; found {_short(value)}")
    _keys(where, value, BOX_KEYS)
    for key in BOX_KEYS:
        if key not in value:
            raise _fail(f"{where}.{key}", "missing: a box needs lo, hi and periodic")
    lo, hi = _numbers(f"{where}.lo", value["lo"], 3), _numbers(f"{where}.hi", value["hi"], 3)
    periodic = booleans(f"{where}.periodic", value["periodic"], 3)
    if np.any(hi <= lo):
        raise _fail(f"{where}.hi", f"each upper bound must exceed its lower bound (lo = {lo.tolist()}, hi = {hi.tolist()})")
    return Box(lo, hi, (periodic[0], periodic[1], periodic[2]))


def _periodic_room(path, box: Box | None, packing: Packing) -> None:
    """Refuse a periodic length shorter than the largest body's bounding radius: that body would
    reach through its own nearest image into the next (and the image search would not end).
    """
    if box is None:
        return
    k = int(np.argmax(packing.radii))
    for a in range(3):
        if box.periodic[a] and box.lengths[a] < packing.radii[k]:
            raise _fail(f"{path}: box.hi", f"the periodic length along {'xyz'[a]}, {box.lengths[a]:g} m, is shorter "
                        f"than the bounding radius {packing.radii[k]:g} m of body {packing.particle_id(k)}: it would "
                        "overlap its own periodic images more than one deep; give a longer periodic box")


def _listed_stiffness(path, doc: dict, packing: Packing, contacts: Contacts) -> Contacts:
    rows = doc["contacts"]
    if not isinstance(rows, list):
        raise _fail(f"{path}: contacts", f"expected an array of {{id1, id2, kn, ks}} objects, found {_short(rows)}")
    assert packing.ids is not None  # a bodies file's packing carries the file's ids
    index = {int(b): k for k, b in enumerate(packing.ids)}
    pairs = [frozenset((int(packing.ids[a]), int(packing.ids[b]))) for a, b in zip(contacts.i, contacts.j)]
    springs: dict = {}
    for k, row in enumerate(rows):
        where = f"{path}: contacts[{k}]"
        if not isinstance(row, dict):
            raise _fail(where, f"expected an object with id1, id2, kn and ks, found {_short(row)}")
        _keys(where, row, CONTACT_KEYS)
        for key in CONTACT_KEYS:
            if key not in row:
                raise _fail(f"{where}.{key}", "missing: a contact needs id1, id2, kn and ks")
        ids = []
        for key in ("id1", "id2"):
            bid = _integer(f"{where}.{key}", row[key])
            if bid not in index:
                raise _fail(f"{where}.{key}", f"no body has id {bid}")
            ids.append(bid)
        pair = frozenset(ids)
        if pair in springs:
            raise _fail(where, f"bodies {ids[0]} and {ids[1]} are already listed in contacts[{springs[pair][0]}]")
        if pair not in pairs:
            raise _fail(where, f"bodies {ids[0]} and {ids[1]} do not touch (no penetration between their surfaces)")
        springs[pair] = (k, _stiffness(f"{where}.kn", row["kn"]), _stiffness(f"{where}.ks", row["ks"]))
    missing = [p for p in pairs if p not in springs]
    if missing:
        a, b = (sorted(missing[0]) * 2)[:2] if len(missing[0]) == 1 else sorted(missing[0])
        raise _fail(f"{path}: contacts", f"bodies {a} and {b} touch but are not listed; list every touching pair "
                    "(kn = ks = 0 leaves one out)")
    kn = np.array([springs[p][1] for p in pairs])
    ks = np.array([springs[p][2] for p in pairs])
    rate = contact_rates(packing.masses, packing.inertia, contacts.i, contacts.j, contacts.arm_i, contacts.arm_j,
                         np.maximum(kn, ks))
    check_rates(rate, lambda c: f"{path}: contacts[{springs[pairs[c]][0]}]")
    return contacts.with_stiffness(kn, ks)


def load_bodies(doc, path, tolerance: float = 1e-9) -> BodiesFile:
    """Validate a parsed ``dtcrit-bodies/1`` document and build it.

    Parameters
    ----------
    doc : Any
        The parsed JSON document.
    path : str or pathlib.Path
        The file it was read from, naming it in messages (and ``InputError.location.source``).
    tolerance : float
        Relative tolerance of the convex contact search (``find_body_contacts``).

    Returns
    -------
    BodiesFile
        The packing, its contacts and the count of each shape.
    """
    with located_in(path):
        return _load_bodies(doc, path, tolerance)


def _load_bodies(doc, path, tolerance: float) -> BodiesFile:
    if not isinstance(doc, dict):
        raise _fail(str(path), f"a {SCHEMA} file is one JSON object")
    if doc.get("schema") != SCHEMA:
        raise _fail(f"{path}: schema", f"expected {SCHEMA!r}, found {_short(doc.get('schema'))}")
    for key in doc:
        if key not in TOP_KEYS:
            raise _fail(f"{path}: {key}", f"unknown key; valid keys here: {', '.join(TOP_KEYS)}")
    if "box" not in doc:
        raise _fail(f"{path}: box", "missing: give the box object, or null for none")
    box = _box(f"{path}: box", doc["box"])
    if box is not None:
        check_lengths(np.vstack([box.lo, box.hi]).T, lambda a: f"{path}: box", "a bound")
    packing, kinds = read_bodies(path, doc, box)
    check_lengths(packing.radii, lambda k: f"{path}: bodies[{k}].shape", "the bounding radius")
    check_inertia(packing.masses, lambda k: f"{path}: bodies[{k}].shape", "the mass [kg]")
    check_inertia(packing.inertia, lambda k: f"{path}: bodies[{k}].shape", "a principal moment of inertia [kg m^2]")
    _periodic_room(path, box, packing)
    try:
        contacts = find_body_contacts(packing, tolerance)
    except InputError as exc:
        raise _fail(f"{path}: bodies", exc.reason) from None
    given = doc.get("contacts") is not None
    if given:
        contacts = _listed_stiffness(path, doc, packing, contacts)
    return BodiesFile(packing, contacts, given, kinds)


def read_bodies_file(path, tolerance: float = 1e-9) -> BodiesFile:
    """Read and validate a ``dtcrit-bodies/1`` file (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    tolerance : float
        Relative tolerance of the convex contact search (``find_body_contacts``).

    Returns
    -------
    BodiesFile
        The packing, its contacts and the count of each shape.
    """
    with located_in(path):
        doc = _load(Path(path))
    return load_bodies(doc, path, tolerance)
