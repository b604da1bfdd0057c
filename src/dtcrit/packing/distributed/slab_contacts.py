"""The sphere contacts one rank of a distributed solve needs: those of its own slab of particles.

A rank owns the particles ``lo <= p < hi`` (PETSc's ownership split, ``split_rows``).  It runs the
serial search (``overlaps.find_sphere_contacts``: one ``cKDTree.query_pairs`` giving each pair once,
sorted by ``(i, j)``, toroidal along periodic axes; every image in range when a periodic box is
narrower than twice the reach) over its *halo*, the particles within reach of its slab's bounding box
(all of them when the particle order has no spatial locality, or on one rank).  A contact belongs to
the rank owning its lower index (``i < j``, or ``i == j`` with a positive image shift: a particle
touching its own periodic image), so each pair is found once across ranks, and its fields come from
the serial chunked fill (``sphere_fields``: arms as lengths, int8 image shifts, int32 indices, one
``R*`` for equal spheres).  Every candidate pair within ``1 + SEARCH_MARGIN`` of touching with an end
among the rank's particles gives the sparsity pattern, in both directions, so that a rank knows every
block of its own rows, whoever adds it.  ``order`` renumbers the particles first (``morton_order``:
then a rank's slab is a compact piece of space, its halo thin, and the matrix's off-rank coupling
small; the eigenvalues do not depend on the numbering).  In the packing's numbering the slabs' lists,
concatenated in rank order, are the serial list (``tests/packing/distributed/test_packing_slepc.py``).
Memory: the serial search's over the halo, plus the pattern (two int32 a block, both directions).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError

from dtcrit.packing.contact_set import index_dtype
from dtcrit.packing.detection.overlaps import (DETECT_CHUNK, _narrow_box_pairs, _search_frame, _sorted_pairs,
                                               wrap_positions)
from dtcrit.packing.detection.sphere_fields import _filled, _image_of, _joined, _touching
from dtcrit.packing.model import Box, Contacts, Packing
from dtcrit.packing.periodic_cell import own_images

SEARCH_MARGIN = 1e-9
"""The neighbour search and the sparsity pattern reach ``(1 + SEARCH_MARGIN)`` times the contact
range, so that a pair touching by the serial test lies in the pattern of both of its ranks whatever
the rounding of the distance (computed from either end)."""


def split_rows(n: int, size: int, rank: int) -> tuple[int, int]:
    """``(lo, hi)``: the particles rank ``rank`` of ``size`` owns, as PETSc splits ``n`` blocks
    (``PetscSplitOwnership``: ``n // size`` each, one more on the first ``n % size`` ranks).

    Parameters
    ----------
    n : int
        Number of particles (matrix block rows).
    size : int
        Number of ranks.
    rank : int
        This rank.

    Returns
    -------
    tuple of int
        ``(lo, hi)``: rank ``rank`` owns particles ``lo <= p < hi``.
    """
    base, extra = divmod(int(n), int(size))
    lo = rank * base + min(rank, extra)
    return lo, lo + base + (1 if rank < extra else 0)


@dataclass(frozen=True)
class SlabContacts:
    """A rank's share: ``contacts`` (global particle indices, each pair on one rank only, in the
    serial order) and the block sparsity of its own rows: ``pattern_rows`` (own particle) and
    ``pattern_cols`` (any particle), one entry per distinct off-diagonal block.

    Parameters
    ----------
    lo, hi : int
        The rank's particles ``lo <= p < hi``.
    contacts : Contacts
        Its contacts, global particle indices.
    pattern_rows, pattern_cols : numpy.ndarray
        Block row (own particle) and block column of each distinct off-diagonal block of its rows.
    """

    lo: int
    hi: int
    contacts: Contacts
    pattern_rows: np.ndarray
    pattern_cols: np.ndarray


MORTON_BITS = 21  # cells per axis 2^21: three axes interleaved in one 64-bit key


def _spread_bits(q: np.ndarray) -> np.ndarray:
    """The 21 low bits of ``q`` moved to every third bit (bit ``b`` to bit ``3 b``)."""
    q = q & np.uint64(0x1FFFFF)
    for shift, mask in ((32, 0x1F00000000FFFF), (16, 0x1F0000FF0000FF), (8, 0x100F00F00F00F00F),
                        (4, 0x10C30C30C30C30C3), (2, 0x1249249249249249)):
        q = (q | (q << np.uint64(shift))) & np.uint64(mask)
    return q


def morton_order(x: np.ndarray) -> np.ndarray:
    """Indices that sort the points ``x`` along a Morton (Z-order) curve over their bounding box, cells
    of ``1/2^21`` of its longest side: consecutive indices are near in space.

    Parameters
    ----------
    x : numpy.ndarray
        Points, shape (N, 3) [m].

    Returns
    -------
    numpy.ndarray
        The permutation, length N.
    """
    lo = x.min(axis=0)
    span = float((x.max(axis=0) - lo).max()) or 1.0
    key = np.zeros(len(x), dtype=np.uint64)
    for a in range(3):
        cell = np.minimum((x[:, a] - lo[a]) * ((1 << MORTON_BITS) / span), (1 << MORTON_BITS) - 1)
        key |= _spread_bits(cell.astype(np.uint64)) << np.uint64(a)
    return np.argsort(key, kind="stable")


def halo(x: np.ndarray, lo: int, hi: int, reach: float, box: Box | None) -> np.ndarray:
    """Indices of the particles within ``reach`` (per axis, minimum image on periodic axes) of the
    bounding box of particles ``lo..hi-1``: every possible neighbour of the slab.

    Parameters
    ----------
    x : numpy.ndarray
        Centres of all particles, shape (N, 3) [m].
    lo, hi : int
        The slab's particles ``lo <= p < hi``.
    reach : float
        Largest centre distance of a contact [m].
    box : Box or None
        The periodic box, if any.

    Returns
    -------
    numpy.ndarray
        Indices of the candidate neighbours.
    """
    own = x[lo:hi]
    keep = np.ones(len(x), bool)
    slack = reach * (1.0 + 1e-6)
    for a in range(3):
        c = 0.5 * (own[:, a].min() + own[:, a].max())
        h = 0.5 * (own[:, a].max() - own[:, a].min())
        dx = x[:, a] - c
        if box is not None and box.periodic[a]:
            length = box.lengths[a]
            if 2.0 * (h + slack) >= length:
                continue
            dx = dx - length * np.rint(dx / length)
        keep &= np.abs(dx) <= h + slack
    return np.flatnonzero(keep)


def _renumbered(packing: Packing, order: np.ndarray | None) -> Packing:
    """``packing`` in the numbering ``order`` (particle ``k`` is ``packing``'s ``order[k]``), its ids kept
    so that messages name the particles as the user knows them.
    """
    if order is None:
        return packing
    ids = order + 1 if packing.ids is None else packing.ids[order]
    return Packing(packing.positions[order], packing.masses[order], packing.inertia[order], packing.radii[order],
                   box=packing.box, label=packing.label, ids=ids)


def _near_pattern(view: Packing, x, i, j, image_of, lo: int, hi: int, reach: float, chunk: int):
    """``(rows, cols)``: the blocks ``(p own, q)`` of the candidate pairs ``(i, j)`` within ``reach``
    times the summed radii, both directions, ``chunk`` pairs at a time (temporaries O(chunk)).
    ``image_of(start, i, j)`` gives the image shifts of the chunk from pair ``start`` on.
    """
    rows, cols = [], []
    r, box = view.radii, view.box
    for start in range(0, len(i), chunk):
        a, b = i[start:start + chunk], j[start:start + chunk]
        sep = x[b] + (0.0 if box is None else box.shift(image_of(start, a, b))) - x[a]
        near = (a != b) & (np.sqrt(np.einsum("ij,ij->i", sep, sep)) <= (r[a] + r[b]) * reach)
        for p, q in ((a, b), (b, a)):
            mine = near & (p >= lo) & (p < hi)
            rows.append(p[mine])
            cols.append(q[mine])
    dtype = index_dtype(view.n)
    return (np.concatenate(rows).astype(dtype, copy=False) if rows else np.zeros(0, dtype),
            np.concatenate(cols).astype(dtype, copy=False) if cols else np.zeros(0, dtype))


def _global(sub: np.ndarray, n: int, *local: np.ndarray) -> list[np.ndarray]:
    """Halo-local indices as particle indices (``sub`` is sorted: the order of pairs is kept)."""
    if len(sub) == n:  # the halo is every particle: its numbering is the packing's
        return list(local)
    return [sub[k].astype(index_dtype(n)) for k in local]


def _slab_search(view: Packing, x: np.ndarray, lo: int, hi: int, tolerance: float, chunk: int):
    """``(contacts, rows, cols)`` of the slab (``slab_sphere_contacts``), found by the serial search
    (``overlaps._sorted_pairs``, or every image in range in a narrow box) over the slab's halo.
    """
    box, r = view.box, view.radii
    cutoff = 2.0 * r.max() * (1.0 + tolerance)
    reach = cutoff * (1.0 + SEARCH_MARGIN)
    sub = halo(x, lo, hi, reach, box)
    y, size = _search_frame(x[sub] if len(sub) < len(x) else x, reach, box)
    pattern_reach = (1.0 + tolerance) * (1.0 + SEARCH_MARGIN)
    if y is not None:  # one candidate per pair, sorted by (i, j): the contacts are those with i own
        i, j = _global(sub, view.n, *_sorted_pairs(y, size, reach))
        del y
        frame = box if size is not None else None
        rows, cols = _near_pattern(view, x, i, j, lambda _s, a, b: _image_of(x[b] - x[a], frame), lo, hi,
                                   pattern_reach, chunk)
        mine = slice(int(np.searchsorted(i, lo)), int(np.searchsorted(i, hi)))
        return _filled(view, x, i[mine], j[mine], frame, tolerance, chunk), rows, cols
    assert box is not None  # no search frame only for a periodic box
    i, j, image = _narrow_box_pairs(x[sub], reach, box)
    i, j = _global(sub, view.n, i, j)
    order = np.lexsort((image[:, 2], image[:, 1], image[:, 0], j, i))
    i, j, image = i[order], j[order], image[order]
    rows, cols = _near_pattern(view, x, i, j, lambda s, _a, _b: image[s:s + chunk], lo, hi, pattern_reach, chunk)
    blocks = np.unique(rows.astype(np.int64) * view.n + cols)  # a neighbour may be near through several images
    rows, cols = (blocks // view.n).astype(rows.dtype), (blocks % view.n).astype(cols.dtype)
    own = (i >= lo) & (i < hi)
    found = _touching(view, x, i[own], j[own], image[own], tolerance, own_images(view, x))
    return _joined([found], r), rows, cols


def slab_sphere_contacts(packing: Packing, lo: int, hi: int, tolerance: float = 1e-9,
                         order: np.ndarray | None = None, chunk: int = DETECT_CHUNK) -> SlabContacts:
    """The contacts of particles ``lo..hi-1`` and their rows' block pattern (module docstring), in the
    numbering ``order`` (particle ``k`` is ``packing``'s ``order[k]``; default: ``packing``'s own).

    Touching test, normals, arms and fields as ``contacts.find_sphere_contacts`` (its candidate
    search over the slab's halo, its chunked fill); raises its ``InputError`` for coincident centres
    found in this slab.

    Parameters
    ----------
    packing : Packing
        The sphere packing (every rank holds all of it).
    lo, hi : int
        This rank's particles ``lo <= p < hi`` (in the numbering ``order``).
    tolerance : float
        Relative overlap tolerance of the touching test (``find_sphere_contacts``).
    order : numpy.ndarray or None
        The numbering: particle ``k`` is ``packing``'s ``order[k]``.
    chunk : int
        Candidate pairs tested per batch (``find_sphere_contacts``).

    Returns
    -------
    SlabContacts
        The slab's contacts (in that numbering) and block pattern.
    """
    if not packing.is_spheres:
        raise InputError("packing", "slab_sphere_contacts needs a sphere packing")
    if not np.isfinite(tolerance) or tolerance < 0:
        raise InputError("tolerance", f"must be a finite number >= 0, got {tolerance}")
    empty = np.zeros(0, dtype=index_dtype(packing.n))
    if hi <= lo:
        return SlabContacts(lo, hi, Contacts.empty(), empty, empty.copy())
    box = packing.box
    if box is not None and box.cell is not None:
        raise InputError("box", "the distributed (MPI) contact search takes axis-aligned boxes only: run a sheared "
                                "(triclinic) cell without the MPI launcher")
    view = _renumbered(packing, order)
    x = wrap_positions(view.positions, box)
    contacts, rows, cols = _slab_search(view, x, lo, hi, tolerance, max(1, int(chunk)))
    return SlabContacts(lo, hi, contacts, rows, cols)


def slab_of_list(contacts: Contacts, n: int, lo: int, hi: int, rank: int, size: int) -> SlabContacts:
    """A rank's share of a contact list every rank holds (non-spherical bodies, given contacts): the
    ``rank``-th of ``size`` contiguous parts of the list, and the block pattern of rows ``lo..hi-1``
    from the whole list.

    Parameters
    ----------
    contacts : Contacts
        The whole contact list.
    n : int
        Number of particles.
    lo, hi : int
        This rank's particles ``lo <= p < hi``.
    rank, size : int
        This rank and the number of ranks.

    Returns
    -------
    SlabContacts
        This rank's part of the list and the block pattern of its rows.
    """
    c_lo, c_hi = split_rows(contacts.count, size, rank)
    pick = np.zeros(contacts.count, bool)
    pick[c_lo:c_hi] = True
    ci, cj = contacts.i.astype(np.int64), contacts.j.astype(np.int64)  # the keys rows * n + cols need int64
    rows = np.concatenate([ci, cj])
    cols = np.concatenate([cj, ci])
    mine = (rows >= lo) & (rows < hi) & (rows != cols)
    pattern = np.unique(rows[mine] * n + cols[mine])
    return SlabContacts(lo, hi, contacts.subset(pick), pattern // n, pattern % n)
