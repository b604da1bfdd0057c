"""Appendix A of Peng et al. 2020 (which contact maximises |xdd_c|?) against independent checks.

The coarse search runs once (module fixture); its findings are then re-derived here without the
code under test:

* relative accelerations from the chain of Eqs. (1)-(19) typed here (Euler's equations with zero
  angular velocity), not from the coefficient-matrix routine;
* eigenvalues by ``numpy.linalg.eigvalsh`` of the matrix built column by column from that chain
  (``F`` = unit vectors);
* admissibility from first principles: for ellipsoids, the contact point lies on both surfaces
  (implicit equations) with antiparallel gradients; for boxes, the contact point is a vertex of
  each box whose normal cone contains the contact normal;
* the exact maximum eigenvalue for two identical ellipsoids, 2/m + 2 a^2/I_yy (attained with
  collinear long axes), checked by random sampling of admissible contacts drawn here.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dtcrit.figures.appendix_a import appendix_a_study
from dtcrit.figures.appendix_a_search import paper_ellipsoid

A_, B_, C_ = 3.0, 2.0, 1.0
F = np.array([1.0, 1.0, 1.0])


@pytest.fixture(scope="module")
def study():
    return appendix_a_study(fine=False)


# ------------------------------------------------------------------------------ independent helpers
def ellipsoid_props():
    """Unit density: m = 4/3 pi abc, I = m (b^2 + c^2)/5 etc. (textbook closed forms)."""
    m = 4.0 / 3.0 * math.pi * A_ * B_ * C_
    return m, np.array([B_**2 + C_**2, A_**2 + C_**2, A_**2 + B_**2]) * m / 5.0


def box_props():
    m = 8.0 * A_ * B_ * C_
    return m, np.array([B_**2 + C_**2, A_**2 + C_**2, A_**2 + B_**2]) * m / 3.0


def xdd_chain(force, r1, r2, Q1, Q2, m, inertia):
    """Eqs. (1)-(19) with zero angular velocity: relative acceleration of the contact points.

    Q: body-to-global; the paper's R = Q^T maps global to local (Eq. (5)).
    """
    M_G1 = np.cross(r1, -force)  # Eq. (3)
    M_G2 = np.cross(r2, force)  # Eq. (4)
    wd_L1 = (Q1.T @ M_G1) / inertia  # Eqs. (5), (11)
    wd_L2 = (Q2.T @ M_G2) / inertia  # Eqs. (6), (12)
    wd_G1, wd_G2 = Q1 @ wd_L1, Q2 @ wd_L2  # Eqs. (13)-(14)
    x1 = np.cross(wd_G1, r1) - force / m  # Eq. (17)
    x2 = np.cross(wd_G2, r2) + force / m  # Eq. (18)
    return x2 - x1  # Eq. (19)


def matrix_chain(r1, r2, Q2, m, inertia):
    return np.column_stack([xdd_chain(e, r1, r2, np.eye(3), Q2, m, inertia) for e in np.eye(3)])


def config_arrays(cfg_dict):
    # body-to-world quaternion (w, x, y, z); SciPy's from_quat takes (x, y, z, w) in the same convention
    Q2 = Rotation.from_quat(np.roll(np.array(cfg_dict["quaternion_2_body_to_world_wxyz"]), -1)).as_matrix()
    return (np.array(cfg_dict["r1"]), np.array(cfg_dict["r2"]), Q2, np.array(cfg_dict["normal_1"]),
            np.array(cfg_dict["centre_2"]))


def ellipsoid_tangent(r1, r2, Q2, tol):
    """Contact point on both ellipsoids, gradients antiparallel (so a separating plane exists)."""
    D2 = np.array([A_, B_, C_]) ** 2
    p1 = r1
    p2 = Q2.T @ r2
    on1 = abs(np.sum(p1**2 / D2) - 1.0) < tol
    on2 = abs(np.sum(p2**2 / D2) - 1.0) < tol
    g1 = p1 / D2
    g2 = Q2 @ (p2 / D2)
    cosang = g1 @ g2 / np.linalg.norm(g1) / np.linalg.norm(g2)
    return on1 and on2 and cosang < -1 + tol


def inside_both(centre2, Q2, n=81):
    """A point inside both ellipsoids near the contact (scan), or None."""
    xs = np.linspace(2.0, 3.2, n)
    zs = np.linspace(-0.5, 1.5, n)
    X, Z = np.meshgrid(xs, zs)
    P = np.column_stack([X.ravel(), np.zeros(X.size), Z.ravel()])
    D2 = np.array([A_, B_, C_]) ** 2
    f1 = np.sum(P**2 / D2, axis=1)
    L = (P - centre2) @ Q2  # local coordinates of particle 2: Q2^T (p - c)
    f2 = np.sum(L**2 / D2, axis=1)
    ok = (f1 < 0.99) & (f2 < 0.99)
    return P[np.argmax(ok)] if np.any(ok) else None


# ------------------------------------------------------------------------------ the ellipsoid pair
def test_orthogonal_configurations_reproduce_eq22(study):
    """The paper's orthogonal tip-to-tip values (Eq. (22) and its 90-degree roll), typed by hand."""
    m, (ixx, iyy, izz) = ellipsoid_props()
    s = 2.0 / m
    sc1 = np.array([s + A_**2 / iyy, s + A_**2 / izz + A_**2 / izz, s + A_**2 / iyy])
    sc2 = np.array([s + A_**2 / izz, s + A_**2 / izz + A_**2 / iyy, s + A_**2 / iyy])
    got = study["summary"]["orthogonal_scenarios"]
    vals = sorted(v["accel"] for v in got.values())
    assert vals == pytest.approx(sorted([np.linalg.norm(sc1 * F), np.linalg.norm(sc2 * F)]), rel=1e-12)
    assert study["summary"]["orthogonal"] == pytest.approx(max(np.linalg.norm(sc1), np.linalg.norm(sc2)), rel=1e-12)
    for o in study["objects"]["orthogonal"]:
        r1, r2, Q2 = np.array(o.r1), np.array(o.r2), np.array(o.orientation)
        np.testing.assert_allclose(matrix_chain(r1, r2, Q2, m, np.array([ixx, iyy, izz])), np.array(o.matrix),
                                   rtol=1e-12, atol=1e-15)


def test_orthogonal_configuration_interpenetrates(study):
    """Outward normals +x and -z are not opposite: a point lies inside both ellipsoids."""
    for o in study["objects"]["orthogonal"]:
        assert inside_both(np.array(o.centre2), np.array(o.orientation)) is not None
    assert all(d > 0.1 for d in study["summary"]["orthogonal_penetration_depth"])
    assert study["summary"]["orthogonal_is_admissible"] is False


def test_counter_example_orthogonal_is_not_the_maximum(study):
    """The search's maximiser is admissible, reproduced by the Eq. (1)-(19) chain, and beats the
    orthogonal configuration by more than 25 %."""
    s = study["summary"]
    m, inertia = ellipsoid_props()
    r1, r2, Q2, n, c2 = config_arrays(s["max_config"])
    acc = np.linalg.norm(xdd_chain(F, r1, r2, np.eye(3), Q2, m, inertia))
    assert acc == pytest.approx(s["max_found"], rel=1e-5)  # the config is rounded to 6 digits
    assert ellipsoid_tangent(r1, r2, Q2, tol=1e-5)
    np.testing.assert_allclose(r1 - r2, c2, atol=1e-5)
    assert s["orthogonal_is_max"] is False
    assert acc > 1.25 * s["orthogonal"]
    # ... and it is not a tip contact: the contact point is off the long axis
    assert np.linalg.norm(r1[1:]) > 0.5


def test_largest_eigenvalue_is_collinear_tip_to_tip(study):
    """max lambda_max(A) = 2/m + 2 a^2/I_yy (collinear long axes); no sampled admissible contact exceeds it;
    Eq. (26) is an upper bound here (by the factor 20/11)."""
    s = study["summary"]
    m, (ixx, iyy, izz) = ellipsoid_props()
    exact = 2.0 / m + 2.0 * A_**2 / iyy
    assert s["max_lambda_found"] == pytest.approx(exact, rel=1e-9)
    r1, r2, Q2, n, c2 = config_arrays(s["max_lambda_config"])
    lam = np.linalg.eigvalsh(matrix_chain(r1, r2, Q2, m, np.array([ixx, iyy, izz])))[-1]
    assert lam == pytest.approx(exact, rel=1e-5)
    assert ellipsoid_tangent(r1, r2, Q2, tol=1e-5)
    # random admissible contacts (drawn here): point with normal n on an ellipsoid is D^2 n / |D n|
    rng = np.random.default_rng(11)
    D = np.array([A_, B_, C_])
    N = 20000
    nrm = rng.normal(size=(N, 3))
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    Q = Rotation.random(N, random_state=rng).as_matrix()
    p1 = D**2 * nrm / np.linalg.norm(D * nrm, axis=1, keepdims=True)
    nu = -np.einsum("nji,nj->ni", Q, nrm)
    p2 = D**2 * nu / np.linalg.norm(D * nu, axis=1, keepdims=True)
    r2 = np.einsum("nij,nj->ni", Q, p2)
    inertia = np.array([ixx, iyy, izz])
    cols = []
    for e in np.eye(3):  # the chain of Eqs. (1)-(19), vectorised, column by column
        f = np.broadcast_to(e, (N, 3))
        wd1 = np.cross(p1, -f) / inertia
        wd2 = np.einsum("nij,nj->ni", Q, np.einsum("nji,nj->ni", Q, np.cross(r2, f)) / inertia)
        cols.append(np.cross(wd2, r2) + f / m - (np.cross(wd1, p1) - f / m))
    M = np.stack(cols, axis=-1)
    worst = np.linalg.eigvalsh(0.5 * (M + np.swapaxes(M, 1, 2)))[:, -1].max()
    assert worst <= exact * (1 + 1e-12)
    assert worst > 0.9 * exact
    eq26 = 2 * A_**2 / ixx + 2 / m
    assert s["a_max_eq26"] == pytest.approx(eq26, rel=1e-12)
    assert exact / eq26 == pytest.approx(11 / 20, rel=1e-12)
    assert s["max_found"] <= eq26 * math.sqrt(3)


def test_scenario_centre_moved_peaks_at_the_tip(study):
    """Paper, Fig. A2: with particle 2's orientation fixed, |xdd_c| is largest at the tip (3, 0, 0)."""
    for fam in study["objects"]["scenarios"]["centre_moved"]:
        np.testing.assert_allclose(fam.best.contact_point, [A_, 0.0, 0.0], atol=1e-12)


def test_paper_pinned_family_prefers_collinear_axes(study):
    """In the paper's own family (tip of 2 pinned on (3, 0, 0)), the collinear configuration beats the
    orthogonal one: A = diag(2/m, 2/m + 2a^2/I_zz, 2/m + 2a^2/I_yy) for roll 0, by hand."""
    m, (ixx, iyy, izz) = ellipsoid_props()
    collinear = np.linalg.norm([2 / m, 2 / m + 2 * A_**2 / izz, 2 / m + 2 * A_**2 / iyy])
    fam = study["objects"]["scenarios"]["orientation_pinned_tip"][0]
    assert fam.best.accel == pytest.approx(collinear, rel=1e-12)
    assert fam.best.accel > 1.1 * fam.reference.accel
    np.testing.assert_allclose(fam.best.centre2, [2 * A_, 0.0, 0.0], atol=1e-12)


# ------------------------------------------------------------------------------ other shapes
def test_box_breaks_eq26(study):
    """For a 3 x 2 x 1 m half-length box the largest eigenvalue exceeds Eq. (26): a vertex-vertex contact."""
    s = study["summary"]["shapes"]["box"]
    m, inertia = box_props()
    eq26 = 2 * A_**2 / inertia[0] + 2 / m
    assert s["a_max_eq26"] == pytest.approx(eq26, rel=1e-12)
    r1, r2, Q2, n, c2 = config_arrays(s["max_lambda_config"])
    corner = np.array([A_, B_, C_])
    # admissible: r1 is the vertex of box 1 selected by n, Q2^T r2 the vertex of box 2 selected by -Q2^T n
    np.testing.assert_allclose(r1, np.sign(n) * corner, atol=1e-5)
    np.testing.assert_allclose(Q2.T @ r2, np.sign(Q2.T @ -n) * corner, atol=1e-4)
    lam = np.linalg.eigvalsh(matrix_chain(r1, r2, Q2, m, inertia))[-1]
    assert lam > 1.03 * eq26
    assert s["eq26_is_upper_bound_lambda"] is False
    assert s["max_lambda"] <= s["a_bound"] * (1 + 1e-12)


def test_superquadric_keeps_eq26_and_meets_a_bound(study):
    s = study["summary"]["shapes"]["superquadric"]
    assert s["eq26_is_upper_bound_lambda"] is True and s["max_lambda"] < 0.75 * s["a_max_eq26"]
    assert s["a_bound"] * (1 - 1e-4) <= s["max_lambda"] <= s["a_bound"] * (1 + 1e-9)
    assert all(abs(d) < 1e-9 for d in s["penetration_of_maximisers"])


def test_unit_density_mass():
    m, _ = ellipsoid_props()
    assert paper_ellipsoid().mass == pytest.approx(m, rel=1e-14)
