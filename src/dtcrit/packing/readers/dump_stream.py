"""Stream the snapshots of a LAMMPS / LIGGGHTS text dump one at a time (the format:
``dtcrit.packing.readers.lammps_dump``).

:func:`iter_dump` is a generator: the file is read one line at a time, only the snapshot being
yielded is held in memory, and its atom rows are parsed when :attr:`DumpSnapshot.rows` is first read.
Malformed content raises ``InputError`` located at its line (``InputError.location``: the file and
the line; ``line N`` for text read without a file name).
"""
from __future__ import annotations

import io
import math
from collections import deque
from collections.abc import Generator, Iterator
from pathlib import Path

import numpy as np

from dtcrit.errors import InputError, Location
from dtcrit.packing.model import Box
from dtcrit.packing.readers.limits import MAX_LENGTH

class DumpSnapshot:
    """One snapshot of a dump: its header parsed, its atom rows kept as text until :attr:`rows` is read.

    Parameters
    ----------
    timestep : int
        The ``ITEM: TIMESTEP`` value.
    box : Box
        The box (orthogonal or triclinic) with its periodic axes.
    columns : list of str
        The names of the ``ITEM: ATOMS`` columns.
    lines : list of str
        The atom rows as text, one per atom.
    first_line : int
        The 1-based line of the first atom row.
    source : str or None
        The file read (None for text), naming it in errors.
    """

    def __init__(self, timestep: int, box: Box, columns: list[str], lines: list[str], first_line: int,
                 source: str | None = None):
        self.timestep = timestep
        self.box = box
        self.columns = columns
        self.first_line = first_line
        self.source = source
        self._lines: list[str] | None = lines
        self._rows: np.ndarray | None = None
        self.count = len(lines)

    @property
    def rows(self) -> np.ndarray:
        """The atom rows as numbers, ``(atoms, columns)``, parsed on first use (then the text is dropped)."""
        if self._rows is None:
            assert self._lines is not None
            self._rows = _parse_rows(self._lines, self.columns, self.first_line, self.source)
            self._lines = None
        return self._rows

    def fail(self, line: int, reason: str) -> InputError:
        """An error at a line of this snapshot's file.

        Parameters
        ----------
        line : int
            The 1-based line number.
        reason : str
            What is wrong.

        Returns
        -------
        InputError
            The error, located at ``(source, line)``.
        """
        return _fail(line, reason, self.source)

    def at(self, line: int) -> Location:
        """The location of a line of this snapshot's file.

        Parameters
        ----------
        line : int
            The 1-based line number.

        Returns
        -------
        Location
            ``Location(source, line)``.
        """
        return Location(self.source, line)


MAX_LINE = 1 << 20
"""Longest line a dump may hold [characters]; longer means it is not a text dump."""


class _Lines:
    """The lines of a binary stream read one at a time (a newline ends one, a trailing carriage return is
    dropped), each decoded as UTF-8 and numbered from 1: a dump is read no further than the
    snapshot asked for, and a byte that is not UTF-8 is named by its line.
    """

    def __init__(self, handle, source: str | None = None):
        self._handle = handle
        self.source = source
        self.number = 0  # of the last line returned

    def next(self) -> str | None:
        raw = self._handle.readline(MAX_LINE + 1)
        if not raw:
            return None
        self.number += 1
        if len(raw) > MAX_LINE:
            raise _fail(self.number, f"a line longer than {MAX_LINE} bytes: not a text dump", self.source)
        if self.number == 1:
            raw = raw.removeprefix(b"\xef\xbb\xbf")
        try:
            return raw.decode("utf-8").rstrip("\r\n")
        except UnicodeDecodeError as exc:
            raise _fail(self.number, f"byte {exc.start + 1} of the line is not UTF-8 text: not a text dump",
                        self.source) from None

    def fail(self, line: int, reason: str) -> InputError:
        return _fail(line, reason, self.source)

    def need(self, what: str) -> str:
        line = self.next()
        if line is None:
            raise _fail(self.number + 1, f"unexpected end of file, expected {what}", self.source)
        return line


def _fail(line: int, reason: str, source: str | None = None) -> InputError:
    return InputError(None, reason, source=source, line=line)


def _expect(lines: _Lines, prefix: str, line: str | None = None) -> str:
    line = lines.need(f"'{prefix}'") if line is None else line
    if not line.strip().startswith(prefix):
        raise lines.fail(lines.number, f"expected '{prefix}', found '{line.strip()[:60]}'")
    return line


def _int_at(lines: _Lines, what: str) -> int:
    text = lines.need(f"the {what}").strip()
    try:
        return int(text)
    except ValueError:
        raise lines.fail(lines.number, f"expected the {what} (a whole number), found '{text[:60]}'") from None


def _box_lines(lines: _Lines, width: int, what: str) -> list[list[float]]:
    """The three bounds lines of ``ITEM: BOX BOUNDS``, ``width`` finite numbers each (``what`` names them)."""
    rows = []
    for _ in range(3):
        text = lines.need(f"the box bounds '{what}' (BOX BOUNDS has three lines)")
        try:
            vals = [float(p) for p in text.split()]
        except ValueError:
            raise lines.fail(lines.number, f"box bounds must be numbers, found '{text.strip()[:60]}'") from None
        if width == 2 and len(vals) == 3:
            raise lines.fail(lines.number, "a third value (a tilt factor) on a bounds line, but the header names no "
                                           "'xy xz yz': a triclinic box says so in its BOX BOUNDS header")
        if len(vals) != width or not all(math.isfinite(v) for v in vals):
            kind = "a triclinic box" if width > 2 else "the box"
            raise lines.fail(lines.number, f"{kind} needs {width} finite numbers '{what}' per line, "
                                           f"found '{text.strip()[:60]}'")
        rows.append(vals)
    return rows


def _parse_box(lines: _Lines, header_text: str) -> Box:
    """The box of ``ITEM: BOX BOUNDS``: orthogonal ``lo hi``; restricted triclinic ``xy xz yz`` with the
    bounding box and tilt factors (LAMMPS Howto triclinic: ``xlo_bound = xlo + min(0, xy, xz, xy + xz)``,
    ``xhi_bound = xhi + max(0, xy, xz, xy + xz)``, ``ylo_bound = ylo + min(0, yz)``,
    ``yhi_bound = yhi + max(0, yz)``); general triclinic ``abc origin`` (``ax ay az xlo`` per line,
    ``dump_modify triclinic/general``).
    """
    k = lines.number
    header = header_text.strip()[len("ITEM: BOX BOUNDS"):].split()
    tilted = [w for w in header if w in ("xy", "xz", "yz")]
    general = header[:2] == ["abc", "origin"]
    if tilted and header[:3] != ["xy", "xz", "yz"]:
        raise lines.fail(k, f"triclinic header: LAMMPS writes 'xy xz yz' before the flags, found '{' '.join(header)}'")
    words = header[3:] if tilted else header[2:] if general else header
    flags = words if words else ["pp", "pp", "pp"]
    if len(flags) != 3 or any(len(f) != 2 or any(ch not in "pfsm" for ch in f) for f in flags):
        raise lines.fail(k, f"boundary flags must be three of pp/ff/ss/mm/fs/..., found '{' '.join(header)}'")
    for a, f in enumerate(flags):
        if ("p" in f) and f != "pp":
            raise lines.fail(k, f"axis {'xyz'[a]}: a periodic axis needs the flag 'pp', found '{f}'")
    periodic = ("p" in flags[0], "p" in flags[1], "p" in flags[2])
    rows = np.array(_box_lines(lines, 4 if general else 3 if tilted else 2,
                               "ax ay az origin" if general else "lo_bound hi_bound tilt" if tilted else "lo hi"))
    big = np.flatnonzero(~(np.abs(rows) <= MAX_LENGTH).all(axis=1) & bool(tilted or general))
    if len(big):  # before the cell's determinant overflows
        raise lines.fail(k + 1 + int(big[0]), f"a box value {np.abs(rows[big[0]]).max():g} m is beyond the "
                                              f"{MAX_LENGTH:g} m a packing's lengths may reach")
    if general:
        lo, cell = rows[:, 3], rows[:, :3].T
    else:
        lo, hi = rows[:, 0].copy(), rows[:, 1].copy()
        cell = None
        if tilted:
            xy, xz, yz = rows[:, 2]
            lo -= [min(0.0, xy, xz, xy + xz), min(0.0, yz), 0.0]
            hi -= [max(0.0, xy, xz, xy + xz), max(0.0, yz), 0.0]
        bad = [a for a in range(3) if not hi[a] - lo[a] > 0]  # also an overflowing length
        if bad:
            raise lines.fail(k + 1 + bad[0], f"upper box bound {hi[bad[0]]:g} must exceed the lower bound {lo[bad[0]]:g}")
        if tilted:
            cell = np.diag(hi - lo) + np.array([[0.0, xy, xz], [0.0, 0.0, yz], [0.0, 0.0, 0.0]])
    if cell is not None and not np.all(np.diag(cell) > 0):
        raise lines.fail(k, f"the cell vectors a, b, c {cell.T.tolist()} need positive x, y, z components "
                            "respectively (LAMMPS's restricted triclinic orientation)")
    if not np.all(np.isfinite(cell if cell is not None else hi - lo)):
        raise lines.fail(lines.number, "the box lengths overflow double precision")
    if cell is not None:
        hi = lo + np.diag(cell)
    try:
        return Box(lo, hi, periodic, cell=cell)
    except InputError as exc:
        raise lines.fail(k, exc.reason) from None


def _frame_header(lines: _Lines, line: str | None = None) -> tuple[int, int, Box, list[str]]:
    """A frame's header, from ``ITEM: TIMESTEP`` (``line`` when already read) to the ``ITEM: ATOMS``
    columns: ``(timestep, number of atoms, box, columns)``; each bad line refused as ``FILE:LINE``.
    """
    _expect(lines, "ITEM: TIMESTEP", line)
    step = _int_at(lines, "timestep")
    _expect(lines, "ITEM: NUMBER OF ATOMS")
    count = _int_at(lines, "number of atoms")
    if count < 1:
        raise lines.fail(lines.number, f"the number of atoms must be at least 1, found {count}")
    box = _parse_box(lines, _expect(lines, "ITEM: BOX BOUNDS"))
    header = _expect(lines, "ITEM: ATOMS")
    columns = header.strip()[len("ITEM: ATOMS"):].split()
    if not columns:
        raise lines.fail(lines.number, "the ATOMS header names no columns")
    return step, count, box, columns


def _next_block(lines: _Lines) -> DumpSnapshot | None:
    """The next snapshot (its rows unparsed), or None at the end of the file."""
    line = lines.next()
    while line is not None and not line.strip():
        line = lines.next()
    if line is None:
        return None
    step, count, box, columns = _frame_header(lines, line)
    first = lines.number + 1
    rows: list[str] = []
    for _ in range(count):
        text = lines.next()
        if text is None:
            raise lines.fail(lines.number + 1, f"unexpected end of file: {count} atom rows announced, {len(rows)} found")
        rows.append(text)
    return DumpSnapshot(step, box, columns, rows, first, lines.source)


def _parse_rows(lines: list[str], columns: list[str], first: int, source: str | None) -> np.ndarray:
    """The atom rows as an ``(atoms, columns)`` array; the first bad row is named by its line."""
    count, width = len(lines), len(columns)
    tokens = " ".join(lines).split()
    values = None
    if len(tokens) == count * width:
        try:
            values = np.array(tokens, dtype=float).reshape(count, width)
        except ValueError:
            values = None
    if values is None:  # locate the first bad row
        for n, text in enumerate(lines):
            parts = text.split()
            if len(parts) != width:
                raise _fail(first + n, f"expected {width} values ({' '.join(columns)[:200]}), found {len(parts)}", source)
            for p in parts:
                try:
                    float(p)
                except ValueError:
                    raise _fail(first + n, f"'{p[:30]}' is not a number", source) from None
        raise _fail(first, "could not read the atom rows", source)  # pragma: no cover
    return values


def _snapshots(lines: _Lines) -> Iterator[DumpSnapshot]:
    """The snapshots of a stream of lines, one at a time; an empty stream is an error at line 1."""
    block = _next_block(lines)
    if block is None:
        raise lines.fail(1, "the file is empty")
    while block is not None:
        yield block
        block = _next_block(lines)


def iter_dump(path) -> Generator[DumpSnapshot, None, None]:
    """Stream the snapshots of a LAMMPS/LIGGGHTS text dump, one at a time.

    The file is read one line at a time: only the snapshot being yielded is held in memory, and its
    atom rows are parsed when its :attr:`DumpSnapshot.rows` is first read.  Errors are located at
    their line of the file (``InputError.location``: source and line).

    Parameters
    ----------
    path : str or pathlib.Path
        The dump file.

    Yields
    ------
    DumpSnapshot
        Each snapshot in the order of the file.
    """
    path = Path(path)
    try:
        with path.open("rb") as handle:
            yield from _snapshots(_Lines(handle, str(path)))
    except OSError as exc:
        raise InputError("file", f"cannot read {path}: {exc.strerror or exc}") from None


def _chosen(snapshots: Iterator[DumpSnapshot], snapshot: int) -> DumpSnapshot:
    """Snapshot ``snapshot`` (Python indexing) of a stream, reading no further than it when
    ``snapshot >= 0`` and holding at most ``-snapshot`` snapshots when it is negative.
    """
    if isinstance(snapshot, bool) or not isinstance(snapshot, (int, np.integer)):
        raise InputError("snapshot", f"must be a whole number, got {snapshot!r}")
    kept: deque = deque(maxlen=1 if snapshot >= 0 else -int(snapshot))
    seen = 0
    for block in snapshots:
        seen += 1
        kept.append(block)
        if seen == snapshot + 1:
            return block
    if snapshot >= 0 or len(kept) < -snapshot:
        raise InputError("snapshot", f"the file has {seen} snapshot(s); index {snapshot} is out of range")
    return kept[0]


def read_snapshots(text: str) -> list[DumpSnapshot]:
    """Every snapshot of a dump's ``text``, its rows parsed.

    Parameters
    ----------
    text : str
        The dump's text.

    Returns
    -------
    list of DumpSnapshot
        The snapshots in order; errors are located ``line N``.
    """
    snaps = list(_snapshots(_Lines(io.BytesIO(text.encode("utf-8", "surrogateescape")))))
    for snap in snaps:
        snap.rows  # noqa: B018 (parsed now, so that a bad row is refused here)
    return snaps
