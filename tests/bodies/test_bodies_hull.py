"""What dtcrit adds to Qhull for polyhedral bodies (dtcrit.bodies.hull): merged planar faces,
corners only, outward counter-clockwise rings, duplicates once, thin bodies accepted.

References are independent: the faces, corners, volumes and areas of a box, an octahedron and a
prism are known in closed form; random point sets are checked against the hull's own definition
(every point inside every face plane, every corner on at least three of them).
"""
from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, strategies as st

from dtcrit.bodies import ConvexPolyhedron
from dtcrit.bodies.hull import HullError, connected_components, convex_hull_2d, convex_hull_3d, nearest_neighbours
from dtcrit.errors import InputError


def _box(a, b, c):
    return np.array([[sx * a, sy * b, sz * c] for sx, sy, sz in itertools.product((1, -1), repeat=3)], float)


def _ring_is_ccw_outward(points, face, normal):
    p = points[face]
    area = np.sum(np.cross(p, np.roll(p, -1, axis=0)), axis=0) / 2
    return float(area @ normal) > 0


@pytest.mark.parametrize("scale", [1e-6, 1.0, 1e6])
def test_box_faces_merged_with_extra_points_on_faces_and_edges(scale):
    a, b, c = 3.0 * scale, 2.0 * scale, 1.0 * scale
    corners = _box(a, b, c)
    extra = np.array([[0, 0, c], [a, 0, 0], [a, b, 0], [0, b, c], [a / 2, b, c]])  # face centres, edge points
    pts = np.vstack([corners, extra, corners[:2]])  # and two duplicates
    hull = convex_hull_3d(pts)
    assert len(hull.faces) == 6
    assert sorted(hull.vertices.tolist()) == list(range(8))
    assert hull.volume == pytest.approx(8 * a * b * c, rel=1e-12)
    assert hull.area == pytest.approx(8 * (a * b + b * c + a * c), rel=1e-12)
    for face, eq in zip(hull.faces, hull.equations):
        assert len(face) == 4
        assert _ring_is_ccw_outward(pts, face, eq[:3])
        assert np.allclose(pts[face] @ eq[:3] + eq[3], 0.0, atol=1e-12 * scale)
    assert np.all(pts @ hull.equations[:, :3].T + hull.equations[:, 3] <= 1e-12 * scale)


@pytest.mark.parametrize("thickness", [1e-7, 1e-9])
def test_thin_bodies_are_accepted(thickness):
    """The hand-written hull refused bodies thinner than about 1e-6 of their size; Qhull takes them."""
    body = ConvexPolyhedron(_box(1.0, 0.5, thickness), density=1000.0)
    assert body.volume == pytest.approx(8 * 0.5 * thickness, rel=1e-9)
    assert body.half_lengths[2] == pytest.approx(thickness, rel=1e-9)


def test_coplanar_and_collinear_input_is_refused():
    with pytest.raises(HullError):
        convex_hull_3d(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 3, 0]], float))
    with pytest.raises(HullError):
        convex_hull_2d(np.array([[0, 0], [1, 1], [2, 2], [3, 3]], float))
    with pytest.raises(InputError):
        ConvexPolyhedron([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], density=1.0)


def test_octahedron_and_hexagonal_prism():
    octa = np.vstack([np.eye(3), -np.eye(3)])
    hull = convex_hull_3d(octa)
    assert len(hull.faces) == 8 and hull.volume == pytest.approx(4 / 3, rel=1e-13)
    ang = np.arange(6) * np.pi / 3
    ring = np.column_stack([np.cos(ang), np.sin(ang)])
    prism = np.vstack([np.column_stack([ring, np.full(6, z)]) for z in (-1.0, 1.0)])
    hull = convex_hull_3d(prism)
    assert sorted(len(f) for f in hull.faces) == [4] * 6 + [6, 6]
    assert hull.volume == pytest.approx(2 * 3 * np.sqrt(3) / 2, rel=1e-13)


@given(st.integers(0, 2**32 - 1), st.integers(5, 60), st.floats(-6, 6))
def test_random_hulls_contain_every_point(seed, n, log_scale):
    pts = np.random.default_rng(seed).normal(size=(n, 3)) * 10.0**log_scale
    hull = convex_hull_3d(pts)
    size = np.max(np.abs(pts))
    assert np.all(pts @ hull.equations[:, :3].T + hull.equations[:, 3] <= 1e-9 * size)
    for face, eq in zip(hull.faces, hull.equations):
        assert _ring_is_ccw_outward(pts, face, eq[:3])
    on_planes = np.sum(np.abs(pts[hull.vertices] @ hull.equations[:, :3].T + hull.equations[:, 3]) <= 1e-9 * size, axis=1)
    assert np.all(on_planes >= 3)


def test_neighbours_and_components():
    pts = np.array([[0.0, 0, 0], [1, 0, 0], [5, 5, 5]])
    dist, idx = nearest_neighbours([[0.9, 0, 0], [4, 5, 5]], pts)
    assert idx.tolist() == [1, 2] and dist == pytest.approx([0.1, 1.0])
    assert connected_components(5, [3, 1], [4, 0]).tolist() == [0, 0, 2, 3, 3]
