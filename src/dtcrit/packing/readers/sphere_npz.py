"""The binary sphere file (``.npz``) read by slices: one snapshot's spheres for the partitioned input.

Layout (format ``dtcrit-spheres/1``): a NumPy ``.npz`` archive written *uncompressed* (zip ``STORED``),
so that each member is a plain ``.npy`` array at a fixed offset of the file and any slice of it can be
read through ``numpy.memmap`` without reading the rest:

* ``spheres.npy``: a structured array of ``N`` rows, dtype :data:`SPHERE_DTYPE`, little-endian:
  ``id`` (int64, the dump's atom id, or the row's 1-based number when the dump has none), ``x``,
  ``y``, ``z`` (float64, centre [m], as the dump gives them; box fractions already scaled),
  ``radius`` [m] and ``mass`` [kg] (float64; from the dump's ``mass`` column, or ``4/3 pi R^3 rho``
  from the density given at conversion);
* ``box.npy``: one record, dtype :data:`BOX_DTYPE`: ``lo`` and ``hi`` (3 float64 each, the box
  bounds [m]), ``periodic`` (3 bools, ``pp`` axes) and ``timestep`` (int64).

Only axis-aligned boxes are written (the distributed contact search takes no sheared cell).
:func:`convert_dump` writes one from a text dump in pieces of ``PIECE_BYTES`` of text (never the whole
dump in memory), with the serial reader's checks on every row, under a temporary name beside the target
renamed onto it once complete (a failed conversion leaves no file); :func:`open_spheres` checks that the
``spheres`` member holds exactly its ``N`` rows (a truncated or corrupted file is refused, never read as
garbage), maps the rows and reads the box.  ``python -m dtcrit.packing.readers.sphere_npz DUMP OUT.npz [--density RHO]
[--snapshot K]`` converts from the command line.
"""
from __future__ import annotations

import os
import secrets
import struct
import sys
import zipfile
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.model import Box

__all__ = ["BOX_DTYPE", "FORMAT", "PIECE_BYTES", "SPHERE_DTYPE", "SphereFile", "convert_dump", "is_sphere_file",
           "open_spheres"]

FORMAT = "dtcrit-spheres/1"
SPHERE_DTYPE = np.dtype([("id", "<i8"), ("x", "<f8"), ("y", "<f8"), ("z", "<f8"), ("radius", "<f8"),
                         ("mass", "<f8")])
"""One sphere: atom id, centre [m], radius [m], mass [kg]."""
BOX_DTYPE = np.dtype([("lo", "<f8", (3,)), ("hi", "<f8", (3,)), ("periodic", "?", (3,)), ("timestep", "<i8")])
"""The box bounds [m], periodic axes and timestep."""
PIECE_BYTES = 1 << 26
"""Text bytes of the dump converted at a time (64 MiB, about 0.6 million rows)."""
_LOCAL_HEADER = struct.Struct("<IHHHHHIIIHH")  # zip local file header (APPNOTE 4.3.7), 30 bytes


def is_sphere_file(path) -> bool:
    """Whether ``path`` names a ``dtcrit-spheres/1`` file (by its ``.npz`` suffix).

    Parameters
    ----------
    path : str or os.PathLike or None
        A file name.

    Returns
    -------
    bool
        True for a ``.npz`` name.
    """
    return path is not None and os.fspath(path).lower().endswith(".npz")


@dataclass(frozen=True)
class SphereFile:
    """An opened sphere file: its rows mapped (not read) and its box.

    Parameters
    ----------
    rows : numpy.ndarray
        The ``spheres`` member as a read-only ``numpy.memmap`` of :data:`SPHERE_DTYPE`.
    box : Box
        The box.
    timestep : int
        The snapshot's timestep.
    source : str
        The file.
    """

    rows: np.ndarray
    box: Box
    timestep: int
    source: str


def _member(handle, info: zipfile.ZipInfo, source: str) -> tuple[np.dtype, tuple, int, int]:
    """``(dtype, shape, offset, nbytes)`` of an uncompressed ``.npy`` member: where its array's bytes begin
    and how many bytes of array the member holds (its size less its ``.npy`` header).
    """
    if info.compress_type != zipfile.ZIP_STORED:
        raise InputError("file", f"{source}: member {info.filename} is compressed; {FORMAT} stores its arrays "
                                 "uncompressed (numpy.savez, not savez_compressed) so that they can be sliced")
    handle.seek(info.header_offset)
    fields = _LOCAL_HEADER.unpack(handle.read(_LOCAL_HEADER.size))
    if fields[0] != 0x04034B50:
        raise InputError("file", f"{source}: member {info.filename} has no zip local header")
    start = info.header_offset + _LOCAL_HEADER.size + fields[9] + fields[10]
    handle.seek(start)
    version = np.lib.format.read_magic(handle)
    reader = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
    shape, fortran, dtype = reader(handle)
    if fortran:
        raise InputError("file", f"{source}: member {info.filename} is in Fortran order")
    offset = handle.tell()
    return dtype, shape, offset, info.file_size - (offset - start)


def _check_size(source: str, shape: tuple, offset: int, nbytes: int) -> None:
    """Refuse a ``spheres.npy`` member whose bytes are not ``N`` rows of :data:`SPHERE_DTYPE` (truncated or
    corrupted): the member's size must be its header plus ``N * itemsize``, and the file must hold them.
    """
    need = shape[0] * SPHERE_DTYPE.itemsize
    if nbytes != need:
        raise InputError("file", f"{source}: spheres.npy announces {shape[0]} rows ({need} bytes) but holds "
                                 f"{nbytes} bytes of rows (truncated or corrupted)")
    if os.path.getsize(source) < offset + need:
        raise InputError("file", f"{source}: the file ends {offset + need - os.path.getsize(source)} bytes before "
                                 f"the {shape[0]} rows of spheres.npy do (truncated)")

def open_spheres(path) -> SphereFile:
    """Map the rows of a ``dtcrit-spheres/1`` file and read its box (module docstring: the layout).

    Parameters
    ----------
    path : str or os.PathLike
        The ``.npz`` file.

    Returns
    -------
    SphereFile
        The mapped rows and the box; nothing of the rows is read until sliced.

    Raises
    ------
    InputError
        Not a ``dtcrit-spheres/1`` file, or one truncated or corrupted (the ``spheres`` member's size is not
        its header plus ``N`` rows, or the file ends before them), naming the file.
    """
    source = os.fspath(path)
    try:
        with zipfile.ZipFile(source) as archive, open(source, "rb") as handle:
            names = set(archive.namelist())
            if not {"spheres.npy", "box.npy"} <= names:
                raise InputError("file", f"{source}: a {FORMAT} file holds spheres.npy and box.npy, found "
                                         f"{sorted(names)[:6]}")
            dtype, shape, offset, nbytes = _member(handle, archive.getinfo("spheres.npy"), source)
            with archive.open("box.npy") as member:
                box_record = np.lib.format.read_array(member, allow_pickle=False)
    except (OSError, zipfile.BadZipFile, ValueError) as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError("file", f"cannot read {source} as a {FORMAT} file: {exc}") from None
    if dtype != SPHERE_DTYPE or len(shape) != 1 or shape[0] < 1:
        raise InputError("file", f"{source}: spheres.npy must be a 1-d array of at least one {SPHERE_DTYPE.descr}, "
                                 f"found {dtype.descr} {shape}")
    _check_size(source, shape, offset, nbytes)
    if box_record.dtype != BOX_DTYPE or box_record.size != 1:
        raise InputError("file", f"{source}: box.npy must be one record of {BOX_DTYPE.descr}")
    record = box_record.reshape(-1)[0]
    rows = np.memmap(source, dtype=SPHERE_DTYPE, mode="r", offset=offset, shape=shape)
    flags = [bool(p) for p in record["periodic"]]
    box = Box(np.array(record["lo"], float), np.array(record["hi"], float), (flags[0], flags[1], flags[2]))
    return SphereFile(rows, box, int(record["timestep"]), source)


def _write_rows(stream, packing, first_id: int) -> None:
    """Append a piece's spheres to the open ``spheres.npy`` member (ids, or row numbers from ``first_id``)."""
    out = np.empty(packing.n, dtype=SPHERE_DTYPE)
    out["id"] = packing.ids if packing.ids is not None else np.arange(first_id, first_id + packing.n)
    for a, name in enumerate("xyz"):
        out[name] = packing.positions[:, a]
    out["radius"], out["mass"] = packing.radii, packing.masses
    stream.write(out.tobytes())


def convert_dump(dump, out, *, density: float | None = None, snapshot: int = -1) -> int:
    """Write one snapshot of a LAMMPS/LIGGGHTS text dump as a ``dtcrit-spheres/1`` file, in pieces
    of ``PIECE_BYTES`` of text (each parsed and checked by the serial reader's code, ``dump_ranges``).

    Parameters
    ----------
    dump : str or os.PathLike
        The text dump.
    out : str or os.PathLike
        The ``.npz`` written.
    density : float or None
        Particle density [kg/m^3] when the dump has no ``mass`` column.
    snapshot : int
        Snapshot index, Python style (default the last).

    Returns
    -------
    int
        The number of spheres written.

    Notes
    -----
    The file is written under a temporary name beside ``out`` and renamed onto it (``os.replace``) once
    complete: a conversion that fails leaves neither a partial ``out`` nor the temporary file.
    """
    from dtcrit.packing.readers.dump_ranges import header_at, scan_markers, snapshot_start

    size = os.path.getsize(dump)
    markers = scan_markers(dump, 0, size)
    header = header_at(dump, *snapshot_start(markers, snapshot))
    if header.box.cell is not None:
        raise InputError("file", f"{dump}: a sheared (triclinic) box; {FORMAT} holds axis-aligned boxes only")
    end = next((o for o in markers.offsets if o > header.rows_start), size)
    target = os.fspath(out)
    head, tail = os.path.split(target)
    temp = os.path.join(head, f".{tail}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        written = _write_archive(temp, dump, header, end, density)
        os.replace(temp, target)
    except BaseException:
        if os.path.exists(temp):
            os.remove(temp)
        raise
    return written


def _write_archive(out: str, dump, header, end: int, density: float | None) -> int:
    """Write the ``.npz`` of the snapshot ``header`` of ``dump`` (rows up to byte ``end``) to ``out``."""
    from dtcrit.packing.readers.dump_ranges import piece_packing, rows_in_range

    written, line = 0, header.first_line
    record = np.zeros((), dtype=BOX_DTYPE)
    record["lo"], record["hi"], record["periodic"] = header.box.lo, header.box.hi, header.box.periodic
    record["timestep"] = header.timestep
    with zipfile.ZipFile(out, "w", zipfile.ZIP_STORED, allowZip64=True) as archive:
        with archive.open("box.npy", "w") as member:
            np.lib.format.write_array(member, record, allow_pickle=False)
        with archive.open("spheres.npy", "w", force_zip64=True) as member:
            np.lib.format.write_array_header_2_0(member, {"descr": np.lib.format.dtype_to_descr(SPHERE_DTYPE),
                                                          "fortran_order": False, "shape": (header.count,)})
            for a in range(header.rows_start, end, PIECE_BYTES):
                lines = rows_in_range(dump, header.rows_start, end, a, a + PIECE_BYTES, line)
                extra = len(lines) - max(0, header.count - written)
                if extra > 0 and any(s.strip() for s in lines[len(lines) - extra:]):
                    bad = next(k for k in range(len(lines) - extra, len(lines)) if lines[k].strip())
                    raise InputError(None, f"expected 'ITEM: TIMESTEP', found '{lines[bad].strip()[:60]}'",
                                     source=os.fspath(dump), line=line + bad)
                rows = lines[:len(lines) - max(extra, 0)]
                if rows:
                    _write_rows(member, piece_packing(header, rows, line, density), written + 1)
                written += len(rows)
                line += len(lines)
            if written != header.count:
                raise InputError(None, f"unexpected end of file: {header.count} atom rows announced, {written} found",
                                 source=os.fspath(dump), line=line)
    return written


def main(argv: list[str] | None = None) -> int:
    """``python -m dtcrit.packing.readers.sphere_npz DUMP OUT.npz [--density RHO] [--snapshot K]``.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status: 0, or 2 on bad input (one line on stderr).
    """
    import argparse

    parser = argparse.ArgumentParser(prog="python -m dtcrit.packing.readers.sphere_npz",
                                     description=f"convert a LAMMPS text dump to a {FORMAT} file")
    parser.add_argument("dump")
    parser.add_argument("out")
    parser.add_argument("--density", type=float, help="particle density [kg/m^3] when the dump has no mass column")
    parser.add_argument("--snapshot", type=int, default=-1, help="snapshot index (default: last)")
    args = parser.parse_args(argv)
    try:
        n = convert_dump(args.dump, args.out, density=args.density, snapshot=args.snapshot)
    except InputError as exc:
        sys.stderr.write(f"error: {exc}\n")
        return 2
    print(f"{args.out}: {n} spheres ({FORMAT})")
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
