"""Read the YADE export (``dtcrit-yade-export/1``) that ``dtcrit/engine_scripts/yade_export.py`` writes
inside YADE: bodies (id, position, radius, mass, principal inertia, fixed) and the real interactions
with YADE's own per-contact ``kn``, ``ks`` (and ``kr``, ``ktw``, ``cn``, ``cs`` when its physics has them).

A fixed body (all degrees of freedom blocked) is a wall to the others: it enters with an inertia
``FIXED_INERTIA`` times the largest free one, which leaves the free bodies' frequencies unchanged to
~1e-150 relative.  The periodic cell must be orthogonal.

Two readers:

* ``read_yade_export`` -- spheres only: the packing and the exported contacts with centre-line arms,
  for ``dtcrit.packing.engines.with_arms(..., "yade")`` to apply YADE's kinematics;
* ``read_yade_audit`` -- any export, clumps included (``dtcrit.packing.yade_clumps``): each clump one
  rigid body, the contacts already carrying YADE's kinematics (arms from each body's centre of
  mass, ``alpha k_s``); for a sphere-only export with ``avoidGranularRatcheting`` on (YADE's default)
  it gives what ``with_arms`` gives on ``read_yade_export``'s contacts, and it also follows the
  export's ``avoid_granular_ratcheting`` when that is off.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError

from dtcrit.packing.engines import overlaps_of_pairs
from dtcrit.packing.model import Box, Contacts, Packing

SCHEMA = "dtcrit-yade-export/1"
FIXED_INERTIA = 1e300


def _number(where: str, value, *, positive: bool = False, allow_none: bool = False):
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(where, f"expected a finite number, found {value!r}")
    if value < 0 or (positive and value == 0):
        raise InputError(where, f"must be {'positive' if positive else '>= 0'}, found {value!r}")
    return float(value)


def _vector(where: str, value) -> np.ndarray:
    if not isinstance(value, list) or len(value) != 3:
        raise InputError(where, f"expected three numbers, found {value!r}")
    out = np.array([v if isinstance(v, (int, float)) and not isinstance(v, bool) else math.nan for v in value], float)
    if not np.all(np.isfinite(out)):
        raise InputError(where, f"expected three finite numbers, found {value!r}")
    return out


def _box(doc: dict, path: Path) -> Box | None:
    if not doc.get("periodic"):
        return None
    h = doc.get("cell_hsize")
    if not isinstance(h, list) or len(h) != 3:
        raise InputError(f"{path}: cell_hsize", "a periodic export needs the 3 x 3 cell_hsize")
    cell = np.array([_vector(f"{path}: cell_hsize[{a}]", row) for a, row in enumerate(h)])
    if np.abs(cell - np.diag(np.diag(cell))).max() > 1e-12 * np.abs(cell).max():
        raise InputError(f"{path}: cell_hsize", "triclinic (sheared) periodic cells are not supported yet")
    return Box(np.zeros(3), np.diag(cell).copy(), (True, True, True))


def _load(path: Path) -> tuple[dict, list, list]:
    try:
        doc = json.loads(path.read_text(encoding="utf-8-sig"))
    except OSError as exc:
        raise InputError(str(path), f"cannot read: {exc.strerror or exc}") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        line = getattr(exc, "lineno", 1)
        raise InputError(f"{path}:{line}", "not a JSON YADE export") from None
    if not isinstance(doc, dict) or doc.get("schema") != SCHEMA:
        raise InputError(f"{path}: schema", f"expected a {SCHEMA!r} export (written by yade_export.py)")
    bodies, inters = doc.get("bodies"), doc.get("interactions")
    if not isinstance(bodies, list) or not bodies or not isinstance(inters, list):
        raise InputError(f"{path}: bodies", "the export needs a non-empty 'bodies' list and an 'interactions' list")
    return doc, bodies, inters


def _meta(doc: dict) -> dict:
    return {"dt": doc.get("dt"), "iter": doc.get("iter"), "yade_version": doc.get("yade_version"),
            "newton_damping": doc.get("newton_damping")}


def _label(path: Path, doc: dict, clumps: int = 0) -> str:
    extra = f", {clumps} clumps as rigid bodies" if clumps else ""
    return f"{path.name}, YADE iteration {doc.get('iter', '?')}{extra}"


def read_yade_audit(path) -> tuple[Packing, Contacts, dict]:
    """``(packing, contacts with YADE's terms and kinematics, metadata)`` from any export, clumps
    included (module docstring; ``dtcrit.packing.yade_clumps``).  The packing's ``radii`` are bounding
    radii and ``orientations`` the clumps' (identity for spheres)."""
    from dtcrit.packing.yade_clumps import rigid_bodies, yade_contacts

    path = Path(path)
    doc, bodies, inters = _load(path)
    rb = rigid_bodies(bodies, path)
    masses, inertia = rb.masses.copy(), rb.inertia.copy()
    if rb.fixed.all():
        raise InputError(f"{path}: bodies", "every body is fixed: nothing moves")
    if rb.fixed.any():
        masses[rb.fixed] = FIXED_INERTIA * masses[~rb.fixed].max()
        inertia[rb.fixed] = FIXED_INERTIA * inertia[~rb.fixed].max()
    box = _box(doc, path)
    x = rb.positions if box is None else np.mod(rb.positions, box.lengths)
    packing = Packing(x, masses, inertia, rb.radii, box=box, orientations=rb.rotations if rb.clumps else None,
                      half_lengths=np.repeat(rb.radii[:, None], 3, 1), label=_label(path, doc, rb.clumps), ids=rb.ids)
    ratcheting = doc.get("avoid_granular_ratcheting")
    contacts = yade_contacts(rb, inters, path, box=box, wrapped=x, ratcheting=ratcheting is not False)
    return packing, contacts, {**_meta(doc), "clumps": rb.clumps}


def read_yade_export(path) -> tuple[Packing, Contacts, dict]:
    """``(packing, contacts with YADE's terms, metadata)`` from a sphere-only export; arms along the
    centre line, to be given YADE's kinematics by ``with_arms`` (an export with clumps: use
    ``read_yade_audit``)."""
    path = Path(path)
    doc, bodies, inters = _load(path)
    ids, x, radii, masses, inertia, fixed = [], [], [], [], [], []
    for k, b in enumerate(bodies):
        where = f"{path}: bodies[{k}]"
        if not isinstance(b, dict):
            raise InputError(where, "expected an object")
        if b.get("is_clump") or b.get("clump_id") is not None:
            raise InputError(where, "a clump: this reader takes spheres only (clump exports are read by "
                                    "dtcrit.packing.yade_export_io.read_yade_audit)")
        if b.get("radius") is None:
            raise InputError(where, "only spheres are analysed (this body has no radius)")
        ids.append(int(_number(f"{where}.id", b.get("id"))))
        x.append(_vector(f"{where}.pos", b.get("pos")))
        radii.append(_number(f"{where}.radius", b.get("radius"), positive=True))
        masses.append(_number(f"{where}.mass", b.get("mass"), positive=True))
        inertia.append([_number(f"{where}.inertia", v, positive=True) for v in _vector(f"{where}.inertia", b.get("inertia"))])
        fixed.append(bool(b.get("fixed")))
    masses, inertia, fixed = np.array(masses), np.array(inertia), np.array(fixed)
    if fixed.all():
        raise InputError(f"{path}: bodies", "every body is fixed: nothing moves")
    if fixed.any():
        masses[fixed] = FIXED_INERTIA * masses[~fixed].max()
        inertia[fixed] = FIXED_INERTIA * inertia[~fixed].max()
    box = _box(doc, path)
    x = np.array(x)
    if box is not None:
        x = np.mod(x, box.lengths)
    packing = Packing(x, masses, inertia, np.array(radii), box=box, half_lengths=np.repeat(np.array(radii)[:, None], 3, 1),
                      label=_label(path, doc), ids=np.array(ids))
    lookup = {v: k for k, v in enumerate(ids)}
    pairs, terms = [], {key: [] for key in ("kn", "ks", "kr", "ktw", "cn", "cs", "fn")}
    for k, it in enumerate(inters):
        where = f"{path}: interactions[{k}]"
        if not isinstance(it, dict) or it.get("id1") not in lookup or it.get("id2") not in lookup:
            raise InputError(where, "id1 and id2 must be ids of exported bodies")
        pairs.append((lookup[it["id1"]], lookup[it["id2"]]))
        for key in terms:
            value = it.get(key)
            if key == "fn" and isinstance(value, (int, float)) and not isinstance(value, bool) and value < 0:
                value = -_number(f"{where}.fn", -value)  # a bond in tension: negative normal force
            else:
                value = _number(f"{where}.{key}", value, allow_none=key not in ("kn", "ks"))
            terms[key].append(value)
        if terms["fn"][-1] is None:  # linear law: the normal force is kn times the penetration
            pen = _number(f"{where}.penetration", it.get("penetration", 0.0))
            terms["fn"][-1] = terms["kn"][-1] * pen
    if not pairs:
        raise InputError(f"{path}: interactions", "no interactions: no contact limits the step")
    ij = np.array(pairs, dtype=np.int64)
    contacts = overlaps_of_pairs(packing, ij[:, 0], ij[:, 1])
    col = {key: np.array([0.0 if v is None else v for v in vals]) for key, vals in terms.items()}
    if np.any(col["kn"] < 0) or np.any(col["ks"] < 0):
        raise InputError(f"{path}: interactions", "negative stiffness")
    contacts = contacts.with_stiffness(col["kn"], col["ks"], col["kr"], col["ktw"])
    contacts = contacts.with_damping(col["cn"], col["cs"]).with_normal_force(col["fn"])
    return packing, contacts, _meta(doc)
