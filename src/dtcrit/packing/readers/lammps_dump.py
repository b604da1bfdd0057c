"""Read and write LAMMPS / LIGGGHTS text dump files of sphere packings.

A snapshot is::

    ITEM: TIMESTEP
    1000
    ITEM: NUMBER OF ATOMS
    2
    ITEM: BOX BOUNDS pp pp ff
    0.0 10.0
    ...
    ITEM: ATOMS id type x y z radius mass
    1 1 1.0 1.0 1.0 0.5 0.52
    ...

Positions come from ``x y z``, ``xu yu zu`` (unwrapped) or ``xs ys zs`` (box fractions); sizes from
``radius`` or ``diameter``; masses from an optional ``mass`` column, otherwise from ``density``.
Each axis is periodic when its boundary flag is ``pp`` (LAMMPS's default ``p p p`` when the header
has no flags).  Non-periodic walls are not part of the packing (no wall contacts).  Triclinic
(sheared) boxes are read from ``ITEM: BOX BOUNDS xy xz yz`` (bounding box and tilt factors, converted to
``lo``/``hi`` as LAMMPS's Howto triclinic gives) or ``abc origin`` (general triclinic), box fractions
``xs ys zs`` as ``lo + H s``.  Any malformed content raises ``InputError`` located at its line (``FILE:N``; ``line N``
for text read without a file name: ``InputError.location`` holds the source and line).

:func:`iter_dump` streams a dump one snapshot at a time (a generator: one snapshot's text in memory,
its atom rows parsed only when read); :func:`read_dump` picks one snapshot from that stream.
"""
from __future__ import annotations

import math
from contextlib import closing
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.model import Box, Packing
from dtcrit.packing.readers.dump_stream import DumpSnapshot, _chosen, iter_dump, read_snapshots
from dtcrit.packing.periodic_cell import spacings
from dtcrit.packing.readers.limits import check_inertia, check_lengths

__all__ = ["DumpSnapshot", "format_dump", "iter_dump", "packing_from_snapshot", "read_dump", "read_snapshots",
           "write_dump"]

_POSITION_SETS = (("x", "y", "z"), ("xu", "yu", "zu"), ("xs", "ys", "zs"))


def _used_columns(snap: DumpSnapshot, cols: dict, header_line: int) -> None:
    """Refuse a repeated column name only when the reader uses it (LIGGGHTS writes ``type type``)."""
    columns = snap.columns
    for name in cols:
        if columns.count(name) > 1:
            raise snap.fail(header_line, f"the ATOMS header names the column '{name}' {columns.count(name)} times; "
                                     "dtcrit reads it, so it must appear once")


def packing_from_snapshot(snap: DumpSnapshot, density: float | None = None, label: str = "") -> Packing:
    """The sphere packing of a dump snapshot (module docstring: columns, units, periodic axes).

    Parameters
    ----------
    snap : DumpSnapshot
        The snapshot (``dtcrit.packing.readers.dump_stream.iter_dump``).
    density : float or None
        The particle density [kg/m^3] when the snapshot has no ``mass`` column (refused with one).
    label : str
        The packing's label (default ``"dump, timestep N"``).

    Returns
    -------
    Packing
        The spheres sorted by atom id (when the dump has ids), masses ``4/3 pi R^3 rho`` or given.
    """
    cols = {name: i for i, name in enumerate(snap.columns)}
    header_line = snap.first_line - 1
    pos = next((s for s in _POSITION_SETS if all(c in cols for c in s)), None)
    if pos is None:
        raise snap.fail(header_line, "the ATOMS columns need positions: x y z, xu yu zu or xs ys zs")
    size = "radius" if "radius" in cols else ("diameter" if "diameter" in cols else None)
    if size is None:
        raise snap.fail(header_line, "the ATOMS columns need a 'radius' (or 'diameter') column")
    used = [*pos, size] + [c for c in ("mass", "id") if c in cols]
    _used_columns(snap, {c: cols[c] for c in used}, header_line)
    bad = ~np.isfinite(snap.rows[:, [cols[c] for c in used]]).all(axis=1)
    if bad.any():
        n = int(np.argmax(bad))
        col = next(c for c in used if not np.isfinite(snap.rows[n, cols[c]]))
        raise snap.fail(snap.first_line + n, f"{col} is not finite ({snap.rows[n, cols[col]]:g})")
    x = snap.rows[:, [cols[c] for c in pos]]
    if pos[0] == "xs":
        with np.errstate(over="ignore", invalid="ignore"):
            x = snap.box.lo + snap.box.shift(x)
    r = snap.rows[:, cols["radius"]] if size == "radius" else 0.5 * snap.rows[:, cols["diameter"]]
    bad = ~(r > 0)
    if bad.any():
        n = int(np.argmax(bad))
        raise snap.fail(snap.first_line + n, f"{size} must be positive, found {snap.rows[n, cols[size]]:g}")
    masses = None
    if "mass" in cols:
        masses = snap.rows[:, cols["mass"]]
        bad = ~(masses > 0)
        if bad.any():
            n = int(np.argmax(bad))
            raise snap.fail(snap.first_line + n, f"mass must be positive, found {masses[n]:g}")
        if density is not None:
            raise snap.fail(header_line, "the ATOMS columns include 'mass': do not give a density (--density) as well")
    elif density is None:
        raise snap.fail(header_line, "the ATOMS columns have no 'mass': give the particle density (--density)")
    _check_sizes(snap, x, r, masses, density)
    bounds = np.vstack([snap.box.lo, snap.box.hi] + ([] if snap.box.cell is None else [snap.box.cell - np.diag(snap.box.lengths)]))
    for what, values in (("a box bound", bounds.T), ("a coordinate", x), ("radius", r)):
        if what == "a box bound":
            check_lengths(values, lambda k: snap.at(snap.first_line - 4 + k), what)
        else:
            check_lengths(values, lambda k: snap.at(snap.first_line + k), what)
    _periodic_room(snap, r)
    order = np.argsort(snap.rows[:, cols["id"]], kind="stable") if "id" in cols else np.arange(len(r))
    ids = None
    if "id" in cols:
        ids = snap.rows[order, cols["id"]]
        dup = np.flatnonzero(ids[1:] == ids[:-1])
        if dup.size:
            raise snap.fail(snap.first_line + int(order[dup[0] + 1]), f"atom id {ids[dup[0]]:g} appears twice")
        bad = np.flatnonzero((ids != np.rint(ids)) | (np.abs(ids) >= 2.0**63))
        if bad.size:
            raise snap.fail(snap.first_line + int(order[bad[0]]), f"atom id {ids[bad[0]]:g} is not a whole number "
                                                               "(64-bit)")
    return Packing.spheres(x[order], r[order], density=density, masses=None if masses is None else masses[order],
                           box=snap.box, label=label or f"dump, timestep {snap.timestep}", ids=ids)


def _check_sizes(snap: DumpSnapshot, x: np.ndarray, r: np.ndarray, masses, density) -> None:
    """Values a double cannot carry through the analysis, named by their line: a mass or moment of
    inertia ``2/5 m R^2`` that overflows or underflows to zero.
    """
    if density is not None and not (math.isfinite(density) and density > 0):
        raise InputError("density", f"must be a positive finite number, got {density:g}")
    with np.errstate(over="ignore", under="ignore"):
        m = masses if masses is not None else (4.0 / 3.0) * np.pi * r**3 * density
        inertia = 0.4 * m * r**2
    bad = ~np.isfinite(x).all(axis=1)
    if bad.any():  # box fractions times a huge box
        n = int(np.argmax(bad))
        raise snap.fail(snap.first_line + n, f"the position {x[n].tolist()} is outside double precision")
    bad = ~(np.isfinite(m) & (m > 0) & np.isfinite(inertia) & (inertia > 0))
    if bad.any():
        n = int(np.argmax(bad))
        raise snap.fail(snap.first_line + n, f"radius {r[n]:g} and mass {m[n]:g} give a moment of inertia "
                                         f"{inertia[n]:g} outside double precision")
    check_inertia(m, lambda n: snap.at(snap.first_line + n), "the mass [kg]")
    check_inertia(inertia, lambda n: snap.at(snap.first_line + n), "the moment of inertia 2/5 m R^2 [kg m^2]")


def _periodic_room(snap: DumpSnapshot, r: np.ndarray) -> None:
    """Refuse a sphere whose radius exceeds a periodic length: it would overlap its own periodic
    images more than one deep (and the image search would not end).
    """
    k = int(np.argmax(r))
    width = spacings(snap.box)  # the box lengths, or a sheared cell's face spacings
    for a in range(3):
        if snap.box.periodic[a] and width[a] < r[k]:
            raise snap.fail(snap.first_line + k, f"radius {r[k]:g} exceeds the periodic box length {width[a]:g} "
                                             f"along {'xyz'[a]}: the sphere would overlap its own images more than "
                                             "one deep")


def read_dump(path, *, density: float | None = None, snapshot: int = -1) -> Packing:
    """The sphere packing in one snapshot of a LAMMPS/LIGGGHTS dump (:func:`iter_dump`).

    The file is streamed: read no further than the snapshot asked for when ``snapshot >= 0``,
    holding at most ``-snapshot`` snapshots' text when it is negative, and parsing only the chosen
    snapshot's atom rows.

    Parameters
    ----------
    path : str or pathlib.Path
        The dump file.
    density : float or None
        The particle density [kg/m^3] for a dump without a ``mass`` column (refused with one).
    snapshot : int
        The snapshot's index, Python style: 0 the first, -1 (default) the last.

    Returns
    -------
    Packing
        The packing, labelled ``"NAME, timestep N"``.
    """
    path = Path(path)
    try:
        with closing(iter_dump(path)) as snapshots:  # the file is closed once the snapshot is read
            chosen = _chosen(snapshots, snapshot)
        return packing_from_snapshot(chosen, density, label=f"{path.name}, timestep {chosen.timestep}")
    except InputError as exc:
        if exc.location.source is None and exc.location.line is not None:  # FILE:LINE: reason
            raise exc.within(path) from None
        raise


def format_dump(packing: Packing, *, timestep: int = 0, with_mass: bool = True) -> str:
    """A one-snapshot dump text (``id type x y z radius [mass]``) of a sphere packing.

    Parameters
    ----------
    packing : Packing
        A sphere packing; without a box, a non-periodic one enclosing the spheres is written.
    timestep : int
        The ``ITEM: TIMESTEP`` value.
    with_mass : bool
        Write the ``mass`` column.

    Returns
    -------
    str
        The dump's text, every number with 17 significant digits (read back exactly).
    """
    if not packing.is_spheres:
        raise InputError("packing", "only sphere packings can be written as a dump")
    box = packing.box
    if box is None:
        lo = packing.positions.min(axis=0) - packing.radii.max()
        hi = packing.positions.max(axis=0) + packing.radii.max()
        box = Box(lo, hi, (False, False, False))
    flags = " ".join("pp" if p else "ff" for p in box.periodic)
    out = ["ITEM: TIMESTEP", str(int(timestep)), "ITEM: NUMBER OF ATOMS", str(packing.n)]
    out += _box_bounds(box, flags)
    out.append("ITEM: ATOMS id type x y z radius" + (" mass" if with_mass else ""))
    for k in range(packing.n):
        x, y, z = packing.positions[k]
        row = f"{k + 1} 1 {x:.17g} {y:.17g} {z:.17g} {packing.radii[k]:.17g}"
        if with_mass:
            row += f" {packing.masses[k]:.17g}"
        out.append(row)
    return "\n".join(out) + "\n"


def _box_bounds(box: Box, flags: str) -> list[str]:
    """The ``ITEM: BOX BOUNDS`` block: orthogonal, restricted triclinic (``xy xz yz``: bounding box and
    tilts, Howto triclinic) for an upper-triangular cell, else general triclinic (``abc origin``).
    """
    if box.cell is None:
        return [f"ITEM: BOX BOUNDS {flags}"] + [f"{box.lo[a]:.17g} {box.hi[a]:.17g}" for a in range(3)]
    h = box.cell
    if np.any(np.tril(h, -1)):
        return [f"ITEM: BOX BOUNDS abc origin {flags}"] + [
            f"{h[0, a]:.17g} {h[1, a]:.17g} {h[2, a]:.17g} {box.lo[a]:.17g}" for a in range(3)]
    xy, xz, yz = h[0, 1], h[0, 2], h[1, 2]
    low = box.lo + [min(0.0, xy, xz, xy + xz), min(0.0, yz), 0.0]
    high = box.hi + [max(0.0, xy, xz, xy + xz), max(0.0, yz), 0.0]
    return [f"ITEM: BOX BOUNDS xy xz yz {flags}"] + [f"{low[a]:.17g} {high[a]:.17g} {t:.17g}"
                                                     for a, t in enumerate((xy, xz, yz))]


def write_dump(path, packing: Packing, **kwargs) -> None:
    """Write :func:`format_dump` of a sphere packing to ``path``.

    Parameters
    ----------
    path : str or pathlib.Path
        The file written.
    packing : Packing
        A sphere packing.
    **kwargs
        ``timestep`` and ``with_mass`` of :func:`format_dump`.
    """
    Path(path).write_text(format_dump(packing, **kwargs))
