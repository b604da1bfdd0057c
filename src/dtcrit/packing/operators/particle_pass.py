"""The bounds' pass of the matrix-free operator gathered by particle: each body's 6 x 6 diagonal block, its
top eigenvalue and its weighted absolute row sums, on Numba's threads without races.

For the scaled operator ``A = M^(-1/2) K M^(-1/2)`` (``matrix_free.ContactOperator``) the rigorous
bounds need per particle ``p`` (``dtcrit.packing.bounds.estimates``):

    A_pp = s_p (sum over the contacts c of p of K_c,pp) s_p            (s = M^(-1/2), 6 x 6)
    lambda_max(A_pp),   diag(A_pp),
    r_p(w) = sum_(c, q) |s_p K_c,pq s_q| w_q  +  |A_pp| w_p             (w = 1 and w = sqrt(m))

with ``K_c,pp`` the element block of ``p``'s own side (``ii`` when ``p = i``, ``jj`` when ``p = j``)
and ``K_c,pq`` its coupling block, each contact's coupling counted on its own (a pair touching
through two periodic images gets a row sum above the assembled one, still a bound).  A contact with
its own periodic image (``i == j``) is one incidence of ``p`` adding ``ii + jj + ij + ij^T`` to
``A_pp`` and nothing to the coupling, as assembled.

``incidence`` lists the contacts of each particle (CSR, a counting sort in contact order);
``summary`` then runs one compiled loop over the particles (``numba.prange``), each particle summing
its contacts in that fixed order into locals, every contact's blocks computed from the side of the
particle summed (``element_matrices.element_side_into``; a contact is computed twice, once from each
of its bodies, instead of being scattered to both): no two threads write one particle, and the bits
do not depend on the thread count.  Memory: the incidence (two contact indices per contact, int32
below 2^31 contacts) and the O(N) results; no (N, 6, 6) array.  ``blocks`` gives the scaled diagonal
blocks of some particles (or all) from the same loop.  Without Numba, ``scattered_pass`` scatters the
blocks contact by contact instead.

Numba caches these loops keyed on this file only: after an edit of ``contact_element`` or
``element_matrices``, touch this file (or clear ``__pycache__``) so that the machine code is rebuilt.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from dtcrit.packing.operators.contact_element import coefficient_at, contact_frame
from dtcrit.packing.operators.element_matrices import element_blocks_into, element_side_into
from dtcrit.packing.operators.matrix_free_kernels import _jit, prange

PARTICLE_BLOCK = 512
"""Particles per task of the compiled loops (each task allocates its small work arrays once)."""


class BlockSummary(NamedTuple):
    """What the serial bounds read of the diagonal blocks ``A_pp`` and the rows of ``A`` (module docstring).

    Parameters
    ----------
    top : numpy.ndarray
        ``lambda_max(A_pp)`` of the symmetrised block, per particle (N,).
    diagonal : numpy.ndarray
        The diagonal of ``A`` (6N,).
    rows_ones, rows_root : numpy.ndarray
        ``sum_q |A_pq| w_q`` per row for ``w = 1`` and for the second weight (``sqrt(m)``), (6N,) each.
    """

    top: np.ndarray
    diagonal: np.ndarray
    rows_ones: np.ndarray
    rows_root: np.ndarray


def _count_incidence(ci, cj, rowmap, counts):
    """``counts[r + 1]`` = contacts of the particle of row ``r`` (``rowmap[p]``; empty: ``r = p``;
    ``-1``: not wanted), a self-image contact once.
    """
    full = rowmap.shape[0] == 0
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        ri = i if full else rowmap[i]
        if ri >= 0:
            counts[ri + 1] += 1
        if j != i:
            rj = j if full else rowmap[j]
            if rj >= 0:
                counts[rj + 1] += 1


def _fill_incidence(ci, cj, rowmap, indptr, fill, out):
    """``out[indptr[r]:indptr[r + 1]]`` = the contacts of row ``r`` in increasing order (``fill``:
    a zeroed cursor per row).
    """
    full = rowmap.shape[0] == 0
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        ri = i if full else rowmap[i]
        if ri >= 0:
            out[indptr[ri] + fill[ri]] = c
            fill[ri] += 1
        if j != i:
            rj = j if full else rowmap[j]
            if rj >= 0:
                out[indptr[rj] + fill[rj]] = c
                fill[rj] += 1


def _gather(p, lo, hi, inc, ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags, scale, weight, take_root,
            want_rows, acc, own, other, ij, r1, r2, wq):
    """Particle ``p``'s unscaled diagonal block into ``acc`` and, when ``want_rows``, its scaled
    coupling row sums for the ones (``r1``) and the weight (``r2``: ``sqrt(weight)`` when
    ``take_root``) over its contacts ``inc[lo:hi]``, summed in that order (module docstring).
    """
    trans, rotl, pre, orient = flags[0] != 0, flags[1] != 0, flags[2] != 0, flags[3] != 0
    acc[:, :] = 0.0
    r1[:] = 0.0
    r2[:] = 0.0
    for e in range(lo, hi):
        c = inc[e]
        i, j, ri, rj, n, ai, aj = contact_frame(c, ci, cj, nrm, arm_i, arm_j, rot, trans, orient)
        k_n, k_s = (coefficient_at(kn, c), coefficient_at(ks, c)) if trans else (0.0, 0.0)
        k_tw, k_r = (coefficient_at(ktw, c), coefficient_at(kr, c)) if rotl else (0.0, 0.0)
        gc = coefficient_at(g, c) if pre else 0.0
        if i == j:  # the contact with its own image: (B_i + B_j)^T K_c (B_i + B_j)
            element_blocks_into(n, ai, aj, ri, rj, orient, k_n, k_s, k_tw, k_r, gc, trans, rotl, pre, own, other, ij)
            for a in range(6):
                for b in range(6):
                    acc[a, b] += own[a, b] + other[a, b] + ij[a, b] + ij[b, a]
            continue
        mine = 0 if p == i else 1
        element_side_into(n, ai, aj, ri, rj, orient, k_n, k_s, k_tw, k_r, gc, trans, rotl, pre, mine, own, ij)
        for a in range(6):
            for b in range(6):
                acc[a, b] += own[a, b]
        if not want_rows:
            continue
        q = j if mine == 0 else i
        for b in range(6):
            wq[b] = np.sqrt(weight[q, b]) if take_root else weight[q, b]
        if mine == 0:
            for a in range(6):
                for b in range(6):
                    v = abs(ij[a, b] * scale[i, a] * scale[j, b])
                    r1[a] += v
                    r2[a] += v * wq[b]
        else:
            for a in range(6):
                for b in range(6):
                    v = abs(ij[b, a] * scale[i, b] * scale[j, a])
                    r1[a] += v
                    r2[a] += v * wq[b]


def _scaled(p, acc, scale):
    """``acc`` scaled in place to ``s_p acc s_p`` (rows then columns, as the NumPy path)."""
    for a in range(6):
        for b in range(6):
            acc[a, b] = acc[a, b] * scale[p, a] * scale[p, b]


def _summary_loop(indptr, inc, ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags, scale, weight, take_root,
                  extra_at, extra_blocks, extra_r1, extra_r2, top, diag, ones, second):
    """``BlockSummary`` of the particles of the incidence rows (``top`` (N,), ``diag``, ``ones``, ``second``
    (N, 6)), particles in tasks of ``PARTICLE_BLOCK`` on Numba's threads; particle ``p`` with
    ``extra_at[p] = k >= 0`` adds ``extra_blocks[k]`` to its scaled block and ``extra_r1[k]``,
    ``extra_r2[k]`` to its coupling sums (``summary``'s ``extras``).
    """
    n = indptr.shape[0] - 1
    tasks = (n + PARTICLE_BLOCK - 1) // PARTICLE_BLOCK
    for t in prange(tasks):
        acc, own, other, ij, sym = np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 6))
        r1, r2, wq = np.empty(6), np.empty(6), np.empty(6)
        for p in range(t * PARTICLE_BLOCK, min(n, (t + 1) * PARTICLE_BLOCK)):
            _gather_c(p, indptr[p], indptr[p + 1], inc, ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags,
                      scale, weight, take_root, True, acc, own, other, ij, r1, r2, wq)
            _scaled_c(p, acc, scale)
            k = extra_at[p] if extra_at.shape[0] > 0 else -1
            if k >= 0:
                for a in range(6):
                    r1[a] += extra_r1[k, a]
                    r2[a] += extra_r2[k, a]
                    for b in range(6):
                        acc[a, b] += extra_blocks[k, a, b]
            for b in range(6):
                wq[b] = np.sqrt(weight[p, b]) if take_root else weight[p, b]
            for a in range(6):
                diag[p, a] = acc[a, a]
                d1 = 0.0
                d2 = 0.0
                for b in range(6):
                    sym[a, b] = 0.5 * (acc[a, b] + acc[b, a])
                    d1 += abs(acc[a, b])
                    d2 += abs(acc[a, b]) * wq[b]
                ones[p, a] = r1[a] + d1
                second[p, a] = r2[a] + d2
            top[p] = np.linalg.eigvalsh(sym)[5]


def _blocks_loop(indptr, inc, particles, ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags, scale, weight,
                 out, out_r1, out_r2):
    """The scaled diagonal blocks ``out[r]`` (m, 6, 6) of the particles ``particles[r]`` and, when
    ``out_r1`` has rows, their coupling sums for the ones and ``sqrt(weight)`` (``out_r1``, ``out_r2``).
    """
    m = indptr.shape[0] - 1
    rows = out_r1.shape[0] > 0
    tasks = (m + PARTICLE_BLOCK - 1) // PARTICLE_BLOCK
    for t in prange(tasks):
        acc, own, other, ij = np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 6))
        r1, r2, wq = np.empty(6), np.empty(6), np.empty(6)
        for r in range(t * PARTICLE_BLOCK, min(m, (t + 1) * PARTICLE_BLOCK)):
            p = particles[r]
            _gather_c(p, indptr[r], indptr[r + 1], inc, ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags,
                      scale, weight, True, rows, acc, own, other, ij, r1, r2, wq)
            _scaled_c(p, acc, scale)
            out[r, :, :] = acc
            if rows:
                out_r1[r, :] = r1
                out_r2[r, :] = r2


_count_c = _jit(_count_incidence)
_fill_c = _jit(_fill_incidence)
_gather_c = _jit(_gather)
_scaled_c = _jit(_scaled)
_summary_c = _jit(_summary_loop, parallel=True)
_blocks_c = _jit(_blocks_loop, parallel=True)


def incidence(ci: np.ndarray, cj: np.ndarray, n: int,
              particles: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The contacts of each particle (or of each of ``particles``), CSR (module docstring).

    Parameters
    ----------
    ci, cj : numpy.ndarray
        The bodies of each contact (int32 or int64, ``matrix_free_kernels.kernel_indices``).
    n : int
        Particles.
    particles : numpy.ndarray or None
        Distinct particles whose rows are wanted, in this order; ``None``: all, row ``p`` = particle ``p``.

    Returns
    -------
    tuple of numpy.ndarray
        ``indptr`` (rows + 1, int64) and the contact indices (int32 below 2^31 contacts, else int64),
        each row's in increasing order, a self-image contact once.
    """
    rowmap = np.zeros(0, dtype=np.int64)
    rows = n
    if particles is not None:
        rowmap = np.full(n, -1, dtype=np.int64)
        rowmap[np.asarray(particles, dtype=np.int64)] = np.arange(len(particles))
        rows = len(particles)
    indptr = np.zeros(rows + 1, dtype=np.int64)
    _count_c(ci, cj, rowmap, indptr)
    np.cumsum(indptr, out=indptr)
    out = np.empty(int(indptr[-1]), dtype=np.int32 if ci.shape[0] < 2**31 else np.int64)
    _fill_c(ci, cj, rowmap, indptr, np.zeros(rows, dtype=np.int64), out)
    return indptr, out


def summary(args: tuple, scale: np.ndarray, weight: np.ndarray, root: bool = True, rows: int | None = None,
            extras: tuple | None = None) -> BlockSummary:
    """``BlockSummary`` by the compiled particle loop, for the weights ``1`` and ``sqrt(weight)``
    (``root``; the mass diagonal gives ``sqrt(m)``) or ``weight`` itself; of the first ``rows``
    particles only when given, with the parts of their blocks and coupling sums summed elsewhere
    (``extras``: the distributed route's other ranks, ``slepc_shell.shell_bounds``).

    Parameters
    ----------
    args : tuple
        ``matrix_free_kernels.loop_arguments``' tuple.
    scale : numpy.ndarray
        ``M^(-1/2)`` per DOF, (N, 6).
    weight : numpy.ndarray
        Per DOF, (N, 6): the mass diagonal, or any weights with ``root=False``.
    root : bool
        Whether the second weight is ``sqrt(weight)``.
    rows : int or None
        Summarise particles ``0 .. rows - 1`` (default: all).
    extras : tuple or None
        ``(at, blocks, r1, r2)``: particle ``p`` with ``at[p] = k >= 0`` adds the scaled block
        ``blocks[k]`` (6 x 6) and the coupling sums ``r1[k]``, ``r2[k]`` (6 each) to its own.

    Returns
    -------
    BlockSummary
        The tops, the diagonal and the two row sums.
    """
    n = scale.shape[0] if rows is None else int(rows)
    indptr, inc = incidence(args[0], args[1], scale.shape[0], None if rows is None else np.arange(n))
    at, blocks, r1, r2 = extras if extras is not None else (np.zeros(0, np.int64), np.zeros((0, 6, 6)),
                                                            np.zeros((0, 6)), np.zeros((0, 6)))
    top, diag, ones, second = np.empty(n), np.empty((n, 6)), np.empty((n, 6)), np.empty((n, 6))
    _summary_c(indptr, inc, *args, np.ascontiguousarray(scale), np.ascontiguousarray(weight, dtype=float), root,
               np.asarray(at, np.int64), np.ascontiguousarray(blocks, float), np.ascontiguousarray(r1, float),
               np.ascontiguousarray(r2, float), top, diag, ones, second)
    return BlockSummary(top, diag.reshape(-1), ones.reshape(-1), second.reshape(-1))


def blocks(args: tuple, scale: np.ndarray, particles: np.ndarray | None = None) -> np.ndarray:
    """The scaled diagonal blocks ``A_pp`` of ``particles`` (default all) by the compiled particle loop.

    Parameters
    ----------
    args : tuple
        ``matrix_free_kernels.loop_arguments``' tuple.
    scale : numpy.ndarray
        ``M^(-1/2)`` per DOF, (N, 6).
    particles : numpy.ndarray or None
        Particle indices (the rows follow their order; a repeated index repeats its block); ``None``:
        every particle.

    Returns
    -------
    numpy.ndarray
        (m, 6, 6).
    """
    if particles is None:
        return _blocks(args, scale, None)
    distinct, back = np.unique(np.asarray(particles, dtype=np.int64), return_inverse=True)  # incidence rows: once each
    return _blocks(args, scale, distinct)[back.reshape(-1)]


def _blocks(args: tuple, scale: np.ndarray, particles: np.ndarray | None, weight: np.ndarray | None = None):
    n = scale.shape[0]
    which = np.arange(n) if particles is None else particles
    indptr, inc = incidence(args[0], args[1], n, particles)
    out = np.empty((len(which), 6, 6))
    rows = 0 if weight is None else len(which)
    r1, r2 = np.empty((rows, 6)), np.empty((rows, 6))
    scale = np.ascontiguousarray(scale)
    _blocks_c(indptr, inc, which, *args, scale, scale if weight is None else np.ascontiguousarray(weight, dtype=float),
              out, r1, r2)
    return out if weight is None else (out, r1, r2)


def partial_rows(args: tuple, scale: np.ndarray, weight: np.ndarray,
                 particles: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The scaled diagonal blocks and coupling row sums (``w = 1`` and ``w = sqrt(weight)``) that these
    contacts give ``particles``: parts of theirs summed on another rank (``summary``'s ``extras``).

    Parameters
    ----------
    args, scale : tuple, numpy.ndarray
        As ``summary``: the loops' arguments and ``M^(-1/2)`` per DOF.
    weight : numpy.ndarray
        The mass diagonal per DOF, (N, 6).
    particles : numpy.ndarray
        Distinct particle indices.

    Returns
    -------
    tuple of numpy.ndarray
        ``(blocks, r1, r2)``: (m, 6, 6), (m, 6), (m, 6).
    """
    return _blocks(args, scale, np.asarray(particles, dtype=np.int64), weight)


def equals(w: np.ndarray, form, base: np.ndarray | None = None, chunk: int = 1 << 20) -> bool:
    """Whether ``w == form(base)`` (``base`` default ``w``) entry for entry, compared in chunks so that
    ``form(base)`` (e.g. ``sqrt(m)``, 480 MB at 1e7 particles) is never whole.

    Parameters
    ----------
    w : numpy.ndarray
        The weights (6N,).
    form : callable
        Elementwise function, e.g. ``numpy.sqrt`` or ``numpy.ones_like``.
    base : numpy.ndarray or None
        Its argument, as long as ``w``; ``None``: ``w``.
    chunk : int
        Entries per comparison.

    Returns
    -------
    bool
        ``True`` when every entry is equal.
    """
    base = w if base is None else base
    if base.shape != w.shape:
        return False
    return all(np.array_equal(w[lo:lo + chunk], form(base[lo:lo + chunk])) for lo in range(0, w.size, chunk))
