"""The NumPy fallback of the bounds' block pass (without Numba; ``particle_pass`` is the compiled one):
the scaled diagonal blocks ``A_pp`` and the weighted absolute row sums ``sum_q |A_pq| w_q`` (the
formulas in ``particle_pass``'s docstring), each contact's blocks (``assembly.contact_blocks``)
scattered to its two bodies chunk by chunk, and the blocks' top eigenvalues by batched LAPACK.
"""
from __future__ import annotations

import numpy as np

from dtcrit.packing.operators.assembly import contact_blocks

__all__ = ["scatter_rows", "scattered_blocks", "top_eigenvalues"]


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


def scatter_rows(out: np.ndarray, idx: np.ndarray, values: np.ndarray) -> None:
    """``out[idx[c]] += values[c]`` for rows of ``values`` (repeated indices summed; ``numpy.add.at``
    on flat indices, measured faster than per-column ``numpy.bincount``).

    Parameters
    ----------
    out : numpy.ndarray
        (N, w), added to.
    idx : numpy.ndarray
        Row of each value row, (m,).
    values : numpy.ndarray
        (m, w).
    """
    w = values.shape[1]
    np.add.at(out.reshape(-1), (idx[:, None] * w + np.arange(w)).reshape(-1), values.reshape(-1))


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
