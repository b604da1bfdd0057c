"""A LAMMPS/LIGGGHTS text dump read by byte ranges: pieces of one snapshot's atom rows, each parsed alone.

The partitioned input of the distributed route (``dtcrit.packing.distributed.partitioned_input``) and
the binary converter (``sphere_npz.convert_dump``) read a dump in pieces, never the whole of it:

1. :func:`scan_markers` finds the snapshots (the ``ITEM: TIMESTEP`` lines) in a byte range, streamed
   in blocks of ``BLOCK`` bytes, with the line number of each (newlines counted before it);
2. :func:`header_at` parses one snapshot's header (timestep, box, ``ITEM: ATOMS`` columns) with the
   serial reader's own functions (``dump_stream``), so its errors and checks are the serial ones;
3. :func:`rows_in_range` returns the atom rows whose first byte lies in ``[a, b)`` of the rows' bytes
   (a row belongs to the piece holding its first byte: the pieces of a split hold every row once);
4. :func:`piece_packing` turns a piece's rows into a packing with the serial reader's column handling
   and checks (``lammps_dump.packing_from_snapshot``: positions ``x y z``/``xu yu zu``/``xs ys zs``,
   ``radius``/``diameter``, ``mass`` or a density), each bad value named by its line of the file.

A piece knows the line number of its first row from the newlines before it (counted by the caller),
so errors read ``FILE:LINE: reason`` as in the serial reader.
"""
from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.model import Box, Packing
from dtcrit.packing.readers.dump_stream import DumpSnapshot, _frame_header, _Lines
from dtcrit.packing.readers.lammps_dump import packing_from_snapshot

__all__ = ["BLOCK", "MARKER", "DumpHeader", "Markers", "header_at", "piece_packing", "rows_in_range", "scan_markers", "snapshot_start"]

BLOCK = 1 << 24
"""Bytes read at a time while scanning for snapshots (16 MiB; nothing of a block is kept)."""
MARKER = b"ITEM: TIMESTEP"
"""The first line of every snapshot."""


@dataclass(frozen=True)
class Markers:
    """The snapshots starting in a byte range of a dump.

    Parameters
    ----------
    offsets : list of int
        Byte offset of each ``ITEM: TIMESTEP`` line starting in the range.
    newlines_before : list of int
        Newlines between the range's start and each of those offsets.
    newlines : int
        Newlines in the whole range.
    """

    offsets: list
    newlines_before: list
    newlines: int


def scan_markers(path, a: int, b: int) -> Markers:
    """The ``ITEM: TIMESTEP`` lines starting in bytes ``[a, b)`` of ``path`` (at a line start), streamed.

    Parameters
    ----------
    path : str or os.PathLike
        The dump file.
    a, b : int
        The byte range scanned.

    Returns
    -------
    Markers
        Their offsets and the newlines counted before each and in the range.
    """
    offsets, before, newlines = [], [], 0
    with open(path, "rb") as handle:
        if a > 0:
            handle.seek(a - 1)
            tail = handle.read(1)  # the byte before the range: a line starts after a newline
        else:
            tail = b"\n"
        pos, stop = a, b + len(MARKER)  # a marker starting just before b is read to its end
        while pos < stop:
            block = handle.read(min(BLOCK, stop - pos))
            if not block:
                break
            text, base = tail + block, pos - len(tail)  # base: the file offset of text[0]
            k = text.find(b"\n" + MARKER)
            while k >= 0:
                if a <= base + k + 1 < b:
                    offsets.append(base + k + 1)
                    before.append(newlines + (text.count(b"\n", len(tail), k + 1) if k + 1 >= len(tail)
                                              else -text.count(b"\n", k + 1, len(tail))))
                k = text.find(b"\n" + MARKER, k + 1)
            newlines += block.count(b"\n", 0, max(0, b - pos))
            tail = text[-len(MARKER):]
            pos += len(block)
    if a == 0 < b and 0 not in offsets and _starts_with_marker(path):  # after a byte-order mark
        offsets.insert(0, 0)
        before.insert(0, 0)
    return Markers(offsets, before, newlines)


def _starts_with_marker(path) -> bool:
    with open(path, "rb") as handle:
        return handle.read(len(MARKER) + 3).removeprefix(b"\xef\xbb\xbf").startswith(MARKER)


def snapshot_start(markers: Markers, snapshot: int) -> tuple[int, int]:
    """``(offset, line)`` of snapshot ``snapshot`` (Python index) among the scanned snapshots.

    Parameters
    ----------
    markers : Markers
        The snapshots of the whole file (``scan_markers`` over all of it, or its pieces joined).
    snapshot : int
        The snapshot's index, Python style.

    Returns
    -------
    tuple of int
        Byte offset and 1-based line of its ``ITEM: TIMESTEP`` line.
    """
    if isinstance(snapshot, bool) or not isinstance(snapshot, (int, np.integer)):
        raise InputError("snapshot", f"must be a whole number, got {snapshot!r}")
    count = len(markers.offsets)
    if count == 0:
        raise InputError("file", "no 'ITEM: TIMESTEP' line: not a LAMMPS text dump")
    if not -count <= snapshot < count:
        raise InputError("snapshot", f"the file has {count} snapshot(s); index {snapshot} is out of range")
    k = snapshot % count
    return markers.offsets[k], markers.newlines_before[k] + 1


@dataclass(frozen=True)
class DumpHeader:
    """A snapshot's header: what every piece of its rows shares.

    Parameters
    ----------
    timestep, count : int
        ``ITEM: TIMESTEP`` and ``ITEM: NUMBER OF ATOMS``.
    box : Box
        The box and its periodic axes.
    columns : list of str
        The ``ITEM: ATOMS`` column names.
    rows_start : int
        Byte offset of the first atom row.
    first_line : int
        1-based line of the first atom row.
    source : str
        The file, naming it in errors.
    """

    timestep: int
    count: int
    box: Box
    columns: list
    rows_start: int
    first_line: int
    source: str


def header_at(path, offset: int, line: int) -> DumpHeader:
    """The header of the snapshot starting at byte ``offset`` (1-based line ``line``) of ``path``,
    parsed and checked by the serial reader's functions (``dump_stream``).

    Parameters
    ----------
    path : str or os.PathLike
        The dump file.
    offset : int
        Byte offset of its ``ITEM: TIMESTEP`` line.
    line : int
        That line's number.

    Returns
    -------
    DumpHeader
        The parsed header.
    """
    source = os.fspath(path)
    with open(path, "rb") as handle:
        handle.seek(offset)
        lines = _Lines(handle, source)
        lines.number = line - 1
        if offset == 0:  # the first line may carry a byte-order mark, which _Lines drops on its line 1 only
            lines.number = 0
        step, count, box, columns = _frame_header(lines)
        return DumpHeader(step, count, box, columns, handle.tell(), lines.number + 1, source)


def rows_in_range(path, start: int, end: int, a: int, b: int, first_line: int | None) -> list[str]:
    """The text lines of bytes ``[start, end)`` whose first byte lies in ``[a, b)`` (a line starting
    before ``b`` is read to its end), decoded as UTF-8, line ends dropped.

    Parameters
    ----------
    path : str or os.PathLike
        The dump file.
    start, end : int
        The bytes of the snapshot's rows (``start`` a line start).
    a, b : int
        This piece's share of ``[start, end)``.
    first_line : int or None
        1-based line of the piece's first line (a byte that is not UTF-8 is named by its line from
        it; None: by the file alone).

    Returns
    -------
    list of str
        The lines, in file order.
    """
    a, b = max(a, start), min(b, end)
    if b <= a:
        return []
    with open(path, "rb") as handle:
        if a > start:
            handle.seek(a - 1)
            if handle.read(1) != b"\n":  # a starts inside a line: that line is the previous piece's
                handle.readline()
        else:
            handle.seek(a)
        first = handle.tell()
        if first >= b:
            return []
        data = handle.read(b - first)
        if not data.endswith(b"\n"):
            data += handle.readline()[: max(end - b, 0)]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = None if first_line is None else first_line + data.count(b"\n", 0, exc.start)
        raise InputError(None, f"byte {first + exc.start + 1} of the file is not UTF-8 text: not a text dump",
                         source=os.fspath(path), line=line) from None
    out = text.split("\n")
    if out and out[-1] == "":
        out.pop()
    return [s.rstrip("\r") for s in out]


def piece_packing(header: DumpHeader, lines: list[str], first_line: int, density: float | None) -> Packing:
    """The spheres of a piece's rows (their lines from ``first_line``), with the serial reader's column
    handling and checks (``lammps_dump.packing_from_snapshot``), sorted by id when the dump has ids.

    Parameters
    ----------
    header : DumpHeader
        The snapshot's header.
    lines : list of str
        The piece's atom rows (at least one).
    first_line : int
        1-based line of ``lines[0]``.
    density : float or None
        Particle density [kg/m^3] for a dump without a ``mass`` column.

    Returns
    -------
    Packing
        The piece's spheres (``ids`` the dump's ids, or None).
    """
    snap = DumpSnapshot(header.timestep, header.box, header.columns, lines, first_line, header.source)
    label = f"{os.path.basename(header.source)}, timestep {header.timestep}"
    return packing_from_snapshot(snap, density, label=label)

