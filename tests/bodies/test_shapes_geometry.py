"""Surface geometry of dtcrit.bodies: max_arm, support points and surface_points.

References, all independent of the code under test:

* superquadric surfaces from the angular parametrisation (Barr 1981)
  ``(a C^e1(eta) C^e2(w), b C^e1(eta) S^e2(w), c S^e1(eta))`` (signed powers), searched densely and
  refined with scipy.optimize;
* ellipsoid support point from the Lagrange condition, ``A^2 d / sqrt(d^T A^2 d)``;
* surface membership from the inside-outside function, normals from its central-difference
  gradient;
* coverage: area-uniform reference points (shell sampling for smooth bodies, barycentric sampling of
  hull triangles for polyhedra) and their distance to the nearest returned point.
"""
from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, strategies as st
from scipy.optimize import minimize
from scipy.spatial import ConvexHull, cKDTree

from dtcrit.bodies import AssumptionWarning, Box, ConvexPolyhedron, Ellipsoid, Sphere, Superquadric
from support.strategies import axes


def quiet(make):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AssumptionWarning)
        return make()


def spow(x, e):
    return np.sign(x) * np.abs(x) ** e


def parametric(a, b, c, e1, e2, eta, om):
    ce = spow(np.cos(eta), e1)
    return np.stack([a * ce * spow(np.cos(om), e2), b * ce * spow(np.sin(om), e2), c * spow(np.sin(eta), e1)], -1)


def inside_outside(p, a, b, c, e1, e2):
    """F^(e1/2) (the nested norm), evaluated in logarithms: 1 on the surface."""
    with np.errstate(divide="ignore"):
        lx, ly, lz = (np.log(np.abs(p[:, k] / s)) for k, s in enumerate((a, b, c)))
    lg = np.logaddexp(2 / e2 * lx, 2 / e2 * ly)
    return np.exp(0.5 * e1 * np.logaddexp(e2 / e1 * lg, 2 / e1 * lz))


@st.composite
def superquadrics(draw, eps_lo=0.01):
    a, b, c = draw(axes())
    return a, b, c, draw(st.floats(eps_lo, 2.0)), draw(st.floats(eps_lo, 2.0))


# ----------------------------------------------------------------------------- max_arm
def dense_max_arm(a, b, c, e1, e2, n=600):
    """Largest |r| over a dense first-octant grid, refined by Nelder-Mead from the best node."""
    t = np.linspace(0.0, np.pi / 2, n)
    eta, om = np.meshgrid(t, t, indexing="ij")
    r = np.linalg.norm(parametric(a, b, c, e1, e2, eta, om), axis=-1)
    k = np.unravel_index(np.argmax(r), r.shape)

    def neg(x):
        x = np.clip(x, 0.0, np.pi / 2)
        return -np.linalg.norm(parametric(a, b, c, e1, e2, x[0], x[1])) / a

    res = minimize(neg, [t[k[0]], t[k[1]]], method="Nelder-Mead", options={"xatol": 1e-12, "fatol": 1e-15})
    return float(r.max()), max(float(r.max()), -res.fun * a)


@given(superquadrics())
def test_superquadric_max_arm_matches_dense_search(params):
    a, b, c, e1, e2 = params
    s = quiet(lambda: Superquadric(a, b, c, e1, e2, mass=1.0))
    grid, refined = dense_max_arm(a, b, c, e1, e2, n=300)
    assert s.max_arm >= grid * (1 - 1e-12)  # never below a point of the surface
    assert s.max_arm == pytest.approx(refined, rel=1e-7)
    assert a <= s.max_arm <= math.sqrt(a * a + b * b + c * c) * (1 + 1e-15)


@pytest.mark.parametrize("e1,e2", [(0.1, 0.1), (0.5, 0.9), (1.0, 0.2), (0.3, 2.0), (2.0, 2.0), (1.0, 1.0)])
def test_superquadric_max_arm_fine_grid(e1, e2):
    s = Superquadric(3.0, 2.0, 1.0, e1, e2, mass=1.0)
    grid, refined = dense_max_arm(3.0, 2.0, 1.0, e1, e2, n=1500)
    assert s.max_arm >= grid * (1 - 1e-14)
    assert s.max_arm == pytest.approx(refined, rel=1e-9)


def test_max_arm_of_closed_shapes():
    assert Ellipsoid(3.0, 2.0, 1.0, mass=1.0).max_arm == 3.0
    assert Box(3.0, 2.0, 1.0, mass=1.0).max_arm == pytest.approx(math.sqrt(14.0), rel=1e-16)
    verts = np.array([[3.0, 1.0, 0.5], [-1.0, 2.0, 0.1], [0.2, -0.4, 1.5]])
    verts = np.r_[verts, -verts] + [5.0, 5.0, 5.0]
    p = quiet(lambda: ConvexPolyhedron(verts, mass=1.0))
    assert p.max_arm == pytest.approx(np.linalg.norm(verts - 5.0, axis=1).max(), rel=1e-14)


# ----------------------------------------------------------------------------- support
def directions(n, seed):
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def test_ellipsoid_support_matches_lagrange_solution():
    a, b, c = 3.0, 2.0, 0.5
    e = Ellipsoid(a, b, c, mass=1.0)
    d = directions(200, 0)
    A2 = np.array([a, b, c]) ** 2
    expected = d * A2 / np.sqrt(d**2 @ A2)[:, None]
    assert np.allclose(e.support(d), expected, rtol=0, atol=1e-14 * a)
    assert np.allclose(e.support(d[3]), expected[3], atol=1e-14 * a)
    assert np.allclose(Sphere(2.0, mass=1.0).support(d), 2.0 * d, atol=1e-15 * 2)


@given(superquadrics(eps_lo=0.05), st.integers(0, 1000))
def test_superquadric_support_is_the_farthest_surface_point(params, seed):
    a, b, c, e1, e2 = params
    s = quiet(lambda: Superquadric(a, b, c, e1, e2, mass=1.0))
    d = directions(8, seed) * 10.0 ** np.random.default_rng(seed).uniform(-3, 3, size=(8, 1))
    p = s.support(d)
    # on the surface
    assert np.allclose(inside_outside(p, a, b, c, e1, e2), 1.0, atol=1e-12)
    # no point of a dense parametric grid of the surface goes farther
    t = np.linspace(-np.pi / 2, np.pi / 2, 181)
    w = np.linspace(-np.pi, np.pi, 361)
    eta, om = np.meshgrid(t, w, indexing="ij")
    surf = parametric(a, b, c, e1, e2, eta, om).reshape(-1, 3)
    best = (d @ surf.T).max(axis=1)
    value = np.einsum("ij,ij->i", d, p)
    assert np.all(value >= best - 1e-12 * a * np.linalg.norm(d, axis=1))
    assert np.all(value <= best + 0.05 * a * np.linalg.norm(d, axis=1))  # the grid is fine enough


def test_polyhedral_support():
    box = Box(3.0, 2.0, 1.0, mass=1.0)
    assert np.allclose(box.support([1.0, 0.0, 0.0]), [3.0, 0.0, 0.0])  # a face: its centre
    assert np.allclose(box.support([1.0, 1.0, 0.0]), [3.0, 2.0, 0.0])  # an edge: its midpoint
    assert np.allclose(box.support([1.0, 1.0, 1.0]), [3.0, 2.0, 1.0])
    z = quiet(lambda: ConvexPolyhedron(np.r_[[[2.0, 0.3, 0.1], [0.1, 1.2, -0.3], [0.2, 0.1, 0.8], [1.0, 1.0, 1.0]],
                                             -np.array([[2.0, 0.3, 0.1], [0.1, 1.2, -0.3], [0.2, 0.1, 0.8], [1.0, 1.0, 1.0]])], mass=1.0))
    d = directions(300, 1)
    p = z.support(d)
    assert np.allclose(np.einsum("ij,ij->i", d, p), (d @ z.vertices.T).max(axis=1), rtol=1e-14)


# ----------------------------------------------------------------------------- smooth surface points
def shell_reference(a, b, c, e1, e2, n=1_500_000, tau=0.02, seed=3):
    """Area-uniform surface sample with weights: points of the shell {1 - tau < N <= 1} (N the
    nested norm) projected radially; a shell point stands for area ~ 1/(x . n), so the weights are
    1/(x . n) (normals from the central-difference gradient of N).  Returns points, weights, area.
    """
    rng = np.random.default_rng(seed)
    x = (rng.random((n, 3)) * 2 - 1) * [a, b, c]
    nn = inside_outside(x, a, b, c, e1, e2)
    keep = (nn <= 1) & (nn > 1 - tau)
    x = x[keep] / nn[keep, None]
    g = np.empty_like(x)
    for k, h in enumerate(1e-7 * np.array([a, b, c])):
        step = np.zeros(3)
        step[k] = h
        g[:, k] = (inside_outside(x + step, a, b, c, e1, e2) - inside_outside(x - step, a, b, c, e1, e2)) / (2 * h)
    normal = g / np.linalg.norm(g, axis=1, keepdims=True)
    w = 1.0 / np.einsum("ij,ij->i", x, normal)
    return x, w


SMOOTH = [
    (1.0, 1.0, 1.0, 1.0, 1.0),
    (3.0, 2.0, 1.0, 1.0, 1.0),
    (100.0, 1.0, 1.0, 1.0, 1.0),
    (100.0, 100.0, 1.0, 1.0, 1.0),
    (3.0, 2.0, 1.0, 0.1, 2.0),
    (3.0, 2.0, 1.0, 2.0, 0.3),
    (30.0, 1.0, 1.0, 0.2, 0.2),
    (1e-3, 1e-4, 1e-5, 0.5, 1.5),
]


@pytest.mark.parametrize("params", SMOOTH, ids=lambda p: "-".join(f"{x:g}" for x in p))
def test_superquadric_surface_points_cover_uniformly(params):
    a, b, c, e1, e2 = params
    s = quiet(lambda: Superquadric(a, b, c, e1, e2, mass=1.0))
    ref, w = shell_reference(a, b, c, e1, e2)
    area = 3 * s.volume * w.mean()  # divergence theorem: int x.n dA = 3V
    for n in (150, 800):
        pts, nrm = s.surface_points(n)
        assert 0.8 * n <= len(pts) <= 1.25 * n
        spacing = math.sqrt(area / len(pts))
        dist, owner = cKDTree(pts).query(ref)
        assert dist.max() <= 1.5 * spacing  # covering radius (observed <= 1.1)
        cells = np.bincount(owner, weights=w, minlength=len(pts))
        cells /= cells.mean()
        lo, hi = np.percentile(cells, [5, 95])
        assert lo >= 0.2 and hi <= 3.0  # Voronoi areas (observed 0.26 .. 2.4)
        # on the surface, outward unit normals
        assert np.allclose(inside_outside(pts, a, b, c, e1, e2), 1.0, atol=1e-12)
        assert np.allclose(np.linalg.norm(nrm, axis=1), 1.0, atol=1e-14)
        assert np.all(np.einsum("ij,ij->i", pts, nrm) > 0)
    tips = np.array([[a, 0, 0], [-a, 0, 0], [0, b, 0], [0, -b, 0], [0, 0, c], [0, 0, -c]])
    assert np.allclose(pts[:6], tips, rtol=0, atol=1e-15 * a)


@given(superquadrics(eps_lo=0.05), st.integers(1, 400))
def test_superquadric_surface_points_properties(params, n):
    a, b, c, e1, e2 = params
    s = quiet(lambda: Superquadric(a, b, c, e1, e2, mass=1.0))
    pts, nrm = s.surface_points(n)
    pts2, nrm2 = quiet(lambda: Superquadric(a, b, c, e1, e2, mass=2.0)).surface_points(n)  # a fresh object
    assert np.array_equal(pts, pts2) and np.array_equal(nrm, nrm2)  # deterministic
    assert len(pts) >= 6 and np.all(np.isfinite(pts)) and np.all(np.isfinite(nrm))
    if n >= 100 and c / a > 0.05:
        assert 0.75 * n <= len(pts) <= 1.3 * n
    assert np.allclose(inside_outside(pts, a, b, c, e1, e2), 1.0, atol=1e-12)
    # normals parallel to the gradient of the inside-outside function where it is smooth
    smooth = np.all(np.abs(pts) > 1e-3 * np.array([a, b, c]), axis=1)
    if e1 < 1.95 and e2 < 1.95 and np.any(smooth):
        p = pts[smooth]
        g = np.empty_like(p)
        for k, h in enumerate(1e-6 * np.array([a, b, c])):
            step = np.zeros(3)
            step[k] = h
            g[:, k] = (inside_outside(p + step, a, b, c, e1, e2) - inside_outside(p - step, a, b, c, e1, e2)) / (2 * h)
        g /= np.linalg.norm(g, axis=1, keepdims=True)
        assert np.min(np.einsum("ij,ij->i", g, nrm[smooth])) > 1 - 1e-5
    pts[0] = np.nan  # callers get copies of the cached arrays
    assert np.all(np.isfinite(s.surface_points(n)[0]))


def test_octahedral_superquadric_normals_are_face_normals():
    a, b, c = 3.0, 2.0, 1.0
    pts, nrm = Superquadric(a, b, c, 2.0, 2.0, mass=1.0).surface_points(300)
    interior = np.all(np.abs(pts) > 1e-9, axis=1)
    expected = np.sign(pts[interior]) / [a, b, c]
    expected /= np.linalg.norm(expected, axis=1, keepdims=True)
    assert np.allclose(nrm[interior], expected, atol=1e-12)


# ----------------------------------------------------------------------------- polyhedral surface points
def triangle_reference(vertices, n=200_000, seed=4):
    hull = ConvexHull(vertices)
    tri = vertices[hull.simplices]
    areas = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    rng = np.random.default_rng(seed)
    k = rng.choice(len(tri), size=n, p=areas / areas.sum())
    r1, r2 = rng.random(n), rng.random(n)
    flip = r1 + r2 > 1
    r1[flip], r2[flip] = 1 - r1[flip], 1 - r2[flip]
    pts = tri[k, 0] + r1[:, None] * (tri[k, 1] - tri[k, 0]) + r2[:, None] * (tri[k, 2] - tri[k, 0])
    return pts, areas.sum(), hull


POLYHEDRA = {
    "box": lambda: Box(3.0, 2.0, 1.0, mass=1.0),
    "needle-box": lambda: Box(100.0, 1.0, 1.0, mass=1.0),
    "plate-box": lambda: Box(1e-3, 1e-3, 1e-5, mass=1.0),
    "octahedron": lambda: ConvexPolyhedron(np.r_[np.eye(3), -np.eye(3)] * [3.0, 2.0, 1.0], mass=1.0),
    "zonotope": lambda: quiet(lambda: ConvexPolyhedron(_zonotope(np.array([[2.0, 0.3, 0.1], [0.1, 1.2, -0.3], [0.2, 0.1, 0.8], [0.5, -0.5, 0.4], [0.3, 0.6, 0.2]])), mass=1.0)),
}


def _zonotope(g):
    pts = np.array([np.array(s) @ g for s in itertools.product([-1.0, 1.0], repeat=len(g))])
    return pts[ConvexHull(pts).vertices]


@pytest.mark.parametrize("name", sorted(POLYHEDRA))
def test_polyhedral_surface_points(name):
    shape = POLYHEDRA[name]()
    ref, area, hull = triangle_reference(shape.vertices)
    scale = shape.max_arm
    for n in (60, 300, 1500):
        pts, nrm = shape.surface_points(n)
        nv = len(shape.vertices)
        assert np.array_equal(pts[:nv], shape.vertices)  # every vertex, first
        if n >= 300:
            assert 0.7 * n <= len(pts) <= 1.3 * n
        # on the boundary of the hull
        signed = pts @ hull.equations[:, :3].T + hull.equations[:, 3]
        assert np.all(signed <= 1e-12 * scale) and np.allclose(signed.max(axis=1), 0.0, atol=1e-12 * scale)
        # every normal is an outward unit normal at its point: the point is a support point along it
        assert np.allclose(np.linalg.norm(nrm, axis=1), 1.0, atol=1e-14)
        reach = (nrm @ shape.vertices.T).max(axis=1)
        assert np.allclose(np.einsum("ij,ij->i", nrm, pts), reach, atol=1e-12 * scale)
        # face points carry the plane normal of their face
        on_face = np.abs(signed) <= 1e-12 * scale
        single = on_face.sum(axis=1) == 1
        planes = hull.equations[np.argmax(on_face[single], axis=1), :3]
        assert np.allclose(nrm[single], planes, atol=1e-9)
        # coverage at the spacing the count implies
        if n >= 300:
            dist, _ = cKDTree(pts).query(ref)
            assert dist.max() <= 1.5 * math.sqrt(area / len(pts))
    assert np.array_equal(shape.surface_points(300)[0], POLYHEDRA[name]().surface_points(300)[0])  # deterministic
