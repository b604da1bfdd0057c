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
    """``y[i] += B_i^T f``, ``y[j] += B_j^T f`` for every contact (module docstring).

    ``flags``: (translational, rotational, preload, oriented) as 0/1; arrays not in use may be
    empty.  ``q`` and ``y`` are (N, 6).
    """
    trans, rotl, pre, orient = flags[0], flags[1], flags[2], flags[3]
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        nx, ny, nz = nrm[c, 0], nrm[c, 1], nrm[c, 2]
        if orient:
            r = rot[i]
            tix = r[0, 0] * q[i, 3] + r[0, 1] * q[i, 4] + r[0, 2] * q[i, 5]
            tiy = r[1, 0] * q[i, 3] + r[1, 1] * q[i, 4] + r[1, 2] * q[i, 5]
            tiz = r[2, 0] * q[i, 3] + r[2, 1] * q[i, 4] + r[2, 2] * q[i, 5]
            r = rot[j]
            tjx = r[0, 0] * q[j, 3] + r[0, 1] * q[j, 4] + r[0, 2] * q[j, 5]
            tjy = r[1, 0] * q[j, 3] + r[1, 1] * q[j, 4] + r[1, 2] * q[j, 5]
            tjz = r[2, 0] * q[j, 3] + r[2, 1] * q[j, 4] + r[2, 2] * q[j, 5]
        else:
            tix, tiy, tiz = q[i, 3], q[i, 4], q[i, 5]
            tjx, tjy, tjz = q[j, 3], q[j, 4], q[j, 5]
        dx = q[j, 0] - q[i, 0]
        dy = q[j, 1] - q[i, 1]
        dz = q[j, 2] - q[i, 2]
        fx = fy = fz = 0.0
        mix = miy = miz = 0.0
        mjx = mjy = mjz = 0.0
        if trans:
            aix, aiy, aiz = arm_i[c, 0], arm_i[c, 1], arm_i[c, 2]
            ajx, ajy, ajz = arm_j[c, 0], arm_j[c, 1], arm_j[c, 2]
            ex = dx + (aiy * tiz - aiz * tiy) - (ajy * tjz - ajz * tjy)
            ey = dy + (aiz * tix - aix * tiz) - (ajz * tjx - ajx * tjz)
            ez = dz + (aix * tiy - aiy * tix) - (ajx * tjy - ajy * tjx)
            s = ks[c]
            t = (kn[c] - s) * (nx * ex + ny * ey + nz * ez)
            fx = s * ex + t * nx
            fy = s * ey + t * ny
            fz = s * ez + t * nz
            mix = -(aiy * fz - aiz * fy)
            miy = -(aiz * fx - aix * fz)
            miz = -(aix * fy - aiy * fx)
            mjx = ajy * fz - ajz * fy
            mjy = ajz * fx - ajx * fz
            mjz = ajx * fy - ajy * fx
        if pre:
            dn = nx * dx + ny * dy + nz * dz
            gc = g[c]
            fx -= gc * (dx - dn * nx)
            fy -= gc * (dy - dn * ny)
            fz -= gc * (dz - dn * nz)
        if rotl:
            wx, wy, wz = tjx - tix, tjy - tiy, tjz - tiz
            s = kr[c]
            t = (ktw[c] - s) * (nx * wx + ny * wy + nz * wz)
            px, py, pz = s * wx + t * nx, s * wy + t * ny, s * wz + t * nz
            mix -= px
            miy -= py
            miz -= pz
            mjx += px
            mjy += py
            mjz += pz
        y[i, 0] -= fx
        y[i, 1] -= fy
        y[i, 2] -= fz
        y[j, 0] += fx
        y[j, 1] += fy
        y[j, 2] += fz
        if orient:
            r = rot[i]
            y[i, 3] += r[0, 0] * mix + r[1, 0] * miy + r[2, 0] * miz
            y[i, 4] += r[0, 1] * mix + r[1, 1] * miy + r[2, 1] * miz
            y[i, 5] += r[0, 2] * mix + r[1, 2] * miy + r[2, 2] * miz
            r = rot[j]
            y[j, 3] += r[0, 0] * mjx + r[1, 0] * mjy + r[2, 0] * mjz
            y[j, 4] += r[0, 1] * mjx + r[1, 1] * mjy + r[2, 1] * mjz
            y[j, 5] += r[0, 2] * mjx + r[1, 2] * mjy + r[2, 2] * mjz
        else:
            y[i, 3] += mix
            y[i, 4] += miy
            y[i, 5] += miz
            y[j, 3] += mjx
            y[j, 4] += mjy
            y[j, 5] += mjz


def _apply_spheres(q, y, ci, cj, nrm, li, lj, kn, ks, g, pre):
    """``_apply`` for sphere contacts with springs (and pre-load) only and no body rotations: the
    arms are ``a_i = l_i n``, ``a_j = -l_j n``, so with ``d = u_j - u_i``

        delta = d + n x (l_i theta_i + l_j theta_j),   f = k_s delta + (k_n - k_s)(n . d) n,
        i: (-f, -l_i k_s n x delta),   j: (f, -l_j k_s n x delta)

    (``n . (n x w) = 0``, ``n x n = 0``): half the arithmetic of ``_apply`` and 48 bytes fewer per
    contact to read.  The tests compare it with ``_apply`` and the assembled matrix.
    """
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        nx, ny, nz = nrm[c, 0], nrm[c, 1], nrm[c, 2]
        a = li[c]
        b = lj[c]
        wx = a * q[i, 3] + b * q[j, 3]
        wy = a * q[i, 4] + b * q[j, 4]
        wz = a * q[i, 5] + b * q[j, 5]
        dx = q[j, 0] - q[i, 0]
        dy = q[j, 1] - q[i, 1]
        dz = q[j, 2] - q[i, 2]
        ex = dx + (ny * wz - nz * wy)
        ey = dy + (nz * wx - nx * wz)
        ez = dz + (nx * wy - ny * wx)
        s = ks[c]
        dn = nx * dx + ny * dy + nz * dz
        t = (kn[c] - s) * dn
        fx = s * ex + t * nx
        fy = s * ey + t * ny
        fz = s * ez + t * nz
        if pre:
            gc = g[c]
            fx -= gc * (dx - dn * nx)
            fy -= gc * (dy - dn * ny)
            fz -= gc * (dz - dn * nz)
        mx = -s * (ny * ez - nz * ey)
        my = -s * (nz * ex - nx * ez)
        mz = -s * (nx * ey - ny * ex)
        y[i, 0] -= fx
        y[i, 1] -= fy
        y[i, 2] -= fz
        y[i, 3] += a * mx
        y[i, 4] += a * my
        y[i, 5] += a * mz
        y[j, 0] += fx
        y[j, 1] += fy
        y[j, 2] += fz
        y[j, 3] += b * mx
        y[j, 4] += b * my
        y[j, 5] += b * mz


def _cross_rotation(arm, rot, sign, out):
    """``out = sign [arm]_x rot`` for a 3-vector and a 3 x 3 array (column ``b``: ``arm x rot e_b``)."""
    for b in range(3):
        out[0, b] = sign * (arm[1] * rot[2, b] - arm[2] * rot[1, b])
        out[1, b] = sign * (arm[2] * rot[0, b] - arm[0] * rot[2, b])
        out[2, b] = sign * (arm[0] * rot[1, b] - arm[1] * rot[0, b])


def _mul(a, b, out):
    """``out = a b`` for 3 x 3 arrays."""
    for r in range(3):
        for s in range(3):
            out[r, s] = a[r, 0] * b[0, s] + a[r, 1] * b[1, s] + a[r, 2] * b[2, s]


def _tmul(a, b, out):
    """``out = a^T b`` for 3 x 3 arrays."""
    for r in range(3):
        for s in range(3):
            out[r, s] = a[0, r] * b[0, s] + a[1, r] * b[1, s] + a[2, r] * b[2, s]


def _element_pass(ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags, scale, weights, diag, rows):
    """Accumulate the unscaled diagonal blocks ``diag`` (N, 6, 6) and, when ``rows`` is not empty,
    the weighted absolute row sums ``sum_q |A_pq| w_q`` of the scaled coupling blocks, one set
    ``rows[:, :, k]`` (N, 6, K) per weight vector ``weights[:, :, k]`` (N, 6, K) (module docstring).
    """
    trans, rotl, pre, orient = flags[0], flags[1], flags[2], flags[3]
    want_rows = rows.shape[0] > 0
    nw = weights.shape[2]
    t = np.zeros((3, 3))
    tr = np.zeros((3, 3))
    x = np.zeros((3, 3))
    yj = np.zeros((3, 3))
    ri = np.eye(3)
    rj = np.eye(3)
    ii = np.zeros((6, 6))
    jj = np.zeros((6, 6))
    ij = np.zeros((6, 6))
    tx = np.zeros((3, 3))
    ty = np.zeros((3, 3))
    xtx = np.zeros((3, 3))
    yty = np.zeros((3, 3))
    xty = np.zeros((3, 3))
    rii = np.zeros((3, 3))
    rjj = np.zeros((3, 3))
    rij = np.zeros((3, 3))
    for c in range(ci.shape[0]):
        i = ci[c]
        j = cj[c]
        n = nrm[c]
        if orient:
            ri = rot[i]
            rj = rot[j]
        ii[:, :] = 0.0
        jj[:, :] = 0.0
        ij[:, :] = 0.0
        if trans:
            for a in range(3):
                for b in range(3):
                    t[a, b] = (kn[c] - ks[c]) * n[a] * n[b] + (ks[c] if a == b else 0.0)
            ai = arm_i[c]
            aj = arm_j[c]
            cross_rotation(ai, ri, 1.0, x)  # X = [a_i]_x R_i
            cross_rotation(aj, rj, -1.0, yj)  # Y = -[a_j]_x R_j
            _mul(t, x, tx)
            _mul(t, yj, ty)
            _tmul(x, tx, xtx)
            _tmul(yj, ty, yty)
            _tmul(x, ty, xty)
            for a in range(3):
                for b in range(3):
                    ii[a, b] += t[a, b]
                    ii[a, 3 + b] -= tx[a, b]
                    ii[3 + a, b] -= tx[b, a]
                    ii[3 + a, 3 + b] += xtx[a, b]
                    jj[a, b] += t[a, b]
                    jj[a, 3 + b] += ty[a, b]
                    jj[3 + a, b] += ty[b, a]
                    jj[3 + a, 3 + b] += yty[a, b]
                    ij[a, b] -= t[a, b]
                    ij[a, 3 + b] -= ty[a, b]
                    ij[3 + a, b] += tx[b, a]
                    ij[3 + a, 3 + b] += xty[a, b]
        if rotl:
            for a in range(3):
                for b in range(3):
                    tr[a, b] = (ktw[c] - kr[c]) * n[a] * n[b] + (kr[c] if a == b else 0.0)
            _mul(tr, ri, tx)
            _tmul(ri, tx, rii)
            _mul(tr, rj, ty)
            _tmul(rj, ty, rjj)
            _tmul(ri, ty, rij)
            for a in range(3):
                for b in range(3):
                    ii[3 + a, 3 + b] += rii[a, b]
                    jj[3 + a, 3 + b] += rjj[a, b]
                    ij[3 + a, 3 + b] -= rij[a, b]
        if pre:
            for a in range(3):
                for b in range(3):
                    tp = -g[c] * ((1.0 if a == b else 0.0) - n[a] * n[b])
                    ii[a, b] += tp
                    jj[a, b] += tp
                    ij[a, b] -= tp
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
    cross_rotation = _jit(_cross_rotation)
    _mul = _jit(_mul)
    _tmul = _jit(_tmul)
    apply_contacts = _jit(_apply)
    apply_sphere_contacts = _jit(_apply_spheres)
    element_pass = _jit(_element_pass)
else:  # pragma: no cover
    cross_rotation = _cross_rotation
    apply_contacts = apply_sphere_contacts = element_pass = None
