"""Read the YADE export (``dtcrit-yade-export/1``) that ``dtcrit/engine_scripts/yade_export.py`` writes
inside YADE: bodies (id, position, radius, mass, principal inertia, fixed) and the real interactions
with YADE's own per-contact ``kn``, ``ks`` (and ``kr``, ``ktw``, ``cn``, ``cs`` when its physics has them).

A fixed body (all degrees of freedom blocked) is a wall to the others: it enters with an inertia
``FIXED_INERTIA`` times the largest free one, which leaves the free bodies' frequencies unchanged to
~1e-150 relative.  The periodic cell may be sheared (``cell_hsize`` off the diagonal).

Two readers:

* ``read_yade_export`` -- spheres only: the packing and the exported contacts with centre-line arms,
  for ``dtcrit.packing.conventions.engines.with_arms(..., "yade")`` to apply YADE's kinematics;
* ``read_yade_audit`` -- any export, clumps included (``dtcrit.packing.readers.yade_clumps``): each clump one
  rigid body, the contacts already carrying YADE's kinematics (arms from each body's centre of
  mass, ``alpha k_s``); for a sphere-only export with ``avoidGranularRatcheting`` on (YADE's default)
  it gives what ``with_arms`` gives on ``read_yade_export``'s contacts, and it also follows the
  export's ``avoid_granular_ratcheting`` when that is off.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError

from dtcrit.packing.conventions.engines import overlaps_of_pairs
from dtcrit.packing.model import Box, Contacts, Packing
from dtcrit.packing.periodic_cell import wrap
from dtcrit.packing.readers.limits import check_inertia, check_lengths
from dtcrit.packing.readers.yade_terms import cell_strain_rate, check_export_terms
from dtcrit.inputs.arrays import triple as _triple
from dtcrit.inputs.files import line_of, located_in
from dtcrit.inputs.text import show
from dtcrit.inputs.values import finite as _finite
from dtcrit.inputs.values import whole

SCHEMA = "dtcrit-yade-export/1"
FIXED_INERTIA = 1e300


def _box(doc: dict, path: Path) -> Box | None:
    if not doc.get("periodic"):
        return None
    h = doc.get("cell_hsize")
    if not isinstance(h, list) or len(h) != 3:
        raise InputError(f"{path}: cell_hsize", f"a periodic export needs the 3 x 3 cell_hsize, found {show(h)}")
    cell = np.array([_triple(f"{path}: cell_hsize[{a}]", row) for a, row in enumerate(h)])
    check_lengths(cell, lambda a: f"{path}: cell_hsize[{a}]", "a cell vector component")
    for a in range(3):
        if not cell[a, a] > 0:
            raise InputError(f"{path}: cell_hsize[{a}][{a}]", f"the cell length must be positive, found {cell[a, a]:g}")
    try:  # columns are the cell vectors (sheared: off-diagonal terms); images are hSize * cellDist
        return Box(np.zeros(3), np.diag(cell).copy(), (True, True, True), cell=cell)
    except InputError as exc:
        raise InputError(f"{path}: cell_hsize", exc.reason) from None


def _wrapped(box: Box, x: np.ndarray) -> np.ndarray:
    """Positions moved by whole cell vectors into the periodic cell (any shear)."""
    return np.mod(x, box.lengths) if box.cell is None else wrap(box, x)


_SCHEMA_KEY = re.compile(rb'"schema"\s*:\s*"([^"\\]{0,80})"')


def check_schema(path) -> None:
    """Refuse, before anything else is read, a JSON file whose ``schema`` names another format.

    The schema is looked for in the file's first 64 KiB (both writers put it first).

    Parameters
    ----------
    path : str or pathlib.Path
        The file to check; an unreadable one passes (the reader says why).
    """
    path = Path(path)
    try:
        with path.open("rb") as handle:
            head = handle.read(1 << 16)
    except OSError:
        return  # the reader says why
    found = _SCHEMA_KEY.search(head)
    if found and found.group(1) != SCHEMA.encode():
        name = found.group(1).decode("utf-8", "replace")
        why = (": a file of bodies, which dtcrit packing reads (dtcrit audit reads dumps and YADE exports)"
               if name == "dtcrit-bodies/1" else "")
        raise InputError("schema", f"expected {SCHEMA!r} (written by yade_export.py), found {name!r}{why}", source=path)


def _load(path: Path) -> tuple[dict, list, list]:
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(str(path), f"cannot read: {exc.strerror or exc}") from None
    try:
        doc = json.loads(data.decode("utf-8-sig"))
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}:{line_of(data, exc.start)}", "not UTF-8 text: not a JSON YADE export") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}:{exc.lineno}", f"not valid JSON ({exc.msg}): not a YADE export") from None
    except RecursionError:
        raise InputError(f"{path}: bodies", "arrays nested too deeply: not a YADE export") from None
    if not isinstance(doc, dict):
        raise InputError(f"{path}:1", f"a {SCHEMA} export is one JSON object, found {show(type(doc).__name__)}")
    if doc.get("schema") != SCHEMA:
        found = doc.get("schema")
        why = (": a file of bodies, which dtcrit packing reads (dtcrit audit reads dumps and YADE exports)"
               if found == "dtcrit-bodies/1" else "")
        raise InputError(f"{path}: schema", f"expected {SCHEMA!r} (written by yade_export.py), found {show(found)}{why}")
    bodies, inters = doc.get("bodies"), doc.get("interactions")
    if not isinstance(bodies, list) or not bodies:
        raise InputError(f"{path}: bodies", f"the export needs a non-empty 'bodies' list, found {show(bodies)}")
    if not isinstance(inters, list):
        raise InputError(f"{path}: interactions", f"the export needs an 'interactions' list, found {show(inters)}")
    check_export_terms(doc, path)  # every setting the audit does not model, refused naming it
    return doc, bodies, inters


def _meta(doc: dict, path: Path) -> dict:
    """The export's run data: ``dt`` [s] (positive) and ``newton_damping`` (in [0, 1)) when given,
    ``iter`` a whole number, ``yade_version`` a string.
    """
    dt = _finite(f"{path}: dt", doc.get("dt"), positive=True, allow_none=True)
    damping = _finite(f"{path}: newton_damping", doc.get("newton_damping"), allow_none=True)
    if damping is not None and damping >= 1.0:
        raise InputError(f"{path}: newton_damping", f"must lie in [0, 1), found {show(damping)}")
    it = doc.get("iter")
    if it is not None and (isinstance(it, bool) or not isinstance(it, int)):
        raise InputError(f"{path}: iter", f"expected the iteration number, found {show(it)}")
    version = doc.get("yade_version")
    if version is not None and not isinstance(version, str):
        raise InputError(f"{path}: yade_version", f"expected a string, found {show(version)}")
    return {"dt": dt, "iter": it, "yade_version": version, "newton_damping": damping}


def _heavy(path: Path, values: np.ndarray, fixed: np.ndarray, what: str) -> np.ndarray:
    """``values`` with the fixed bodies' set to ``FIXED_INERTIA`` times the largest free one."""
    with np.errstate(over="ignore"):
        big = FIXED_INERTIA * values[~fixed].max()
    if not np.isfinite(big):
        raise InputError(f"{path}: bodies", f"a fixed body enters with {FIXED_INERTIA:g} times the largest free {what}, "
                                            f"which overflows for {values[~fixed].max():g}")
    out = values.copy()
    out[fixed] = big
    return out


def _keyed(path: Path, exc: InputError) -> InputError:
    """A check of the packing layer (key ``masses``, ``force_n``, ...) named in the export."""
    return exc if exc.key.startswith(str(path)) else InputError(f"{path}: bodies", f"{exc.key}: {exc.reason}")


def _label(path: Path, doc: dict, clumps: int = 0) -> str:
    extra = f", {clumps} clumps as rigid bodies" if clumps else ""
    return f"{path.name}, YADE iteration {doc.get('iter', '?')}{extra}"


def read_yade_audit(path) -> tuple[Packing, Contacts, dict]:
    """Read any YADE export, clumps included, with YADE's contact kinematics applied.

    The module docstring and ``dtcrit.packing.readers.yade_clumps`` give the conventions; errors name
    the file and the entry (``InputError.location``: source and key).

    Parameters
    ----------
    path : str or pathlib.Path
        The ``dtcrit-yade-export/1`` file.

    Returns
    -------
    tuple
        ``(packing, contacts, metadata)``: the packing's ``radii`` are bounding radii and
        ``orientations`` the clumps' (identity for spheres); the contacts carry YADE's terms and
        kinematics; the metadata holds ``dt``, ``iter``, ``yade_version``, ``newton_damping``, the
        number of ``clumps`` and the ``cell_strain_rate`` (``yade_terms.cell_strain_rate``).
    """
    with located_in(path):
        return _read_yade_audit(Path(path))


def _read_yade_audit(path: Path) -> tuple[Packing, Contacts, dict]:
    from dtcrit.packing.readers.yade_clumps import rigid_bodies, yade_contacts
    from dtcrit.packing.readers.yade_walls import add_yade_walls, split_walls

    doc, bodies, inters = _load(path)
    meta = _meta(doc, path)
    bodies, inters, walls, touching = split_walls(bodies, inters, path)  # Wall and Facet bodies: yade_walls
    rb = rigid_bodies(bodies, path)
    if rb.fixed.all():
        raise InputError(f"{path}: bodies", "every body is fixed: nothing moves")
    masses, inertia = rb.masses, rb.inertia
    if rb.fixed.any():
        masses, inertia = _heavy(path, masses, rb.fixed, "mass"), _heavy(path, inertia, rb.fixed, "moment of inertia")
    box = _box(doc, path)
    x = rb.positions if box is None else _wrapped(box, rb.positions)
    ratcheting = doc.get("avoid_granular_ratcheting")
    try:
        packing = Packing(x, masses, inertia, rb.radii, box=box, orientations=rb.rotations if rb.clumps else None,
                          half_lengths=np.repeat(rb.radii[:, None], 3, 1), label=_label(path, doc, rb.clumps),
                          ids=rb.ids)
        contacts = (yade_contacts(rb, inters, path, box=box, wrapped=x, ratcheting=ratcheting is not False)
                    if inters or not touching else Contacts.empty())
        if walls:
            packing, contacts, meta["fixed_bodies"] = add_yade_walls(
                packing, contacts, rb.members, walls, touching, path, doc.get("wall_no_ratch") is not False,
                rb.positions, ~rb.fixed)
    except InputError as exc:
        raise _keyed(path, exc) from None
    return packing, contacts, {**meta, "clumps": rb.clumps, "cell_strain_rate": cell_strain_rate(doc, path)}


def read_yade_export(path) -> tuple[Packing, Contacts, dict]:
    """Read a sphere-only YADE export with its contacts' arms along the centre line.

    ``with_arms`` gives the contacts YADE's kinematics (an export with clumps: use
    :func:`read_yade_audit`); errors name the file and the entry (``InputError.location``).

    Parameters
    ----------
    path : str or pathlib.Path
        The ``dtcrit-yade-export/1`` file.

    Returns
    -------
    tuple
        ``(packing, contacts with YADE's terms, metadata)``.
    """
    with located_in(path):
        return _read_yade_export(Path(path))


def _read_yade_export(path: Path) -> tuple[Packing, Contacts, dict]:
    doc, bodies, inters = _load(path)
    meta = _meta(doc, path)
    ids: list[int] = []
    x: list[np.ndarray] = []
    radii: list[float] = []
    masses: list[float] = []
    inertia: list[np.ndarray] = []
    fixed: list[bool] = []
    seen: dict[int, int] = {}
    for k, b in enumerate(bodies):
        where = f"{path}: bodies[{k}]"
        if not isinstance(b, dict):
            raise InputError(where, f"expected an object, found {show(b)}")
        if b.get("is_clump") or b.get("clump_id") is not None:
            raise InputError(where, "a clump: this reader takes spheres only (clump exports are read by "
                                    "dtcrit.packing.readers.yade_export.read_yade_audit)")
        if b.get("radius") is None:
            raise InputError(where, "only spheres are analysed (this body has no radius)")
        bid = whole(f"{where}.id", b.get("id"))
        if bid in seen:
            raise InputError(f"{where}.id", f"id {bid} is already used by bodies[{seen[bid]}]")
        seen[bid] = k
        ids.append(bid)
        x.append(_triple(f"{where}.pos", b.get("pos")))
        radii.append(_finite(f"{where}.radius", b.get("radius"), positive=True))
        check_lengths([x[-1], [radii[-1]] * 3], lambda a: f"{where}.{('pos', 'radius')[a]}", "a length")
        masses.append(_finite(f"{where}.mass", b.get("mass"), positive=True))
        inertia.append(_triple(f"{where}.inertia", b.get("inertia"), positive=True))
        check_inertia([inertia[-1], [masses[-1]] * 3], lambda a: f"{where}.{('inertia', 'mass')[a]}",
                      "a mass or moment of inertia")
        fixed.append(bool(b.get("fixed")))
    mass_of, inertia_of, is_fixed = np.array(masses), np.array(inertia), np.array(fixed)
    if is_fixed.all():
        raise InputError(f"{path}: bodies", "every body is fixed: nothing moves")
    if is_fixed.any():
        mass_of, inertia_of = _heavy(path, mass_of, is_fixed, "mass"), _heavy(path, inertia_of, is_fixed, "moment of inertia")
    box = _box(doc, path)
    positions = np.array(x)
    if box is not None:
        positions = _wrapped(box, positions)
    try:
        packing = Packing(positions, mass_of, inertia_of, np.array(radii), box=box,
                          half_lengths=np.repeat(np.array(radii)[:, None], 3, 1), label=_label(path, doc),
                          ids=np.array(ids))
    except InputError as exc:
        raise _keyed(path, exc) from None
    lookup = {v: k for k, v in enumerate(ids)}
    pairs: list[tuple[int, ...]] = []
    terms: dict[str, list[float | None]] = {key: [] for key in ("kn", "ks", "kr", "ktw", "cn", "cs", "fn")}
    for k, it in enumerate(inters):
        where = f"{path}: interactions[{k}]"
        if not isinstance(it, dict):
            raise InputError(where, f"expected an object, found {show(it)}")
        pair = []
        for key in ("id1", "id2"):
            bid = whole(f"{where}.{key}", it.get(key))
            if bid not in lookup:
                raise InputError(f"{where}.{key}", f"{bid} is not the id of an exported body")
            pair.append(lookup[bid])
        pairs.append(tuple(pair))
        for key in terms:
            value = it.get(key)
            if key == "fn" and isinstance(value, (int, float)) and not isinstance(value, bool) and value < 0:
                value = -_finite(f"{where}.fn", -value)  # a bond in tension: negative normal force
            else:
                value = _finite(f"{where}.{key}", value, allow_none=key not in ("kn", "ks"))
            terms[key].append(value)
        kn = terms["kn"][-1]
        if terms["fn"][-1] is None and kn is not None:  # linear law: fn = kn times the penetration (kn is required)
            pen = _finite(f"{where}.penetration", it.get("penetration", 0.0))
            terms["fn"][-1] = kn * pen
    if not pairs:
        raise InputError(f"{path}: interactions", "no interactions: no contact limits the step")
    ij = np.array(pairs, dtype=np.int64)
    col = {key: np.array([0.0 if v is None else v for v in vals]) for key, vals in terms.items()}
    try:
        contacts = overlaps_of_pairs(packing, ij[:, 0], ij[:, 1])
        contacts = contacts.with_stiffness(col["kn"], col["ks"], col["kr"], col["ktw"])
        contacts = contacts.with_damping(col["cn"], col["cs"]).with_normal_force(col["fn"])
    except InputError as exc:
        raise _keyed(path, exc) from None
    return packing, contacts, meta
