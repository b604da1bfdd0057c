"""The input of YADE's GlobalStiffnessTimeStepper read from a ``dtcrit-yade-export/1`` file.

``dtcrit.packing.bounds.yade_stepper`` computes the stepper's step; this module collects what it reads
from the export's own entries (``dtcrit/engine_scripts/yade_export.py`` writes them): each sphere's
body (a clump member's ``clump_id``, else itself) and radius (a Wall or Facet body is its own, fixed, body
whose contacts carry their arms in ``radius1``, ``radius2``); each interaction's ``normal``
(``geom.normal``), ``radius1``, ``radius2`` (``geom.refR1``, ``refR2``), ``kn``, ``ks``, ``fn`` (its
normal force: zero skips it, as the stepper does), ``phys`` (whether ``getRotStiffness()`` is
``(ktw, kr, kr)``, :data:`~dtcrit.packing.bounds.yade_stepper.ROTATIONAL_PHYSICS`) and ``kr``, ``ktw``;
the bodies' masses, principal moments and ``fixed`` (not dynamic) flags.

The export writes CohFrictPhys's ``kr``, ``ktw`` only where its moment law acts, while the stepper adds
them whatever the law does: an export of such physics without them has no step (``missing`` says
why).  Entries the export gives in another form than it writes them also leave ``missing`` set,
never a guessed step.
"""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from dtcrit.packing.bounds.yade_stepper import ROTATIONAL_PHYSICS, StepperInput

if TYPE_CHECKING:
    from dtcrit.packing.model import Packing

__all__ = ["from_export", "from_snapshot"]


class _Missing(Exception):
    """An entry the stepper needs is not in the export as written."""


def _number(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise _Missing(f"{what} is not a finite number")
    return float(value)


def _vector(value: Any, what: str) -> np.ndarray:
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise _Missing(f"{what} is not a vector of 3 numbers")
    return np.array([_number(v, what) for v in value])


def _whole(value: Any, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise _Missing(f"{what} is not a whole number")
    return value


def _spheres(bodies: list, index: Mapping[int, int]) -> tuple[dict, list[int], list[float]]:
    """Sphere id -> its slot (in id order, as a clump's member map); each slot's body index and radius."""
    spheres = {}
    for k, b in enumerate(bodies):
        if isinstance(b, dict) and not b.get("is_clump"):
            spheres[_whole(b.get("id"), f"bodies[{k}].id")] = b
    slot: dict[int, int] = {}
    body: list[int] = []
    radius: list[float] = []
    for bid in sorted(spheres):
        b = spheres[bid]
        owner = bid if b.get("clump_id") is None else _whole(b["clump_id"], f"the clump_id of sphere {bid}")
        if owner not in index:
            raise _Missing(f"sphere {bid} belongs to no body of the packing")
        slot[bid] = len(body)
        body.append(index[owner])
        wall = b.get("shape") in ("Wall", "Facet")  # a fixed wall body: its contacts carry refR1, refR2
        radius.append(0.0 if wall else _number(b.get("radius"), f"the radius of sphere {bid}"))
    return slot, body, radius


def _rot_stiffness(it: dict, where: str) -> np.ndarray:
    phys = it.get("phys")
    kr, ktw = it.get("kr"), it.get("ktw")
    if phys is not None and phys not in ROTATIONAL_PHYSICS:
        return np.zeros(3)  # NormPhys::getRotStiffness: zero
    if phys is not None and (kr is None or ktw is None):
        raise _Missing(f"{where} ({phys}) has no kr, ktw in the export (written only where the moment law "
                       "acts), but YADE's stepper adds them")
    kr = 0.0 if kr is None else _number(kr, f"{where}.kr")
    ktw = 0.0 if ktw is None else _number(ktw, f"{where}.ktw")
    return np.array([ktw, kr, kr])


def _contact(it: dict, where: str, slot: dict, radius: list[float]) -> tuple:
    a, b = it.get("id1"), it.get("id2")
    if a not in slot or b not in slot:
        raise _Missing(f"{where} joins a body that is not a sphere")
    r1 = it.get("radius1") if it.get("radius1") is not None else radius[slot[a]]
    r2 = it.get("radius2") if it.get("radius2") is not None else radius[slot[b]]
    fn = it.get("fn")
    loaded = True if fn is None else _number(fn, f"{where}.fn") != 0.0
    return (slot[a], slot[b], _vector(it.get("normal"), f"{where}.normal"), _number(it.get("kn"), f"{where}.kn"),
            _number(it.get("ks"), f"{where}.ks"), _rot_stiffness(it, where), _number(r1, f"{where}.radius1"),
            _number(r2, f"{where}.radius2"), loaded)


def from_export(doc: Mapping[str, Any], packing: Packing) -> StepperInput:
    """The stepper's input from an export's entries, on the packing ``read_yade_audit`` made of it.

    Parameters
    ----------
    doc : Mapping
        The export as read (``bodies``, ``interactions``).
    packing : Packing
        Its rigid bodies (clumps and free spheres) by the engine's ids, with their masses and moments.

    Returns
    -------
    StepperInput
        The input of :func:`dtcrit.packing.bounds.yade_stepper.yade_stepper`; ``missing`` set when the
        export lacks what the stepper reads.
    """
    ids = tuple(packing.particle_id(p) for p in range(packing.n))
    index = {bid: k for k, bid in enumerate(ids)}
    bodies, inters = doc.get("bodies") or [], doc.get("interactions") or []
    dynamic = np.ones(packing.n, bool)
    for b in bodies:
        if isinstance(b, dict) and b.get("id") in index and b.get("fixed"):
            dynamic[index[b["id"]]] = False
    empty = StepperInput(packing.masses, packing.inertia, dynamic, np.zeros(0, np.int64), np.zeros(0, np.int64),
                         np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0), np.zeros(0), np.zeros((0, 3)),
                         np.zeros(0), np.zeros(0), np.zeros(0, bool), ids)
    try:
        slot, body, radius = _spheres(bodies, index)
        rows = [_contact(it, f"interactions[{k}]", slot, radius) for k, it in enumerate(inters)]
    except (_Missing, TypeError) as exc:
        return StepperInput(**{**empty.__dict__, "missing": str(exc) or "an entry of the export is not as written"})
    cols = list(zip(*rows)) if rows else [()] * 9
    as_int = lambda v: np.array(v, np.int64)  # noqa: E731
    return StepperInput(packing.masses, packing.inertia, dynamic, as_int(body), as_int(cols[0]), as_int(cols[1]),
                        np.array(cols[2], float).reshape(-1, 3), np.array(cols[3], float), np.array(cols[4], float),
                        np.array(cols[5], float).reshape(-1, 3), np.array(cols[6], float), np.array(cols[7], float),
                        np.array(cols[8], bool), ids)


def from_snapshot(snapshot) -> StepperInput | None:
    """The stepper's input of a snapshot read from a YADE export (None for any other snapshot).

    Parameters
    ----------
    snapshot : dtcrit.packing.audit.results.Snapshot
        A snapshot (``source``, ``packing``, ``meta``); a ready input in ``meta["yade_stepper"]`` is used as is.

    Returns
    -------
    StepperInput or None
        :func:`from_export` of the export file ``source``, or None when ``source`` is not one.
    """
    ready = snapshot.meta.get("yade_stepper")
    if ready is not None:
        return ready
    path = Path(snapshot.source)
    try:
        with path.open("rb") as fh:
            if not fh.read(64).lstrip(b"\xef\xbb\xbf \t\r\n").startswith(b"{"):
                return None
        doc = json.loads(path.read_bytes().decode("utf-8-sig"))
    except (OSError, ValueError):
        return None
    if not isinstance(doc, dict) or not isinstance(doc.get("bodies"), list):
        return None
    return from_export(doc, snapshot.packing)
