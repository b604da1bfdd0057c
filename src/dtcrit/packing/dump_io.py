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
has no flags).  Non-periodic walls are not part of the packing (no wall contacts).  Triclinic boxes
are rejected.  Any malformed content raises ``InputError`` whose key is ``line N`` (``FILE:N`` from
``read_dump``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError

from dtcrit.packing.model import Box, Packing

_POSITION_SETS = (("x", "y", "z"), ("xu", "yu", "zu"), ("xs", "ys", "zs"))


@dataclass
class _Snapshot:
    timestep: int
    box: Box
    columns: list[str]
    rows: np.ndarray
    first_line: int  # 1-based line number of the first atom row


def _fail(line: int, reason: str) -> InputError:
    return InputError(f"line {line}", reason)


def _expect(lines: list[str], k: int, prefix: str) -> None:
    if k >= len(lines):
        raise _fail(k + 1, f"unexpected end of file, expected '{prefix}'")
    if not lines[k].strip().startswith(prefix):
        raise _fail(k + 1, f"expected '{prefix}', found '{lines[k].strip()[:60]}'")


def _int_at(lines: list[str], k: int, what: str) -> int:
    if k >= len(lines):
        raise _fail(k + 1, f"unexpected end of file, expected the {what}")
    text = lines[k].strip()
    try:
        return int(text)
    except ValueError:
        raise _fail(k + 1, f"expected the {what} (a whole number), found '{text[:60]}'") from None


def _parse_box(lines: list[str], k: int) -> tuple[Box, int]:
    header = lines[k].strip()[len("ITEM: BOX BOUNDS"):].split()
    if any(flag in ("xy", "xz", "yz") for flag in header):
        raise _fail(k + 1, "triclinic boxes are not supported (orthogonal boxes only)")
    flags = header if header else ["pp", "pp", "pp"]
    if len(flags) != 3 or any(len(f) != 2 or any(ch not in "pfsm" for ch in f) for f in flags):
        raise _fail(k + 1, f"boundary flags must be three of pp/ff/ss/mm/fs/..., found '{' '.join(header)}'")
    lo, hi = np.zeros(3), np.zeros(3)
    for a in range(3):
        n = k + 1 + a
        if n >= len(lines):
            raise _fail(n + 1, "unexpected end of file inside BOX BOUNDS")
        parts = lines[n].split()
        try:
            vals = [float(p) for p in parts]
        except ValueError:
            raise _fail(n + 1, f"box bounds must be numbers, found '{lines[n].strip()[:60]}'") from None
        if len(vals) == 3:
            raise _fail(n + 1, "triclinic boxes are not supported (orthogonal boxes only)")
        if len(vals) != 2 or not all(math.isfinite(v) for v in vals):
            raise _fail(n + 1, f"expected two finite numbers 'lo hi', found '{lines[n].strip()[:60]}'")
        if vals[1] <= vals[0]:
            raise _fail(n + 1, f"upper box bound {vals[1]} must exceed the lower bound {vals[0]}")
        lo[a], hi[a] = vals
    periodic = tuple("p" in f for f in flags)
    for a, f in enumerate(flags):
        if ("p" in f) and f != "pp":
            raise _fail(k + 1, f"axis {'xyz'[a]}: a periodic axis needs the flag 'pp', found '{f}'")
    return Box(lo, hi, periodic), k + 4


def _parse_atoms(lines: list[str], k: int, count: int) -> tuple[list[str], np.ndarray, int]:
    columns = lines[k].strip()[len("ITEM: ATOMS"):].split()
    if not columns:
        raise _fail(k + 1, "the ATOMS header names no columns")
    if len(set(columns)) != len(columns):
        raise _fail(k + 1, "the ATOMS header repeats a column name")
    first = k + 1
    block = lines[first:first + count]
    if len(block) < count:
        raise _fail(len(lines) + 1, f"unexpected end of file: {count} atom rows announced, {len(block)} found")
    width = len(columns)
    tokens = " ".join(block).split()
    values = None
    if len(tokens) == count * width:
        try:
            values = np.array(tokens, dtype=float).reshape(count, width)
        except ValueError:
            values = None
    if values is None:  # locate the first bad row
        for n, text in enumerate(block):
            parts = text.split()
            if len(parts) != width:
                raise _fail(first + n + 1, f"expected {width} values ({' '.join(columns)}), found {len(parts)}")
            for p in parts:
                try:
                    float(p)
                except ValueError:
                    raise _fail(first + n + 1, f"'{p[:30]}' is not a number") from None
        raise _fail(first + 1, "could not read the atom rows")  # pragma: no cover
    bad = ~np.isfinite(values).all(axis=1)
    if bad.any():
        n = int(np.argmax(bad))
        raise _fail(first + n + 1, "a value is not finite (nan or inf)")
    return columns, values, first + 1


def read_snapshots(text: str) -> list[_Snapshot]:
    lines = text.splitlines()
    snaps: list[_Snapshot] = []
    k = 0
    while k < len(lines) and not lines[k].strip():
        k += 1
    if k >= len(lines):
        raise _fail(1, "the file is empty")
    while k < len(lines):
        if not lines[k].strip():
            k += 1
            continue
        _expect(lines, k, "ITEM: TIMESTEP")
        step = _int_at(lines, k + 1, "timestep")
        _expect(lines, k + 2, "ITEM: NUMBER OF ATOMS")
        count = _int_at(lines, k + 3, "number of atoms")
        if count < 1:
            raise _fail(k + 4, f"the number of atoms must be at least 1, found {count}")
        _expect(lines, k + 4, "ITEM: BOX BOUNDS")
        box, k = _parse_box(lines, k + 4)
        _expect(lines, k, "ITEM: ATOMS")
        columns, rows, first = _parse_atoms(lines, k, count)
        snaps.append(_Snapshot(step, box, columns, rows, first))
        k = k + 1 + count
    return snaps


def packing_from_snapshot(snap: _Snapshot, density: float | None = None, label: str = "") -> Packing:
    cols = {name: i for i, name in enumerate(snap.columns)}
    header_line = snap.first_line - 1
    pos = next((s for s in _POSITION_SETS if all(c in cols for c in s)), None)
    if pos is None:
        raise _fail(header_line, "the ATOMS columns need positions: x y z, xu yu zu or xs ys zs")
    x = snap.rows[:, [cols[c] for c in pos]]
    if pos[0] == "xs":
        x = snap.box.lo + x * snap.box.lengths
    if "radius" in cols:
        r = snap.rows[:, cols["radius"]]
    elif "diameter" in cols:
        r = 0.5 * snap.rows[:, cols["diameter"]]
    else:
        raise _fail(header_line, "the ATOMS columns need a 'radius' (or 'diameter') column")
    bad = ~(r > 0)
    if bad.any():
        n = int(np.argmax(bad))
        raise _fail(snap.first_line + n, f"radius must be positive, found {r[n]:g}")
    masses = None
    if "mass" in cols:
        masses = snap.rows[:, cols["mass"]]
        bad = ~(masses > 0)
        if bad.any():
            n = int(np.argmax(bad))
            raise _fail(snap.first_line + n, f"mass must be positive, found {masses[n]:g}")
        if density is not None:
            raise InputError("density", "the dump has a mass column; do not give a density as well")
    elif density is None:
        raise InputError("density", "the dump has no mass column: give the particle density")
    order = np.argsort(snap.rows[:, cols["id"]], kind="stable") if "id" in cols else np.arange(len(r))
    ids = None
    if "id" in cols:
        ids = snap.rows[order, cols["id"]]
        dup = np.flatnonzero(ids[1:] == ids[:-1])
        if dup.size:
            raise _fail(snap.first_line + int(order[dup[0] + 1]), f"atom id {ids[dup[0]]:g} appears twice")
        bad = np.flatnonzero(ids != np.rint(ids))
        if bad.size:
            raise _fail(snap.first_line + int(order[bad[0]]), f"atom id {ids[bad[0]]:g} is not a whole number")
    return Packing.spheres(x[order], r[order], density=density, masses=None if masses is None else masses[order],
                           box=snap.box, label=label or f"dump, timestep {snap.timestep}", ids=ids)


def read_dump(path, *, density: float | None = None, snapshot: int = -1) -> Packing:
    """The sphere packing in snapshot ``snapshot`` (default: the last) of a LAMMPS/LIGGGHTS dump."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError("file", f"cannot read {path}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise InputError("file", f"{path} is not a text dump file") from None
    try:
        snaps = read_snapshots(text)
        try:
            snap = snaps[snapshot]
        except IndexError:
            raise InputError("snapshot", f"the file has {len(snaps)} snapshot(s); index {snapshot} is out of range") from None
        return packing_from_snapshot(snap, density, label=f"{path.name}, timestep {snap.timestep}")
    except InputError as exc:
        if exc.key.startswith("line "):  # FILE:LINE: reason
            raise InputError(f"{path}:{exc.key[5:]}", exc.reason) from None
        raise


def format_dump(packing: Packing, *, timestep: int = 0, with_mass: bool = True) -> str:
    """A one-snapshot dump text (``id type x y z radius [mass]``) of a sphere packing."""
    if not packing.is_spheres:
        raise InputError("packing", "only sphere packings can be written as a dump")
    box = packing.box
    if box is None:
        lo = packing.positions.min(axis=0) - packing.radii.max()
        hi = packing.positions.max(axis=0) + packing.radii.max()
        box = Box(lo, hi, (False, False, False))
    flags = " ".join("pp" if p else "ff" for p in box.periodic)
    out = ["ITEM: TIMESTEP", str(int(timestep)), "ITEM: NUMBER OF ATOMS", str(packing.n), f"ITEM: BOX BOUNDS {flags}"]
    out += [f"{box.lo[a]:.17g} {box.hi[a]:.17g}" for a in range(3)]
    out.append("ITEM: ATOMS id type x y z radius" + (" mass" if with_mass else ""))
    for k in range(packing.n):
        x, y, z = packing.positions[k]
        row = f"{k + 1} 1 {x:.17g} {y:.17g} {z:.17g} {packing.radii[k]:.17g}"
        if with_mass:
            row += f" {packing.masses[k]:.17g}"
        out.append(row)
    return "\n".join(out) + "\n"


def write_dump(path, packing: Packing, **kwargs) -> None:
    Path(path).write_text(format_dump(packing, **kwargs))
