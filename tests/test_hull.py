"""dtcrit.bodies.hull against an independent implementation: scipy.spatial (Qhull, cKDTree) and scipy.sparse.csgraph.

* 3-D hulls: corner sets (as coordinates, so duplicates compare equal), volumes and face planes
  (Qhull's triangle equations with coplanar ones merged) on random clouds, points on spheres,
  lattices, boxes with points on faces and edges, duplicates, prisms with many coplanar points,
  thin slabs and coordinates from 1e-6 to 1e6; degenerate input is refused by both;
* every hull is also checked for what a closed convex polytope must be (independent of Qhull):
  each edge in exactly two faces with opposite directions, V - E + F = 2, every point below every
  face plane, corners on their face plane, faces counter-clockwise seen from outside;
* 2-D hulls, nearest neighbours and connected components against Qhull, cKDTree and csgraph;
* building polyhedral shapes does not import scipy.spatial or scipy.sparse (start-up time).
"""
from __future__ import annotations

import itertools
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, strategies as st
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components as csgraph_components
from scipy.spatial import ConvexHull, QhullError, cKDTree
from scipy.spatial.transform import Rotation

from dtcrit.bodies.hull import HULL_RTOL, HullError, connected_components, convex_hull_2d, convex_hull_3d, nearest_neighbours

CUBE = np.array(list(itertools.product([-1.0, 1.0], repeat=3)))


# ============================================================================================
# helpers
# ============================================================================================
def placed(points, seed, log_scale, shift):
    """Rotate (seeded), scale by 10**log_scale and shift by ``shift`` sizes."""
    scale = 10.0**log_scale
    return points @ Rotation.random(random_state=seed).as_matrix().T * scale + scale * np.asarray(shift)


def size_of(p):
    return float(np.max(np.linalg.norm(p - p.mean(axis=0), axis=1)))


def merged_planes(hull, tol):
    """Distinct planes of a Qhull hull: neighbouring facets whose equations differ by at most ``tol``
    (per component) are one plane (connected components, scipy.sparse.csgraph)."""
    eq = hull.equations
    f = np.repeat(np.arange(len(eq)), 3)
    g = hull.neighbors.ravel()
    same = np.all(np.abs(eq[f] - eq[g]) <= tol, axis=1)
    graph = coo_matrix((np.ones(same.sum()), (f[same], g[same])), shape=(len(eq),) * 2)
    n, label = csgraph_components(graph, directed=False)
    total = np.zeros((n, 4))
    np.add.at(total, label, eq)
    return total / np.bincount(label, minlength=n)[:, None]


def rows_as_set(points, tol):
    """Points with near-duplicates (within ``tol`` of an earlier point) removed."""
    d = np.max(np.abs(points[:, None, :] - points[None, :, :]), axis=2)
    return points[~np.any(np.tril(d <= tol, -1), axis=1)]


def same_rows(a, b, tol):
    """Every row of a is within tol of a row of b and vice versa (as sets)."""
    if a.shape != b.shape:
        return False
    d = np.max(np.abs(a[:, None, :] - b[None, :, :]), axis=2)
    return bool(np.all(d.min(axis=1) <= tol) and np.all(d.min(axis=0) <= tol))


def check_polytope(h, p):
    """What every closed convex polytope must satisfy (no reference implementation needed)."""
    size = size_of(p)
    tol = max(1e-9 * size, 4.0 * h.tolerance)
    eq = h.equations
    assert np.allclose(np.linalg.norm(eq[:, :3], axis=1), 1.0, atol=1e-12)
    # every point on or below every face plane
    assert np.max(p @ eq[:, :3].T + eq[:, 3]) <= tol
    directed = set()
    for poly, row in zip(h.faces, eq):
        assert len(poly) >= 3 and len(set(poly.tolist())) == len(poly)
        corners = p[poly]
        assert np.max(np.abs(corners @ row[:3] + row[3])) <= tol  # corners on their plane
        # counter-clockwise seen from outside: Newell normal along the outward normal
        newell = np.sum(np.cross(corners, np.roll(corners, -1, axis=0)), axis=0)
        assert newell @ row[:3] > 0
        # convex polygon: every turn to the left
        e = np.roll(corners, -1, axis=0) - corners
        assert np.all(np.cross(e, np.roll(e, -1, axis=0)) @ row[:3] > 0)
        for i in range(len(poly)):
            edge = (int(poly[i]), int(poly[(i + 1) % len(poly)]))
            assert edge not in directed
            directed.add(edge)
    assert all((b, a) in directed for a, b in directed)  # closed, consistently oriented
    nv, ne, nf = len(h.vertices), len(directed) // 2, len(h.faces)
    assert nv - ne + nf == 2  # Euler
    assert set(np.concatenate(h.faces).tolist()) == set(h.vertices.tolist())
    # fan triangles outward, areas and volume consistent with them
    t = p[h.simplices]
    cross = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    assert np.all(np.einsum("ij,ij->i", cross, h.simplex_equations[:, :3]) > 0)
    assert h.area == pytest.approx(0.5 * np.sum(np.linalg.norm(cross, axis=1)), rel=1e-12)
    centre = p.mean(axis=0)
    vol = np.sum(np.einsum("ij,ij->i", cross, t[:, 0] - centre)) / 6.0
    assert abs(h.volume - vol) <= 1e-10 * h.volume + 1e-14 * size * h.area


def compare_with_qhull(p, true_corners=None):
    """Corners (as coordinates), volume, area and merged face planes against scipy.spatial.ConvexHull.

    Random input can put a point within a few rtol of a face plane of the others (thin slabs, many
    points on a sphere).  Qhull, working near rounding, may keep it as a corner or a separate
    facet; the tolerance here does not.  In that case ("ambiguous") the corner sets may differ only
    by points on the surface within the tolerance, the volume only by area x tolerance, and the
    face planes are not compared.
    """
    h = convex_hull_3d(p)
    check_polytope(h, p)
    ref = ConvexHull(p)
    size = size_of(p)
    scale = size + float(np.max(np.abs(p.mean(axis=0))))
    dist = -(p @ h.equations[:, :3].T + h.equations[:, 3])  # >= 0 up to the tolerance
    ambiguous = bool(np.any((np.abs(dist) > 1e-13 * scale) & (np.abs(dist) <= 100 * h.tolerance)))
    assert not (ambiguous and true_corners is not None)
    slack = 10 * h.tolerance if ambiguous else 1e-12 * scale
    assert abs(h.volume - ref.volume) <= 1e-10 * ref.volume + ref.area * slack
    assert abs(h.area - ref.area) <= 1e-10 * ref.area + 10 * size * slack
    mine = rows_as_set(p[h.vertices], 1e-12 * scale)
    assert len(mine) == len(h.vertices)  # no corner twice
    if true_corners is not None:
        assert same_rows(mine, true_corners, 1e-9 * scale)
    theirs = rows_as_set(p[ref.vertices], 1e-12 * scale)
    if ambiguous:
        differ = np.r_[mine, theirs]
        assert np.all(np.max(differ @ h.equations[:, :3].T + h.equations[:, 3], axis=1) >= -10 * h.tolerance)
        return h
    assert same_rows(mine, theirs, 1e-12 * scale)
    planes = merged_planes(ref, 1e-10 * np.r_[1.0, 1.0, 1.0, scale])
    assert len(planes) == len(h.equations)
    # one to one: each face plane's nearest Qhull plane is close, and no two share one
    gap = np.max(np.abs(h.equations[:, None, :] - planes[None, :, :]) / np.r_[1.0, 1.0, 1.0, scale], axis=2)
    nearest = np.argmin(gap, axis=1)
    assert len(set(nearest.tolist())) == len(planes)
    assert np.max(gap[np.arange(len(nearest)), nearest]) <= 1e-8
    return h


placements = st.tuples(st.integers(0, 10_000), st.floats(-6.0, 6.0), st.tuples(*[st.floats(-10.0, 10.0)] * 3))


# ============================================================================================
# 3-D hulls against Qhull
# ============================================================================================
@given(st.integers(4, 150), st.integers(0, 2**32 - 1), placements)
def test_random_clouds(n, seed, where):
    pts = np.random.default_rng(seed).normal(size=(n, 3)) * [1.0, 0.6, 0.3]
    compare_with_qhull(placed(pts, *where))


@given(st.integers(8, 250), st.integers(0, 2**32 - 1), placements)
def test_points_on_spheres_are_all_corners(n, seed, where):
    pts = np.random.default_rng(seed).normal(size=(n, 3))
    pts /= np.linalg.norm(pts, axis=1)[:, None]
    p = placed(pts, *where)
    h = compare_with_qhull(p)
    assert h.vertices.size == n
    assert h.tolerance == pytest.approx(HULL_RTOL * size_of(p), rel=1e-12)  # no retry on clean input


@given(st.floats(0.05, 1.0), st.floats(0.05, 1.0), st.integers(0, 40), st.integers(0, 20), st.integers(0, 30),
       st.integers(0, 8), st.integers(0, 2**32 - 1), placements)
def test_boxes_with_points_on_faces_edges_inside_and_duplicates(b, c, on_faces, on_edges, inside, dup, seed, where):
    rng = np.random.default_rng(seed)
    half = np.array([1.0, b, c])
    corners = CUBE * half
    f = rng.uniform(-1, 1, size=(on_faces, 3))
    axis = rng.integers(0, 3, size=on_faces)
    f[np.arange(on_faces), axis] = rng.choice([-1.0, 1.0], size=on_faces)
    e = rng.choice([-1.0, 1.0], size=(on_edges, 3))
    e[np.arange(on_edges), rng.integers(0, 3, size=on_edges)] = rng.uniform(-1, 1, size=on_edges)
    i = rng.uniform(-0.99, 0.99, size=(inside, 3))
    d = CUBE[rng.integers(0, 8, size=dup)]
    pts = np.r_[f, corners / half, e, i, d] * half
    pts = pts[rng.permutation(len(pts))]
    p = placed(pts, *where)
    h = compare_with_qhull(p, true_corners=placed(corners, *where))
    assert len(h.faces) == 6 and all(len(poly) == 4 for poly in h.faces)


@given(st.integers(2, 7), st.integers(0, 2**32 - 1), placements)
def test_lattice_cube_has_eight_corners_and_six_square_faces(m, seed, where):
    g = np.linspace(-1.0, 1.0, m)
    pts = np.array(list(itertools.product(g, g, g)))
    pts = pts[np.random.default_rng(seed).permutation(len(pts))]
    h = compare_with_qhull(placed(pts, *where), true_corners=placed(CUBE, *where))
    assert sorted(len(f) for f in h.faces) == [4] * 6


@given(st.integers(3, 24), st.integers(0, 200), st.integers(0, 2**32 - 1), placements)
def test_prisms_with_many_coplanar_points(k, extra, seed, where):
    """Regular k-gon prism: two k-gon caps and k rectangles, with extra points on caps and sides."""
    rng = np.random.default_rng(seed)
    ang = 2 * np.pi * np.arange(k) / k
    ring = np.column_stack([np.cos(ang), np.sin(ang)])
    corners = np.r_[np.column_stack([ring, np.full(k, 0.7)]), np.column_stack([ring, np.full(k, -0.7)])]
    # extra points: convex combinations of a cap's corners, or on a side rectangle
    w = rng.dirichlet(np.ones(k), size=extra)
    cap = np.column_stack([w @ ring, rng.choice([-0.7, 0.7], size=extra)])
    j = rng.integers(0, k, size=extra)
    t = rng.uniform(0, 1, size=extra)[:, None]
    side = np.column_stack([(1 - t) * ring[j] + t * ring[(j + 1) % k], rng.uniform(-0.7, 0.7, size=extra)])
    pts = np.r_[corners, cap, side][rng.permutation(2 * k + 2 * extra)]
    h = compare_with_qhull(placed(pts, *where), true_corners=placed(corners, *where))
    assert sorted(len(f) for f in h.faces) == sorted([4] * k + [k, k])


@given(st.floats(-5.0, -1.0), st.integers(0, 2**32 - 1), placements)
def test_thin_slabs(log_thickness, seed, where):
    """Down to 1e-5 of the size (thinner slabs may be refused: rounding defeats the tolerance)."""
    pts = np.random.default_rng(seed).uniform(-1, 1, size=(60, 3)) * [1.0, 1.0, 10.0**log_thickness]
    compare_with_qhull(placed(pts, *where))


@given(st.integers(2, 5), st.floats(-13.0, -8.0), st.integers(0, 2**32 - 1), placements)
def test_nearly_degenerate_jitter_still_gives_a_closed_convex_hull(m, log_noise, seed, where):
    """Lattice points (with random extra points) jittered by 1e-13 .. 1e-8 of the size: slivers too
    thin for rounding at rtol are absorbed by a larger tolerance (at most 1000 rtol); the result is a
    closed convex polytope with Qhull's volume to that tolerance."""
    rng = np.random.default_rng(seed)
    g = np.linspace(-1.0, 1.0, m)
    pts = np.r_[np.array(list(itertools.product(g, g, g))), rng.uniform(-1, 1, size=(10, 3))]
    p = placed(pts + 10.0**log_noise * rng.normal(size=pts.shape), *where)
    h = convex_hull_3d(p)
    check_polytope(h, p)
    size = size_of(p)
    assert HULL_RTOL * size * (1 - 1e-12) <= h.tolerance <= 1000 * HULL_RTOL * size * (1 + 1e-12)
    assert h.volume == pytest.approx(ConvexHull(p).volume, rel=max(1e-10, 20 * h.tolerance / size))


def test_fan_of_points_near_one_corner():
    """Corners close together (1e-6 of the size) stay distinct corners."""
    pts = np.r_[CUBE, CUBE[:1] + 1e-6 * np.array([[0.3, -0.2, 0.1], [-0.1, 0.4, 0.2]])]
    compare_with_qhull(pts)


# ============================================================================================
# degenerate input
# ============================================================================================
@given(st.integers(4, 60), st.integers(0, 2**32 - 1), placements)
def test_coplanar_points_are_refused_like_qhull(n, seed, where):
    pts = np.column_stack([np.random.default_rng(seed).normal(size=(n, 2)), np.zeros(n)])
    p = placed(pts, *where)
    with pytest.raises(HullError, match="coplanar"):
        convex_hull_3d(p)
    with pytest.raises(QhullError):
        ConvexHull(p)


@given(st.integers(4, 30), st.integers(0, 2**32 - 1), placements)
def test_collinear_and_coincident_points_are_refused(n, seed, where):
    t = np.random.default_rng(seed).normal(size=(n, 1))
    with pytest.raises(HullError, match="collinear"):
        convex_hull_3d(placed(t * [[1.0, 0.0, 0.0]], *where))
    with pytest.raises(HullError, match="coincide"):
        convex_hull_3d(np.repeat(placed(np.ones((1, 3)), *where), n, axis=0))


def test_too_few_points_and_bad_arrays():
    with pytest.raises(HullError, match="at least 4"):
        convex_hull_3d(CUBE[:3])
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        convex_hull_3d(np.zeros((5, 2)))
    with pytest.raises(ValueError, match="finite"):
        convex_hull_3d(np.r_[CUBE, [[np.nan, 0, 0]]])
    with pytest.raises(HullError, match="collinear"):
        convex_hull_2d([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [0.5, 0.5]])
    with pytest.raises(HullError, match="at least 3"):
        convex_hull_2d([[0.0, 0.0], [1.0, 1.0]])
    assert issubclass(HullError, ValueError)


def test_near_coplanar_within_tolerance_counts_as_flat():
    pts = np.r_[CUBE[:, :2], CUBE[:, :2] * 0.5]
    pts = np.column_stack([pts, np.r_[np.zeros(8), np.full(8, 0.1 * HULL_RTOL)]])
    with pytest.raises(HullError, match="coplanar"):
        convex_hull_3d(pts)


# ============================================================================================
# 2-D hulls, nearest neighbours, connected components
# ============================================================================================
@given(st.integers(3, 200), st.integers(0, 2**32 - 1), st.floats(-6.0, 6.0), st.booleans())
def test_hull_2d_against_qhull(n, seed, log_scale, on_circle):
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(n, 2))
    if on_circle:
        pts /= np.linalg.norm(pts, axis=1)[:, None]
    pts = pts * 10.0**log_scale + 10.0**log_scale * rng.uniform(-5, 5, size=2)
    ring = convex_hull_2d(pts)
    ref = ConvexHull(pts).vertices  # counter-clockwise in 2-D
    # same corners in the same cyclic order, except Qhull corners within rtol of an edge of ours
    assert set(ring.tolist()) <= set(ref.tolist())
    kept = [i for i in ref.tolist() if i in set(ring.tolist())]
    start = kept.index(int(ring[0]))
    assert ring.tolist() == kept[start:] + kept[:start]
    size = float(np.max(np.linalg.norm(pts - pts.mean(axis=0), axis=1)))
    a, b = pts[ring], pts[np.roll(ring, -1)]
    for i in set(ref.tolist()) - set(ring.tolist()):
        e, w = b - a, pts[i] - a
        outside = (e[:, 0] * w[:, 1] - e[:, 1] * w[:, 0]) / np.linalg.norm(e, axis=1)
        assert -np.min(outside) <= 2 * HULL_RTOL * size


def test_hull_2d_drops_points_on_edges_and_duplicates():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    extra = np.array([[0.5, 0.0], [1.0, 0.5], [0.0, 0.5], [0.5, 1.0], [0.5, 0.5], [0.0, 0.0], [1.0, 1.0]])
    pts = np.r_[extra, square]
    ring = convex_hull_2d(pts)
    assert len(ring) == 4 and same_rows(pts[ring], square, 0.0)
    (ax, ay), (bx, by) = pts[ring[1]] - pts[ring[0]], pts[ring[2]] - pts[ring[1]]
    assert ax * by - ay * bx > 0  # counter-clockwise


@given(st.integers(1, 300), st.integers(1, 300), st.integers(0, 2**32 - 1))
def test_nearest_neighbours_against_ckdtree(nq, npts, seed):
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(npts, 3))
    queries = np.r_[rng.normal(size=(nq, 3)), pts[: min(nq, npts)]]
    dist, index = nearest_neighbours(queries, pts, chunk=257)
    ref_dist, _ = cKDTree(pts).query(queries)
    assert np.allclose(dist, ref_dist, rtol=1e-14, atol=1e-300)
    assert np.allclose(np.linalg.norm(queries - pts[index], axis=1), ref_dist, rtol=1e-14, atol=1e-300)


@given(st.integers(1, 80), st.integers(0, 200), st.integers(0, 2**32 - 1))
def test_connected_components_against_csgraph(n, m, seed):
    rng = np.random.default_rng(seed)
    i, j = rng.integers(0, n, size=m), rng.integers(0, n, size=m)
    label = connected_components(n, i, j)
    _, ref = csgraph_components(coo_matrix((np.ones(m), (i, j)), shape=(n, n)), directed=False)
    # same partition; each label is the smallest node of its component
    for a in range(n):
        assert np.array_equal(label == label[a], ref == ref[a])
        assert label[a] == np.flatnonzero(ref == ref[a]).min()


# ============================================================================================
# imports (hull timings are reported by the bench, never asserted)
# ============================================================================================
def test_polyhedral_shapes_do_not_import_scipy_spatial_or_sparse():
    code = (
        "import itertools, sys\n"
        "from dtcrit.bodies import Box, ConvexPolyhedron\n"
        "cube = [list(c) for c in itertools.product([-0.05, 0.05], repeat=3)]\n"
        "p = ConvexPolyhedron(cube, density=2700.0)\n"
        "b = Box(3.0, 2.0, 1.0, density=1.0)\n"
        "for s in (p, b):\n"
        "    s.surface_points(200); s.support([1.0, 2.0, 3.0])\n"
        "ConvexPolyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 1], [0, 1, -1], [0, -1, 1], [0, -1, -1]], mass=1.0)\n"
        "print(sorted(m for m in sys.modules if m.startswith(('scipy.spatial', 'scipy.sparse'))))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
