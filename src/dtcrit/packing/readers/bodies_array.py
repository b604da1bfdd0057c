"""The ``bodies`` array of a bodies file read into a packing: keys, ids, shapes, positions, orientations.

The format is described in ``dtcrit.packing.readers.bodies_file``; orientations are unit quaternions
``[qw, qx, qy, qz]`` mapped body to world (the matrix of
``dtcrit.packing.readers.yade_clumps.rotation_from_quaternion``).
"""
from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from dtcrit.numerics.rotations import unit_body_to_world_matrix
from dtcrit._generated import mass_properties as _mp
from dtcrit.bodies.spec import shape_from_table
from dtcrit.packing.detection.overlaps import wrap_positions
from dtcrit.packing.model import Box, Packing
from dtcrit.packing.readers.bodies_values import _array, _fail, _integer, _keys, _numbers, _short, _sphere_table
from dtcrit.packing.readers.limits import check_lengths
from dtcrit.packing.readers.yade_clumps import rotation_from_quaternion

BODY_KEYS = ("id", "shape", "position", "orientation")
BODY_SET = frozenset(BODY_KEYS)
NEEDED = frozenset(("id", "shape", "position"))
REFUSED_SHAPE_KEYS = {
    "radii": "a body is one sphere: give its radius",
    "fractions": "a body is one sphere: give its radius",
    "lognormal": "a body is one sphere: give its radius",
    "youngs_modulus": "not used in a bodies file: the contact law comes from 'contacts' or --kn/--ks/--youngs",
    "poisson_ratio": "not used in a bodies file: the contact law comes from 'contacts' or --kn/--ks/--youngs",
}
UNIT_TOLERANCE = 1e-6
"""Largest accepted ``| |q| - 1 |`` of an orientation (eight digits of 0.70710678 pass)."""


def _shape(where: str, table):
    if not isinstance(table, dict):
        raise _fail(where, f"expected an object with the keys of a scene's [[particle]] table, found {_short(table)}")
    for key, why in REFUSED_SHAPE_KEYS.items():
        if key in table:
            raise _fail(f"{where}.{key}", why)
    return shape_from_table(where + ".", table)


def _orientation(where: str, value) -> np.ndarray:
    if value is None:
        return np.eye(3)
    q = _numbers(where, value, 4)
    with np.errstate(over="ignore"):
        norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > UNIT_TOLERANCE:
        raise _fail(where, f"not a unit quaternion (|q| = {norm:.9g}); give [qw, qx, qy, qz] with unit length")
    return rotation_from_quaternion(where, list(q / norm))


def _frame(shape) -> tuple[np.ndarray, np.ndarray]:
    """``(G, c)`` with ``given = G principal + c`` for the shape's given frame (module docstring)."""
    if hasattr(shape, "frame_rotation"):  # clump: x_given = Q x_principal + centre
        return np.asarray(shape.frame_rotation, float), np.asarray(shape.centre_of_mass, float)
    if hasattr(shape, "centroid") and hasattr(shape, "rotation"):  # polyhedron: local = rot (input - centroid)
        return np.asarray(shape.rotation, float).T, np.asarray(shape.centroid, float)
    return np.eye(3), np.zeros(3)


def _sphere_properties(where: list, tables: list, found: np.ndarray):
    """``(radius, mass, inertia)`` of plain sphere tables (``found`` their rows of ``_sphere_table``),
    for all at once: ``m = rho 4/3 pi R^3`` or the given mass, ``I = 2/5 m R^2`` (the formulas of
    ``dtcrit.bodies.Sphere``).  A table whose numbers do not give a positive finite radius, density,
    mass and moment is read by the shape parser, which names the key.
    """
    r, rho, given = found[:, 0], found[:, 1], found[:, 2]
    with np.errstate(over="ignore", under="ignore", invalid="ignore", divide="ignore"):
        volume = _mp.sphere_volume(r)
        mass = np.where(np.isnan(rho), given, rho * volume)
        density = np.where(np.isnan(rho), given / volume, rho)
        inertia = mass * _mp.sphere_inertia_per_mass(r)
    ok = np.ones(len(r), bool)
    for v in (r, volume, mass, density, inertia):
        ok &= np.isfinite(v) & (v > 0)
    if not ok.all():
        k = int(np.argmin(ok))
        _shape(where[k], tables[k])
        raise _fail(where[k], "the radius and density (or mass) give a moment of inertia outside double precision")
    return r, mass, inertia


def _entries(path, bodies: list):
    """Per-body checks of keys and ids: ``(ids, shape tables, positions, orientations)`` as given."""
    ids: list[int] = []
    tables: list = []
    positions: list = []
    quats: list = []
    seen: dict[int, int] = {}
    for k, body in enumerate(bodies):
        if type(body) is not dict:
            raise _fail(f"{path}: bodies[{k}]", "expected an object with id, shape, position (and orientation), "
                                                 f"found {_short(body)}")
        if not body.keys() <= BODY_SET or not body.keys() >= NEEDED:
            where = f"{path}: bodies[{k}]"
            _keys(where, body, BODY_KEYS)
            key = next(key for key in BODY_KEYS if key not in body)
            raise _fail(f"{where}.{key}", "missing: a body needs id, shape and position")
        bid = body["id"]
        if type(bid) is not int or abs(bid) >= 2**63:
            _integer(f"{path}: bodies[{k}].id", bid)
        if bid in seen:
            raise _fail(f"{path}: bodies[{k}].id", f"id {bid} is already used by bodies[{seen[bid]}]")
        seen[bid] = k
        ids.append(bid)
        tables.append(body["shape"])
        positions.append(body["position"])
        quats.append(body.get("orientation"))
    return ids, tables, positions, quats


def _rotations(path, quats: list) -> np.ndarray:
    """Body-to-world rotations of every body's unit quaternion ``[qw, qx, qy, qz]`` (module
    docstring; ``dtcrit.numerics.rotations.unit_body_to_world_matrix``).
    """
    q = _array(path, "orientation", quats, 4, [1.0, 0.0, 0.0, 0.0])
    with np.errstate(over="ignore"):  # |q| = inf is refused below
        norm = np.linalg.norm(q, axis=1)
    bad = np.flatnonzero(np.abs(norm - 1.0) > UNIT_TOLERANCE)
    if bad.size:
        _orientation(f"{path}: bodies[{bad[0]}].orientation", quats[bad[0]])
    return unit_body_to_world_matrix(q / norm[:, None])


def _shapes(path, tables: list, sphere_rows: list):
    """One shape object per body: equal tables share one (parsed once), plain spheres are built
    from their checked numbers.
    """
    from dtcrit.bodies import Sphere

    parsed: dict = {}
    out = []
    for k, table in enumerate(tables):
        row = sphere_rows[k]
        key: tuple | str
        if row is not None:
            key = ("sphere",) + tuple(row)
            if key not in parsed:
                r, rho, m = (float(v) for v in row)
                parsed[key] = Sphere(r, density=None if math.isnan(rho) else rho, mass=None if math.isnan(m) else m)
        else:
            key = json.dumps(table, sort_keys=True)
            if key not in parsed:
                parsed[key] = _shape(f"{path}: bodies[{k}].shape", table)
        out.append(parsed[key])
    return out


def read_bodies(path, doc: dict, box: Box | None) -> tuple[Packing, dict[str, int]]:
    """The bodies of a parsed bodies file as a packing (the file format of ``dtcrit.packing.readers.bodies_file``).

    Every body's keys, id, shape table, position and unit quaternion are checked; plain spheres are
    built from their numbers at once (``m = rho 4/3 pi R^3``, ``I = 2/5 m R^2``), other shapes through
    ``dtcrit.bodies.spec.shape_from_table``, and each body's given frame is moved to its principal frame.

    Parameters
    ----------
    path : str or pathlib.Path
        The file, named in error messages and in the packing's label.
    doc : dict
        The parsed JSON document (its ``bodies`` array is read).
    box : Box or None
        The simulation box (positions are wrapped into its periodic directions), or None.

    Returns
    -------
    tuple
        ``(packing, kinds)``: the packing (ids from the file) and the number of bodies of each shape kind.
    """
    bodies = doc.get("bodies")
    if not isinstance(bodies, list) or not bodies:
        raise _fail(f"{path}: bodies", "missing: a non-empty array of bodies")
    ids, tables, positions, quats = _entries(path, bodies)
    rows = [_sphere_table(t) for t in tables]
    spheres = [k for k, row in enumerate(rows) if row is not None]
    found = np.array([rows[k] for k in spheres], dtype=float).reshape(-1, 3)
    radius, mass, inertia = _sphere_properties([f"{path}: bodies[{k}].shape" for k in spheres],
                                               [tables[k] for k in spheres], found)
    shapes = None if len(spheres) == len(ids) else _shapes(path, tables, rows)
    position = _array(path, "position", positions, 3)
    check_lengths(position, lambda k: f"{path}: bodies[{k}].position", "a coordinate")
    rot = _rotations(path, quats)
    if shapes is None:  # spheres only: a sphere packing (a sphere's orientation changes nothing)
        kinds = {"sphere": len(ids)}
        packing = Packing(wrap_positions(position, box), mass, inertia, radius, box=box,
                          half_lengths=np.repeat(radius[:, None], 3, axis=1))
    else:
        frames = {id(s): _frame(s) for s in shapes}
        g = np.array([frames[id(s)][0] for s in shapes])
        c = np.array([frames[id(s)][1] for s in shapes])
        x = wrap_positions(position + np.einsum("nij,nj->ni", rot, c), box)
        packing = Packing.from_shapes(shapes, x, rot @ g, box=box)
        kinds = {}
        for s in shapes:
            kinds[s.kind] = kinds.get(s.kind, 0) + 1
    text = ", ".join(f"{n} {kind}{'s' if n > 1 else ''}" for kind, n in kinds.items())
    label = f"{Path(path).name}: {text}" + (", periodic" if box is not None and any(box.periodic) else "")
    return replace(packing, ids=np.array(ids, dtype=np.int64), label=label), kinds
