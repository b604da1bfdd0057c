"""Leapfrog with YADE's and PFC's local damping (``dtcrit.integrators.local_damping``).

References are independent of the module: the laws re-written here component by component from their
sources, the undamped leapfrog of ``dtcrit.integrators.schemes``, mpmath spectral radii, SciPy eigen-solves.
"""
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy import linalg

from dtcrit.integrators import local_damping as L
from dtcrit.integrators.schemes import INTEGRATORS, LinearForce


def _sign(v):
    return float(v > 0) - float(v < 0)


def _reference_step(x, u, h, K, m, alpha, law):
    """One step written from the sources, scalar loops (YADE cundallDamp2nd; PFC F_d = -alpha |F| sign(v))."""
    n = len(x)
    F = [-sum(K[i][j] * x[j] for j in range(n)) for i in range(n)]
    u2 = []
    for i in range(n):
        if law == "pfc":
            Fd = F[i] - alpha * abs(F[i]) * _sign(u[i])
            u2.append(u[i] + h * Fd / m[i])
        else:
            a = F[i] / m[i]
            a *= 1 - alpha * _sign(a * (u[i] + 0.5 * h * a))
            u2.append(u[i] + h * a)
    return [x[i] + h * u2[i] for i in range(n)], u2


@pytest.mark.parametrize("law", L.LAWS)
def test_step_matches_the_laws_as_the_sources_state_them(law):
    rng = np.random.default_rng(3)
    K, im = L.sphere_wall_sphere((1.0, 0.4, -0.2), 1.0, 0.3, 2.0, 0.5, 1.0, 0.25)
    for _ in range(50):
        x, u = rng.standard_normal(6), rng.standard_normal(6)
        h, a = rng.uniform(0.05, 1.0), rng.uniform(0.0, 0.9)
        xr, ur = _reference_step(list(x), list(u), h, K.tolist(), list(1 / im), a, law)
        xs, us = L.step(x[None, :], u[None, :], h, K, im, a, law)
        np.testing.assert_allclose(xs[0], xr, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(us[0], ur, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("law", L.LAWS)
def test_alpha_zero_is_the_undamped_leapfrog(law):
    f = LinearForce(2.5, 0.0)
    x, u = 0.3, -0.7
    xs, us = np.array([[x]]), np.array([[u]])
    for _ in range(100):
        x, u = INTEGRATORS["leapfrog"].step((x, u), 0.9, f)
        xs, us = L.step(xs, us, 0.9, np.array([[2.5]]), np.array([1.0]), 0.0, law)
    assert xs[0, 0] == pytest.approx(x, rel=1e-12) and us[0, 0] == pytest.approx(u, rel=1e-12)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.floats(-30, 30), st.floats(0.0, 0.9), st.floats(0.05, 1.4), st.sampled_from(L.LAWS), st.integers(0, 2**31))
def test_the_law_is_homogeneous_of_degree_one(log10c, alpha, tau, law, seed):
    """Scaling by a power of two is exact in floating point: the whole run scales exactly."""
    rng = np.random.default_rng(seed)
    c = 2.0 ** round(log10c * math.log2(10))
    x, u = rng.standard_normal((1, 3)), rng.standard_normal((1, 3))
    K, im = L.chain([1.0, 0.5, 2.0], [1.0, 2.0, 1.0, 0.5])
    h = tau / L.omega_max(K, im)
    xa, ua, xb, ub = x, u, c * x, c * u
    for _ in range(200):
        xa, ua = L.step(xa, ua, h, K, im, alpha, law)
        xb, ub = L.step(xb, ub, h, K, im, alpha, law)
    assert np.array_equal(c * xa, xb) and np.array_equal(c * ua, ub)


def _rho_stiffened(tau, alpha):
    mp.mp.dps = 50
    t2 = (1 + mp.mpf(alpha)) * mp.mpf(tau) ** 2
    return max(abs(e) for e in mp.eig(mp.matrix([[1 - t2, 1], [-t2, 1]]))[0])


@pytest.mark.parametrize("alpha", [0.1, 0.3, 0.7, 0.9])
def test_flip_threshold_is_where_the_stiffened_leapfrog_reaches_minus_one(alpha):
    f = float(L.flip_threshold(alpha))
    assert _rho_stiffened(f * (1 - 1e-9), alpha) == pytest.approx(1, abs=1e-30)
    assert _rho_stiffened(f * (1 + 1e-6), alpha) > 1.002


@pytest.mark.parametrize("law", L.LAWS)
@pytest.mark.parametrize("alpha", [0.0, 0.2, 0.5, 0.9])
def test_one_dof_bounded_below_and_growing_above(law, alpha):
    rng = np.random.default_rng(11)
    th = rng.uniform(0, 2 * np.pi, 16)
    amp = 10.0 ** rng.uniform(-12, 12, 16)[:, None]
    x0, u0 = amp * np.cos(th)[:, None], amp * np.sin(th)[:, None]
    f = 2 / math.sqrt(1 + alpha)  # independently: the flip map's stiffness (1 + alpha) omega^2
    K, im = np.array([[4.0]]), np.array([0.25])  # omega = 1
    assert not L.grows(x0, u0, 0.99 * f, K, im, alpha, law, 5000).any()
    assert L.grows(x0, u0, 1.01 * f, K, im, alpha, law, 5000).all()


def test_pfc_lyapunov_form_never_increases_and_yade_has_a_counterexample():
    rng = np.random.default_rng(5)
    n = 5000
    K, im = L.sphere_wall_sphere((1.0, 1.0, 1.0), 1.0, 0.3, 2.0, 0.5, 1.0, 0.25)
    w = float(np.sqrt(linalg.eigh(K, np.diag(1 / im), eigvals_only=True)[-1]))
    x, u = rng.standard_normal((n, 6)), rng.standard_normal((n, 6))
    al = rng.uniform(0, 0.9, n)
    h = rng.uniform(0.05, 1.0, n) * 2 / np.sqrt(1 + al) / w
    i0 = L.lyapunov(x, u, h, K, im, al)
    assert (i0 > 0).all()
    x1, u1 = L.step(x, u, h, K, im, al, "pfc")
    assert ((L.lyapunov(x1, u1, h, K, im, al) - i0) / i0).max() < 1e-12
    x1, u1 = L.step(x, u, h, K, im, al, "yade")
    assert ((L.lyapunov(x1, u1, h, K, im, al) - i0) / i0).max() > 1e-3


@pytest.mark.parametrize("alpha", [0.3, 0.7])
def test_multi_dof_pfc_bound_from_an_independent_eigen_solve(alpha):
    rng = np.random.default_rng(9)
    m, k = 10.0 ** rng.uniform(-1, 1, 5), 10.0 ** rng.uniform(-1, 1, 6)
    K, im = L.chain(m, k)
    w = float(np.sqrt(linalg.eigh(K, np.diag(m), eigvals_only=True)[-1]))
    x0, u0 = rng.standard_normal((8, 5)), rng.standard_normal((8, 5))
    f = 2 / math.sqrt(1 + alpha)
    assert not L.grows(x0, u0, 0.99 * f / w, K, im, alpha, "pfc", 4000).any()
    assert L.grows(x0, u0, 1.01 * f / w, K, im, alpha, "pfc", 4000).all()


def test_yade_grows_below_the_bound_on_a_chain():
    """The counterexample of derivations/records/local_damping.md: PFC's law stays bounded on the same starts."""
    rng = np.random.default_rng(20240917 + 1)
    for _ in range(3):
        m, k = 10.0 ** rng.uniform(-1, 1, 5), 10.0 ** rng.uniform(-1, 1, 6)
    K, im = L.chain(m, k)
    w = float(np.sqrt(linalg.eigh(K, np.diag(m), eigvals_only=True)[-1]))
    v = np.random.default_rng(1).standard_normal((256, 10))
    x0, u0 = v[:, :5], v[:, 5:]
    h = 0.95 * (2 / math.sqrt(1.9)) / w
    assert L.grows(x0, u0, h, K, im, 0.9, "yade", 4000).any()
    assert not L.grows(x0, u0, h, K, im, 0.9, "pfc", 4000).any()


def test_bad_law_and_bracket_are_refused():
    with pytest.raises(ValueError, match="law"):
        L.step(np.ones((1, 1)), np.ones((1, 1)), 0.1, np.eye(1), np.ones(1), 0.5, "edem")
    with pytest.raises(ValueError, match="lower end"):
        L.bisect_threshold(np.ones((1, 1)), np.ones((1, 1)), np.eye(1), np.ones(1), 0.0, "pfc", 1.0, 2.1, 2.5)
