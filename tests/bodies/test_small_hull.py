"""The NumPy hull pieces for small point sets (``dtcrit.bodies.small_hull``) against SciPy: faces as
Qhull's merged facets, counter-clockwise 2-D corners as Qhull's, components as ``csgraph``'s, nearest
neighbours and close pairs as ``cKDTree``'s.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import ConvexHull, cKDTree

from dtcrit.bodies import hull as hull_module
from dtcrit.bodies.small_hull import ccw_order, close_pairs, components, nearest, planar_faces


def _points(seed: int, n: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((n, 3))
    return x / np.linalg.norm(x, axis=1).max()


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("n", [4, 9, 25, 40])
def test_faces_are_qhulls_facets(seed, n):
    q = _points(seed, n)
    qh = ConvexHull(q)
    wanted = {tuple(sorted(s)) for s in qh.simplices.tolist()}  # random points: triangular faces
    faces = planar_faces(q, 1e-10)
    assert {tuple(on.tolist()) for _, on in faces} == wanted
    for normal, on in faces:  # outward: every point on the inner side
        assert np.all(q @ normal - q[on[0]] @ normal <= 1e-10)


def test_a_cube_with_points_on_faces_and_edges():
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    extra = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, -1.0, -1.0]])
    q = np.vstack([corners, extra]) / np.sqrt(3.0)
    faces = planar_faces(q, 1e-10)
    assert len(faces) == 6 and sorted(len(on) for _, on in faces) == [4, 5, 5, 5, 5, 6]
    small = hull_module.convex_hull_3d(q)
    inside = np.random.default_rng(3).uniform(-0.3, 0.3, (40, 3))  # 40 more points inside: the Qhull route
    ref = hull_module.convex_hull_3d(np.vstack([q, inside]))
    assert sorted(map(len, small.faces)) == sorted(map(len, ref.faces)) == [4] * 6
    assert small.volume == pytest.approx(ref.volume, rel=1e-14) and small.area == pytest.approx(ref.area, rel=1e-14)


def test_coplanar_points_have_no_faces():
    rng = np.random.default_rng(1)
    q = np.column_stack([rng.random((10, 2)), np.zeros(10)])
    assert planar_faces(q, 1e-10) == []


@pytest.mark.parametrize("seed", range(5))
def test_ccw_corners_are_qhulls(seed):
    xy = np.random.default_rng(seed).random((30, 2))
    got, ref = ccw_order(xy).tolist(), ConvexHull(xy).vertices.tolist()
    k = got.index(ref[0])
    assert got[k:] + got[:k] == ref


@pytest.mark.parametrize("seed", range(5))
def test_components_are_csgraphs(seed):
    rng = np.random.default_rng(seed)
    n = 60
    a, b = rng.integers(0, n, 45), rng.integers(0, n, 45)
    _, label = connected_components(coo_matrix((np.ones(45), (a, b)), shape=(n, n)), directed=False)
    smallest = np.array([np.flatnonzero(label == label[k]).min() for k in range(n)])
    assert np.array_equal(components(n, a, b), smallest)


def test_nearest_and_close_pairs_are_the_kd_trees():
    rng = np.random.default_rng(2)
    p, q = rng.random((50, 3)), rng.random((20, 3))
    dist, index = nearest(q, p)
    ref_d, ref_i = cKDTree(p).query(q)
    assert np.array_equal(index, ref_i) and np.allclose(dist, ref_d, rtol=1e-15)
    pairs = close_pairs(p, 0.2)
    assert {tuple(r) for r in pairs.tolist()} == {tuple(r) for r in cKDTree(p).query_pairs(0.2, output_type="ndarray").tolist()}
