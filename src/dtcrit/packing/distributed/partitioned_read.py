"""Step 1 of the partitioned input (``partitioned_input``): each rank reads its piece of a text dump
(a byte range of the chosen snapshot's atom rows: ``dtcrit.packing.readers.dump_ranges``) or of a
``dtcrit-spheres/1`` file (a slice of rows: ``dtcrit.packing.readers.sphere_npz``), with the serial
reader's checks; an error met on any rank stops every rank (``mpi_support.agree``).  MPI through
``mpi4py`` (``PETSc.COMM_WORLD.tompi4py()``), imported inside the functions.
"""
from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.distributed.mpi_support import agree
from dtcrit.packing.distributed.petsc_build import check_dofs
from dtcrit.packing.distributed.slab_contacts import split_rows
from dtcrit.packing.model import Box, Packing
from dtcrit.packing.readers.sphere_npz import is_sphere_file

__all__ = ["ROW_DTYPE", "Piece", "collective", "mpi", "read_piece"]

ROW_DTYPE = np.dtype([("key", "<u8"), ("id", "<i8"), ("glob", "<i8"), ("x", "<f8", (3,)), ("radius", "<f8"),
                      ("mass", "<f8")])
"""A sphere in transit: Morton key, atom id (or row number), global index, centre [m], radius [m], mass [kg]."""


@dataclass
class Piece:
    """The spheres one rank read, and what every rank shares about the packing.

    Parameters
    ----------
    rows : numpy.ndarray
        This rank's spheres, :data:`ROW_DTYPE` (keys and global indices not yet set).
    n : int
        Spheres in the packing.
    box : Box
        The box.
    label : str
        The packing's label (``NAME, timestep N``).
    has_ids : bool
        Whether the file gives atom ids (else ``id`` is the row's 1-based number).
    """

    rows: np.ndarray
    n: int
    box: Box
    label: str
    has_ids: bool


def mpi():
    """The mpi4py communicator of ``PETSc.COMM_WORLD`` and the ``MPI`` module.

    Returns
    -------
    tuple
        ``(comm, MPI)``.
    """
    from petsc4py import PETSc

    from mpi4py import MPI

    return PETSc.COMM_WORLD.tompi4py(), MPI


def _check_count(n: int, size: int) -> None:
    """Refuse more DOFs than the loaded PETSc build numbers (``petsc_build.check_dofs``), or fewer particles than ranks."""
    check_dofs(n)
    if n < size:
        raise InputError("packing", f"{n} particles cannot be shared by {size} ranks (fewer ranks, please)")


def _rows(packing: Packing, ids) -> np.ndarray:
    out = np.zeros(packing.n, dtype=ROW_DTYPE)
    out["id"], out["x"], out["radius"], out["mass"] = ids, packing.positions, packing.radii, packing.masses
    return out


def collective(step, *args):
    """``step(*args)`` on every rank; an ``InputError`` on any rank is raised everywhere (``agree``).

    Parameters
    ----------
    step : callable
        What every rank runs.
    *args
        Its arguments.

    Returns
    -------
    object
        What ``step`` returned on this rank.
    """
    result, error = None, None
    try:
        result = step(*args)
    except ValueError as exc:
        error = exc
    agree(error)
    return result


def _npz_piece(source, density, snapshot) -> Piece:
    from dtcrit.packing.readers.sphere_npz import open_spheres

    comm, _ = mpi()
    rank, size = comm.Get_rank(), comm.Get_size()
    if density is not None:
        raise InputError("density", "a dtcrit-spheres/1 file carries each sphere's mass: drop --density")
    if snapshot not in (0, -1):
        raise InputError("snapshot", "a dtcrit-spheres/1 file holds one snapshot (0 or -1)")
    spheres = open_spheres(source)
    n = len(spheres.rows)
    _check_count(n, size)
    lo, hi = split_rows(n, size, rank)
    part = np.array(spheres.rows[lo:hi])
    try:
        packing = Packing.spheres(np.stack([part["x"], part["y"], part["z"]], axis=1), part["radius"],
                                  masses=part["mass"], box=spheres.box)
    except InputError as exc:
        raise InputError("file", f"{source}: rows {lo + 1}..{hi}: {exc.reason}") from None
    label = f"{os.path.basename(source)}, timestep {spheres.timestep}"
    return Piece(_rows(packing, part["id"]), n, spheres.box, label, True)


def _markers(source, comm):
    """Every snapshot of the dump: each rank scans its byte range, the finds are gathered."""
    from dtcrit.packing.readers.dump_ranges import Markers, scan_markers

    rank, size = comm.Get_rank(), comm.Get_size()
    total = os.path.getsize(source)
    a, b = split_rows(total, size, rank)
    found = collective(scan_markers, source, a, b)
    offsets, before, base = [], [], 0
    for offs, lines, count in comm.allgather((found.offsets, found.newlines_before, found.newlines)):
        offsets += offs
        before += [base + k for k in lines]
        base += count
    return Markers(offsets, before, base), total


def _header(source, markers, snapshot, size: int):
    from dtcrit.packing.readers.dump_ranges import header_at, snapshot_start

    header = header_at(source, *snapshot_start(markers, snapshot))
    if header.box.cell is not None:
        raise InputError("box", "the partitioned read takes axis-aligned boxes only: a sheared (triclinic) cell "
                                "runs without --partitioned-read")
    _check_count(header.count, size)
    return header


def _text_piece(source, density, snapshot) -> Piece:
    from dtcrit.packing.readers.dump_ranges import piece_packing, rows_in_range

    comm, _ = mpi()
    rank, size = comm.Get_rank(), comm.Get_size()
    markers, total = _markers(source, comm)
    header = collective(_header, source, markers, snapshot, size)
    end = next((o for o in markers.offsets if o > header.rows_start), total)
    a, b = split_rows(end - header.rows_start, size, rank)
    lines = collective(rows_in_range, source, header.rows_start, end, header.rows_start + a,
                        header.rows_start + b, None)
    counts = np.array(comm.allgather(len(lines)))
    first = int(counts[:rank].sum())  # this piece's first row, 0-based, in the snapshot
    line0 = header.first_line + first

    def parse():
        keep = max(0, min(len(lines), header.count - first))
        extra = [k for k in range(keep, len(lines)) if lines[k].strip()]
        if extra:
            raise InputError(None, f"expected 'ITEM: TIMESTEP', found '{lines[extra[0]].strip()[:60]}'",
                             source=source, line=line0 + extra[0])
        if rank == size - 1 and counts.sum() < header.count:
            raise InputError(None, f"unexpected end of file: {header.count} atom rows announced, {counts.sum()} "
                                   "found", source=source, line=header.first_line + int(counts.sum()))
        if keep == 0:
            return np.zeros(0, ROW_DTYPE), "id" in header.columns
        packing = piece_packing(header, lines[:keep], line0, density)
        ids = packing.ids if packing.ids is not None else np.arange(first + 1, first + keep + 1)
        return _rows(packing, ids), packing.ids is not None

    rows, has_ids = collective(parse)
    label = f"{os.path.basename(source)}, timestep {header.timestep}"
    return Piece(rows, header.count, header.box, label, has_ids)


def read_piece(source, *, density: float | None = None, snapshot: int = -1) -> Piece:
    """The calling rank's piece of a text dump or a ``dtcrit-spheres/1`` file (module docstring, step 1; collective).

    Parameters
    ----------
    source : str or os.PathLike
        The dump, or a ``.npz`` sphere file.
    density : float or None
        Particle density [kg/m^3] for a dump without a ``mass`` column.
    snapshot : int
        Snapshot index, Python style (default the last).

    Returns
    -------
    Piece
        This rank's spheres and the packing's size, box and label.
    """
    source = os.fspath(source)
    if not os.path.isfile(source):
        collective(_raise, InputError("file", f"cannot read {source}: no such file"))
    if is_sphere_file(source):
        return collective(_npz_piece, source, density, snapshot)
    return _text_piece(source, density, snapshot)


def _raise(error: Exception):
    raise error
