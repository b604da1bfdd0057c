"""Convex hulls in 2-D and 3-D, nearest neighbours and connected components, with NumPy only.

:mod:`dtcrit.bodies` needs these for boxes and polyhedra.  ``scipy.spatial`` (Qhull, cKDTree) and
``scipy.sparse.csgraph`` would do, but importing them costs about 0.4 s, more than everything else
``dtcrit step`` does for a polyhedron scene.  The point sets here are small (corners of a particle),
so plain algorithms are enough:

* :func:`convex_hull_3d`: gift wrapping over faces (Chand & Kapur 1970; Preparata & Shamos,
  *Computational Geometry*, 1985, Sec. 3.4.1).  From one face, each edge not yet shared by two faces
  is the axis about which the face's plane is turned until it meets a point; that plane, with every
  point within the tolerance of it, is the neighbouring face.  Coplanar points therefore make one
  planar face (a polygon, not triangles), points on faces or edges are not corners, and near
  duplicates count once.  The edges of a round are turned about together, O(N) array work per
  face: a cube takes ~2 ms, 300 points on a sphere (600 faces) ~30 ms.  The faces are checked to
  close into a convex polytope; near-degenerate input that defeats rounding at the tolerance is
  retried with a larger one (bodies thinner than about 1e-6 of their size may still be refused).
* :func:`convex_hull_2d`: Andrew's monotone chain (Andrew 1979), with the same tolerance.
* :func:`nearest_neighbours`: brute force in chunks.
* :func:`connected_components`: union-find with path halving (Tarjan 1975).

Tolerances are relative: coordinates are shifted to the mean and divided by the largest distance
from it, and ``rtol`` is a distance in those units.  Degenerate input (fewer than 4 points, or all
within ``rtol`` of a plane, a line or a point) raises :class:`HullError`.  Tested against
``scipy.spatial`` and ``scipy.sparse.csgraph`` in ``tests/test_hull.py``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "HullError",
    "Hull3D",
    "convex_hull_3d",
    "convex_hull_2d",
    "nearest_neighbours",
    "connected_components",
    "HULL_RTOL",
]

HULL_RTOL = 1e-10
"""Default tolerance: points closer than this (relative to the size of the set) to a face plane lie
on it, and points closer to each other coincide."""


class HullError(ValueError):
    """The points span fewer dimensions than the hull needs (coincident, collinear or coplanar)."""


class _Inconsistent(Exception):
    """The faces found do not close into a convex polytope at this tolerance (near-degenerate input)."""


# ============================================================================================
# Connected components and nearest neighbours
# ============================================================================================
def connected_components(n: int, first, second) -> np.ndarray:
    """Component label of each of ``n`` nodes joined by the edges ``(first[k], second[k])``.

    Union-find with path halving; each label is the smallest node of its component.
    """
    parent = list(range(n))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, j in zip(np.asarray(first, dtype=int).tolist(), np.asarray(second, dtype=int).tolist()):
        ri, rj = root(i), root(j)
        if ri != rj:
            parent[max(ri, rj)] = min(ri, rj)
    return np.array([root(i) for i in range(n)], dtype=int)


def nearest_neighbours(queries, points, *, chunk: int = 1 << 20) -> tuple[np.ndarray, np.ndarray]:
    """Distance to, and index of, the nearest of ``points`` for each row of ``queries`` (brute force).

    Differences are formed explicitly (no ``|x|^2 + |y|^2 - 2 x.y`` cancellation); at most about
    ``chunk`` differences are held at a time.  Ties go to the smallest index.
    """
    q = np.atleast_2d(np.asarray(queries, dtype=float))
    p = np.atleast_2d(np.asarray(points, dtype=float))
    if p.shape[0] == 0:
        raise ValueError("nearest_neighbours needs at least one point")
    dist = np.empty(q.shape[0])
    index = np.empty(q.shape[0], dtype=int)
    step = max(1, chunk // p.shape[0])
    for start in range(0, q.shape[0], step):
        block = q[start : start + step]
        d2 = np.einsum("ijk,ijk->ij", block[:, None, :] - p[None, :, :], block[:, None, :] - p[None, :, :])
        k = np.argmin(d2, axis=1)
        index[start : start + step] = k
        dist[start : start + step] = np.sqrt(d2[np.arange(block.shape[0]), k])
    return dist, index


def _coincident(q: np.ndarray, tol: float) -> np.ndarray:
    """Label per point: the smallest index of the cluster of points chained within ``tol``.

    Pairs within ``tol`` are also within ``tol`` along any direction, so they are found among
    neighbours in the order of a projection (a sweep; O(N log N) for spread-out points).
    """
    direction = np.array([1.0, math.sqrt(2.0), math.pi])  # no lattice plane is normal to it
    proj = q @ (direction / np.linalg.norm(direction))
    order = np.argsort(proj, kind="stable")
    sp = proj[order]
    firsts, seconds = [], []
    for k in range(1, q.shape[0]):
        close = sp[k:] - sp[:-k] <= tol
        if not close.any():
            break
        i, j = order[:-k][close], order[k:][close]
        same = np.linalg.norm(q[i] - q[j], axis=1) <= tol
        firsts.append(i[same])
        seconds.append(j[same])
    if not firsts:
        return np.arange(q.shape[0])
    return connected_components(q.shape[0], np.concatenate(firsts), np.concatenate(seconds))


# ============================================================================================
# 2-D hull
# ============================================================================================
def _monotone_chain(xy: np.ndarray, tol: float) -> list[int]:
    """Corners of the 2-D hull of ``xy`` in counter-clockwise order (indices into ``xy``).

    Andrew's monotone chain; a point within ``tol`` of the line through its neighbours, or within
    ``tol`` of the previous corner, is not a corner.  A final cyclic pass removes the same from the
    ends of the chains (the lexicographic extremes are kept by the chain itself).
    """
    order = np.lexsort((xy[:, 1], xy[:, 0])).tolist()
    pts = xy.tolist()

    def turn_left(a: int, b: int, c: int) -> bool:
        ax, ay = pts[a]
        bx, by = pts[b][0] - ax, pts[b][1] - ay
        cx, cy = pts[c][0] - ax, pts[c][1] - ay
        if math.hypot(bx, by) <= tol:
            return False
        return bx * cy - by * cx > tol * math.hypot(cx, cy)

    def chain(seq: list[int]) -> list[int]:
        out: list[int] = []
        for k in seq:
            while len(out) >= 2 and not turn_left(out[-2], out[-1], k):
                out.pop()
            out.append(k)
        return out

    ring = chain(order)[:-1] + chain(order[::-1])[:-1]
    changed = True
    while changed and len(ring) >= 3:
        changed = False
        for i in range(len(ring)):
            if not turn_left(ring[i - 1], ring[i], ring[(i + 1) % len(ring)]):
                del ring[i]
                changed = True
                break
    return ring


def convex_hull_2d(points, rtol: float = HULL_RTOL) -> np.ndarray:
    """Indices of the corners of the convex hull of 2-D ``points``, counter-clockwise.

    ``rtol`` is relative to the largest distance of a point from the mean.  Raises
    :class:`HullError` when the points are within ``rtol`` of a line (or coincide).
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"convex_hull_2d needs an (N, 2) array (got shape {p.shape})")
    if not np.all(np.isfinite(p)):
        raise ValueError("convex_hull_2d needs finite coordinates")
    if p.shape[0] < 3:
        raise HullError(f"a 2-D hull needs at least 3 points (got {p.shape[0]})")
    rel = p - p.mean(axis=0)
    scale = float(np.max(np.linalg.norm(rel, axis=1)))
    if not scale > 0.0:
        raise HullError("all points coincide")
    ring = _monotone_chain(rel / scale, rtol)
    if len(ring) < 3:
        raise HullError("the points are collinear")
    return np.array(ring, dtype=int)


# ============================================================================================
# 3-D hull
# ============================================================================================
@dataclass(frozen=True)
class Hull3D:
    """Convex hull of a 3-D point set (indices refer to the input points).

    * ``faces``: one index array per planar face, its corners counter-clockwise seen from outside;
    * ``equations``: ``(F, 4)`` rows ``(n_x, n_y, n_z, offset)`` per face, ``n`` the outward unit
      normal, ``n . x + offset <= 0`` inside (the layout of ``scipy.spatial.ConvexHull.equations``);
    * ``simplices``: ``(T, 3)`` fan triangles of the faces, outward (counter-clockwise), and
      ``simplex_face`` the face of each;
    * ``vertices``: the corners, ascending;
    * ``volume``, ``area``;
    * ``tolerance``: the distance (input units) within which points were taken to be on a plane.
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


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product of 3-vectors (rows of ``(..., 3)`` arrays); ``np.cross`` is slow on small input."""
    if a.ndim == 1 and b.ndim == 1:
        (ax, ay, az), (bx, by, bz) = a.tolist(), b.tolist()
        return np.array([ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx])
    ax, ay, az = a[..., 0], a[..., 1], a[..., 2]
    bx, by, bz = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = ay * bz - az * by
    out[..., 1] = az * bx - ax * bz
    out[..., 2] = ax * by - ay * bx
    return out


def _unit(v: np.ndarray) -> np.ndarray:
    return v / math.sqrt(float(v @ v))


def _unit_rows(v: np.ndarray) -> np.ndarray:
    return v / np.sqrt(np.sum(v * v, axis=1, keepdims=True))


def _plane_axes(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit u, v with u x v = normal."""
    helper = np.zeros(3)
    helper[int(np.argmin(np.abs(normal)))] = 1.0
    u = _unit(_cross(normal, helper))
    return u, _cross(normal, u)


def _turn(q: np.ndarray, a: np.ndarray, e: np.ndarray, n: np.ndarray, tol: float):
    """Turn supporting planes about lines until each meets a point (gift-wrapping step, batched).

    Row j: the plane with outward unit normal ``n[j]`` supports the points ``q`` and contains the
    line ``a[j] + t e[j]`` (``e[j]`` unit).  With u = e x n the outer direction, a point has
    coordinates (x, y) = ((p - a).u, (p - a).n), y <= 0; the plane turned by alpha has normal
    cos(alpha) n + sin(alpha) u, and the first point it meets has the least alpha = atan2(-y, x)
    in [0, pi].  Points within 4 tol of the line lie on it and are skipped.  Among the points within
    tol of that plane, the one farthest from the line fixes it (best conditioned) unless that would
    leave a point more than tol above.

    Returns ``(on, normal)``: ``(N, k)`` mask of the points within tol of each new plane and the
    ``(k, 3)`` outward unit normals.  A line with every point on it (degenerate set) gets no point.
    """
    n = n - np.sum(n * e, axis=1, keepdims=True) * e
    n /= np.sqrt(np.sum(n * n, axis=1, keepdims=True))
    u = _cross(e, n)
    x = q @ u.T - np.sum(a * u, axis=1)
    depth = np.maximum(np.sum(a * n, axis=1) - q @ n.T, 0.0)  # -y >= 0
    r = np.sqrt(x * x + depth * depth)
    cand = r > 4.0 * tol
    safe_r = np.where(cand, r, 1.0)
    cols = np.arange(a.shape[0])

    def plane(k):
        nrm = (depth[k, cols][:, None] * u + x[k, cols][:, None] * n) / safe_r[k, cols][:, None]
        return nrm, q @ nrm.T - np.sum(a * nrm, axis=1)

    # least alpha = largest cos(alpha) = x / r; cos cannot tell angles within ~1e-8 of 0 apart, so
    # where a point is left more than tol above, take the point most above in angle instead:
    # sin(alpha_first - alpha_p) = s_p / r_p
    first = np.argmax(np.where(cand, x / safe_r, -2.0), axis=0)
    normal, s = plane(first)
    above = np.max(s, axis=0) > tol
    if above.any():
        first = np.where(above, np.argmax(np.where(cand, s / safe_r, -2.0), axis=0), first)
        normal, s = plane(first)
    far = np.argmax(np.where(cand & (s >= -tol), r, -1.0), axis=0)
    change = far != first
    if change.any():
        alt, s_alt = plane(far)
        use = change & (np.max(s_alt, axis=0) <= tol)
        normal[use], s[:, use] = alt[use], s_alt[:, use]
    on = np.abs(s) <= tol
    on &= cand.any(axis=0)
    return on, normal


def _check_dimension(q: np.ndarray, tol: float) -> np.ndarray:
    """Indices of four points spanning a tetrahedron thicker than ``tol``; HullError otherwise."""
    i0 = int(np.argmax(np.einsum("ij,ij->i", q, q)))
    d1 = np.linalg.norm(q - q[i0], axis=1)
    i1 = int(np.argmax(d1))
    if d1[i1] <= tol:
        raise HullError("all points coincide")
    e = (q[i1] - q[i0]) / d1[i1]
    w = q - q[i0]
    d2 = np.linalg.norm(w - np.outer(w @ e, e), axis=1)
    i2 = int(np.argmax(d2))
    if d2[i2] <= tol:
        raise HullError("the points are collinear")
    n = _unit(_cross(e, w[i2]))
    d3 = np.abs(w @ n)
    i3 = int(np.argmax(d3))
    if d3[i3] <= tol:
        raise HullError("the points are coplanar")
    return np.array([i0, i1, i2, i3])


def _outside_tetrahedron(q: np.ndarray, corners: np.ndarray, tol: float) -> np.ndarray:
    """Mask of the points not deeper than ``tol`` inside the tetrahedron of ``corners``.

    A deeper point is deeper than ``tol`` inside the hull, so it can be neither a corner nor on a
    face; dropping it only saves work.
    """
    t = q[corners]
    centre = t.mean(axis=0)
    keep = np.zeros(q.shape[0], dtype=bool)
    depth = np.full(q.shape[0], np.inf)
    for skip in range(4):
        a, b, c = t[[k for k in range(4) if k != skip]]
        n = _unit(_cross(b - a, c - a))
        if (centre - a) @ n > 0:
            n = -n
        depth = np.minimum(depth, -((q - a) @ n))
    keep[depth <= tol] = True
    keep[corners] = True
    return keep




def _newell(q: np.ndarray, polys: list[np.ndarray]) -> np.ndarray:
    """Unit normals of planar polygons, right-handed with their vertex order (Newell's method)."""
    flat = np.concatenate(polys)
    lens = np.array([len(p) for p in polys])
    starts = np.cumsum(lens) - lens
    nxt = np.arange(1, flat.size + 1)
    nxt[starts + lens - 1] = starts
    return _unit_rows(np.add.reduceat(_cross(q[flat], q[flat[nxt]]), starts, axis=0))


def _polygons(q: np.ndarray, on: np.ndarray, normal: np.ndarray, tol: float) -> list[np.ndarray | None]:
    """Per column of ``on``: corners of the points on that plane, counter-clockwise about ``normal``.

    Three points (the usual case) are ordered by the sign of their triple product, in one batch;
    more go through :func:`_monotone_chain`.  None where the points are collinear.
    """
    cols, rows = np.nonzero(on.T)
    counts = np.bincount(cols, minlength=on.shape[1])
    starts = np.cumsum(counts) - counts
    out: list[np.ndarray | None] = [None] * on.shape[1]
    three = np.flatnonzero(counts == 3)
    if three.size:
        tri = rows[starts[three][:, None] + np.arange(3)]
        p0, p1, p2 = q[tri[:, 0]], q[tri[:, 1]], q[tri[:, 2]]
        c = _cross(p1 - p0, p2 - p0)
        size = np.sqrt(np.sum(c * c, axis=1))
        base = np.maximum(np.sqrt(np.sum((p2 - p1) ** 2, axis=1)), tol)
        flip = np.sum(c * normal[three], axis=1) < 0
        tri[flip] = tri[flip][:, [0, 2, 1]]
        for j, t, ok in zip(three.tolist(), tri, (size > tol * base).tolist()):
            out[j] = t if ok else None
    for j in np.flatnonzero(counts > 3).tolist():
        idx = rows[starts[j] : starts[j] + counts[j]]
        u, v = _plane_axes(normal[j])
        ring = _monotone_chain(q[idx] @ np.array([u, v]).T, tol)
        out[j] = idx[ring] if len(ring) >= 3 else None
    return out


def _first_face(q: np.ndarray, top: int, tol: float) -> np.ndarray:
    """A face through point ``top`` (the farthest from the mean, so a corner).

    The plane normal to ``top`` supports the set; turning it about a line through ``top`` meets a
    second point; if that plane holds only collinear points, turning it about their line meets a
    third, off the line.
    """
    a = q[top]
    n0 = _unit(a)
    e, _ = _plane_axes(n0)
    on, n1 = _turn(q, a[None], e[None], n0[None], tol)
    poly = _polygons(q, on, n1, tol)[0]
    if poly is not None:
        return poly
    idx = np.flatnonzero(on[:, 0])
    b = idx[int(np.argmax(np.linalg.norm(q[idx] - a, axis=1)))]
    on, n2 = _turn(q, a[None], _unit(q[b] - a)[None], n1, tol)
    poly = _polygons(q, on, n2, tol)[0]
    if poly is None:  # pragma: no cover - excluded by the dimension checks
        raise HullError("the points are coplanar")
    return poly


def _within(q: np.ndarray, inner: np.ndarray, outer: np.ndarray, tol: float) -> bool:
    """Whether the corners ``inner`` all lie within ``tol`` of the plane of the polygon ``outer``."""
    pts = q[outer]
    nrm = _unit(np.sum(_cross(pts, np.concatenate([pts[1:], pts[:1]])), axis=0))  # Newell
    return bool(np.max(np.abs(q[inner] @ nrm - np.mean(pts @ nrm))) <= tol)


def _wrap_faces(q: np.ndarray, top: int, tol: float) -> tuple[list[np.ndarray], np.ndarray]:
    """Face polygons of the hull of ``q`` (unit-scaled) and their unit normals, by gift wrapping.

    Works in rounds from the face at ``top``: every edge of the faces found so far that has no face
    on its other side is turned about at once (:func:`_turn`); each new plane, with the points on
    it, gives a face, identified by its corners (two edges of one new face find it twice).  A new
    face that runs over an earlier one (a shared edge in the same direction) replaces it when the
    earlier face's corners all lie within tol of its plane (faces within the tolerance of one plane
    are one face); otherwise the hull is inconsistent at this tolerance.
    """
    polys: list[np.ndarray | None] = []  # None: replaced by a larger coplanar face
    normals = np.empty((0, 3))
    seen: set[tuple[int, ...]] = set()
    owner: dict[tuple[int, int], int] = {}  # directed edge (counter-clockwise) -> face; -1: turned about
    frontier: list[tuple[int, int, int]] = []
    limit = 4 * q.shape[0] + 16  # Euler: at most 2N - 4 faces at once; replacements are rare

    def add(candidates: list[np.ndarray | None]) -> None:
        nonlocal normals
        start = len(polys)
        for poly in candidates:
            if poly is None:
                continue
            key = tuple(sorted(poly.tolist()))
            if key in seen:
                continue
            seen.add(key)
            ring = poly.tolist()
            edges = [(ring[i], ring[i + 1 - len(ring)]) for i in range(len(ring))]
            clash = {owner[e] for e in edges if owner.get(e, -1) >= 0}
            if clash:
                if not all(_within(q, polys[g], poly, tol) for g in clash):
                    raise _Inconsistent
                for g in clash:
                    old = polys[g].tolist()
                    for e in zip(old, old[1:] + old[:1]):
                        if owner.get(e) == g:
                            del owner[e]
                    polys[g] = None
            if len(polys) >= limit:
                raise _Inconsistent
            f = len(polys)
            polys.append(poly)
            for e in edges:
                owner[e] = f
                frontier.append((e[0], e[1], f))
        if len(polys) > start:
            block = np.zeros((len(polys) - start, 3))  # replaced faces keep a zero normal (unused)
            alive = [f for f in range(start, len(polys)) if polys[f] is not None]
            if alive:
                block[np.array(alive) - start] = _newell(q, [polys[f] for f in alive])
            normals = np.concatenate([normals, block])

    add([_first_face(q, top, tol)])
    chunk = max(1, (1 << 18) // q.shape[0])  # edges per batch: arrays of at most ~2e5 entries
    while frontier:
        todo = [(a, b, f) for a, b, f in frontier if owner.get((a, b)) == f and (b, a) not in owner]
        frontier.clear()
        for start in range(0, len(todo), chunk):
            part = np.array(todo[start : start + chunk])
            ia, ib = part[:, 0], part[:, 1]
            on, nrm = _turn(q, q[ia], _unit_rows(q[ib] - q[ia]), normals[part[:, 2]], tol)
            add(_polygons(q, on, nrm, tol))
            for e in zip(ib.tolist(), ia.tolist()):
                owner.setdefault(e, -1)  # turned about: never again, even if tolerance hid a face
    live = [f for f, poly in enumerate(polys) if poly is not None]
    return [polys[f] for f in live], normals[live]


def _offsets_checked(q: np.ndarray, polys: list[np.ndarray], normals: np.ndarray, tol: float) -> np.ndarray:
    """Plane offsets of the faces, after checking that they make a closed convex polytope.

    Checked: every edge in two faces, once in each direction; V - E + F = 2; every corner within
    4 tol of its face plane and every point at most 4 tol above every face plane.  Otherwise
    :class:`_Inconsistent` (near-degenerate input: slivers thinner than rounding allows at ``tol``).
    """
    lens = np.array([len(p) for p in polys])
    owner = np.repeat(np.arange(len(polys)), lens)
    flat = np.concatenate(polys)
    succ = np.arange(1, flat.size + 1)
    succ[np.cumsum(lens) - 1] = np.cumsum(lens) - lens
    edges = set(zip(flat.tolist(), flat[succ].tolist()))
    if len(edges) != flat.size or any((b, a) not in edges for a, b in edges):
        raise _Inconsistent
    if np.count_nonzero(np.bincount(flat)) - flat.size // 2 + len(polys) != 2:
        raise _Inconsistent
    height = np.sum(q[flat] * normals[owner], axis=1)
    offsets = -np.bincount(owner, weights=height) / lens
    if np.max(np.abs(height + offsets[owner])) > 4.0 * tol or np.max(q @ normals.T + offsets) > 4.0 * tol:
        raise _Inconsistent
    return offsets


def _unit_hull(q_all: np.ndarray, tol: float):
    """Hull of unit-scaled points at one tolerance: (input index per row of q, q, faces, normals, offsets)."""
    label = _coincident(q_all, tol)
    reps = np.flatnonzero(label == np.arange(q_all.shape[0]))
    q = q_all[reps]
    tetra = _check_dimension(q, tol)
    keep = np.flatnonzero(_outside_tetrahedron(q, tetra, tol))
    q = q[keep]
    top = int(np.flatnonzero(keep == tetra[0])[0])
    polys, normals = _wrap_faces(q, top, tol)
    return reps[keep], q, polys, normals, _offsets_checked(q, polys, normals, tol)


RETRY_FACTORS = (1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0)
"""Tolerances tried, as multiples of ``rtol``: near-degenerate input (slivers thinner than rounding
allows at ``rtol``) is retried with larger ones before :class:`HullError`."""


def convex_hull_3d(points, rtol: float = HULL_RTOL) -> Hull3D:
    """Convex hull of 3-D ``points`` (``(N, 3)``) by gift wrapping over planar faces.

    Coordinates are shifted to the mean and divided by the largest distance from it; ``rtol`` is a
    distance in those units.  Points within ``rtol`` of each other count once (the smallest index
    is the corner), points within ``rtol`` of a face plane belong to that face, and only the corners
    of each face polygon are hull vertices.  The faces are checked to close into a convex polytope;
    if rounding defeats that at ``rtol`` (points a few ``rtol`` off a line or plane through others),
    the hull is retried with tolerances up to 1000 times larger (``RETRY_FACTORS``;
    ``Hull3D.tolerance`` says which was used).  Bodies thinner than about 1e-6 of their size may
    be refused that way (or as coplanar).  Raises :class:`HullError` for fewer than 4 points, points within
    ``rtol`` of a plane, line or point, or when no tolerance gives a consistent hull.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"convex_hull_3d needs an (N, 3) array (got shape {p.shape})")
    if not np.all(np.isfinite(p)):
        raise ValueError("convex_hull_3d needs finite coordinates")
    if p.shape[0] < 4:
        raise HullError(f"a 3-D hull needs at least 4 points (got {p.shape[0]})")
    tol = float(rtol)
    if not (math.isfinite(tol) and tol > 0.0):
        raise ValueError(f"rtol must be positive and finite (got {rtol!r})")
    centre = p.mean(axis=0)
    rel = p - centre
    scale = float(np.max(np.linalg.norm(rel, axis=1)))
    if not (math.isfinite(scale) and scale > 0.0):
        raise HullError("all points coincide")
    q_all = rel / scale
    for factor in RETRY_FACTORS:
        try:
            index, q, polys, normals, offsets = _unit_hull(q_all, tol * factor)
            break
        except _Inconsistent:
            continue
    else:
        raise HullError(f"no consistent hull with tolerances up to {tol * factor:g} (nearly degenerate points)")
    tol *= factor
    lens = np.array([len(p) for p in polys])
    flat = np.concatenate(polys)
    # fan triangles (poly[0], poly[i], poly[i + 1]) of each face
    tri_face = np.repeat(np.arange(len(polys)), lens - 2)
    first = (np.cumsum(lens) - lens)[tri_face]
    i = np.arange(tri_face.size) - (np.cumsum(lens - 2) - (lens - 2))[tri_face]
    tri = np.column_stack([flat[first], flat[first + i + 1], flat[first + i + 2]])
    corners = q[tri]
    cross = _cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    volume = float(np.sum(np.einsum("ij,ij->i", cross, corners[:, 0]))) / 6.0
    area = 0.5 * float(np.sum(np.linalg.norm(cross, axis=1)))
    equations = np.column_stack([normals, scale * offsets - normals @ centre])
    return Hull3D(
        faces=tuple(index[poly] for poly in polys),
        equations=equations,
        simplices=index[tri],
        simplex_face=tri_face,
        vertices=np.flatnonzero(np.bincount(index[flat], minlength=p.shape[0])),
        volume=volume * scale**3,
        area=area * scale**2,
        tolerance=tol * scale,
    )
