"""Hull pieces for small point sets in NumPy alone, so that a polyhedron of a few dozen corners does
not pay for importing ``scipy.spatial`` (Qhull, about 0.5 s of a ``dtcrit step`` run) or
``scipy.sparse``; ``dtcrit.bodies.hull`` takes this route up to ``SMALL_POINTS`` points and Qhull
above.

* :func:`planar_faces`: the faces of the hull of ``N`` points as the planes through three of them
  with every point on one side (within ``tol``), grouped by the points on them: O(N^4) work, which
  at ``N = SMALL_POINTS`` is a few million multiply-adds;
* :func:`ccw_order`: the counter-clockwise corners of 2-D points (Andrew's monotone chain);
* :func:`components`: connected components (label propagation with pointer jumping), each labelled
  by its smallest node, as ``scipy.sparse.csgraph.connected_components`` then the smallest member;
* :func:`close_pairs` and :func:`nearest`: all pairs within a distance and nearest neighbours by
  direct distances (for sizes where that is cheaper than building a k-d tree).
"""
from __future__ import annotations

import itertools

import numpy as np

from dtcrit.numerics.distinct import distinct_rows

__all__ = ["BRUTE_PAIRS", "SMALL_POINTS", "ccw_order", "close_pairs", "components", "nearest", "planar_faces"]

SMALL_POINTS = 40
"""Largest point count whose 3-D hull is found here (above it: Qhull)."""
BRUTE_PAIRS = 1 << 22
"""Largest ``queries x points`` product for direct nearest-neighbour distances (above it: a k-d tree)."""


def components(n: int, first, second) -> np.ndarray:
    """The smallest node of each node's connected component, edges ``(first[k], second[k])``.

    Parameters
    ----------
    n : int
        Number of nodes.
    first, second : array_like
        End nodes of the edges.

    Returns
    -------
    numpy.ndarray
        The label of each node (the smallest node of its component).
    """
    a = np.asarray(first, dtype=int).ravel()
    b = np.asarray(second, dtype=int).ravel()
    label = np.arange(n)
    while True:
        low = np.minimum(label[a], label[b])
        new = label.copy()
        np.minimum.at(new, a, low)
        np.minimum.at(new, b, low)
        new = new[new]  # a label is a node of the same component with a smaller index: jump to its label
        if np.array_equal(new, label):
            return label
        label = new


def close_pairs(q: np.ndarray, tol: float) -> np.ndarray:
    """Index pairs ``(i, j)``, ``i < j``, of rows of ``q`` at most ``tol`` apart (``(M, 2)``).

    Parameters
    ----------
    q : numpy.ndarray
        Points, (N, d).
    tol : float
        Distance.

    Returns
    -------
    numpy.ndarray
        The pairs, (M, 2).
    """
    d = np.sqrt(((q[:, None, :] - q[None, :, :]) ** 2).sum(axis=-1))
    i, j = np.nonzero(np.triu(d <= tol, 1))
    return np.column_stack([i, j])


def nearest(queries: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance to, and index of, the nearest of ``points`` for each query (direct distances).

    Parameters
    ----------
    queries : numpy.ndarray
        Query points, (M, d).
    points : numpy.ndarray
        Points searched, (N, d).

    Returns
    -------
    tuple of numpy.ndarray
        Distances and indices, each (M,).
    """
    d2 = ((queries[:, None, :] - points[None, :, :]) ** 2).sum(axis=-1)
    index = np.argmin(d2, axis=1)
    return np.sqrt(d2[np.arange(len(queries)), index]), index


def ccw_order(xy: np.ndarray) -> np.ndarray:
    """Indices of the corners of the 2-D hull of ``xy``, counter-clockwise (monotone chain; points on
    an edge dropped).

    Parameters
    ----------
    xy : numpy.ndarray
        Points, (N, 2).

    Returns
    -------
    numpy.ndarray
        Corner indices, counter-clockwise, starting at the lowest-leftmost point.
    """
    order = np.lexsort((xy[:, 1], xy[:, 0]))

    def chain(indices) -> list:
        out: list = []
        for k in indices:
            while len(out) >= 2:
                o, a, b = xy[out[-2]], xy[out[-1]], xy[k]
                if (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]) > 0:
                    break
                out.pop()
            out.append(int(k))
        return out

    lower, upper = chain(order), chain(order[::-1])
    return np.array(lower[:-1] + upper[:-1], dtype=int)


def planar_faces(q: np.ndarray, tol: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """The planar faces of the hull of ``q`` (distinct points, scaled to unit size): ``(normal, on)``
    per face, ``normal`` outward and ``on`` the indices of the points within ``tol`` of its plane.

    A face is a plane through three points with every point within ``tol`` on its inner side and at
    least three points on it that do not lie within ``tol`` of one line.  An empty list means the
    points are coplanar, collinear or coincident (within ``tol``).

    Parameters
    ----------
    q : numpy.ndarray
        Points, (N, 3), ``N <= SMALL_POINTS`` advised.
    tol : float
        Distance in the units of ``q``.

    Returns
    -------
    list of tuple
        ``(normal, on)`` per face, ordered by their point sets.
    """
    i, j, k = np.array(list(itertools.combinations(range(len(q)), 3))).T
    n = np.cross(q[j] - q[i], q[k] - q[i])
    size = np.linalg.norm(n, axis=1)
    good = size > tol * np.maximum(np.linalg.norm(q[j] - q[i], axis=1), np.linalg.norm(q[k] - q[i], axis=1))
    n, i = n[good] / size[good, None], i[good]
    dist = q @ n.T - np.einsum("ij,ij->i", q[i], n)[None, :]  # (points, planes)
    below, above = (dist <= tol).all(axis=0), (dist >= -tol).all(axis=0)
    if np.any(below & above):  # every point on one plane
        return []
    n = np.where(above[:, None], -n, n)[below | above]
    on = (np.abs(dist[:, below | above]) <= tol).T
    faces = []
    for row in distinct_rows(on)[::-1]:
        pick = np.flatnonzero((on == row).all(axis=1))
        normal = n[pick].sum(axis=0)
        normal /= np.linalg.norm(normal)
        members = np.flatnonzero(row)
        faces.append((normal, members))
    return faces
