"""Compiled (Numba) loops of the matrix-free contact operator (``dtcrit.packing.operators.matrix_free``).

One pass over the contacts per product; per contact, the element of
``dtcrit.packing.operators.contact_element`` (``body_forces``, inlined into the loop), the same
function the vectorised NumPy path of ``matrix_free.ContactOperator`` calls on arrays:

    delta = u_j - u_i + a_i x theta_i - a_j x theta_j,   f = k_n (n . delta) n + k_s (delta - (n . delta) n),
    i: (-f, -R_i^T (a_i x f)),   j: (f, R_j^T (a_j x f));
    w = theta_j - theta_i,  m = k_tw (n . w) n + k_r (w - (n . w) n),   i: -R_i^T m,   j: R_j^T m;
    d = u_j - u_i,  p = -g (d - (n . d) n),   i: -p,   j: p      (g = F / r, the pre-load term).

Measured on the jittered FCC benchmark (585k contacts): the vectorised NumPy product takes 4x the
time of an assembled BSR product, the compiled loop under half of it, which is why this module
exists.  ``available()`` says whether Numba is installed; without it the NumPy path is used
(``available``, ``threads`` and ``use_threads`` are ``numba_runtime``'s, re-exported here).

The bounds' pass over the same arguments (``loop_arguments``) is ``particle_pass``.

Numba caches these loops keyed on this file only: after an edit of ``contact_element``, touch this
file (or clear ``__pycache__``) so that the cached machine code is rebuilt.
"""
from __future__ import annotations

import numpy as np

from dtcrit.packing.normal_arms import kernel_arms, lengths_along
from dtcrit.packing.operators.contact_element import IDENTITY, body_forces, coefficient_at, contact_frame
from dtcrit.packing.operators.numba_runtime import _jit, available, numba, prange, threads, use_threads  # noqa: F401 (re-exported)
from dtcrit.packing.uniform_values import kernel_values


NO_LIMIT = 1 << 62
"""``below`` of a span that takes every contact."""


def _apply_span(x, s, y, lo, hi, below, ci, cj, nrm, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags):
    """``y[i] += B_i^T f``, ``y[j] += B_j^T f`` for the contacts ``lo <= c < hi`` with ``j < below``:
    ``contact_element.body_forces`` on ``q = s x``, scaled as it is read (no scaled copy of ``x``).

    ``flags``: (translational, rotational, preload, oriented) as 0/1; arrays not in use may be
    empty, coefficients of one value for all contacts length 1 (``coefficient_at``).  ``x``, ``s``
    and ``y`` are (N, 6).
    """
    trans, rotl, pre, orient = flags[0] != 0, flags[1] != 0, flags[2] != 0, flags[3] != 0
    for c in range(lo, hi):
        if cj[c] >= below:
            continue
        i, j, ri, rj, n, ai, aj = contact_frame(c, ci, cj, nrm, arm_i, arm_j, rot, trans, orient)
        f, m_i, m_j = body_forces(n, ai, aj, ri, rj, orient, scaled_row(x, s, i, 0), scaled_row(x, s, i, 3),
                                  scaled_row(x, s, j, 0), scaled_row(x, s, j, 3),
                                  coefficient_at(kn, c) if trans else 0.0, coefficient_at(ks, c) if trans else 0.0,
                                  coefficient_at(ktw, c) if rotl else 0.0, coefficient_at(kr, c) if rotl else 0.0,
                                  coefficient_at(g, c) if pre else 0.0, trans, rotl, pre)
        for a in range(3):
            y[i, a] -= f[a]
            y[i, 3 + a] += m_i[a]
            y[j, a] += f[a]
            y[j, 3 + a] += m_j[a]


def _apply_spheres_span(x, s, y, lo, hi, below, ci, cj, nrm, li, lj, kn, ks, g, pre):
    """``_apply_span`` for sphere contacts with springs (and pre-load) only and no body rotations:
    the arms are ``a_i = l_i n``, ``a_j = -l_j n``, rebuilt from the two lengths, so that the loop
    reads 48 bytes fewer per contact; the element is the same ``contact_element.body_forces``.  The
    tests compare it with ``_apply_span`` and the assembled matrix.
    """
    for c in range(lo, hi):
        j = cj[c]
        if j >= below:
            continue
        i = ci[c]
        n = (nrm[c, 0], nrm[c, 1], nrm[c, 2])
        a = li[c]
        b = -lj[c]
        f, m_i, m_j = body_forces(n, (a * n[0], a * n[1], a * n[2]), (b * n[0], b * n[1], b * n[2]), IDENTITY, IDENTITY, False,
                                  scaled_row(x, s, i, 0), scaled_row(x, s, i, 3),
                                  scaled_row(x, s, j, 0), scaled_row(x, s, j, 3),
                                  coefficient_at(kn, c), coefficient_at(ks, c), 0.0, 0.0,
                                  coefficient_at(g, c) if pre else 0.0, True, False, pre)
        for k in range(3):
            y[i, k] -= f[k]
            y[i, 3 + k] += m_i[k]
            y[j, k] += f[k]
            y[j, 3 + k] += m_j[k]


def _scaled_row(x, s, i, k):
    """``q[i, k:k + 3]`` of ``q = s x``, scaled as it is read."""
    return (x[i, k] * s[i, k], x[i, k + 1] * s[i, k + 1], x[i, k + 2] * s[i, k + 2])


def _blocks_general(x, s, y, spare, bounds, *args):
    """``_apply_span`` over the contact blocks ``bounds[b] <= c < bounds[b + 1]``, one thread each
    (``numba.prange``): block 0 adds into ``y``, block ``b > 0`` into its own zeroed ``spare[b - 1]``
    (N, 6), summed into ``y`` in block order afterwards, so the result depends on the blocks, not on
    the threads or their timing.  The span is called by its global name so that Numba caches this.
    """
    blocks = bounds.shape[0] - 1
    for b in prange(blocks):
        if b == 0:
            apply_span(x, s, y, bounds[0], bounds[1], NO_LIMIT, *args)
        else:
            out = spare[b - 1]
            out[:] = 0.0
            apply_span(x, s, out, bounds[b], bounds[b + 1], NO_LIMIT, *args)
    _add_spares(y, spare, blocks)


def _blocks_spheres(x, s, y, spare, bounds, *args):
    """``_blocks_general`` with ``_apply_spheres_span`` (the sphere loop's arguments).  Two drivers, not
    one taking its span as an argument: Numba does not cache a function that takes another.
    """
    blocks = bounds.shape[0] - 1
    for b in prange(blocks):
        if b == 0:
            apply_spheres_span(x, s, y, bounds[0], bounds[1], NO_LIMIT, *args)
        else:
            out = spare[b - 1]
            out[:] = 0.0
            apply_spheres_span(x, s, out, bounds[b], bounds[b + 1], NO_LIMIT, *args)
    _add_spares(y, spare, blocks)


def _halves_general(x, s, y, halves, cross, *args):
    """``_apply_span`` on the two halves of the particles (``halves_of``), one thread each, straight
    into ``y`` (they write disjoint rows: no spare vector), then the contacts that cross, in order, on
    one thread: the result depends on the halves only, not on the threads or their timing.
    """
    for b in prange(2):
        if b == 0:
            apply_span(x, s, y, 0, halves[1], halves[0], *args)
        else:
            apply_span(x, s, y, halves[1], halves[2], NO_LIMIT, *args)
    for t in range(cross.shape[0]):
        apply_span(x, s, y, cross[t], cross[t] + 1, NO_LIMIT, *args)


def _halves_spheres(x, s, y, halves, cross, *args):
    """``_halves_general`` with ``_apply_spheres_span`` (two drivers: see ``_blocks_spheres``)."""
    for b in prange(2):
        if b == 0:
            apply_spheres_span(x, s, y, 0, halves[1], halves[0], *args)
        else:
            apply_spheres_span(x, s, y, halves[1], halves[2], NO_LIMIT, *args)
    for t in range(cross.shape[0]):
        apply_spheres_span(x, s, y, cross[t], cross[t] + 1, NO_LIMIT, *args)


CROSSING_MAX = 0.125
"""Largest fraction of contacts crossing the two halves of the particles (``halves_of``): beyond it
the crossing contacts, on one thread, would cost more than a spare vector's passes."""


def halves_of(ci: np.ndarray, cj: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Two halves of the particles that two threads can update without a spare vector.

    When the contacts are sorted by ``i`` with ``i <= j`` (the order of the sphere detection), the
    contacts ``[middle, count)`` (``i >= split``) touch only particles ``>= split`` and those of
    ``[0, middle)`` with ``j < split`` only particles below it; the rest cross, and are few when the
    particles are numbered in space (a lattice, a sorted dump).  ``split`` is the ``i`` of the middle
    contact.

    Parameters
    ----------
    ci, cj : numpy.ndarray
        The contacts' particle indices.

    Returns
    -------
    tuple of numpy.ndarray or None
        ``([split, middle, count], crossing contacts in order)``, or ``None`` when the contacts are
        not so sorted or more than ``CROSSING_MAX`` of them cross.
    """
    count = int(ci.shape[0])
    if count < 2 or bool(np.any(ci[1:] < ci[:-1])) or bool(np.any(ci > cj)):
        return None
    split = int(ci[count // 2])
    middle = int(np.searchsorted(ci, split))
    cross = np.flatnonzero(cj[:middle] >= split)
    if cross.size > CROSSING_MAX * count:
        return None
    return np.array([split, middle, count], dtype=np.int64), cross.astype(np.int64)


def _add_spares_loop(y, spare, blocks):
    """``y += spare[0] + spare[1] + ...`` in block order, particles on Numba's threads."""
    for p in prange(y.shape[0]):
        for b in range(blocks - 1):
            for a in range(6):
                y[p, a] += spare[b, p, a]


def kernel_indices(contacts) -> tuple[np.ndarray, np.ndarray]:
    """``(ci, cj)`` as the compiled loops take them: contiguous, both int32 or both int64 (one compiled
    version of a loop each), no copy of a contact list's own int32 or int64 indices.

    Parameters
    ----------
    contacts : Contacts
        The contacts (``i``, ``j``: int32 when ``6 N < 2^31``, ``contact_set.index_dtype``).

    Returns
    -------
    tuple of numpy.ndarray
        The two index arrays.
    """
    same = contacts.i.dtype == contacts.j.dtype and contacts.i.dtype in (np.int32, np.int64)
    dtype = contacts.i.dtype if same else np.int64
    return np.ascontiguousarray(contacts.i, dtype=dtype), np.ascontiguousarray(contacts.j, dtype=dtype)


def loop_arguments(contacts, along, across, twist, roll, preload, orientations) -> tuple:
    """The arguments of ``apply_contacts`` after ``q, y`` (and of ``particle_pass``): contiguous arrays (no
    copy where the contacts already are; indices int32 or int64, ``kernel_indices``), empty ones for the
    terms absent, a coefficient of one value
    for every contact (or a zero partner of a given one) as that value, length 1
    (``uniform_values.kernel_values``).

    Parameters
    ----------
    contacts : Contacts
        The contacts (indices, normals, arms).
    along, across, twist, roll : numpy.ndarray or None
        Per-contact ``k_n``, ``k_s``, ``k_tw``, ``k_r`` (or the dashpots); ``None`` counts as absent
        (zero when its partner is given).
    preload : numpy.ndarray or None
        ``F/r`` per contact [N/m], or ``None``.
    orientations : numpy.ndarray or None
        Body rotation matrices (N, 3, 3), or ``None`` (global axes).

    Returns
    -------
    tuple
        ``(ci, cj, normal, arm_i, arm_j, kn, ks, ktw, kr, g, rot, flags)``.
    """
    translational = along is not None or across is not None
    rotational = twist is not None or roll is not None
    empty = np.zeros(0)

    def arr(a, use):
        if not use:
            return empty
        return np.zeros(1) if a is None else kernel_values(a)

    flags = np.array([translational, rotational, preload is not None, orientations is not None], dtype=np.int64)
    rot = np.zeros((0, 3, 3)) if orientations is None else np.ascontiguousarray(orientations)
    arm_i, arm_j = kernel_arms(contacts) if translational else (np.zeros((0, 3)), np.zeros((0, 3)))
    return (*kernel_indices(contacts), np.ascontiguousarray(contacts.normal, dtype=float), arm_i, arm_j,
            arr(along, translational), arr(across, translational), arr(twist, rotational), arr(roll, rotational),
            arr(preload, preload is not None), rot, flags)


def sphere_arm_lengths(normal: np.ndarray, arm_i: np.ndarray, arm_j: np.ndarray,
                       chunk: int) -> tuple[np.ndarray, np.ndarray] | None:
    """``(l_i, l_j)`` with ``a_i = l_i n``, ``a_j = -l_j n`` to 4 ulps for every contact (sphere
    contacts: the arguments of ``apply_sphere_contacts``), or ``None`` when an arm leaves the normal.

    Parameters
    ----------
    normal, arm_i, arm_j : numpy.ndarray
        Unit normals and branch vectors of the contacts, each (nc, 3).
    chunk : int
        Contacts per vectorised chunk.

    Returns
    -------
    tuple of numpy.ndarray or None
        The two arm lengths per contact [m].
    """
    stored = lengths_along(arm_i, arm_j, normal)
    if stored is not None:  # held as lengths (dtcrit.packing.normal_arms): exact, no copy
        return stored
    nc = normal.shape[0]
    li, lj = np.empty(nc), np.empty(nc)
    for lo in range(0, nc, chunk):
        sl = slice(lo, min(lo + chunk, nc))
        n = normal[sl]
        for arm, out, sign in ((arm_i[sl], li, 1.0), (arm_j[sl], lj, -1.0)):
            length = sign * (arm[:, 0] * n[:, 0] + arm[:, 1] * n[:, 1] + arm[:, 2] * n[:, 2])
            off = np.abs(arm - sign * length[:, None] * n).max(axis=1)
            if np.any(off > 4 * np.finfo(float).eps * np.abs(arm).max(axis=1)):
                return None
            out[sl] = length
    return li, lj


scaled_row = _jit(_scaled_row)
apply_span = _jit(_apply_span)
apply_spheres_span = _jit(_apply_spheres_span)
_add_spares = _jit(_add_spares_loop, parallel=True)
apply_blocks_general = _jit(_blocks_general, parallel=True)
apply_blocks_spheres = _jit(_blocks_spheres, parallel=True)
apply_halves_general = _jit(_halves_general, parallel=True)
apply_halves_spheres = _jit(_halves_spheres, parallel=True)


def apply_contacts(q, y, *args) -> None:
    """``y += A_K q`` over every contact (``_apply_span``, ``q`` unscaled), on one thread.

    Parameters
    ----------
    q, y : numpy.ndarray
        (N, 6) scaled displacements and the accumulated forces.
    *args
        ``loop_arguments``' tuple.
    """
    apply_span(q, np.ones_like(q), y, 0, args[0].shape[0], NO_LIMIT, *args)


def apply_sphere_contacts(q, y, *args) -> None:
    """``apply_contacts`` for sphere contacts (``_apply_spheres_span``), on one thread.

    Parameters
    ----------
    q, y : numpy.ndarray
        (N, 6) scaled displacements and the accumulated forces.
    *args
        ``(ci, cj, normal, l_i, l_j, kn, ks, g, preload)``.
    """
    apply_spheres_span(q, np.ones_like(q), y, 0, args[0].shape[0], NO_LIMIT, *args)


def block_bounds(count: int, blocks: int) -> np.ndarray:
    """Contact ranges of ``apply_blocks_general`` and ``apply_blocks_spheres``: ``blocks`` nearly equal spans of ``count`` contacts.

    Parameters
    ----------
    count : int
        Contacts.
    blocks : int
        Spans (>= 1).

    Returns
    -------
    numpy.ndarray
        ``blocks + 1`` increasing int64 bounds from 0 to ``count``.
    """
    return np.linspace(0, count, max(1, int(blocks)) + 1).round().astype(np.int64)
