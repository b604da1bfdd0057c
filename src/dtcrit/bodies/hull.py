"""Convex hulls, nearest neighbours and connected components for polyhedral bodies, on the libraries the
field relies on: Qhull (``scipy.spatial.ConvexHull``), ``scipy.spatial.cKDTree`` and
``scipy.sparse.csgraph``.

SciPy is imported on first use, so scenes without boxes or polyhedra never pay for it.  What this
module adds to Qhull is the face structure a DEM body needs:

* Qhull's triangular facets whose vertices lie within the tolerance of each other's planes are merged
  into one planar face (connected components of the facet-neighbour graph, ``csgraph``);
* each face's corners are the 2-D hull of its points in its plane, counter-clockwise seen from
  outside, so points on a face or on an edge are not corners;
* points within the tolerance of each other count once (the smallest index is the corner).

Tolerances are relative: coordinates are shifted to the mean and divided by the largest distance
from it, and ``rtol`` is a distance in those units.  Degenerate input (fewer than 4 points, or all
within ``rtol`` of a plane, a line or a point) raises :class:`HullError` on either route (the NumPy
faces of ``small_hull`` for a few points, Qhull for more: a hull no thicker than ``rtol`` along a facet
normal, or whose merged faces do not close, is refused); bodies thicker than that are accepted.
"""
from __future__ import annotations

import math
from typing import Any
from dataclasses import dataclass

import numpy as np

from dtcrit.numerics.distinct import distinct

__all__ = ["HullError", "Hull3D", "convex_hull_3d", "convex_hull_2d", "nearest_neighbours", "connected_components", "HULL_RTOL"]

HULL_RTOL = 1e-10
"""Default tolerance: points closer than this (relative to the size of the set) to a face plane lie
on it, and points closer to each other coincide."""


class HullError(ValueError):
    """The points span fewer dimensions than the hull needs (coincident, collinear or coplanar)."""


def connected_components(n: int, first, second) -> np.ndarray:
    """Component label of each of ``n`` nodes joined by the edges ``(first[k], second[k])``: the
    smallest node of its component (NumPy label propagation, ``small_hull.components``).

    Parameters
    ----------
    n : int
        Number of nodes.
    first, second : array_like
        End nodes of the edges.

    Returns
    -------
    numpy.ndarray
        The label of each node.
    """
    from dtcrit.bodies.small_hull import components

    return components(int(n), first, second)


def nearest_neighbours(queries, points) -> tuple[np.ndarray, np.ndarray]:
    """Distance to, and index of, the nearest of ``points`` for each row of ``queries`` (``cKDTree``).

    Parameters
    ----------
    queries : array_like
        Query points, (M, d).
    points : array_like
        Points searched, (N, d).

    Returns
    -------
    tuple of numpy.ndarray
        Distances and indices, each (M,).
    """
    from dtcrit.bodies.small_hull import BRUTE_PAIRS, nearest

    p = np.atleast_2d(np.asarray(points, dtype=float))
    if p.shape[0] == 0:
        raise ValueError("nearest_neighbours needs at least one point")
    q = np.atleast_2d(np.asarray(queries, dtype=float))
    if q.shape[0] * p.shape[0] <= BRUTE_PAIRS:  # direct distances: no SciPy import for small sets
        return nearest(q, p)
    from scipy.spatial import cKDTree

    dist, index = cKDTree(p).query(q)
    return np.asarray(dist, dtype=float), np.asarray(index, dtype=int)


def _unit_scaled(points, dim: int, name: str) -> tuple[np.ndarray, np.ndarray, float]:
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != dim:
        raise ValueError(f"{name} needs an (N, {dim}) array (got shape {p.shape})")
    if not np.all(np.isfinite(p)):
        raise ValueError(f"{name} needs finite coordinates")
    if p.shape[0] < dim + 1:
        raise HullError(f"a {dim}-D hull needs at least {dim + 1} points (got {p.shape[0]})")
    centre = p.mean(axis=0)
    scale = float(np.max(np.linalg.norm(p - centre, axis=1)))
    if not (math.isfinite(scale) and scale > 0.0):
        raise HullError("all points coincide")
    return (p - centre) / scale, centre, scale


def _qhull(q: np.ndarray, what: str):
    from scipy.spatial import ConvexHull, QhullError

    try:
        return ConvexHull(q)
    except QhullError:
        raise HullError(f"the points are {what} (Qhull found no full-dimensional hull)") from None


def _ring(xy: np.ndarray, index: np.ndarray, tol: float) -> np.ndarray:
    """Corners of the 2-D points ``xy`` counter-clockwise, dropping points within ``tol`` of an edge
    (Qhull, or the monotone chain of ``small_hull.ccw_order`` for a few points).
    """
    from dtcrit.bodies.small_hull import SMALL_POINTS, ccw_order

    corners = ccw_order(xy) if len(xy) <= SMALL_POINTS else _qhull(xy, "collinear").vertices
    ring = list(index[corners])  # counter-clockwise in 2-D
    pts = {int(i): xy[k] for k, i in zip(corners, index[corners])}
    changed = True
    while changed and len(ring) > 3:
        changed = False
        for k in range(len(ring)):
            a, b, c = pts[ring[k - 1]], pts[ring[k]], pts[ring[(k + 1) % len(ring)]]
            edge = c - a
            length = float(np.hypot(*edge))
            if length > 0 and abs(edge[0] * (b - a)[1] - edge[1] * (b - a)[0]) / length <= tol:
                del ring[k]
                changed = True
                break
    return np.array(ring, dtype=int)


def convex_hull_2d(points, rtol: float = HULL_RTOL) -> np.ndarray:
    """Indices of the corners of the convex hull of 2-D ``points``, counter-clockwise (Qhull).

    Parameters
    ----------
    points : array_like
        Points, (N, 2).
    rtol : float
        Tolerance relative to the points' extent.

    Returns
    -------
    numpy.ndarray
        Indices of the corners.

    Raises
    ------
    HullError
        When the points are within ``rtol`` (relative) of a line or coincide.
    """
    q, _, _ = _unit_scaled(points, 2, "convex_hull_2d")
    ring = _ring(q, np.arange(q.shape[0]), rtol)
    if len(ring) < 3:
        raise HullError("the points are collinear")
    area = 0.5 * abs(float(np.sum(q[ring, 0] * np.roll(q[ring, 1], -1) - np.roll(q[ring, 0], -1) * q[ring, 1])))
    if area <= rtol:
        raise HullError("the points are collinear")
    return ring


@dataclass(frozen=True)
class Hull3D:
    """Convex hull of a 3-D point set (indices refer to the input points).

    * ``faces``: one index array per planar face, its corners counter-clockwise seen from outside;
    * ``equations``: ``(F, 4)`` rows ``(n_x, n_y, n_z, offset)`` per face, ``n`` the outward unit
      normal, ``n . x + offset <= 0`` inside (the layout of ``scipy.spatial.ConvexHull.equations``);
    * ``simplices``: ``(T, 3)`` fan triangles of the faces, outward, and ``simplex_face`` the face of each;
    * ``vertices``: the corners, ascending;
    * ``volume``, ``area``;
    * ``tolerance``: the distance (input units) within which points were taken to be on a plane.

    Parameters
    ----------
    faces : tuple of numpy.ndarray
        Corner indices of each face, counter-clockwise from outside.
    equations : numpy.ndarray
        ``(F, 4)`` plane equations, outward normals.
    simplices : numpy.ndarray
        ``(T, 3)`` fan triangles.
    simplex_face : numpy.ndarray
        Face of each triangle.
    vertices : numpy.ndarray
        The corners, ascending.
    volume : float
        Enclosed volume.
    area : float
        Surface area.
    tolerance : float
        Distance within which points were taken to be on a plane.
    """

    faces: tuple
    equations: np.ndarray
    simplices: np.ndarray
    simplex_face: np.ndarray
    vertices: np.ndarray
    volume: float
    area: float
    tolerance: float

    @property
    def simplex_equations(self) -> np.ndarray:
        """Plane equation of each fan triangle (its face's)."""
        return self.equations[self.simplex_face]


def _distinct_points(q: np.ndarray, tol: float) -> np.ndarray:
    """Representative (smallest index) of each group of points within ``tol`` of each other."""
    from dtcrit.bodies.small_hull import SMALL_POINTS, close_pairs

    if q.shape[0] <= SMALL_POINTS:
        pairs = close_pairs(q, tol)
    else:
        from scipy.spatial import cKDTree

        pairs = cKDTree(q).query_pairs(tol, output_type="ndarray")
    return connected_components(q.shape[0], pairs[:, 0], pairs[:, 1]) if pairs.size else np.arange(q.shape[0])


def _merged_faces(q: np.ndarray, hull, tol: float) -> list[np.ndarray]:
    """Qhull facets grouped into planar faces: neighbours each of whose vertices lie within ``tol``
    of the other's plane are one face.
    """
    eq = hull.equations
    simp = hull.simplices
    f = np.repeat(np.arange(simp.shape[0]), 3)
    g = hull.neighbors.ravel()
    dist_fg = np.abs(np.einsum("kj,kij->ki", eq[f, :3], q[simp[g]]) + eq[f, 3:4]).max(axis=1)
    dist_gf = np.abs(np.einsum("kj,kij->ki", eq[g, :3], q[simp[f]]) + eq[g, 3:4]).max(axis=1)
    same = (dist_fg <= tol) & (dist_gf <= tol)
    label = connected_components(simp.shape[0], f[same], g[same])
    return [np.flatnonzero(label == first) for first in np.flatnonzero(label == np.arange(simp.shape[0]))]


def _face_planes(q: np.ndarray, tol: float) -> list:
    """``(outward unit normal, indices of the points on it)`` per planar face: by
    ``small_hull.planar_faces`` for a few points, else Qhull's facets merged (``_merged_faces``).
    """
    from dtcrit.bodies.small_hull import SMALL_POINTS, planar_faces

    if q.shape[0] <= SMALL_POINTS:
        found = planar_faces(q, tol)
        if not found:
            raise HullError("the points are coplanar or degenerate (no full-dimensional hull)")
        return found
    hull = _qhull(q, "coplanar or degenerate")
    if _flat(q[hull.vertices], hull.equations, tol):
        raise HullError("the points are coplanar or degenerate (no full-dimensional hull)")
    out = []
    for group in _merged_faces(q, hull, tol):
        normal = hull.equations[group, :3].sum(axis=0)
        out.append((normal / np.linalg.norm(normal), distinct(hull.simplices[group])))
    if len(out) < 4:  # a closed polyhedron has at least four faces
        raise HullError(f"the points are coplanar or degenerate (the merged faces do not close: {len(out)} found)")
    return out


def _flat(corners: np.ndarray, equations: np.ndarray, tol: float) -> bool:
    """Whether Qhull's hull is thinner than ``tol`` along one of its facet normals (every corner within
    ``tol`` of that facet's plane): the points are coplanar within the tolerance, as
    ``small_hull.planar_faces`` finds them (a plane through three points with every point within ``tol``).
    Facets are taken in chunks of at most ``2**22`` corner-facet pairs.
    """
    step = max(1, (1 << 22) // corners.shape[0])
    for a in range(0, equations.shape[0], step):
        eq = equations[a:a + step]
        depth = -(corners @ eq[:, :3].T + eq[:, 3])  # (corners, facets), >= 0 inside
        if np.min(np.max(depth, axis=0)) <= tol:
            return True
    return False


def convex_hull_3d(points, rtol: float = HULL_RTOL) -> Hull3D:
    """Convex hull of 3-D ``points`` (``(N, 3)``) by Qhull, with coplanar facets merged into planar faces.

    Coordinates are shifted to the mean and divided by the largest distance from it; ``rtol`` is a
    distance in those units.  Points within ``rtol`` of each other count once (the smallest index is
    the corner), points within ``rtol`` of a face plane belong to that face, and only the corners of
    each face polygon are hull vertices.  Raises :class:`HullError` for fewer than 4 points or points
    coplanar, collinear or coincident within ``rtol`` (for any number of points).

    Parameters
    ----------
    points : array_like
        Points, (N, 3).
    rtol : float
        Tolerance in the scaled units.

    Returns
    -------
    Hull3D
        The hull.
    """
    q_all, centre, scale = _unit_scaled(points, 3, "convex_hull_3d")
    tol = float(rtol)
    if not (math.isfinite(tol) and tol > 0.0):
        raise ValueError(f"rtol must be positive and finite (got {rtol!r})")
    rep = _distinct_points(q_all, tol)
    keep = np.flatnonzero(rep == np.arange(q_all.shape[0]))
    if keep.size < 4:
        raise HullError(f"a 3-D hull needs at least 4 distinct points (got {keep.size})")
    q = q_all[keep]
    faces: list = []
    normals: Any = []  # rows appended per face, then one array
    offsets: list = []
    for normal, on in _face_planes(q, tol):
        u = np.cross(normal, np.eye(3)[int(np.argmin(np.abs(normal)))])
        u /= np.linalg.norm(u)
        v = np.cross(normal, u)  # (u, v, normal) right-handed: counter-clockwise seen from outside
        ring = _ring(np.column_stack([q[on] @ u, q[on] @ v]), on, tol)
        faces.append(ring)
        normals.append(normal)
        offsets.append(-float(np.mean(q[ring] @ normal)))
    lens = np.array([len(face) for face in faces])
    flat = np.concatenate(faces)
    tri_face = np.repeat(np.arange(len(faces)), lens - 2)
    first = (np.cumsum(lens) - lens)[tri_face]
    i = np.arange(tri_face.size) - (np.cumsum(lens - 2) - (lens - 2))[tri_face]
    tri = np.column_stack([flat[first], flat[first + i + 1], flat[first + i + 2]])
    corners = q[tri]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals = np.array(normals)
    equations = np.column_stack([normals, scale * np.array(offsets) - normals @ centre])
    return Hull3D(
        faces=tuple(keep[face] for face in faces),
        equations=equations,
        simplices=keep[tri],
        simplex_face=tri_face,
        vertices=np.sort(keep[distinct(flat)]),
        volume=float(np.sum(np.einsum("ij,ij->i", cross, corners[:, 0]))) / 6.0 * scale**3,
        area=0.5 * float(np.sum(np.linalg.norm(cross, axis=1))) * scale**2,
        tolerance=tol * scale,
    )
