"""Compiled (Numba) loop for the single-contact frequencies of ``estimates.single_contact_frequencies``.

For each contact, alone between its two free bodies (``dtcrit.packing.bounds.estimates``, module docstring):

    omega_c^2 = lambda_max(K_c^(1/2) W K_c^(1/2)),   W = B_i M_i^-1 B_i^T + B_j M_j^-1 B_j^T,
    B_i = [-1 | [a_i]_x R_i],   B_j = [1 | -[a_j]_x R_j]   (``assembly``, module docstring),

``W = (B_i + B_j) M_i^-1 (B_i + B_j)^T`` for a contact with the particle's own periodic image, and
``K_c^(1/2) = sqrt(k_n) n n^T + sqrt(k_s) (1 - n n^T)``.  The largest eigenvalue of the symmetric
3 x 3 matrix comes from cyclic Jacobi rotations (Golub & Van Loan, Algorithm 8.5.2, with the stable
rotation of Eq. (8.5.4)) swept until every off-diagonal entry is below ``eps`` times the diagonal's
scale: absolute error of a few ulps of ``||S||``, as LAPACK's.  The vectorised NumPy path (batched
``numpy.linalg.eigvalsh``) is the reference the tests compare this loop with, and is used when
Numba is absent.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.packing.normal_arms import kernel_arms
from dtcrit.packing.operators.contact_element import IDENTITY, arm_rows, coefficient_at, rotation_rows
from dtcrit.packing.operators.element_matrices import slip_jacobians_into
from dtcrit.packing.operators.matrix_free import PARALLEL_MIN_CONTACTS
from dtcrit.packing.operators.matrix_free_kernels import _jit, available, block_bounds, kernel_indices, prange, threads
from dtcrit.packing.uniform_values import kernel_values

__all__ = ["available", "contact_frequencies"]

MAX_BLOCKS = 4
"""Most threads of the frequencies' loop (each contact's value is its own: the blocks do not change it)."""


def _top_eigenvalue(s):
    """Largest eigenvalue of the symmetric 3 x 3 ``s`` (overwritten) by cyclic Jacobi."""
    eps = 2.220446049250313e-16
    for _sweep in range(30):
        off = abs(s[0, 1]) + abs(s[0, 2]) + abs(s[1, 2])
        scale = abs(s[0, 0]) + abs(s[1, 1]) + abs(s[2, 2])
        if off <= eps * scale:
            break
        for p in range(2):
            for q in range(p + 1, 3):
                apq = s[p, q]
                if apq == 0.0:
                    continue
                tau = (s[q, q] - s[p, p]) / (2.0 * apq)
                t = (1.0 if tau >= 0.0 else -1.0) / (abs(tau) + math.sqrt(1.0 + tau * tau))
                if abs(tau) > 1e150:  # rotation angle below an ulp: the entry is negligible
                    t = 0.5 / tau
                c = 1.0 / math.sqrt(1.0 + t * t)
                sn = t * c
                for k in range(3):  # columns p, q
                    skp = s[k, p]
                    skq = s[k, q]
                    s[k, p] = c * skp - sn * skq
                    s[k, q] = sn * skp + c * skq
                for k in range(3):  # rows p, q
                    spk = s[p, k]
                    sqk = s[q, k]
                    s[p, k] = c * spk - sn * sqk
                    s[q, k] = sn * spk + c * sqk
                s[p, q] = 0.0
                s[q, p] = 0.0
    return max(s[0, 0], s[1, 1], s[2, 2])


def _frequencies_span(lo, hi, ci, cj, nrm, arm_i, arm_j, kn, ks, rot, inv_mass, oriented, out):
    """``out[c] = omega_c^2`` for the contacts ``lo <= c < hi`` (module docstring); ``inv_mass``
    (N, 6) holds ``1/m, 1/m, 1/m, 1/I_1, 1/I_2, 1/I_3``; ``rot`` (N, 3, 3) is used when ``oriented``;
    ``kn``, ``ks`` of length 1 hold one value for every contact (``coefficient_at``).
    """
    bi = np.zeros((3, 6))
    bj = np.zeros((3, 6))
    w = np.zeros((3, 3))
    root = np.zeros((3, 3))
    rw = np.zeros((3, 3))
    s = np.zeros((3, 3))
    for c in range(lo, hi):
        i = ci[c]
        j = cj[c]
        ri = rotation_rows(rot, i) if oriented else IDENTITY
        rj = rotation_rows(rot, j) if oriented else IDENTITY
        ai, aj = arm_rows(arm_i, arm_j, nrm, c)
        slip_jacobians_into(ai, aj, ri, rj, oriented, bi, bj)
        for r in range(3):
            for col in range(3):
                acc = 0.0
                if i == j:
                    for d in range(6):
                        acc += (bi[r, d] + bj[r, d]) * inv_mass[i, d] * (bi[col, d] + bj[col, d])
                else:
                    for d in range(6):
                        acc += bi[r, d] * inv_mass[i, d] * bi[col, d] + bj[r, d] * inv_mass[j, d] * bj[col, d]
                w[r, col] = acc
        sn = math.sqrt(coefficient_at(kn, c))
        st = math.sqrt(coefficient_at(ks, c))
        n = nrm[c]
        for r in range(3):
            for col in range(3):
                root[r, col] = (sn - st) * n[r] * n[col] + (st if r == col else 0.0)
        for r in range(3):
            for col in range(3):
                rw[r, col] = root[r, 0] * w[0, col] + root[r, 1] * w[1, col] + root[r, 2] * w[2, col]
        for r in range(3):
            for col in range(r, 3):
                v = rw[r, 0] * root[0, col] + rw[r, 1] * root[1, col] + rw[r, 2] * root[2, col]
                s[r, col] = v
                s[col, r] = v
        out[c] = _top_eigenvalue(s)


def _frequencies_blocks(bounds, *args):
    """``_frequencies_span`` over the contact blocks ``bounds[b] <= c < bounds[b + 1]``, one thread
    each (every contact's value is its own: no sum across blocks).
    """
    for b in prange(bounds.shape[0] - 1):
        frequencies_span(bounds[b], bounds[b + 1], *args)


if available():  # the loop calls the compiled eigenvalue by this global name
    _top_eigenvalue = _jit(_top_eigenvalue)
frequencies_span = _jit(_frequencies_span)
frequencies_blocks = _jit(_frequencies_blocks, parallel=True)


def contact_frequencies(packing, contacts) -> np.ndarray:
    """``omega_c^2`` of every contact by the compiled loop (Numba required: ``available()``), on
    Numba's threads (blocks of contacts, as the matrix-free product) from ``PARALLEL_MIN_CONTACTS``.

    Parameters
    ----------
    packing : Packing
        The bodies (masses, principal moments, orientations).
    contacts : Contacts
        The contacts with their springs ``kn``, ``ks`` [N/m].

    Returns
    -------
    numpy.ndarray
        ``omega_c^2`` per contact [1/s^2].
    """
    oriented = packing.orientations is not None
    rot = np.ascontiguousarray(packing.orientations) if oriented else np.zeros((1, 3, 3))
    inv_mass = 1.0 / np.concatenate([np.repeat(packing.masses[:, None], 3, axis=1), packing.inertia], axis=1)
    out = np.empty(contacts.count)
    args = (*kernel_indices(contacts), np.ascontiguousarray(contacts.normal, dtype=float), *kernel_arms(contacts),
            kernel_values(contacts.kn), kernel_values(contacts.ks), rot, inv_mass, oriented, out)
    blocks = min(threads(), MAX_BLOCKS) if contacts.count >= PARALLEL_MIN_CONTACTS else 1
    if blocks > 1:
        frequencies_blocks(block_bounds(contacts.count, blocks), *args)
    else:
        frequencies_span(0, contacts.count, *args)
    return out
