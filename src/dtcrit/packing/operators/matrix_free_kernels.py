"""Compiled (Numba) loops of the matrix-free contact operator (``dtcrit.packing.operators.matrix_free``).

One pass over the contacts per product, scalar code per contact, the same formulas as the
vectorised NumPy path of ``operator.ContactOperator`` (which the tests compare them with):

    delta = u_j - u_i + a_i x theta_i - a_j x theta_j,   f = k_s delta + (k_n - k_s)(n . delta) n,
    i: (-f, -R_i^T (a_i x f)),   j: (f, R_j^T (a_j x f));
    w = theta_j - theta_i,  m = k_r w + (k_tw - k_r)(n . w) n,   i: -R_i^T m,   j: R_j^T m;
    d = u_j - u_i,  p = -g (d - (n . d) n),   i: -p,   j: p      (g = F / r, the pre-load term).

Measured on the jittered FCC benchmark (585k contacts): the vectorised NumPy product takes 4x the
time of an assembled BSR product, the compiled loop under half of it, which is why this module
exists.  ``available()`` says whether Numba is installed; without it the NumPy path is used.

``element_pass`` gives in the same way each particle's 6 x 6 diagonal block and the absolute row
sums of the scaled coupling blocks, from ``L_i = [-1 | X_i]``, ``L_j = [1 | Y_j]`` with
``X_i = [a_i]_x R_i``, ``Y_j = -[a_j]_x R_j``:

    ii = [[T, -T X_i], [-X_i^T T, X_i^T T X_i]],   jj = [[T, T Y_j], [Y_j^T T, Y_j^T T Y_j]],
    ij = [[-T, -T Y_j], [X_i^T T, X_i^T T Y_j]]

plus ``R^T T_r R`` (rotation-rotation; ``-R_i^T T_r R_j`` coupling) for the rolling/twisting springs
and ``T_p = -g (1 - n n^T)`` (translation-translation; ``-T_p`` coupling) for the pre-load.
"""
from __future__ import annotations

import numpy as np

from dtcrit.packing.operators.contact_element import IDENTITY, body_forces, element_blocks_into, rotation_rows

try:  # pragma: no cover - exercised by whichever environment runs the tests
    import numba

    _jit = numba.njit(cache=True, nogil=True)
except ImportError:  # the NumPy path of operator.ContactOperator is used instead
    numba = None
    _jit = None


def available() -> bool:
    """Whether the compiled loops can be used (Numba importable)."""
    return numba is not None


def _apply(q, y, ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags):
    """``y[i] += B_i^T f``, ``y[j] += B_j^T f`` for every contact: ``contact_element.body_forces``.

    ``flags``: (translational, rotational, preload, oriented) as 0/1; arrays not in use may be
    empty.  ``q`` and ``y`` are (N, 6).
    """
    trans, rotl, pre, orient = flags[0] != 0, flags[1] != 0, flags[2] != 0, flags[3] != 0
    zero = (0.0, 0.0, 0.0)
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        ri = rotation_rows(rot, i) if orient else IDENTITY
        rj = rotation_rows(rot, j) if orient else IDENTITY
        n = (nrm[c, 0], nrm[c, 1], nrm[c, 2])
        ai = (arm_i[c, 0], arm_i[c, 1], arm_i[c, 2]) if trans else zero
        aj = (arm_j[c, 0], arm_j[c, 1], arm_j[c, 2]) if trans else zero
        f, m_i, m_j = body_forces(n, ai, aj, ri, rj, orient, (q[i, 0], q[i, 1], q[i, 2]), (q[i, 3], q[i, 4], q[i, 5]),
                                  (q[j, 0], q[j, 1], q[j, 2]), (q[j, 3], q[j, 4], q[j, 5]),
                                  kn[c] if trans else 0.0, ks[c] if trans else 0.0, ktw[c] if rotl else 0.0,
                                  kr[c] if rotl else 0.0, g[c] if pre else 0.0, trans, rotl, pre)
        for a in range(3):
            y[i, a] -= f[a]
            y[i, 3 + a] += m_i[a]
            y[j, a] += f[a]
            y[j, 3 + a] += m_j[a]


def _apply_spheres(q, y, ci, cj, nrm, li, lj, kn, ks, g, pre):
    """``_apply`` for sphere contacts with springs (and pre-load) only and no body rotations: the
    arms are ``a_i = l_i n``, ``a_j = -l_j n``, rebuilt from the two lengths, so that the loop reads
    48 bytes fewer per contact; the element is the same ``contact_element.body_forces``.  The tests
    compare it with ``_apply`` and the assembled matrix.
    """
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        n = (nrm[c, 0], nrm[c, 1], nrm[c, 2])
        a = li[c]
        b = -lj[c]
        f, m_i, m_j = body_forces(n, (a * n[0], a * n[1], a * n[2]), (b * n[0], b * n[1], b * n[2]), IDENTITY, IDENTITY, False,
                                  (q[i, 0], q[i, 1], q[i, 2]), (q[i, 3], q[i, 4], q[i, 5]),
                                  (q[j, 0], q[j, 1], q[j, 2]), (q[j, 3], q[j, 4], q[j, 5]),
                                  kn[c], ks[c], 0.0, 0.0, g[c] if pre else 0.0, True, False, pre)
        for k in range(3):
            y[i, k] -= f[k]
            y[i, 3 + k] += m_i[k]
            y[j, k] += f[k]
            y[j, 3 + k] += m_j[k]


def _element_pass(ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags, scale, weights, diag, rows):
    """Accumulate the unscaled diagonal blocks ``diag`` (N, 6, 6) and, when ``rows`` is not empty,
    the weighted absolute row sums ``sum_q |A_pq| w_q`` of the scaled coupling blocks, one set
    ``rows[:, :, k]`` (N, 6, K) per weight vector ``weights[:, :, k]`` (N, 6, K) (module docstring);
    the blocks come from ``contact_element.element_blocks_into``.
    """
    trans, rotl, pre, orient = flags[0] != 0, flags[1] != 0, flags[2] != 0, flags[3] != 0
    want_rows = rows.shape[0] > 0
    nw = weights.shape[2]
    zero = (0.0, 0.0, 0.0)
    ii = np.zeros((6, 6))
    jj = np.zeros((6, 6))
    ij = np.zeros((6, 6))
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        ri = rotation_rows(rot, i) if orient else IDENTITY
        rj = rotation_rows(rot, j) if orient else IDENTITY
        n = (nrm[c, 0], nrm[c, 1], nrm[c, 2])
        ai = (arm_i[c, 0], arm_i[c, 1], arm_i[c, 2]) if trans else zero
        aj = (arm_j[c, 0], arm_j[c, 1], arm_j[c, 2]) if trans else zero
        element_blocks_into(n, ai, aj, ri, rj, orient, kn[c] if trans else 0.0, ks[c] if trans else 0.0,
                            ktw[c] if rotl else 0.0, kr[c] if rotl else 0.0, g[c] if pre else 0.0,
                            trans, rotl, pre, ii, jj, ij)
        if i == j:
            for a in range(6):
                for b in range(6):
                    diag[i, a, b] += ii[a, b] + jj[a, b] + ij[a, b] + ij[b, a]
            continue
        for a in range(6):
            for b in range(6):
                diag[i, a, b] += ii[a, b]
                diag[j, a, b] += jj[a, b]
        if want_rows:
            for a in range(6):
                sia = scale[i, a]
                for b in range(6):
                    v = abs(ij[a, b] * sia * scale[j, b])
                    for k in range(nw):
                        rows[i, a, k] += v * weights[j, b, k]
                        rows[j, b, k] += v * weights[i, a, k]


if numba is not None:
    apply_contacts = _jit(_apply)
    apply_sphere_contacts = _jit(_apply_spheres)
    element_pass = _jit(_element_pass)
else:  # pragma: no cover
    apply_contacts = apply_sphere_contacts = element_pass = None
