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

import io
import math
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError

from dtcrit.packing.model import Box, Packing
from dtcrit.packing.readers.limits import check_inertia, check_lengths

_POSITION_SETS = (("x", "y", "z"), ("xu", "yu", "zu"), ("xs", "ys", "zs"))


@dataclass
class _Snapshot:
    timestep: int
    box: Box
    columns: list[str]
    rows: np.ndarray
    first_line: int  # 1-based line number of the first atom row


@dataclass
class _Block:
    """A snapshot as read: its header parsed, its atom rows still text (parsed only when chosen)."""

    timestep: int
    box: Box
    columns: list[str]
    lines: list[str]
    first_line: int


MAX_LINE = 1 << 20
"""Longest line a dump may hold [characters]; longer means it is not a text dump."""


class _Lines:
    """The lines of a binary stream read one at a time (``\n`` ends one, a trailing ``\r`` is
    dropped), each decoded as UTF-8 and numbered from 1: a dump is read no further than the
    snapshot asked for, and a byte that is not UTF-8 is named by its line.
    """

    def __init__(self, handle):
        self._handle = handle
        self.number = 0  # of the last line returned

    def next(self) -> str | None:
        raw = self._handle.readline(MAX_LINE + 1)
        if not raw:
            return None
        self.number += 1
        if len(raw) > MAX_LINE:
            raise _fail(self.number, f"a line longer than {MAX_LINE} bytes: not a text dump")
        if self.number == 1:
            raw = raw.removeprefix(b"\xef\xbb\xbf")
        try:
            return raw.decode("utf-8").rstrip("\r\n")
        except UnicodeDecodeError as exc:
            raise _fail(self.number, f"byte {exc.start + 1} of the line is not UTF-8 text: not a text dump") from None

    def need(self, what: str) -> str:
        line = self.next()
        if line is None:
            raise _fail(self.number + 1, f"unexpected end of file, expected {what}")
        return line


def _fail(line: int, reason: str) -> InputError:
    return InputError(f"line {line}", reason)


def _expect(lines: _Lines, prefix: str, line: str | None = None) -> str:
    line = lines.need(f"'{prefix}'") if line is None else line
    if not line.strip().startswith(prefix):
        raise _fail(lines.number, f"expected '{prefix}', found '{line.strip()[:60]}'")
    return line


def _int_at(lines: _Lines, what: str) -> int:
    text = lines.need(f"the {what}").strip()
    try:
        return int(text)
    except ValueError:
        raise _fail(lines.number, f"expected the {what} (a whole number), found '{text[:60]}'") from None


def _parse_box(lines: _Lines, header_text: str) -> Box:
    k = lines.number
    header = header_text.strip()[len("ITEM: BOX BOUNDS"):].split()
    if any(flag in ("xy", "xz", "yz") for flag in header):
        raise _fail(k, "triclinic boxes are not supported (orthogonal boxes only)")
    flags = header if header else ["pp", "pp", "pp"]
    if len(flags) != 3 or any(len(f) != 2 or any(ch not in "pfsm" for ch in f) for f in flags):
        raise _fail(k, f"boundary flags must be three of pp/ff/ss/mm/fs/..., found '{' '.join(header)}'")
    for a, f in enumerate(flags):
        if ("p" in f) and f != "pp":
            raise _fail(k, f"axis {'xyz'[a]}: a periodic axis needs the flag 'pp', found '{f}'")
    lo, hi = np.zeros(3), np.zeros(3)
    for a in range(3):
        text = lines.need("the box bounds 'lo hi' (BOX BOUNDS has three lines)")
        try:
            vals = [float(p) for p in text.split()]
        except ValueError:
            raise _fail(lines.number, f"box bounds must be numbers, found '{text.strip()[:60]}'") from None
        if len(vals) == 3:
            raise _fail(lines.number, "triclinic boxes are not supported (orthogonal boxes only)")
        if len(vals) != 2 or not all(math.isfinite(v) for v in vals):
            raise _fail(lines.number, f"expected two finite numbers 'lo hi', found '{text.strip()[:60]}'")
        if not vals[1] - vals[0] > 0:  # also an overflowing length
            raise _fail(lines.number, f"upper box bound {vals[1]:g} must exceed the lower bound {vals[0]:g}")
        lo[a], hi[a] = vals
    if not np.all(np.isfinite(hi - lo)):
        raise _fail(lines.number, "the box lengths overflow double precision")
    return Box(lo, hi, tuple("p" in f for f in flags))


def _next_block(lines: _Lines) -> _Block | None:
    """The next snapshot (its rows unparsed), or None at the end of the file."""
    line = lines.next()
    while line is not None and not line.strip():
        line = lines.next()
    if line is None:
        return None
    _expect(lines, "ITEM: TIMESTEP", line)
    step = _int_at(lines, "timestep")
    _expect(lines, "ITEM: NUMBER OF ATOMS")
    count = _int_at(lines, "number of atoms")
    if count < 1:
        raise _fail(lines.number, f"the number of atoms must be at least 1, found {count}")
    box = _parse_box(lines, _expect(lines, "ITEM: BOX BOUNDS"))
    header = _expect(lines, "ITEM: ATOMS")
    columns = header.strip()[len("ITEM: ATOMS"):].split()
    if not columns:
        raise _fail(lines.number, "the ATOMS header names no columns")
    first = lines.number + 1
    rows = []
    for _ in range(count):
        text = lines.next()
        if text is None:
            raise _fail(lines.number + 1, f"unexpected end of file: {count} atom rows announced, {len(rows)} found")
        rows.append(text)
    return _Block(step, box, columns, rows, first)


def _parse_rows(block: _Block) -> _Snapshot:
    columns, first, count = block.columns, block.first_line, len(block.lines)
    width = len(columns)
    tokens = " ".join(block.lines).split()
    values = None
    if len(tokens) == count * width:
        try:
            values = np.array(tokens, dtype=float).reshape(count, width)
        except ValueError:
            values = None
    if values is None:  # locate the first bad row
        for n, text in enumerate(block.lines):
            parts = text.split()
            if len(parts) != width:
                raise _fail(first + n, f"expected {width} values ({' '.join(columns)[:200]}), found {len(parts)}")
            for p in parts:
                try:
                    float(p)
                except ValueError:
                    raise _fail(first + n, f"'{p[:30]}' is not a number") from None
        raise _fail(first, "could not read the atom rows")  # pragma: no cover
    return _Snapshot(block.timestep, block.box, columns, values, first)


def _chosen_block(lines: _Lines, snapshot: int) -> _Block:
    """Snapshot ``snapshot`` (Python indexing), reading no further than it when ``snapshot >= 0``."""
    if isinstance(snapshot, bool) or not isinstance(snapshot, (int, np.integer)):
        raise InputError("snapshot", f"must be a whole number, got {snapshot!r}")
    kept: deque = deque(maxlen=1 if snapshot >= 0 else -int(snapshot))
    seen = 0
    while True:
        block = _next_block(lines)
        if block is None:
            break
        seen += 1
        kept.append(block)
        if seen == snapshot + 1:
            return block
    if seen == 0:
        raise _fail(1, "the file is empty")
    if snapshot >= 0 or len(kept) < -snapshot:
        raise InputError("snapshot", f"the file has {seen} snapshot(s); index {snapshot} is out of range")
    return kept[0]


def read_snapshots(text: str) -> list[_Snapshot]:
    """Every snapshot of a dump's ``text``."""
    lines = _Lines(io.BytesIO(text.encode("utf-8", "surrogateescape")))
    snaps = []
    while (block := _next_block(lines)) is not None:
        snaps.append(_parse_rows(block))
    if not snaps:
        raise _fail(1, "the file is empty")
    return snaps


def _used_columns(cols: dict, columns: list[str], header_line: int) -> None:
    """Refuse a repeated column name only when the reader uses it (LIGGGHTS writes ``type type``)."""
    for name in cols:
        if columns.count(name) > 1:
            raise _fail(header_line, f"the ATOMS header names the column '{name}' {columns.count(name)} times; "
                                     "dtcrit reads it, so it must appear once")


def packing_from_snapshot(snap: _Snapshot, density: float | None = None, label: str = "") -> Packing:
    cols = {name: i for i, name in enumerate(snap.columns)}
    header_line = snap.first_line - 1
    pos = next((s for s in _POSITION_SETS if all(c in cols for c in s)), None)
    if pos is None:
        raise _fail(header_line, "the ATOMS columns need positions: x y z, xu yu zu or xs ys zs")
    size = "radius" if "radius" in cols else ("diameter" if "diameter" in cols else None)
    if size is None:
        raise _fail(header_line, "the ATOMS columns need a 'radius' (or 'diameter') column")
    used = [*pos, size] + [c for c in ("mass", "id") if c in cols]
    _used_columns({c: cols[c] for c in used}, snap.columns, header_line)
    bad = ~np.isfinite(snap.rows[:, [cols[c] for c in used]]).all(axis=1)
    if bad.any():
        n = int(np.argmax(bad))
        col = next(c for c in used if not np.isfinite(snap.rows[n, cols[c]]))
        raise _fail(snap.first_line + n, f"{col} is not finite ({snap.rows[n, cols[col]]:g})")
    x = snap.rows[:, [cols[c] for c in pos]]
    if pos[0] == "xs":
        with np.errstate(over="ignore", invalid="ignore"):
            x = snap.box.lo + x * snap.box.lengths
    r = snap.rows[:, cols["radius"]] if size == "radius" else 0.5 * snap.rows[:, cols["diameter"]]
    bad = ~(r > 0)
    if bad.any():
        n = int(np.argmax(bad))
        raise _fail(snap.first_line + n, f"{size} must be positive, found {snap.rows[n, cols[size]]:g}")
    masses = None
    if "mass" in cols:
        masses = snap.rows[:, cols["mass"]]
        bad = ~(masses > 0)
        if bad.any():
            n = int(np.argmax(bad))
            raise _fail(snap.first_line + n, f"mass must be positive, found {masses[n]:g}")
        if density is not None:
            raise _fail(header_line, "the ATOMS columns include 'mass': do not give a density (--density) as well")
    elif density is None:
        raise _fail(header_line, "the ATOMS columns have no 'mass': give the particle density (--density)")
    _check_sizes(snap, x, r, masses, density)
    for what, values in (("a box bound", np.vstack([snap.box.lo, snap.box.hi]).T), ("a coordinate", x), ("radius", r)):
        if what == "a box bound":
            check_lengths(values, lambda k: f"line {snap.first_line - 4 + k}", what)
        else:
            check_lengths(values, lambda k: f"line {snap.first_line + k}", what)
    _periodic_room(snap, r)
    order = np.argsort(snap.rows[:, cols["id"]], kind="stable") if "id" in cols else np.arange(len(r))
    ids = None
    if "id" in cols:
        ids = snap.rows[order, cols["id"]]
        dup = np.flatnonzero(ids[1:] == ids[:-1])
        if dup.size:
            raise _fail(snap.first_line + int(order[dup[0] + 1]), f"atom id {ids[dup[0]]:g} appears twice")
        bad = np.flatnonzero((ids != np.rint(ids)) | (np.abs(ids) >= 2.0**63))
        if bad.size:
            raise _fail(snap.first_line + int(order[bad[0]]), f"atom id {ids[bad[0]]:g} is not a whole number "
                                                               "(64-bit)")
    return Packing.spheres(x[order], r[order], density=density, masses=None if masses is None else masses[order],
                           box=snap.box, label=label or f"dump, timestep {snap.timestep}", ids=ids)


def _check_sizes(snap: _Snapshot, x: np.ndarray, r: np.ndarray, masses, density) -> None:
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
        raise _fail(snap.first_line + n, f"the position {x[n].tolist()} is outside double precision")
    bad = ~(np.isfinite(m) & (m > 0) & np.isfinite(inertia) & (inertia > 0))
    if bad.any():
        n = int(np.argmax(bad))
        raise _fail(snap.first_line + n, f"radius {r[n]:g} and mass {m[n]:g} give a moment of inertia "
                                         f"{inertia[n]:g} outside double precision")
    check_inertia(m, lambda n: f"line {snap.first_line + n}", "the mass [kg]")
    check_inertia(inertia, lambda n: f"line {snap.first_line + n}", "the moment of inertia 2/5 m R^2 [kg m^2]")


def _periodic_room(snap: _Snapshot, r: np.ndarray) -> None:
    """Refuse a sphere whose radius exceeds a periodic length: it would overlap its own periodic
    images more than one deep (and the image search would not end).
    """
    k = int(np.argmax(r))
    for a in range(3):
        if snap.box.periodic[a] and snap.box.lengths[a] < r[k]:
            raise _fail(snap.first_line + k, f"radius {r[k]:g} exceeds the periodic box length {snap.box.lengths[a]:g} "
                                             f"along {'xyz'[a]}: the sphere would overlap its own images more than "
                                             "one deep")


def read_dump(path, *, density: float | None = None, snapshot: int = -1) -> Packing:
    """The sphere packing in snapshot ``snapshot`` (default: the last) of a LAMMPS/LIGGGHTS dump.

    The file is read one line at a time: no further than the snapshot asked for when ``snapshot >= 0``,
    and only the chosen snapshot's atom rows are parsed.
    """
    path = Path(path)
    try:
        with path.open("rb") as handle:
            block = _chosen_block(_Lines(handle), snapshot)
        return packing_from_snapshot(_parse_rows(block), density, label=f"{path.name}, timestep {block.timestep}")
    except OSError as exc:
        raise InputError("file", f"cannot read {path}: {exc.strerror or exc}") from None
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
