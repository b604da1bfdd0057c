"""The NumPy fallbacks (without Numba) of the matrix-free product's contact forces (``chunk_forces``,
the compiled loop is ``matrix_free_kernels``) and of the bounds' block pass (``particle_pass`` is the
compiled one): the scaled diagonal blocks ``A_pp`` and the weighted absolute row sums ``sum_q |A_pq| w_q`` (the
formulas in ``particle_pass``'s docstring), each contact's blocks (``assembly.contact_blocks``)
scattered to its two bodies chunk by chunk, and the blocks' top eigenvalues by batched LAPACK.
"""
from __future__ import annotations

import numpy as np

from dtcrit.packing.operators.assembly import contact_blocks
from dtcrit.packing.operators.contact_element import IDENTITY, ZERO3, body_forces, rotation_rows
from dtcrit.packing.operators.element_matrices import components

__all__ = ["chunk_forces", "row_entries", "scatter_rows", "scattered_blocks", "top_eigenvalues"]


def chunk_forces(op, q: np.ndarray, sl: slice) -> tuple[np.ndarray, np.ndarray]:
    """``(B_i^T f, B_j^T f)`` per contact of a chunk: ``contact_element.body_forces`` on arrays over
    the chunk's contacts (the NumPy path of ``matrix_free.ContactOperator``'s product).

    Parameters
    ----------
    op : dtcrit.packing.operators.matrix_free.ContactOperator
        The operator (its contacts, coefficients and orientations).
    q : numpy.ndarray
        (N, 6) scaled displacements.
    sl : slice
        The chunk's contacts.

    Returns
    -------
    tuple of numpy.ndarray
        What the chunk's contacts add on ``i`` and on ``j``, each (m, 6).
    """
    c = op.contacts
    ci, cj = c.i[sl], c.j[sl]
    qi, qj = q[ci], q[cj]
    rot = op.orientations
    oriented = rot is not None
    rot_i = rotation_rows(rot, ci) if oriented else IDENTITY
    rot_j = rotation_rows(rot, cj) if oriented else IDENTITY
    arm_i, arm_j = (components(c.arm_i[sl]), components(c.arm_j[sl])) if op.translational else (ZERO3, ZERO3)

    def coefficient(values):
        return 0.0 if values is None else values[sl]

    f, m_i, m_j = body_forces(components(c.normal[sl]), arm_i, arm_j, rot_i, rot_j, oriented,
                              components(qi[:, :3]), components(qi[:, 3:]), components(qj[:, :3]),
                              components(qj[:, 3:]), coefficient(op.along), coefficient(op.across),
                              coefficient(op.twist), coefficient(op.roll), coefficient(op.preload),
                              op.translational, op.rotational, op.preload is not None)
    oi, oj = np.empty((qi.shape[0], 6)), np.empty((qi.shape[0], 6))
    for a in range(3):
        oi[:, a] = -f[a]
        oi[:, 3 + a] = m_i[a]
        oj[:, a] = f[a]
        oj[:, 3 + a] = m_j[a]
    return oi, oj


def top_eigenvalues(blocks: np.ndarray, chunk: int = 1 << 16) -> np.ndarray:
    """``lambda_max`` of each symmetrised 6 x 6 block, batched ``numpy.linalg.eigvalsh`` in chunks.

    Parameters
    ----------
    blocks : numpy.ndarray
        (N, 6, 6).
    chunk : int
        Blocks per batch.

    Returns
    -------
    numpy.ndarray
        (N,).
    """
    top = np.empty(blocks.shape[0])
    for lo in range(0, blocks.shape[0], chunk):
        part = blocks[lo:lo + chunk]
        top[lo:lo + chunk] = np.linalg.eigvalsh(0.5 * (part + np.swapaxes(part, 1, 2)))[:, -1]
    return top


def row_entries(idx: np.ndarray, w: int) -> np.ndarray:
    """The flat indices ``w idx[c] + k`` (``0 <= k < w``) of rows ``idx`` of an (N, w) array, in int64
    whatever the dtype of ``idx`` (``36 idx`` leaves int32 above 6e7 particles).

    Parameters
    ----------
    idx : numpy.ndarray
        (m,) row indices (int32 or int64).
    w : int
        Row width.

    Returns
    -------
    numpy.ndarray
        (m, w) int64.
    """
    return idx.astype(np.int64)[:, None] * w + np.arange(w, dtype=np.int64)


def scatter_rows(out: np.ndarray, idx: np.ndarray, values: np.ndarray) -> None:
    """``out[idx[c]] += values[c]`` for rows of ``values`` (repeated indices summed; ``numpy.add.at``
    on flat indices, ``row_entries``, measured faster than per-column ``numpy.bincount``).

    Parameters
    ----------
    out : numpy.ndarray
        (N, w), added to.
    idx : numpy.ndarray
        Row of each value row, (m,).
    values : numpy.ndarray
        (m, w).
    """
    np.add.at(out.reshape(-1), row_entries(idx, values.shape[1]).reshape(-1), values.reshape(-1))


def scattered_blocks(op, weights: list[np.ndarray]) -> tuple[np.ndarray, list[np.ndarray]]:
    """The NumPy fallback: the scaled diagonal blocks (N, 6, 6) and, per weight vector ``w`` (6N,),
    ``sum_q |A_pq| w_q`` (6N,), the contacts' blocks (``assembly.contact_blocks``) scattered chunk by chunk.

    Parameters
    ----------
    op : dtcrit.packing.operators.matrix_free.ContactOperator
        The operator (``packing``, ``contacts``, ``kind``, ``scale6``, ``chunk``).
    weights : list of numpy.ndarray
        The weight vectors.

    Returns
    -------
    tuple
        The blocks and the row sums per weight vector.
    """
    p, c, s = op.packing, op.contacts, op.scale6
    n = p.n
    w6 = [np.asarray(w, float).reshape(n, 6) for w in weights]
    diag = np.zeros((n, 36))
    sums = [np.zeros((n, 6)) for _ in weights]
    for start in range(0, c.count, op.chunk):
        sl = slice(start, min(start + op.chunk, c.count))
        k_ii, k_jj, k_ij = contact_blocks(p, c, sl, op.kind)
        ci, cj = c.i[sl], c.j[sl]
        same = ci == cj
        if same.any():
            k_ii = k_ii.copy()
            k_ii[same] += k_ij[same] + np.swapaxes(k_ij[same], 1, 2)
            k_ij = k_ij.copy()
            k_ij[same] = 0.0
        scatter_rows(diag, ci, k_ii.reshape(-1, 36))
        scatter_rows(diag, cj, k_jj.reshape(-1, 36))
        if weights:
            scaled = np.abs(k_ij * s[ci][:, :, None] * s[cj][:, None, :])
            for w, out in zip(w6, sums):
                scatter_rows(out, ci, np.einsum("cab,cb->ca", scaled, w[cj]))
                scatter_rows(out, cj, np.einsum("cab,ca->cb", scaled, w[ci]))
    blocks = diag.reshape(n, 6, 6)
    blocks *= s[:, :, None]
    blocks *= s[:, None, :]
    for w, out in zip(w6, sums):
        out += np.einsum("pab,pb->pa", np.abs(blocks), w)
    return blocks, [out.reshape(-1) for out in sums]
