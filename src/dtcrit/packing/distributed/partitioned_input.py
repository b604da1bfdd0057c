"""Partitioned input of the distributed route: each rank reads a piece of the file, then keeps its
Morton slab of spheres and the halo around it; no rank ever holds the whole packing.

1. Read (``partitioned_read.read_piece``): a text dump is split into ``P`` byte ranges: each rank scans its range
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
   one of that rank's ``HALO_BOXES`` boxes (bounding boxes of consecutive runs of its spheres along
   the curve; minimum image on periodic axes, as ``slab_contacts.halo`` tests).
4. Contacts (``partitioned_slab``): ``slab_contacts.slab_sphere_contacts`` on the rank's own
   particles and halo in global order, mapped back to the global numbering: the same list as the
   serial back-end's.  Atom ids are checked distinct by one more all-to-all (ids hashed to ranks).

MPI through ``mpi4py`` (``PETSc.COMM_WORLD.tompi4py()``), imported inside the functions.  A packing
with more DOFs (``6 N``) than the loaded PETSc build numbers (``petsc_build.check_dofs``: ``2^31 - 1``
with 32-bit indices) is refused from the header, before any row is read.
"""
from __future__ import annotations

import os
import time
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.detection.overlaps import wrap_positions
from dtcrit.packing.distributed.mpi_support import agree, world
from dtcrit.packing.distributed.partitioned_read import ROW_DTYPE, Piece, collective, mpi, read_piece
from dtcrit.packing.distributed.slab_contacts import (MORTON_BITS, SEARCH_MARGIN, SlabContacts, _spread_bits,
                                                      slab_sphere_contacts, split_rows)
from dtcrit.packing.model import Box, Contacts, Packing

__all__ = ["HALO_BOXES", "SAMPLES", "PartitionedSlab", "partitioned_slab", "to_slabs"]

SAMPLES = 64
"""Keys each rank contributes to choose the sample sort's splitters."""
HALO_BOXES = 16
"""Boxes per rank that select its halo: bounding boxes of that many consecutive runs of its spheres."""


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
    comm, MPI = mpi()
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
    comm, MPI = mpi()
    mine = _exchange(own, (own["id"] % comm.Get_size()).astype(np.int64), comm, MPI)
    ids = np.sort(mine["id"])
    dup = np.flatnonzero(ids[1:] == ids[:-1])
    error = InputError("file", f"{source}: atom id {ids[dup[0]]} appears twice") if dup.size else None
    agree(error)


def _near_box(x: np.ndarray, lo: np.ndarray, hi: np.ndarray, slack: float, box: Box) -> np.ndarray:
    """Which of the wrapped centres ``x`` lie within ``slack`` of the box ``[lo, hi]`` per axis
    (minimum image on periodic axes), as ``slab_contacts.halo`` tests.
    """
    near = np.ones(len(x), bool)
    for a in range(3):
        c, h = 0.5 * (lo[a] + hi[a]), 0.5 * (hi[a] - lo[a])
        dx = x[:, a] - c
        if box.periodic[a]:
            length = box.lengths[a]
            if 2.0 * (h + slack) >= length:
                continue
            dx = dx - length * np.rint(dx / length)
        near &= np.abs(dx) <= h + slack
    return near


def _halo(own: np.ndarray, box: Box, reach: float) -> np.ndarray:
    """The spheres of other ranks within ``reach`` of one of this rank's ``HALO_BOXES`` boxes (module
    docstring, step 3): the bounding boxes of consecutive runs of its Morton-ordered spheres, compact
    even where the rank's slab straddles two octants of the curve.
    """
    comm, MPI = mpi()
    rank = comm.Get_rank()
    x = wrap_positions(own["x"], box)
    runs = [r for r in np.array_split(np.arange(len(x)), min(HALO_BOXES, len(x))) if len(r)]
    boxes = comm.allgather([(x[r].min(axis=0), x[r].max(axis=0)) for r in runs])
    slack = reach * (1.0 + 1e-6)
    dest, pick = [], []
    for s, theirs in enumerate(boxes):
        if s == rank:
            continue
        near = np.zeros(len(x), bool)
        for lo, hi in theirs:
            near |= _near_box(x, lo, hi, slack, box)
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
    comm, MPI = mpi()
    r_max = np.zeros(1)
    comm.Allreduce(np.array([own["radius"].max()]), r_max, op=MPI.MAX)
    halo = _halo(own, piece.box, 2.0 * float(r_max[0]) * (1.0 + tolerance) * (1.0 + SEARCH_MARGIN))
    t_exchange = lap()
    local, glob, slab = collective(_local_slab, own, halo, lo, hi, piece.n, piece.box, piece.label)
    seconds = {"read": t_read, "exchange": t_exchange, "contacts": lap()}
    return PartitionedSlab(piece.n, lo, hi, local, glob, slab, max(held, moved, len(own) + len(halo)), piece.label,
                           seconds)
