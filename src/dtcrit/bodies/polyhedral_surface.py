"""Faces, edges and vertex normals of a convex polytope (box and convex polyhedron), in the local frame:
merged coplanar hull facets, surface samples at a common spacing, support points.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.bodies.checks import _PLANE_RTOL, _readonly, _unit_rows
from dtcrit.bodies.hull import connected_components, convex_hull_3d
from dtcrit.errors import InputError


class _PolyhedralSurface:
    """Faces (merged coplanar hull facets), edges and vertex normals of a convex polytope.

    Every point of ``vertices`` must be a corner of the hull.  ``faces`` (corner indices, counter-
    clockwise seen from outside) and their outward unit ``normals`` may be given (a hull already
    taken); otherwise :func:`dtcrit.bodies.hull.convex_hull_3d` finds them.  Neighbouring faces whose unit
    normals and offsets differ by less than ``_PLANE_RTOL`` (offsets relative to the largest
    vertex distance) are merged into one face.
    """

    def __init__(self, vertices: np.ndarray, faces: tuple[np.ndarray, ...] | None = None,
                 normals: np.ndarray | None = None):
        self.vertices = vertices
        scale = float(np.max(np.linalg.norm(vertices, axis=1)))
        if faces is None:
            hull = convex_hull_3d(vertices)
            faces, normals = hull.faces, hull.equations[:, :3]
        assert normals is not None  # given with the faces, or from the hull
        lens = np.array([len(poly) for poly in faces])
        owner0 = np.repeat(np.arange(len(faces)), lens)
        flat = np.concatenate(faces)
        offsets = -np.bincount(owner0, weights=np.einsum("ij,ij->i", vertices[flat], normals[owner0])) / lens
        nxt = flat[_ring_successor(lens)]
        newell = np.zeros((len(faces), 3))  # twice the vector area of each face
        np.add.at(newell, owner0, np.cross(vertices[flat], vertices[nxt]))
        self.area = float(0.5 * np.sum(np.linalg.norm(newell, axis=1)))
        # merge neighbouring faces of one plane: connected components of the "same plane" graph
        across = {(a, b): f for a, b, f in zip(flat.tolist(), nxt.tolist(), owner0.tolist())}
        pair_list = [(f, across[(b, a)]) for (a, b), f in across.items() if (b, a) in across]
        pairs = np.array(pair_list, dtype=int).reshape(-1, 2)
        f, g = pairs[:, 0], pairs[:, 1]
        same = (np.max(np.abs(normals[f] - normals[g]), axis=1) < _PLANE_RTOL) & (np.abs(offsets[f] - offsets[g]) < _PLANE_RTOL * scale)
        comp = connected_components(len(faces), f[same], g[same])  # label: the first face of each
        is_first = comp == np.arange(len(faces))
        label = (np.cumsum(is_first) - 1)[comp]  # merged faces numbered by their first face
        nface = int(np.count_nonzero(is_first))
        self.face_normals = np.empty((nface, 3))
        self.face_normals[label] = normals
        self.face_normals = _unit_rows(self.face_normals)
        # corners of each face counter-clockwise: by angle about their mean in the basis of
        # _plane_basis(normal), from -pi (ties in ascending vertex order)
        pairs, _ = _distinct_pairs(np.column_stack([label[owner0], flat]))
        face_of, idx = pairs[:, 0], pairs[:, 1]
        count = np.bincount(face_of, minlength=nface)
        centre = np.zeros((nface, 3))
        np.add.at(centre, face_of, vertices[idx])
        rel = vertices[idx] - (centre / count[:, None])[face_of]
        u, v = _plane_basis_rows(self.face_normals)
        ang = np.arctan2(np.einsum("ij,ij->i", rel, v[face_of]), np.einsum("ij,ij->i", rel, u[face_of]))
        order = np.lexsort((ang, face_of))
        self.faces: list[np.ndarray] = np.split(idx[order], np.cumsum(count)[:-1])
        sizes = np.array([len(poly) for poly in self.faces])
        starts = np.concatenate(self.faces)
        ends = starts[_ring_successor(sizes)]
        owner = np.repeat(np.arange(nface), sizes)
        keys = np.sort(np.column_stack([starts, ends]), axis=1)
        self.edges, inverse = _distinct_pairs(keys)
        esum = np.zeros((self.edges.shape[0], 3))
        np.add.at(esum, inverse.ravel(), self.face_normals[owner])
        self.edge_normals = _unit_rows(esum)
        vsum = np.zeros_like(vertices)
        np.add.at(vsum, starts, self.face_normals[owner])
        self.vertex_normals = _unit_rows(vsum)
        self.edge_length = float(np.sum(np.linalg.norm(vertices[self.edges[:, 1]] - vertices[self.edges[:, 0]], axis=1)))
        # per face: longest edge and centroid (fan of triangles from the vertex mean)
        counts = np.bincount(owner, minlength=nface)
        self.face_max_edge = np.zeros(nface)
        np.maximum.at(self.face_max_edge, owner, np.linalg.norm(vertices[ends] - vertices[starts], axis=1))
        ref = np.zeros((nface, 3))
        np.add.at(ref, owner, vertices[starts])
        ref /= counts[:, None]
        fan = np.einsum("ij,ij->i", np.cross(vertices[starts] - ref[owner], vertices[ends] - ref[owner]), self.face_normals[owner])
        cen = np.zeros((nface, 3))
        np.add.at(cen, owner, fan[:, None] * (ref[owner] + vertices[starts] + vertices[ends]) / 3.0)
        total = np.bincount(owner, weights=fan, minlength=nface)
        self.face_centroids = np.where(total[:, None] > 0, cen / np.where(total > 0, total, 1.0)[:, None], ref)

    def transformed(self, rotation: np.ndarray, scale: float) -> "_PolyhedralSurface":
        """The same polytope rotated (rows of ``rotation`` are the new axes) and scaled."""
        out = object.__new__(_PolyhedralSurface)
        out.vertices = _readonly(scale * self.vertices @ rotation.T)
        out.faces, out.edges = self.faces, self.edges
        out.face_normals = self.face_normals @ rotation.T
        out.edge_normals = self.edge_normals @ rotation.T
        out.vertex_normals = self.vertex_normals @ rotation.T
        out.area, out.edge_length = self.area * scale**2, self.edge_length * scale
        out.face_max_edge = self.face_max_edge * scale
        out.face_centroids = scale * self.face_centroids @ rotation.T
        return out

    def sample(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """All vertices, edge points and face points at a common spacing h, ``n`` points in total.

        h solves ``area/h^2 + edge_length/h + vertices = n``; every face gets at least its
        centroid.  Normals: face normal on faces, mean of the two face normals on edges, mean of
        the adjacent face normals at vertices.
        """
        nv = self.vertices.shape[0]
        room = n - nv
        inv_h = 0.0 if room <= 0 else (-self.edge_length + math.sqrt(self.edge_length**2 + 4 * self.area * room)) / (2 * self.area)
        pts, nrm = [self.vertices], [self.vertex_normals]
        if inv_h > 0:
            p0, p1 = self.vertices[self.edges[:, 0]], self.vertices[self.edges[:, 1]]
            k = np.rint(np.linalg.norm(p1 - p0, axis=1) * inv_h).astype(int)  # segments per edge
            e = np.repeat(np.arange(self.edges.shape[0]), np.maximum(k - 1, 0))
            if e.size:
                j = np.arange(e.size) - np.repeat(np.cumsum(np.maximum(k - 1, 0)) - np.maximum(k - 1, 0), np.maximum(k - 1, 0)) + 1
                t = (j / k[e])[:, None]
                pts.append(p0[e] + t * (p1[e] - p0[e]))
                nrm.append(self.edge_normals[e])
        h = math.inf if inv_h == 0 else 1.0 / inv_h
        # faces smaller than the spacing (every edge shorter than h) get their centroid only
        small = self.face_max_edge < h
        for g in np.flatnonzero(~small):
            fp = _face_grid(self.vertices[self.faces[g]], self.face_normals[g], h)
            pts.append(fp)
            nrm.append(np.repeat(self.face_normals[g : g + 1], fp.shape[0], axis=0))
        pts.append(self.face_centroids[small])
        nrm.append(self.face_normals[small])
        return np.concatenate(pts), np.concatenate(nrm)

    def support(self, d: np.ndarray) -> np.ndarray:
        """Farthest point along each row of ``d``: the mean of the maximising vertices (ties within 1e-12)."""
        proj = d @ self.vertices.T
        best = np.max(proj, axis=1, keepdims=True)
        scale = np.linalg.norm(d, axis=1, keepdims=True) * float(np.max(np.linalg.norm(self.vertices, axis=1)))
        ties = proj >= best - 1e-12 * scale
        return (ties @ self.vertices) / np.sum(ties, axis=1, keepdims=True)


def _distinct_pairs(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distinct rows of a non-negative ``(K, 2)`` int array, lexicographic, and each row's position."""
    code = keys[:, 0] * (int(keys.max()) + 1) + keys[:, 1]
    order = np.argsort(code, kind="stable")
    new = np.concatenate([[True], code[order][1:] != code[order][:-1]])
    inverse = np.empty(code.size, dtype=int)
    inverse[order] = np.cumsum(new) - 1
    return keys[order[new]], inverse


def _ring_successor(sizes: np.ndarray) -> np.ndarray:
    """For rings of ``sizes`` laid end to end, the position of each entry's successor in its ring."""
    nxt = np.arange(1, int(np.sum(sizes)) + 1)
    ends = np.cumsum(sizes)
    nxt[ends - 1] = ends - sizes
    return nxt


def _plane_basis_rows(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_plane_basis` of each row of ``normals``."""
    helper = np.eye(3)[np.argmin(np.abs(normals), axis=1)]
    u = np.cross(normals, helper)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return u, np.cross(normals, u)


def _plane_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors spanning the plane normal to ``normal`` (deterministic)."""
    u, v = _plane_basis_rows(np.asarray(normal, dtype=float)[None, :])
    return u[0], v[0]


def _face_grid(poly: np.ndarray, normal: np.ndarray, h: float) -> np.ndarray:
    """Points of a grid of about h x h cells inside a convex planar polygon (cell centres).

    The grid is aligned with the polygon's longest edge and its cells divide the bounding
    rectangle evenly (so a rectangular face of sides W x H gets round(W/h) x round(H/h) points,
    half a cell from its edges); centres closer than a quarter cell to an edge are dropped.  A face
    too small for any cell contributes its centroid.
    """
    centre = _polygon_centroid(poly, normal)
    if not math.isfinite(h):
        return centre[None, :]
    edges = np.roll(poly, -1, axis=0) - poly
    longest = edges[int(np.argmax(np.linalg.norm(edges, axis=1)))]
    u = longest / np.linalg.norm(longest)
    v = np.cross(normal, u)
    rel = poly - centre
    pu, pv = rel @ u, rel @ v
    ku = max(1, int(round(np.ptp(pu) / h)))
    kv = max(1, int(round(np.ptp(pv) / h)))
    if ku * kv > 4_000_000:
        raise InputError("n", "too many surface points requested")
    step_u, step_v = np.ptp(pu) / ku, np.ptp(pv) / kv
    gu, gv = np.meshgrid(pu.min() + (np.arange(ku) + 0.5) * step_u, pv.min() + (np.arange(kv) + 0.5) * step_v, indexing="ij")
    grid = np.column_stack([gu.ravel(), gv.ravel()])
    # inward edge normals in the (u, v) plane: the polygon runs counter-clockwise about +normal
    ring = np.column_stack([pu, pv])
    e2 = np.roll(ring, -1, axis=0) - ring
    inward = np.column_stack([-e2[:, 1], e2[:, 0]]) / np.linalg.norm(e2, axis=1)[:, None]
    signed = grid @ inward.T - np.einsum("ek,ek->e", ring, inward)[None, :]
    inside = np.min(signed, axis=1) >= 0.25 * min(step_u, step_v)
    if not np.any(inside):
        return centre[None, :]
    g = grid[inside]
    return centre + g[:, :1] * u + g[:, 1:] * v


def _polygon_centroid(poly: np.ndarray, normal: np.ndarray) -> np.ndarray:
    ref = poly.mean(axis=0)
    a = np.cross(poly - ref, np.roll(poly, -1, axis=0) - ref) @ normal
    c = (poly + np.roll(poly, -1, axis=0) + ref) / 3.0
    total = np.sum(a)
    return ref if total <= 0 else (a[:, None] * c).sum(axis=0) / total
