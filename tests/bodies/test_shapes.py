"""Mass properties of dtcrit.bodies against independent routes; bad input; paper assumption 3.

Independent references (none uses the closed forms or the slicing/Beta derivation):

* ``de_moments``: double-exponential (tanh-sinh) product quadrature in *physical* coordinates of
  the definition ``int f dV`` over the body {F <= 1}, with z integrated analytically between
  +-Z(x, y) and the inner y-range split where the integrand has a kink.  Its error is estimated by
  halving the step; with h = 1/48 it agrees with the h = 1/96 result to ~1e-15 on every body
  below, so the tolerance 1e-11 (relative) is a stated bound with margin.
* Monte-Carlo over the bounding box (seeded) with a 5-sigma bound from the sample variance.
* mpmath (50 digits) quadrature of the two one-dimensional slice integrals, which checks the
  SymPy Beta/Gamma algebra at high precision.
"""
from __future__ import annotations

import math
import subprocess
import sys
import warnings

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, strategies as st

from dtcrit.errors import InputError
from dtcrit.bodies import (
    AssumptionWarning,
    Box,
    ConvexPolyhedron,
    Ellipsoid,
    Sphere,
    Superquadric,
    shape_from_spec,
)
from support.strategies import axes


# ----------------------------------------------------------------------------- references
def _de_nodes(h: float, t_max: float = 3.3):
    """Tanh-sinh nodes on (0, 1): x, 1 - x (accurate) and weights."""
    t = np.arange(-t_max, t_max + h / 2, h)
    s = 0.5 * np.pi * np.sinh(t)
    x = 0.5 * (1.0 + np.tanh(s))
    one_minus_x = 0.5 * np.exp(-s) / np.cosh(s)
    w = h * 0.25 * np.pi * np.cosh(t) / np.cosh(s) ** 2
    return x, one_minus_x, w


def de_moments(a, b, c, eps1, eps2, h=1.0 / 48):
    """(V, int x^2, int y^2, int z^2) of the superquadric body by tanh-sinh quadrature.

    Body: (|x/a|^(2/e2) + |y/b|^(2/e2))^(e2/e1) + |z/c|^(2/e1) <= 1.  For each x in (0, a) and
    y in (0, Y(x)), z runs over |z| <= Z(x, y) (done exactly: 2Z and 2Z^3/3); the y-range is split
    at y = b x / a where max(|x/a|, |y/b|) has a kink that matters for small eps.
    """
    p1, p2 = 2.0 / eps1, 2.0 / eps2
    u, _, wu = _de_nodes(h)
    x = a * u
    with np.errstate(divide="ignore", under="ignore"):
        ymax = b * (-np.expm1(p2 * np.log(u))) ** (1.0 / p2)
    v, _, wv = _de_nodes(h)
    total = np.zeros(4)
    split = np.minimum(ymax, b * u)
    for lo, hi in ((np.zeros_like(split), split), (split, ymax)):
        y = lo[:, None] + (hi - lo)[:, None] * v[None, :]
        with np.errstate(under="ignore", divide="ignore"):  # logarithms: u^(2/eps) underflows for eps ~ 0.01
            log_g = np.logaddexp(p2 * np.log(u)[:, None], p2 * np.log(y / b))
            r = np.clip(-np.expm1(p1 / p2 * log_g), 0.0, None)
            z = c * r ** (1.0 / p1)
        w = 4.0 * (a * wu)[:, None] * ((hi - lo)[:, None] * wv[None, :])
        total += [
            np.sum(w * 2 * z),
            np.sum(w * 2 * z * x[:, None] ** 2),
            np.sum(w * 2 * z * y**2),
            np.sum(w * 2 * z**3 / 3),
        ]
    return total


def inertia_from_moments(m):
    v, xx, yy, zz = m
    return np.array([yy + zz, xx + zz, xx + yy]) / v


def monte_carlo_moments(inside, half, n=400_000, seed=7):
    """Volume and second moments over {inside} by uniform sampling of the bounding box.

    Returns (estimate, 5-sigma half-width) for (V, int x^2, int y^2, int z^2).
    """
    rng = np.random.default_rng(seed)
    box = 8.0 * np.prod(half)
    p = (rng.random((n, 3)) * 2.0 - 1.0) * half
    hit = inside(p).astype(float)
    samples = np.column_stack([hit, hit * p[:, 0] ** 2, hit * p[:, 1] ** 2, hit * p[:, 2] ** 2]) * box
    return samples.mean(axis=0), 5.0 * samples.std(axis=0) / math.sqrt(n)


def superquadric_inside(a, b, c, e1, e2):
    def inside(p):
        with np.errstate(under="ignore"):
            g = np.abs(p[:, 0] / a) ** (2 / e2) + np.abs(p[:, 1] / b) ** (2 / e2)
            return g ** (e2 / e1) + np.abs(p[:, 2] / c) ** (2 / e1) <= 1.0

    return inside


EPS_GRID = [(1.0, 1.0), (0.5, 1.5), (0.1, 0.1), (2.0, 2.0), (1.99, 0.3), (0.01, 0.01), (0.01, 2.0), (2.0, 0.01), (1.999, 1.999)]


# ----------------------------------------------------------------------------- sphere
@pytest.mark.parametrize("radius", [1e-6, 3.7e-3, 1.0, 2.5, 999.0])
def test_sphere_exact_to_a_few_ulp(radius):
    s = Sphere(radius, density=2650.0)
    mp.mp.dps = 50
    vol = mp.mpf(4) / 3 * mp.pi * mp.mpf(radius) ** 3
    assert abs(s.volume - float(vol)) <= 2 * math.ulp(s.volume)
    exact_i = mp.mpf(2) / 5 * mp.mpf(s.mass) * mp.mpf(radius) ** 2  # with the object's own mass
    for i in s.inertia:
        assert abs(i - float(exact_i)) <= 3 * math.ulp(i)
    assert s.inertia[0] == s.inertia[1] == s.inertia[2]
    assert s.max_arm == radius and s.half_lengths == (radius, radius, radius)
    assert s.equivalent_radius == radius
    assert s.kind == "sphere" and s.vertices is None and s.satisfies_paper_assumptions


# ----------------------------------------------------------------------------- quadrature anchors
@pytest.mark.parametrize("eps1,eps2", EPS_GRID)
def test_superquadric_against_quadrature_of_the_definition(eps1, eps2):
    a, b, c = 3.0, 2.0, 1.0
    coarse, fine = de_moments(a, b, c, eps1, eps2, 1 / 24), de_moments(a, b, c, eps1, eps2, 1 / 48)
    est = np.max(np.abs(fine / coarse - 1))
    s = Superquadric(a, b, c, eps1, eps2, density=1.0)
    tol = max(1e-11, 10 * est)
    assert est < 1e-8
    assert s.volume == pytest.approx(fine[0], rel=tol)
    assert np.allclose(np.array(s.inertia) / s.mass, inertia_from_moments(fine), rtol=tol, atol=0)


def test_ellipsoid_and_box_against_quadrature_of_the_definition():
    e = Ellipsoid(3.0, 2.0, 1.0, mass=5.0)
    ref = de_moments(3.0, 2.0, 1.0, 1.0, 1.0)
    assert e.volume == pytest.approx(ref[0], rel=1e-12)
    assert np.allclose(np.array(e.inertia) / 5.0, inertia_from_moments(ref), rtol=1e-12, atol=0)
    # a box is the eps -> 0 limit; the quadrature at eps = 0.01 is within 1 % and converges
    b = Box(3.0, 2.0, 1.0, mass=5.0)
    near = de_moments(3.0, 2.0, 1.0, 0.01, 0.01)
    assert b.volume == pytest.approx(near[0], rel=0.02)
    assert b.volume > near[0]


def test_paper_ellipsoid_numbers():
    """Peng et al. 2020, Section 6: a, b, c = 3, 2, 1 m, rho = 1000 kg/m^3; V = 4/3 pi a b c = 8 pi."""
    e = Ellipsoid(3.0, 2.0, 1.0, density=1000.0)
    assert e.volume == pytest.approx(8 * math.pi, rel=1e-15)
    assert e.mass == pytest.approx(8000 * math.pi, rel=1e-15)
    # mass / 5 times (b^2 + c^2, a^2 + c^2, a^2 + b^2), written out by hand
    assert np.allclose(e.inertia, np.array([5.0, 10.0, 13.0]) * 1600 * math.pi, rtol=1e-15)


@pytest.mark.parametrize(
    "shape,inside,half",
    [
        (Ellipsoid(3.0, 2.0, 1.0, density=1.0), superquadric_inside(3, 2, 1, 1, 1), (3, 2, 1)),
        (Box(3.0, 2.0, 1.0, density=1.0), lambda p: np.ones(len(p), bool), (3, 2, 1)),
        (Superquadric(3.0, 2.0, 1.0, 0.3, 1.7, density=1.0), superquadric_inside(3, 2, 1, 0.3, 1.7), (3, 2, 1)),
        (Superquadric(2.0, 2.0, 1.5, 2.0, 0.05, density=1.0), superquadric_inside(2, 2, 1.5, 2.0, 0.05), (2, 2, 1.5)),
    ],
    ids=["ellipsoid", "box", "superquadric", "superquadric-eps1=2"],
)
def test_monte_carlo_with_five_sigma_bound(shape, inside, half):
    est, bound = monte_carlo_moments(inside, np.array(half, float))
    assert abs(shape.volume - est[0]) <= bound[0]
    second = np.array([shape.inertia[1] + shape.inertia[2] - shape.inertia[0],
                       shape.inertia[0] + shape.inertia[2] - shape.inertia[1],
                       shape.inertia[0] + shape.inertia[1] - shape.inertia[2]]) / 2 / shape.density
    assert np.all(np.abs(second - est[1:]) <= bound[1:])


@pytest.mark.parametrize("eps1,eps2", [(1.0, 1.0), (0.1, 0.1), (1.999, 0.37), (0.01, 2.0), (2.0, 2.0)])
def test_superquadric_slice_integrals_at_fifty_digits(eps1, eps2):
    """V = 8abc int_0^1 rho(w)^2 A dw and <z^2>: the 1-D integrals at 50 digits vs the closed form.

    rho(w) = (1 - w^p1)^(1/p1) scales the quarter superellipse of area A = int_0^1 (1-u^p2)^(1/p2) du
    and second moment Q = int_0^1 int_0^{Y(u)} u^2 dv du = int_0^1 u^2 (1-u^p2)^(1/p2) du.
    """
    mp.mp.dps = 50
    e1, e2 = mp.mpf(eps1), mp.mpf(eps2)
    p1, p2 = 2 / e1, 2 / e2
    area = mp.quad(lambda u: (1 - u**p2) ** (1 / p2), [0, 1])
    quad2 = mp.quad(lambda u: u**2 * (1 - u**p2) ** (1 / p2), [0, 1])
    vol_w = mp.quad(lambda w: (1 - w**p1) ** (2 / p1), [0, 1])
    z2_w = mp.quad(lambda w: w**2 * (1 - w**p1) ** (2 / p1), [0, 1])
    x2_w = mp.quad(lambda w: (1 - w**p1) ** (4 / p1), [0, 1])
    a, b, c = 3.0, 2.0, 1.0
    volume = 8 * a * b * c * area * vol_w
    mean_z2 = c**2 * z2_w / vol_w
    mean_x2 = a**2 * quad2 * x2_w / (area * vol_w)
    mean_y2 = b**2 * quad2 * x2_w / (area * vol_w)
    s = Superquadric(a, b, c, eps1, eps2, mass=1.0)
    assert s.volume == pytest.approx(float(volume), rel=5e-15)
    expected = [float(mean_y2 + mean_z2), float(mean_x2 + mean_z2), float(mean_x2 + mean_y2)]
    assert np.allclose(s.inertia, expected, rtol=5e-15, atol=0)


# ----------------------------------------------------------------------------- across decades

@given(axes(), st.floats(0.01, 2.0), st.floats(0.01, 2.0), st.floats(-3.0, 5.0))
def test_superquadric_across_decades(abc, eps1, eps2, log_rho):
    a, b, c = abc
    rho = 10.0**log_rho
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AssumptionWarning)
        s = Superquadric(a, b, c, eps1, eps2, density=rho)
    ref = de_moments(a, b, c, eps1, eps2)
    assert s.volume == pytest.approx(ref[0], rel=1e-9)
    assert s.mass == pytest.approx(rho * ref[0], rel=1e-9)
    assert np.allclose(np.array(s.inertia) / s.mass, inertia_from_moments(ref), rtol=1e-9, atol=0)
    assert all(math.isfinite(i) and i > 0 for i in s.inertia)


@given(axes(), st.floats(-3.0, 5.0), st.booleans())
def test_ellipsoid_and_box_across_decades(abc, log_m, by_mass):
    a, b, c = abc
    m = 10.0**log_m
    kw = {"mass": m} if by_mass else {"density": m}
    e, bx = Ellipsoid(a, b, c, **kw), Box(a, b, c, **kw)
    ref = de_moments(a, b, c, 1.0, 1.0)
    assert e.volume == pytest.approx(ref[0], rel=1e-11)
    assert np.allclose(np.array(e.inertia) / e.mass, inertia_from_moments(ref), rtol=1e-11, atol=0)
    # box: vertices as a polyhedron (tetrahedral decomposition, another route)
    poly = ConvexPolyhedron(bx.vertices, **kw)
    assert bx.volume == pytest.approx(poly.volume, rel=1e-12)
    assert np.allclose(bx.inertia, poly.inertia, rtol=1e-11, atol=0)
    for shape in (e, bx):
        assert shape.satisfies_paper_assumptions
        assert shape.mass == pytest.approx(m if by_mass else m * shape.volume, rel=1e-15)
        assert shape.density * shape.volume == pytest.approx(shape.mass, rel=1e-15)
        assert shape.equivalent_radius == pytest.approx((3 * shape.volume / (4 * math.pi)) ** (1 / 3), rel=1e-14)


# ----------------------------------------------------------------------------- bad input
BAD = [
    (lambda: Sphere(-1.0, density=1.0), "radius", "positive"),
    (lambda: Sphere(0.0, density=1.0), "radius", "positive"),
    (lambda: Sphere(float("nan"), density=1.0), "radius", "finite"),
    (lambda: Sphere(float("inf"), density=1.0), "radius", "finite"),
    (lambda: Sphere("1", density=1.0), "radius", "real number"),
    (lambda: Sphere(True, density=1.0), "radius", "real number"),
    (lambda: Sphere(1.0, density=-2.0), "density", "positive"),
    (lambda: Sphere(1.0, density=0.0), "density", "positive"),
    (lambda: Sphere(1.0, density=float("nan")), "density", "finite"),
    (lambda: Sphere(1.0, mass=float("inf")), "mass", "finite"),
    (lambda: Sphere(1.0, mass=0.0), "mass", "positive"),
    (lambda: Sphere(1.0, mass=-1.0), "mass", "positive"),
    (lambda: Sphere(1.0, density=1.0, mass=1.0), "density", "exactly one"),
    (lambda: Sphere(1.0), "density", "exactly one"),
    (lambda: Sphere(1e100, density=1e300), "density", "finite mass"),
    (lambda: Sphere(1e200, density=1.0), "radius", "outside double precision"),
    (lambda: Ellipsoid(1e-100, 1e-110, 1e-120, density=1.0), "a", "outside double precision"),
    (lambda: Ellipsoid(1.0, 2.0, 0.5, density=1.0), "b", "a >= b >= c"),
    (lambda: Ellipsoid(3.0, 2.0, 2.5, density=1.0), "c", "a >= b >= c"),
    (lambda: Ellipsoid(3.0, -2.0, 1.0, density=1.0), "b", "positive"),
    (lambda: Ellipsoid(3.0, 2.0, float("nan"), density=1.0), "c", "finite"),
    (lambda: Box(1.0, 2.0, 0.5, mass=1.0), "b", "a >= b >= c"),
    (lambda: Box(2.0, 1.0, 0.0, mass=1.0), "c", "positive"),
    (lambda: Box(float("inf"), 1.0, 1.0, mass=1.0), "a", "finite"),
    (lambda: Superquadric(1.0, 2.0, 0.5, 1.0, 1.0, mass=1.0), "b", "a >= b >= c"),
    (lambda: Superquadric(3.0, 2.0, 1.0, 2.5, 1.0, mass=1.0), "eps1", "convex"),
    (lambda: Superquadric(3.0, 2.0, 1.0, 1.0, 2.0001, mass=1.0), "eps2", "convex"),
    (lambda: Superquadric(3.0, 2.0, 1.0, 0.0, 1.0, mass=1.0), "eps1", "[0.01, 2]"),
    (lambda: Superquadric(3.0, 2.0, 1.0, 1.0, 0.005, mass=1.0), "eps2", "[0.01, 2]"),
    (lambda: Superquadric(3.0, 2.0, 1.0, -1.0, 1.0, mass=1.0), "eps1", "[0.01, 2]"),
    (lambda: Superquadric(3.0, 2.0, 1.0, float("nan"), 1.0, mass=1.0), "eps1", "finite"),
    (lambda: ConvexPolyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 0]], mass=1.0), "vertices", "at least 4"),
    (lambda: ConvexPolyhedron([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]], mass=1.0), "vertices", "coplanar"),
    (lambda: ConvexPolyhedron(np.r_[np.eye(3), -np.eye(3), [[0.2, 0.1, 0.0]]], mass=1.0), "vertices", "not convex"),
    (lambda: ConvexPolyhedron(np.r_[np.eye(3), -np.eye(3), [[0.6, 0.6, 0.6]]], mass=1.0), "vertices", "centrally symmetric"),
    (lambda: ConvexPolyhedron([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], mass=1.0), "vertices", "centrally symmetric"),
    (lambda: ConvexPolyhedron(np.r_[np.eye(3), -np.eye(3)] * [1, 1, np.nan], mass=1.0), "vertices", "finite"),
    (lambda: ConvexPolyhedron([[1, 2], [3, 4]], mass=1.0), "vertices", "(N, 3)"),
    (lambda: ConvexPolyhedron(np.r_[np.eye(3), -np.eye(3)], mass=1.0, density=1.0), "density", "exactly one"),
    (lambda: shape_from_spec("torus", radius=1.0, mass=1.0), "kind", "one of"),
    (lambda: shape_from_spec("sphere", r=1.0, mass=1.0), "r", "unknown"),
    (lambda: shape_from_spec("ellipsoid", a=3.0, b=2.0, mass=1.0), "c", "missing"),
    (lambda: Sphere(1.0, density=1.0).surface_points(0), "n", "at least 1"),
    (lambda: Sphere(1.0, density=1.0).surface_points(2.5), "n", "integer"),
    (lambda: Sphere(1.0, density=1.0).support([0, 0, 0]), "direction", "non-zero"),
    (lambda: Box(1.0, 1.0, 1.0, density=1.0).support([1, np.inf, 0]), "direction", "finite"),
    (lambda: Box(1.0, 1.0, 1.0, density=1.0).support([1, 0]), "direction", "shape"),
]


@pytest.mark.parametrize("make,key,words", BAD, ids=[f"{k}-{i}" for i, (_, k, _) in enumerate(BAD)])
def test_bad_input_names_the_argument(make, key, words):
    with pytest.raises(InputError) as info:
        make()
    assert info.value.key == key
    assert words in info.value.reason
    assert isinstance(info.value, ValueError)
    assert str(info.value).startswith(f"{key}: ")


# ----------------------------------------------------------------------------- assumption 3
def _superquadric_flag_boundary(eps1, eps2):
    """<y^2>/b^2 and <z^2>/c^2 of the unit superquadric by quadrature (independent of the code)."""
    v, _, yy, zz = de_moments(1.0, 1.0, 1.0, eps1, eps2)
    return yy / v, zz / v


def test_superquadric_that_breaks_assumption_3_is_flagged_not_reordered():
    # box-like along z (eps1 = 0.1), diamond cross-section (eps2 = 2), b = c: <y^2> < <z^2>
    y2, z2 = _superquadric_flag_boundary(0.1, 2.0)
    assert y2 < z2  # so I_zz = m(<x^2> + <y^2>) < I_yy = m(<x^2> + <z^2>)
    with pytest.warns(AssumptionWarning, match=r"Superquadric\(a=1, b=1, c=1, eps1=0\.1, eps2=2\).*I_zz >= I_yy"):
        s = Superquadric(1.0, 1.0, 1.0, 0.1, 2.0, mass=1.0)
    assert not s.satisfies_paper_assumptions
    assert len(s.assumption_issues) == 1 and "I_zz >= I_yy >= I_xx" in s.assumption_issues[0]
    assert s.half_lengths == (1.0, 1.0, 1.0)  # axes as given
    assert s.inertia[2] < s.inertia[1]
    # it still fails with a strictly ordered a > b > c while b/c < sqrt(<z^2>/<y^2>) ...
    ratio = math.sqrt(z2 / y2)
    with pytest.warns(AssumptionWarning):
        assert not Superquadric(1.2, 1.0, 1.0 / (0.5 * (1 + ratio)), 0.1, 2.0, mass=1.0).satisfies_paper_assumptions
    # ... and passes once b/c exceeds it
    with warnings.catch_warnings():
        warnings.simplefilter("error", AssumptionWarning)
        assert Superquadric(1.2, 1.0, 1.0 / (1.01 * ratio), 0.1, 2.0, mass=1.0).satisfies_paper_assumptions


@given(axes(), st.floats(0.01, 2.0), st.floats(0.01, 2.0))
def test_flag_matches_the_quadrature_ordering(abc, eps1, eps2):
    a, b, c = abc
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s = Superquadric(a, b, c, eps1, eps2, mass=1.0)
    ref = inertia_from_moments(de_moments(a, b, c, eps1, eps2))
    gap = ref[2] - ref[1]
    if abs(gap) > 1e-8 * ref[2]:  # clear cases only (the flag has a 1e-9 slack)
        assert s.satisfies_paper_assumptions == (gap > 0)
        assert bool(caught) == (gap < 0)
    assert ref[1] >= ref[0] * (1 - 1e-12)  # a >= b always gives I_yy >= I_xx


@pytest.mark.parametrize("make", [lambda: Sphere(1.0, mass=1.0), lambda: Ellipsoid(3.0, 3.0, 3.0, mass=1.0),
                                  lambda: Ellipsoid(3.0, 1.0, 1.0, mass=1.0), lambda: Box(2.0, 2.0, 1.0, mass=1.0),
                                  lambda: Superquadric(2.0, 2.0, 2.0, 1.0, 1.0, mass=1.0)])
def test_ties_are_not_flagged(make):
    with warnings.catch_warnings():
        warnings.simplefilter("error", AssumptionWarning)
        assert make().satisfies_paper_assumptions


# ----------------------------------------------------------------------------- object contract
def test_shapes_are_immutable_and_typed():
    for s in (Sphere(1.0, mass=1.0), Ellipsoid(3.0, 2.0, 1.0, mass=1.0), Superquadric(3.0, 2.0, 1.0, 0.5, 0.5, mass=1.0),
              Box(3.0, 2.0, 1.0, mass=1.0), ConvexPolyhedron(np.r_[np.eye(3), -np.eye(3)], mass=1.0)):
        with pytest.raises(AttributeError):
            s.mass = 2.0
        with pytest.raises(AttributeError):
            s._mass = 2.0
        assert isinstance(s.inertia, tuple) and len(s.inertia) == 3 and all(type(i) is float for i in s.inertia)
        assert isinstance(s.half_lengths, tuple) and all(type(h) is float for h in s.half_lengths)
        assert s.kind in {"sphere", "ellipsoid", "superquadric", "box", "polyhedron"}
        if s.vertices is not None:
            with pytest.raises(ValueError):
                s.vertices[0, 0] = 9.0
        assert s.kind in repr(s).lower() or "polyhedron" in repr(s).lower()


def test_shape_from_spec_builds_every_kind():
    specs = {
        "sphere": dict(radius=1.0, density=2.0),
        "ellipsoid": dict(a=3.0, b=2.0, c=1.0, mass=4.0),
        "superquadric": dict(a=3.0, b=2.0, c=1.0, eps1=0.5, eps2=1.5, density=2.0),
        "box": dict(a=3.0, b=2.0, c=1.0, density=2.0),
        "polyhedron": dict(vertices=np.r_[np.eye(3), -np.eye(3)], mass=1.0, rtol=1e-8),
    }
    for kind, params in specs.items():
        s = shape_from_spec(kind, **dict(params))
        assert s.kind == kind
    assert shape_from_spec("Ellipsoid", a=3.0, b=2.0, c=1.0, mass=4.0).inertia == Ellipsoid(3.0, 2.0, 1.0, mass=4.0).inertia


def test_runtime_module_does_not_import_sympy():
    code = "import sys, dtcrit.bodies; s = dtcrit.bodies.Superquadric(3, 2, 1, .5, .5, mass=1); s.surface_points(50); print('sympy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
