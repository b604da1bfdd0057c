"""The sphere contacts one rank of a distributed solve needs: those of its own slab of particles.

A rank owns the particles ``lo <= p < hi`` (PETSc's ownership split, ``split_rows``).  It searches the
neighbours of its own particles only: a ``scipy.spatial.cKDTree`` over its own centres is matched
(``sparse_distance_matrix``) against a tree over the particles within reach of its slab's bounding
box (the halo: all of them when the particle order has no spatial locality).  Every candidate
``(p own, q any)`` is kept for the sparsity pattern (both directions, so a rank knows every block of
its own rows, whoever adds it); a contact itself belongs to the rank owning its lower index
(``p < q``, or ``p == q`` with a positive image shift: a particle touching its own periodic image),
so each pair is found once across ranks.  ``order`` renumbers the particles first (``morton_order``:
then a rank's slab is a compact piece of space, its halo thin, and the matrix's off-rank coupling
small; the eigenvalues do not depend on the numbering).  Periodic boxes are searched as
``contacts.find_sphere_contacts`` does (minimum image in a toroidal tree when the box is wider than
twice the reach, every image in range otherwise), and the touching test, normals, arms and order
are its own: in the packing's numbering the slabs' lists, concatenated in rank order, are the
serial list (``tests/packing/distributed/test_packing_slepc.py``).
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from dtcrit.errors import InputError

from dtcrit.packing.detection.overlaps import wrap_positions
from dtcrit.packing.detection.sphere_fields import equal_radius_eff, narrowest_image
from dtcrit.packing.model import Box, Contacts, Packing
from dtcrit.packing.normal_arms import NormalArms

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


def _slab_pairs(x: np.ndarray, lo: int, hi: int, reach: float, box: Box | None):
    """``(p, q, image)``: every pair with ``lo <= p < hi`` and centre distance <= ``reach``, both
    orders of a pair of own particles, ``p == q`` only through a non-zero image.
    """
    periodic = np.zeros(3, bool) if box is None else np.array(box.periodic)
    lengths = np.ones(3) if box is None else box.lengths
    sub = halo(x, lo, hi, reach, box)
    if not periodic.any() or np.all(lengths[periodic] > 2.0 * reach):
        if box is not None and periodic.any():  # unique minimum image: a toroidal tree, as contacts._candidate_pairs
            shift = x.min(axis=0)
            size = np.where(periodic, lengths, (x.max(axis=0) - shift) + 4.0 * reach + 1.0)
            origin = np.where(periodic, box.lo, shift)
            y_own = np.minimum(x[lo:hi] - origin, np.nextafter(size, 0))
            y_sub = np.minimum(x[sub] - origin, np.nextafter(size, 0))
            trees = cKDTree(y_own, boxsize=size), cKDTree(y_sub, boxsize=size)
        else:
            trees = cKDTree(x[lo:hi]), cKDTree(x[sub])
        sdm = trees[0].sparse_distance_matrix(trees[1], reach, output_type="ndarray")
        p, q = sdm["i"].astype(np.int64) + lo, sub[sdm["j"]].astype(np.int64)
        other = p != q
        p, q = p[other], q[other]
        image = np.zeros((len(p), 3), dtype=np.int64)
        sep = x[q] - x[p]
        image[:, periodic] = -np.rint(sep[:, periodic] / lengths[periodic]).astype(np.int64)
        return p, q, image
    reach_images = [int(np.ceil(reach / lengths[a])) if periodic[a] else 0 for a in range(3)]
    own = cKDTree(x[lo:hi])
    out_p, out_q, out_s = [], [], []
    for s in itertools.product(*(range(-r, r + 1) for r in reach_images)):
        shift = np.array(s, dtype=np.int64)
        sdm = own.sparse_distance_matrix(cKDTree(x[sub] + shift * lengths), reach, output_type="ndarray")
        p, q = sdm["i"].astype(np.int64) + lo, sub[sdm["j"]].astype(np.int64)
        keep = (p != q) | shift.any()
        out_p.append(p[keep])
        out_q.append(q[keep])
        out_s.append(np.repeat(shift[None, :], keep.sum(), axis=0))
    return np.concatenate(out_p), np.concatenate(out_q), np.concatenate(out_s)


def slab_sphere_contacts(packing: Packing, lo: int, hi: int, tolerance: float = 1e-9,
                         order: np.ndarray | None = None) -> SlabContacts:
    """The contacts of particles ``lo..hi-1`` and their rows' block pattern (module docstring), in the
    numbering ``order`` (particle ``k`` is ``packing``'s ``order[k]``; default: ``packing``'s own).

    Touching test, normals and arms as ``contacts.find_sphere_contacts``; raises its ``InputError``
    for coincident centres found in this slab.

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

    Returns
    -------
    SlabContacts
        The slab's contacts (in that numbering) and block pattern.
    """
    if not packing.is_spheres:
        raise InputError("packing", "slab_sphere_contacts needs a sphere packing")
    if not np.isfinite(tolerance) or tolerance < 0:
        raise InputError("tolerance", f"must be a finite number >= 0, got {tolerance}")
    empty = np.zeros(0, dtype=np.int64)
    if hi <= lo:
        return SlabContacts(lo, hi, Contacts.empty(), empty, empty.copy())
    box = packing.box
    if box is not None and box.cell is not None:
        raise InputError("box", "the distributed (MPI) contact search takes axis-aligned boxes only: run a sheared "
                                "(triclinic) cell without the MPI launcher")
    x = wrap_positions(packing.positions, box)
    r = packing.radii
    if order is not None:
        x, r = x[order], r[order]
    cutoff = 2.0 * r.max() * (1.0 + tolerance)
    p, q, image = _slab_pairs(x, lo, hi, cutoff * (1.0 + SEARCH_MARGIN), box)
    lengths = np.zeros(3) if box is None else box.lengths
    sep = x[q] + image * lengths - x[p]
    d = np.sqrt(np.einsum("ij,ij->i", sep, sep))
    near = (p != q) & (d <= (r[p] + r[q]) * (1.0 + tolerance) * (1.0 + SEARCH_MARGIN))
    pattern = np.unique(p[near] * packing.n + q[near])
    positive = (image[:, 0] > 0) | ((image[:, 0] == 0) & ((image[:, 1] > 0) | ((image[:, 1] == 0) & (image[:, 2] > 0))))
    once = (p < q) | ((p == q) & positive)
    i, j, image, sep, d = p[once], q[once], image[once], sep[once], d[once]
    touch = d <= (r[i] + r[j]) * (1.0 + tolerance)
    i, j, image, sep, d = i[touch], j[touch], image[touch], sep[touch], d[touch]
    if np.any(d <= 0):
        k = int(np.argmax(d <= 0))
        a, b = (i[k], j[k]) if order is None else (order[i[k]], order[j[k]])
        raise InputError("positions", f"particles {packing.particle_id(min(a, b))} and {packing.particle_id(max(a, b))} "
                                      "have coincident centres")
    order = np.lexsort((image[:, 2], image[:, 1], image[:, 0], j, i))
    i, j, image, sep, d = i[order], j[order], image[order], sep[order], d[order]
    n = sep / d[:, None]
    overlap = np.maximum(r[i] + r[j] - d, 0.0)
    same = equal_radius_eff(r, len(i))
    contacts = Contacts(  # the arms as their lengths and the shifts as int8, as the serial search holds them
        i=i, j=j, normal=n, arm_i=NormalArms(r[i] - 0.5 * overlap, n, 1.0), arm_j=NormalArms(r[j] - 0.5 * overlap, n, -1.0),
        overlap=overlap, image=narrowest_image(image), radius_eff=r[i] * r[j] / (r[i] + r[j]) if same is None else same,
    )
    return SlabContacts(lo, hi, contacts, pattern // packing.n, pattern % packing.n)


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
