"""The geometric lemmas behind the sphere-packing bound (dtcrit.scenes.dense_cells), against facts derived
independently here: the law of cosines for touching spheres, the kissing configurations, and the end matrix
against a contact element assembled by hand."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, strategies as st

from dtcrit.scenes.dense_cells import end_matrix, max_code_size, min_contact_angle_cos


def test_equal_touching_spheres_are_sixty_degrees_apart():
    assert min_contact_angle_cos(1.0, 1.0, 1.0, overlap=0.0, contact_tolerance=0.0) == pytest.approx(0.5, rel=1e-15)


@given(st.floats(-2, 2), st.floats(-2, 2), st.floats(-2, 2))
def test_law_of_cosines_for_touching_spheres(li, lj, lk):
    """Spheres j, k touching i and each other: the angle between the normals is the triangle's angle at i."""
    ri, rj, rk = 10.0**li, 10.0**lj, 10.0**lk
    a, b, c = ri + rj, ri + rk, rj + rk
    cos_i = (a * a + b * b - c * c) / (2 * a * b)
    got = float(min_contact_angle_cos(ri, rj, rk, overlap=0.0, contact_tolerance=0.0))
    assert got == pytest.approx(cos_i, abs=1e-12)


@pytest.mark.parametrize("deg,expected", [(61.0, 12), (60.0, 12), (57.2, 12), (56.0, 13), (90.0, 6), (120.0, 3)])
def test_how_many_normals_fit(deg, expected):
    """Configurations that exist: 12 points pairwise 63.4 deg apart (icosahedron), 13 at 57.1 deg (Tammes), the
    octahedron's 6 at 90 deg, 3 on a great circle at 120 deg."""
    n = max_code_size(math.radians(deg))
    assert n >= expected  # an upper bound on the count: never below a configuration that exists
    if deg in (60.0, 61.0, 57.2):  # above the Tammes angle of 13 points (57.137 deg): exactly the kissing number
        assert n == 12


def test_end_matrix_is_the_contact_element_of_one_particle():
    """Q(n) with weights 1 is the block of particle i of k_n (n.d)^2 + k_s |P d|^2, d = u + theta x (R n),
    in mass-scaled coordinates x = sqrt(m) u, y = sqrt(I) theta."""
    m, i, r, kn, ks = 2.0, 0.3, 0.7, 5.0, 3.0
    n = np.array([0.2, -0.6, 0.77])
    n /= np.linalg.norm(n)
    rn = r * n
    skew = np.array([[0, -rn[2], rn[1]], [rn[2], 0, -rn[0]], [-rn[1], rn[0], 0]])
    B = np.hstack([np.eye(3), -skew])  # d = u - [R n]x theta = u + theta x R n
    Kc = kn * np.outer(n, n) + ks * (np.eye(3) - np.outer(n, n))
    scale = np.diag([m ** -0.5] * 3 + [i ** -0.5] * 3)
    by_hand = scale @ B.T @ Kc @ B @ scale
    Q = end_matrix(n, (kn / m, ks / m, ks * r * r / i, 0.0, 0.0))
    assert np.allclose(np.linalg.eigvalsh(Q), np.linalg.eigvalsh(by_hand), rtol=1e-12, atol=1e-12)
