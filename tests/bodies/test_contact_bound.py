"""The coefficient matrix of the contact force, Eq. (26) and the valid bound ``a_bound``.

Independent routes: direct rigid-body evaluation of the coefficient matrix (cross products and a
linear solve written out here), brute-force maxima over vertices / dense surface samples, closed
forms (spheres, ellipsoid tips, cube corners) and random admissible contacts.
"""
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import dtcrit
from dtcrit.bodies import arm_supremum as asup, contact, contact_search as cs
from dtcrit.errors import InputError
from dtcrit.bodies import Box, ConvexPolyhedron, Ellipsoid, Sphere, Superquadric

decades = st.floats(min_value=-5.0, max_value=5.0)
SLACK = 1e-12


def direct_matrix(m1, I1, R1, r1, m2, I2, R2, r2):
    """Coefficient matrix by applying unit forces to the rigid-body equations (paper's R: global -> local)."""
    cols = []
    for F in np.eye(3):
        acc = np.zeros(3)
        for m, I, R, r, sign in ((m1, I1, R1, r1, -1.0), (m2, I2, R2, r2, 1.0)):
            alpha = R.T @ np.linalg.solve(np.diag(I), R @ np.cross(r, sign * F))
            acc += sign * (np.cross(alpha, r) + sign * F / m)
        cols.append(acc)
    return np.column_stack(cols)


def lam_arm(p, inertia):
    """lambda_max([p]x^T I^-1 [p]x) by an explicit eigen-solve."""
    X = np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])
    return np.linalg.eigvalsh(X.T @ np.diag(1.0 / np.asarray(inertia)) @ X)[-1]


def _polyhedron(seed=7):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(7, 3))
    half = d / np.linalg.norm(d, axis=1, keepdims=True) * np.array([2.0, 1.3, 0.8])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ConvexPolyhedron(np.vstack([half, -half]), density=1000.0)


SHAPES = {
    "ellipsoid": Ellipsoid(3.0, 2.0, 1.0, density=1000.0),
    "ellipsoid2": Ellipsoid(2.0, 1.5, 1.0, density=2500.0),
    "superquadric": Superquadric(3.0, 2.0, 1.0, 0.3, 0.5, density=1000.0),
    "superquadric-boxy": Superquadric(1.0, 1.0, 1.0, 0.1, 0.1, density=1000.0),
    "box": Box(3.0, 2.0, 1.0, density=1000.0),
    "cube": Box(1.0, 1.0, 1.0, density=500.0),
    "polyhedron": _polyhedron(),
    "sphere": Sphere(1.0, density=1000.0),
}

PAIRS = [("ellipsoid", "ellipsoid"), ("ellipsoid", "ellipsoid2"), ("superquadric", "superquadric"),
         ("superquadric-boxy", "box"), ("box", "box"), ("cube", "polyhedron"), ("polyhedron", "polyhedron"),
         ("sphere", "cube"), ("ellipsoid", "polyhedron")]


# ---------------------------------------------------------------------------------- input checks


@pytest.mark.parametrize("func", [contact.a_max, contact.a_bound, contact.b_max, contact.b_bound])
@pytest.mark.parametrize("bad", ["sphere", 3.0, None, object()])
def test_non_shapes_are_refused(func, bad):
    with pytest.raises(InputError) as err:
        func(bad)
    assert err.value.key in ("p", "p1")


def test_second_argument_is_checked_too():
    with pytest.raises(InputError) as err:
        contact.a_max(SHAPES["box"], "box")
    assert err.value.key == "p2"


@pytest.mark.parametrize("R,key", [(np.ones(3), "body_to_world[1]"), (np.zeros(4), "body_to_world[1]"),
                                   (2 * np.eye(3), "body_to_world[1]"), (np.diag([1.0, 1.0, -1.0]), "body_to_world[1]"),
                                   ([np.nan, 0, 0, 1], "body_to_world[1]")])
def test_bad_rotations_are_refused(R, key):
    s = SHAPES["box"]
    with pytest.raises(InputError) as err:
        contact.coefficient_matrix(s, s, [1, 0, 0], [-1, 0, 0], body_to_world=(R, None))
    assert err.value.key == key


def test_bad_arm_is_refused():
    s = SHAPES["box"]
    with pytest.raises(InputError) as err:
        contact.coefficient_matrix(s, s, [1, 0], [-1, 0, 0])
    assert err.value.key == "r1"


# ---------------------------------------------------------------------------------- spheres, Eq. (26)


@given(decades, st.floats(0.0, 5.0))
def test_two_spheres_a_max_and_a_bound_are_7_over_m(log_r, log_rho):
    s = Sphere(10.0**log_r, density=10.0**log_rho)
    assert math.isclose(dtcrit.a_max(s) * s.mass, 7.0, rel_tol=1e-14)
    assert math.isclose(dtcrit.a_bound(s) * s.mass, 7.0, rel_tol=1e-14)
    assert dtcrit.b_max(s) == 0.0


def test_a_max_is_eq26_term_by_term():
    e, b = SHAPES["ellipsoid"], SHAPES["box"]
    expected = e.half_lengths[0] ** 2 / e.inertia[0] + b.half_lengths[0] ** 2 / b.inertia[0] + 1 / e.mass + 1 / b.mass
    assert math.isclose(dtcrit.a_max(e, b), expected, rel_tol=1e-15)


# ---------------------------------------------------------------------------------- coefficient matrix


@given(st.sampled_from(sorted(SHAPES)), st.sampled_from(sorted(SHAPES)),
       st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda q: sum(c * c for c in q) > 1e-3),
       st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda q: sum(c * c for c in q) > 1e-3),
       st.tuples(*[st.floats(-3, 3)] * 3), st.tuples(*[st.floats(-3, 3)] * 3))
def test_coefficient_matrix_matches_direct_rigid_body_evaluation(n1, n2, q1, q2, r1, r2):
    s1, s2 = SHAPES[n1], SHAPES[n2]
    q1, q2 = np.array(q1) / np.linalg.norm(q1), np.array(q2) / np.linalg.norm(q2)
    # orientations body to world: the active matrix of q (Eq. 7), i.e. scipy's from_quat; the paper's R
    # (global -> local, Eq. 5) that direct_matrix takes is its transpose
    Q1 = Rotation.from_quat([*q1[1:], q1[0]]).as_matrix()
    Q2 = Rotation.from_quat([*q2[1:], q2[0]]).as_matrix()
    A = contact.coefficient_matrix(s1, s2, r1, r2, body_to_world=(q1, q2))
    A_mat = contact.coefficient_matrix(s1, s2, r1, r2, body_to_world=(Q1, Q2))
    D = direct_matrix(s1.mass, s1.inertia, Q1.T, np.array(r1), s2.mass, s2.inertia, Q2.T, np.array(r2))
    scale = np.max(np.abs(D))
    np.testing.assert_allclose(A, D, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(A_mat, D, rtol=0, atol=1e-13 * scale)
    assert np.allclose(A, A.T, rtol=0, atol=1e-15 * scale)
    assert np.linalg.eigvalsh(A)[0] >= (1 / s1.mass + 1 / s2.mass) * (1 - 1e-9)


# ---------------------------------------------------------------------------------- per-particle suprema


@pytest.mark.parametrize("name", ["box", "cube", "polyhedron"])
def test_polyhedral_supremum_is_the_vertex_maximum(name):
    s = SHAPES[name]
    sup = asup.arm_term_supremum(s)
    vertex_max = max(lam_arm(v, s.inertia) for v in s.vertices)
    assert sup.method == "vertices" and sup.upper == sup.lower
    assert math.isclose(sup.upper, vertex_max, rel_tol=1e-13)
    pts, _ = s.surface_points(3000)  # faces and edges never exceed the vertices (convexity)
    assert max(lam_arm(p, s.inertia) for p in pts) <= sup.upper * (1 + SLACK)


@pytest.mark.parametrize("name", ["ellipsoid", "ellipsoid2", "superquadric", "superquadric-boxy"])
def test_smooth_supremum_brackets_dense_surface_samples(name):
    s = SHAPES[name]
    sup = asup.arm_term_supremum(s)
    pts, _ = s.surface_points(4000)
    dense = max(lam_arm(p, s.inertia) for p in pts)
    assert dense <= sup.upper * (1 + SLACK)
    assert sup.lower <= sup.upper * (1 + SLACK)
    assert sup.upper <= sup.lower * (1 + 2 * asup.SUP_RTOL)
    assert math.isclose(lam_arm(np.array(sup.point), s.inertia), sup.lower, rel_tol=1e-12)


@settings(max_examples=15)
@given(st.floats(-3, 3), st.floats(0, 1), st.floats(0, 1), st.floats(0, 5))
def test_ellipsoid_supremum_is_the_tip_formula(log_a, fb, fc, log_rho):
    a = 10.0**log_a
    b = a * (0.05 + 0.95 * fb)
    c = b * (0.05 + 0.95 * fc)
    e = Ellipsoid(a, b, c, density=10.0**log_rho)
    tip = 5 * a * a / (e.mass * (a * a + c * c))  # a^2 / I_yy at the tip a e_x
    sup = asup.arm_term_supremum(e)
    assert sup.lower <= tip * (1 + 1e-12)
    assert tip <= sup.upper * (1 + 1e-12)
    assert sup.upper <= tip * (1 + 2 * asup.SUP_RTOL)
    assert dtcrit.a_bound(e) <= dtcrit.a_max(e) * (1 + 1e-12)  # Eq. (26) holds for ellipsoids


# ---------------------------------------------------------------------------------- admissible contacts


@pytest.mark.parametrize("pair", PAIRS, ids=lambda p: f"{p[0]}-{p[1]}")
def test_random_admissible_contacts_never_exceed_a_bound(pair):
    s1, s2 = SHAPES[pair[0]], SHAPES[pair[1]]
    batch = cs.random_contacts(s1, s2, 20000, seed=1)
    # admissibility: opposite outward normals, contact points are support points of those normals
    n1 = np.einsum("nji,nj->ni", batch.Q1, batch.normal)
    n2 = -np.einsum("nji,nj->ni", batch.Q2, batch.normal)
    h1 = np.einsum("ni,ni->n", n1, s1.support(n1))
    h2 = np.einsum("ni,ni->n", n2, s2.support(n2))
    assert np.all(np.einsum("ni,ni->n", n1, batch.p1) >= h1 - 1e-9 * s1.max_arm)
    assert np.all(np.einsum("ni,ni->n", n2, batch.p2) >= h2 - 1e-9 * s2.max_arm)
    lam = batch.largest_eigenvalues(s1, s2)
    bound = dtcrit.a_bound(s1, s2)
    assert np.all(lam <= bound * (1 + SLACK))
    # the arms seen from the global frame give the same matrices through the public function
    i = int(np.argmax(lam))
    A = contact.coefficient_matrix(s1, s2, batch.r1[i], batch.r2[i], body_to_world=(batch.Q1[i], batch.Q2[i]))
    assert math.isclose(np.linalg.eigvalsh(A)[-1], lam[i], rel_tol=1e-12)


@pytest.mark.parametrize("name", ["ellipsoid", "superquadric", "box", "cube", "polyhedron", "superquadric-boxy"])
def test_mirror_contact_attains_a_bound_for_identical_particles(name):
    s = SHAPES[name]
    sup = asup.arm_term_supremum(s)
    p, normal = np.array(sup.point), np.array(sup.normal)
    # the stored normal is admissible at the point: the point is the support point of the normal
    assert np.linalg.norm(s.support(normal) - p) <= 1e-12 * np.linalg.norm(p)
    c = cs.mirror_contact(s, p, normal)
    # particle 2's outward normal at its contact point is opposite: Q2 n = -n
    assert np.allclose(c.Q2[0] @ normal, -normal, atol=1e-12)
    lam = c.largest_eigenvalues(s, s)[0]
    tol = 1e-12 if s.vertices is not None else 2 * asup.SUP_RTOL
    assert lam <= dtcrit.a_bound(s) * (1 + SLACK)
    assert lam >= dtcrit.a_bound(s) * (1 - tol)


# ---------------------------------------------------------------------------------- Eq. (26) counter-examples


@given(st.floats(-4, 4), st.floats(0, 5))
def test_cube_corner_contact_violates_eq26(log_a, log_rho):
    a = 10.0**log_a
    cube = Box(a, a, a, density=10.0**log_rho)
    m = cube.mass
    A = contact.coefficient_matrix(cube, cube, [a, a, a], [-a, -a, -a])
    lam = np.linalg.eigvalsh(A)
    np.testing.assert_allclose(lam * m, [2.0, 11.0, 11.0], rtol=1e-12)
    assert math.isclose(dtcrit.a_max(cube) * m, 5.0, rel_tol=1e-13)
    assert math.isclose(dtcrit.a_bound(cube) * m, 11.0, rel_tol=1e-13)
    assert lam[-1] > 2.19 * dtcrit.a_max(cube)


@pytest.mark.parametrize("name,exceeds", [("box", True), ("cube", True), ("superquadric-boxy", True),
                                          ("ellipsoid", False), ("superquadric", False), ("polyhedron", False)])
def test_search_establishes_where_eq26_fails(name, exceeds):
    s = SHAPES[name]
    res = cs.search_supremum(s, s, n_random=1500, n_starts=4, iterations=80, seed=2)
    c = res.contact
    # the returned contact reproduces the value through the public coefficient matrix
    A = contact.coefficient_matrix(s, s, c.r1[0], c.r2[0], body_to_world=(c.Q1[0], c.Q2[0]))
    assert math.isclose(np.linalg.eigvalsh(A)[-1], res.value, rel_tol=1e-12)
    assert res.value <= dtcrit.a_bound(s) * (1 + SLACK)
    assert res.value >= dtcrit.a_bound(s) * (1 - 1e-6)
    assert (res.value > dtcrit.a_max(s) * (1 + 1e-9)) == exceeds


# ---------------------------------------------------------------------------------- scale invariance


@given(decades, st.floats(1, 4), st.floats(1, 4), st.floats(-1, 6))
def test_box_bounds_scale_with_mass_over_decades(log_c, rb, ra, log_rho):
    c = 10.0**log_c
    b, a = c * rb, c * rb * ra
    box = Box(a, b, c, density=10.0**log_rho)
    unit = Box(ra * rb, rb, 1.0, density=1.0)
    assert math.isclose(dtcrit.a_bound(box) * box.mass, dtcrit.a_bound(unit) * unit.mass, rel_tol=1e-12)
    assert math.isclose(dtcrit.a_max(box) * box.mass, dtcrit.a_max(unit) * unit.mass, rel_tol=1e-12)
    batch = cs.random_contacts(box, box, 500, seed=4)
    assert np.all(batch.largest_eigenvalues(box, box) <= dtcrit.a_bound(box) * (1 + SLACK))


def test_runtime_contact_modules_do_not_import_sympy():
    import subprocess
    import sys

    code = ("import sys, dtcrit, dtcrit.bodies.contact, dtcrit.bodies.contact_search; from dtcrit.bodies import Box; "
            "dtcrit.a_bound(Box(1.0, 1.0, 1.0, density=1.0)); assert 'sympy' not in sys.modules, 'sympy imported'")
    subprocess.run([sys.executable, "-c", code], check=True)
