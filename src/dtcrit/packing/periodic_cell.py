"""Periodic images in a general (sheared, triclinic) cell: wrapping, nearest images and the search
of every image within a contact range.

A box with a ``cell`` (``dtcrit.packing.model.Box``) is the parallelepiped ``lo + H f``, ``f`` in
``[0, 1)^3``, whose columns ``H = (a, b, c)`` are the edge vectors (YADE's ``O.cell.hSize``; LAMMPS's
``a = (lx, 0, 0), b = (xy, ly, 0), c = (xz, yz, lz)``, Howto triclinic).  Its periodic images are the
translations ``H n``, ``n`` integer along the periodic cell vectors (YADE: ``shift2 = hSize cellDist``).
Fractional coordinates are ``f = H^-1 (x - lo)``; the distance between the two faces of the cell
spanned by the other two vectors is ``w_k = 1 / |g_k|``, ``g_k`` the k-th row of ``H^-1``.

The search (:func:`cell_pairs`) does not rely on a minimum image, which a strongly sheared cell does
not have: every point within ``r`` of the (wrapped) cell has ``-r/w_k <= f_k <= 1 + r/w_k`` (because
``|f_k(x) - f_k(y)| <= |g_k| |x - y|``), so the images ``x_j + H n`` of every particle whose
fractional coordinates fall in that slab, ``|n_k| <= floor(r / w_k) + 1``, are ghosts; one
``cKDTree`` over the particles and their ghosts, queried with the particles, finds every pair
``(i, j, n)`` with ``|x_j + H n - x_i| <= r`` for any tilt (the ghost layer is as thick as ``r``
across each face, so its size grows only with the tilt's thinning of ``w_k``).  Each pair is found from
both ends and kept once: ``i < j``, or ``i == j`` with ``n`` lexicographically positive.

Nearest images (:func:`nearest_image`) are exact too: from the rounded fractional separation, every
shift that can still be shorter (``|delta_k| <= D / w_k + 1/2``, ``D`` the rounded image's length) is
tried.  Contacts carry images of the packing's own positions, wrapped or not (:func:`own_images`), as
the pre-load's centre distances ``|x_j + H n - x_i|`` need.
"""
from __future__ import annotations

import itertools
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from dtcrit.packing.model import Box, Packing

MARGIN = 1e-9
"""Relative widening of the ghost slab and of the search reach, so that rounding never loses a pair."""


def fractional(box: Box, vectors: np.ndarray) -> np.ndarray:
    """Cell coordinates ``H^-1 v`` of displacement vectors ``v`` (not positions: no origin).

    Parameters
    ----------
    box : Box
        The box.
    vectors : numpy.ndarray
        Displacements, shape ``(..., 3)`` [m].

    Returns
    -------
    numpy.ndarray
        Their coordinates along the cell vectors (``v / lengths`` for an axis-aligned box).
    """
    v = np.asarray(vectors, dtype=float)
    return v / box.lengths if box.cell is None else np.linalg.solve(box.cell, v.reshape(-1, 3).T).T.reshape(v.shape)


def spacings(box: Box) -> np.ndarray:
    """Distances ``w_k`` [m] between the cell's opposite faces (``lengths`` for an axis-aligned box).

    Parameters
    ----------
    box : Box
        The box.

    Returns
    -------
    numpy.ndarray
        ``1 / |g_k|``, ``g_k`` the rows of ``H^-1`` (module docstring).
    """
    return box.lengths.copy() if box.cell is None else 1.0 / np.linalg.norm(np.linalg.inv(box.cell), axis=1)


def wrap(box: Box, positions: np.ndarray) -> np.ndarray:
    """Positions moved by whole cell vectors into the cell along its periodic directions.

    Parameters
    ----------
    box : Box
        A box with a ``cell``.
    positions : numpy.ndarray
        Centres ``(n, 3)`` [m] (not modified).

    Returns
    -------
    numpy.ndarray
        ``x - H floor(f)`` (periodic components of ``f`` only): fractional coordinates in ``[0, 1)`` up
        to rounding.
    """
    x = np.array(positions, dtype=float, copy=True)
    n = np.floor(fractional(box, x - box.lo))
    n[:, ~np.array(box.periodic)] = 0.0
    return x - box.shift(n)


def image_of(box: Box, translation: np.ndarray) -> np.ndarray:
    """The integer images ``n`` whose translations ``H n`` are ``translation`` (rounded; 0 off the periodic axes).

    Parameters
    ----------
    box : Box
        The box.
    translation : numpy.ndarray
        Whole-cell translations ``(m, 3)`` [m], e.g. YADE's ``shift2``.

    Returns
    -------
    numpy.ndarray
        ``(m, 3)`` int64 images.
    """
    f = fractional(box, translation)
    f[..., ~np.array(box.periodic)] = 0.0
    return np.rint(f).astype(np.int64)


def nearest_image(box: Box, sep: np.ndarray) -> np.ndarray:
    """The integer image ``n`` making ``|sep + H n|`` smallest, per row (exact in any cell; module docstring).

    Parameters
    ----------
    box : Box
        The box.
    sep : numpy.ndarray
        Separations ``x_j - x_i``, shape ``(m, 3)`` [m].

    Returns
    -------
    numpy.ndarray
        ``(m, 3)`` int64 images (0 along non-periodic directions).
    """
    sep = np.asarray(sep, dtype=float).reshape(-1, 3)
    best = -image_of(box, sep)
    if box.cell is None or len(sep) == 0:
        return best
    length = np.linalg.norm(sep + box.shift(best), axis=1)
    periodic = np.array(box.periodic)
    reach = np.where(periodic, np.floor(float(length.max()) / spacings(box) + 0.5), 0).astype(int)
    start = best.copy()
    for delta in itertools.product(*(range(-m, m + 1) for m in reach)):
        if not any(delta):
            continue
        trial = start + np.array(delta)
        d = np.linalg.norm(sep + box.shift(trial), axis=1)
        better = d < length
        best[better], length[better] = trial[better], d[better]
    return best


def own_images(packing: Packing, x: np.ndarray) -> np.ndarray | None:
    """Whole cell vectors ``n`` with ``x = positions + H n``: an image among the wrapped centres ``x``
    plus ``n_j - n_i`` is the image of the packing's own positions.

    Parameters
    ----------
    packing : Packing
        The particles (their own positions and box).
    x : numpy.ndarray
        The same centres wrapped into the box (``dtcrit.packing.detection.overlaps.wrap_positions``).

    Returns
    -------
    numpy.ndarray or None
        ``(n, 3)`` int64, or None when no centre was moved.
    """
    moved = None if packing.box is None else image_of(packing.box, x - packing.positions)
    return moved if moved is not None and moved.any() else None


def shortest_translation(box: Box) -> float:
    """Length [m] of the shortest periodic translation ``H n``, ``n != 0`` (inf without periodic axes).

    Parameters
    ----------
    box : Box
        The box.

    Returns
    -------
    float
        The shortest lattice vector's length: a sphere wider than it overlaps its own image.
    """
    periodic = np.array(box.periodic)
    if not periodic.any():
        return float("inf")
    h = box.matrix
    bound = float(np.linalg.norm(h[:, periodic], axis=0).min())
    reach = np.where(periodic, np.floor(bound / spacings(box) * (1 + MARGIN)), 0).astype(int)
    shortest = bound
    for n in itertools.product(*(range(-m, m + 1) for m in reach)):
        if any(n):
            shortest = min(shortest, float(np.linalg.norm(h @ np.array(n, float))))
    return shortest


def _ghosts(box: Box, x: np.ndarray, cutoff: float):
    """``(points, owner, image)``: the particles (image 0) and their images within the widened slab."""
    periodic = np.array(box.periodic)
    f = fractional(box, x - box.lo)
    reach = cutoff * (1.0 + MARGIN) / spacings(box) + MARGIN
    span = [range(-(int(reach[k]) + 1), int(reach[k]) + 2) if periodic[k] else range(0, 1) for k in range(3)]
    points, owner, image = [x], [np.arange(len(x))], [np.zeros((len(x), 3), np.int64)]
    for n in itertools.product(*span):
        if not any(n):
            continue
        g = f + np.array(n)
        inside = np.all((g >= -reach) & (g <= 1.0 + reach) | ~periodic, axis=1)
        k = np.flatnonzero(inside)
        s = np.repeat(np.array(n, np.int64)[None], len(k), axis=0)
        points.append(x[k] + box.shift(s))
        owner.append(k)
        image.append(s)
    return np.concatenate(points), np.concatenate(owner), np.concatenate(image)


def cell_pairs(x: np.ndarray, cutoff: float, box: Box, chunk: int = 1 << 18):
    """Every pair ``(i, j, image)`` with ``|x_j + H image - x_i| <= cutoff`` in a general cell, each once.

    Parameters
    ----------
    x : numpy.ndarray
        Centres ``(n, 3)`` [m], wrapped into the cell (:func:`wrap`).
    cutoff : float
        Search range [m].
    box : Box
        The periodic box (any tilt).
    chunk : int
        Particles queried per pass.

    Returns
    -------
    tuple of numpy.ndarray
        ``i``, ``j`` (int64) and ``image`` ``(m, 3)`` int64, with ``i < j`` or ``i == j`` and ``image``
        lexicographically positive (module docstring), sorted by ``(i, j, image)``.
    """
    from scipy.spatial import cKDTree

    points, owner, image = _ghosts(box, x, cutoff)
    tree = cKDTree(points)
    out_i, out_g = [], []
    for lo in range(0, len(x), max(1, int(chunk))):
        found = cKDTree(x[lo:lo + chunk]).sparse_distance_matrix(tree, cutoff, output_type="ndarray")
        out_i.append(found["i"].astype(np.int64) + lo)
        out_g.append(found["j"].astype(np.int64))
    i = np.concatenate(out_i) if out_i else np.zeros(0, np.int64)
    g = np.concatenate(out_g) if out_g else np.zeros(0, np.int64)
    j, s = owner[g], image[g]
    positive = (s[:, 0] > 0) | ((s[:, 0] == 0) & ((s[:, 1] > 0) | ((s[:, 1] == 0) & (s[:, 2] > 0))))
    keep = (i < j) | ((i == j) & positive)
    i, j, s = i[keep], j[keep], s[keep]
    order = np.lexsort((s[:, 2], s[:, 1], s[:, 0], j, i))
    return i[order], j[order], s[order]
