"""Partitioned input of the distributed route: each rank reads a piece of the file, then keeps its
Morton slab of spheres and the halo around it; no rank ever holds the whole packing.

1. Read (``read_piece``): a text dump is split into ``P`` byte ranges: each rank scans its range
   for snapshots (``dump_ranges.scan_markers``), every rank parses the chosen snapshot's header, and
   rank ``r`` parses the atom rows whose first byte lies in its ``r``-th share of the snapshot's rows
   (``dump_ranges.rows_in_range``, ``piece_packing``: the serial reader's columns and checks, errors
   at ``FILE:LINE``).  A ``dtcrit-spheres/1`` file (``sphere_npz``) is sliced by rows instead.
2. Morton order (``to_slabs``): the keys of ``slab_contacts.morton_order`` over the global bounding
   box of the wrapped centres (an all-reduce), ties broken by atom id, which is the serial reader's
   order (it sorts by id); a sample sort (``SAMPLES`` keys per rank, one all-to-all) and an exact
   rebalance (a second all-to-all) leave rank ``r`` the particles ``lo <= p < hi`` of
   ``slab_contacts.split_rows``, the rows the serial ``slepc_backend.distribute`` gives it.
3. Halo (``_halo``): each rank sends every other rank its particles within the contact reach of
   that rank's bounding box (minimum image on periodic axes), as ``slab_contacts.halo`` selects.
4. Contacts (``partitioned_slab``): ``slab_contacts.slab_sphere_contacts`` on the rank's own
   particles and halo in global order, mapped back to the global numbering: the same list as the
   serial back-end's.  Atom ids are checked distinct by one more all-to-all (ids hashed to ranks).

MPI through ``mpi4py`` (``PETSc.COMM_WORLD.tompi4py()``), imported inside the functions.  PETSc's
indices here are 32-bit: a packing with ``6 N > 2^31 - 1`` DOFs is refused from the header, before
any row is read.
"""
from __future__ import annotations

import os
import time
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.detection.overlaps import wrap_positions
from dtcrit.packing.distributed.mpi_support import agree, world
from dtcrit.packing.distributed.slab_contacts import (MORTON_BITS, SEARCH_MARGIN, SlabContacts, _spread_bits,
                                                      slab_sphere_contacts, split_rows)
from dtcrit.packing.model import Box, Contacts, Packing
from dtcrit.packing.readers.sphere_npz import is_sphere_file

__all__ = ["INDEX_LIMIT", "ROW_DTYPE", "SAMPLES", "Piece", "PartitionedSlab", "partitioned_slab", "read_piece",
           "to_slabs"]

INDEX_LIMIT = 2**31 - 1
"""Largest index of this PETSc build (``PetscInt`` is 32-bit): ``6 N`` must not exceed it."""
SAMPLES = 64
"""Keys each rank contributes to choose the sample sort's splitters."""
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


def _mpi():
    """The mpi4py communicator of ``PETSc.COMM_WORLD`` and the ``MPI`` module."""
    from petsc4py import PETSc

    from mpi4py import MPI

    return PETSc.COMM_WORLD.tompi4py(), MPI


def _check_count(n: int, size: int) -> None:
    if 6 * n > INDEX_LIMIT:
        raise InputError("packing", f"{n} spheres need {6 * n} DOFs, beyond this PETSc's 32-bit index limit "
                                    f"2^31 - 1 = {INDEX_LIMIT} (at most {INDEX_LIMIT // 6} spheres)")
    if n < size:
        raise InputError("packing", f"{n} particles cannot be shared by {size} ranks (fewer ranks, please)")


def _rows(packing: Packing, ids) -> np.ndarray:
    out = np.zeros(packing.n, dtype=ROW_DTYPE)
    out["id"], out["x"], out["radius"], out["mass"] = ids, packing.positions, packing.radii, packing.masses
    return out


def _collective(step, *args):
    """``step(*args)`` on every rank; an ``InputError`` on any rank is raised everywhere (``agree``)."""
    result, error = None, None
    try:
        result = step(*args)
    except ValueError as exc:
        error = exc
    agree(error)
    return result


def _npz_piece(source, density, snapshot) -> Piece:
    from dtcrit.packing.readers.sphere_npz import open_spheres

    comm, _ = _mpi()
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
    found = _collective(scan_markers, source, a, b)
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

    comm, _ = _mpi()
    rank, size = comm.Get_rank(), comm.Get_size()
    markers, total = _markers(source, comm)
    header = _collective(_header, source, markers, snapshot, size)
    end = next((o for o in markers.offsets if o > header.rows_start), total)
    a, b = split_rows(end - header.rows_start, size, rank)
    lines = _collective(rows_in_range, source, header.rows_start, end, header.rows_start + a,
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

    rows, has_ids = _collective(parse)
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
        _collective(_raise, InputError("file", f"cannot read {source}: no such file"))
    if is_sphere_file(source):
        return _collective(_npz_piece, source, density, snapshot)
    return _text_piece(source, density, snapshot)


def _raise(error: Exception):
    raise error


def _exchange(rows: np.ndarray, dest: np.ndarray, comm, MPI) -> np.ndarray:
    """Send each row to rank ``dest`` (an all-to-all of counts, then of the rows); received in rank order."""
    size = comm.Get_size()
    order = np.argsort(dest, kind="stable")
    send = np.ascontiguousarray(rows[order])
    counts = np.bincount(dest, minlength=size).astype(np.int64)
    got = np.empty(size, dtype=np.int64)
    comm.Alltoall(counts, got)
    recv = np.empty(int(got.sum()), dtype=ROW_DTYPE)
    kind = MPI.BYTE.Create_contiguous(ROW_DTYPE.itemsize).Commit()
    displ = lambda c: np.concatenate([[0], np.cumsum(c)[:-1]]).astype(np.int64)  # noqa: E731
    comm.Alltoallv([send, (counts, displ(counts)), kind], [recv, (got, displ(got)), kind])
    kind.Free()
    return recv


def _sorted(rows: np.ndarray) -> np.ndarray:
    return rows[np.lexsort((rows["id"], rows["key"]))]


def to_slabs(piece: Piece) -> tuple[np.ndarray, int, int, int]:
    """Key the piece's spheres along the global Morton curve and move them to their ranks (module
    docstring, step 2; collective).

    Parameters
    ----------
    piece : Piece
        This rank's piece (``read_piece``).

    Returns
    -------
    tuple
        ``(own, lo, hi, held)``: this rank's spheres ``lo <= p < hi`` in Morton order (``glob`` set) and
        the most rows it held at once.
    """
    comm, MPI = _mpi()
    rank, size = comm.Get_rank(), comm.Get_size()
    rows = piece.rows
    x = wrap_positions(rows["x"], piece.box)
    low, high = np.full(3, np.inf), np.full(3, -np.inf)
    comm.Allreduce(x.min(axis=0) if len(x) else low.copy(), low, op=MPI.MIN)
    comm.Allreduce(x.max(axis=0) if len(x) else high.copy(), high, op=MPI.MAX)
    span = float((high - low).max()) or 1.0
    key = np.zeros(len(x), dtype=np.uint64)
    for a in range(3):  # as slab_contacts.morton_order
        cell = np.minimum((x[:, a] - low[a]) * ((1 << MORTON_BITS) / span), (1 << MORTON_BITS) - 1)
        key |= _spread_bits(cell.astype(np.uint64)) << np.uint64(a)
    rows["key"] = key
    rows = _sorted(rows)
    held = len(rows)
    sample = rows["key"][np.linspace(0, len(rows) - 1, min(SAMPLES, len(rows))).astype(int)] if len(rows) else []
    pool = np.sort(np.concatenate([np.asarray(s, dtype=np.uint64) for s in comm.allgather(sample)]))
    splitters = pool[(np.arange(1, size) * len(pool)) // size]
    rows = _sorted(_exchange(rows, np.searchsorted(splitters, rows["key"], side="right"), comm, MPI))
    held = max(held, len(rows))
    start = int(np.array(comm.allgather(len(rows)))[:rank].sum())
    bounds = np.array([split_rows(piece.n, size, r)[1] for r in range(size)])
    glob = start + np.arange(len(rows))
    rows["glob"] = glob
    own = _exchange(rows, np.searchsorted(bounds, glob, side="right"), comm, MPI)
    lo, hi = split_rows(piece.n, size, rank)
    if len(own) != hi - lo or (len(own) and (own["glob"][0] != lo or own["glob"][-1] != hi - 1)):
        raise RuntimeError(f"rank {rank}: the rebalance left rows {len(own)}, expected {lo}..{hi}")
    return own, lo, hi, max(held, len(own))


def _distinct_ids(own: np.ndarray, source: str) -> None:
    """Refuse an atom id given twice (ids hashed to ranks, one all-to-all)."""
    comm, MPI = _mpi()
    mine = _exchange(own, (own["id"] % comm.Get_size()).astype(np.int64), comm, MPI)
    ids = np.sort(mine["id"])
    dup = np.flatnonzero(ids[1:] == ids[:-1])
    error = InputError("file", f"{source}: atom id {ids[dup[0]]} appears twice") if dup.size else None
    agree(error)


def _halo(own: np.ndarray, box: Box, reach: float) -> np.ndarray:
    """The spheres of other ranks within ``reach`` of this rank's bounding box (module docstring, step 3)."""
    comm, MPI = _mpi()
    rank = comm.Get_rank()
    x = wrap_positions(own["x"], box)
    boxes = comm.allgather((x.min(axis=0), x.max(axis=0)))
    slack = reach * (1.0 + 1e-6)
    dest, pick = [], []
    for s, (lo, hi) in enumerate(boxes):
        if s == rank:
            continue
        near = np.ones(len(x), bool)
        for a in range(3):  # as slab_contacts.halo
            c, h = 0.5 * (lo[a] + hi[a]), 0.5 * (hi[a] - lo[a])
            dx = x[:, a] - c
            if box.periodic[a]:
                length = box.lengths[a]
                if 2.0 * (h + slack) >= length:
                    continue
                dx = dx - length * np.rint(dx / length)
            near &= np.abs(dx) <= h + slack
        k = np.flatnonzero(near)
        pick.append(k)
        dest.append(np.full(len(k), s, dtype=np.int64))
    if not pick:
        return np.zeros(0, ROW_DTYPE)
    return _exchange(own[np.concatenate(pick)], np.concatenate(dest), comm, MPI)


@dataclass
class PartitionedSlab:
    """One rank's share after the partitioned read: its own spheres and halo, and its contacts.

    Parameters
    ----------
    n : int
        Spheres in the packing.
    lo, hi : int
        This rank's spheres ``lo <= p < hi`` (global Morton numbering).
    packing : Packing
        Its own spheres and their halo, in global order (``ids``: the atom ids).
    glob : numpy.ndarray
        Global index of each sphere of ``packing``.
    slab : SlabContacts
        Its contacts and block pattern, global numbering (as ``slab_sphere_contacts`` on the whole packing).
    rows_held : int
        The most sphere rows this rank held at once (read, sorted, own plus halo).
    label : str
        The packing's label.
    seconds : dict
        Wall time of ``read``, ``exchange`` (Morton sort, id check, halo) and ``contacts`` [s].
    """

    n: int
    lo: int
    hi: int
    packing: Packing
    glob: np.ndarray
    slab: SlabContacts
    rows_held: int
    label: str
    seconds: dict


def _local_slab(own: np.ndarray, halo: np.ndarray, lo: int, hi: int, n: int, box: Box, label: str):
    rows = np.concatenate([own, halo])
    rows = rows[np.argsort(rows["glob"], kind="stable")]
    glob = rows["glob"]
    local = Packing.spheres(rows["x"], rows["radius"], masses=rows["mass"], box=box, label=label, ids=rows["id"])
    a, b = int(np.searchsorted(glob, lo)), int(np.searchsorted(glob, hi))
    found = slab_sphere_contacts(local, a, b)
    c = found.contacts
    contacts = Contacts(i=glob[c.i], j=glob[c.j], normal=c.normal, arm_i=c.arm_i, arm_j=c.arm_j, overlap=c.overlap,
                        image=c.image, radius_eff=c.radius_eff)
    slab = SlabContacts(lo, hi, contacts, glob[found.pattern_rows], glob[found.pattern_cols])
    return local, glob, slab


def partitioned_slab(source, *, density: float | None = None, snapshot: int = -1,
                     tolerance: float = 1e-9) -> PartitionedSlab:
    """Read a dump or sphere file in pieces and give this rank its Morton slab, halo and contacts
    (module docstring, steps 1-4; collective).

    Parameters
    ----------
    source : str or os.PathLike
        The text dump or ``.npz`` sphere file.
    density : float or None
        Particle density [kg/m^3] for a dump without a ``mass`` column.
    snapshot : int
        Snapshot index, Python style (default the last).
    tolerance : float
        Relative overlap tolerance of the touching test (``find_sphere_contacts``).

    Returns
    -------
    PartitionedSlab
        This rank's spheres and contacts.
    """
    world()  # PETSc initialised, or the one-line install message
    clock = [time.perf_counter()]

    def lap() -> float:
        clock.append(time.perf_counter())
        return clock[-1] - clock[-2]

    piece = read_piece(source, density=density, snapshot=snapshot)
    held = len(piece.rows)
    t_read = lap()
    own, lo, hi, moved = to_slabs(piece)
    del piece.rows
    _distinct_ids(own, os.fspath(source))
    comm, MPI = _mpi()
    r_max = np.zeros(1)
    comm.Allreduce(np.array([own["radius"].max()]), r_max, op=MPI.MAX)
    halo = _halo(own, piece.box, 2.0 * float(r_max[0]) * (1.0 + tolerance) * (1.0 + SEARCH_MARGIN))
    t_exchange = lap()
    local, glob, slab = _collective(_local_slab, own, halo, lo, hi, piece.n, piece.box, piece.label)
    seconds = {"read": t_read, "exchange": t_exchange, "contacts": lap()}
    return PartitionedSlab(piece.n, lo, hi, local, glob, slab, max(held, moved, len(own) + len(halo)), piece.label,
                           seconds)
