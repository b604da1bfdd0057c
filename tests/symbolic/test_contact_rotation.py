"""Rotation-dominant terms (Peng et al. 2020, Eqs 50-57): ``b_max`` (Eq 54) and the tight ``b_bound``.

Independent route: Euler's equations evaluated directly (``-I^-1 (w x I w)`` with NumPy cross
products) for random angular velocities and orientations; the maximum of the gyroscopic term by
dense sampling plus local maximisation of that direct evaluation.
"""
import math
from types import SimpleNamespace

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize
from scipy.spatial.transform import Rotation

import dtcrit
from dtcrit.bodies import contact
from dtcrit.bodies import Box, Ellipsoid, Sphere
from dtcrit.symbolic import tip_configurations as tips


def body(inertia):
    """A minimal object with the shape interface (only the inertia matters here)."""
    return SimpleNamespace(mass=1.0, inertia=tuple(float(i) for i in inertia), half_lengths=(1.0, 1.0, 1.0), max_arm=1.0)


# physical principal moments: I_x = s_y + s_z, ... with second moments s_i >= 0 over many decades
second_moments = st.tuples(*[st.floats(-6, 6)] * 3).map(lambda t: np.array([10.0**x for x in t]))


def inertia_from(s):
    return np.array([s[1] + s[2], s[0] + s[2], s[0] + s[1]])


def euler(I, w):
    """Torque-free angular acceleration in the local frame, directly from Euler's equations."""
    return -np.cross(w, I * w) / I


@given(second_moments, second_moments, st.integers(0, 2**32 - 1))
def test_relative_angular_acceleration_respects_eq53_and_the_tight_bound(s1, s2, seed):
    I1, I2 = inertia_from(s1), inertia_from(s2)
    rng = np.random.default_rng(seed)
    n = 2000
    wmax = 10.0 ** rng.uniform(-3, 3)
    w1 = rng.normal(size=(n, 3))
    w2 = rng.normal(size=(n, 3))
    w1 *= (wmax * rng.uniform(0, 1, (n, 1)) ** (1 / 3)) / np.linalg.norm(w1, axis=1, keepdims=True)
    w2 *= (wmax * rng.uniform(0, 1, (n, 1)) ** (1 / 3)) / np.linalg.norm(w2, axis=1, keepdims=True)
    Q1 = Rotation.random(n, random_state=seed % 2**31).as_matrix()  # body -> global
    Q2 = Rotation.random(n, random_state=(seed + 1) % 2**31).as_matrix()
    a1 = np.einsum("nij,nj->ni", Q1, euler(I1, np.einsum("nji,nj->ni", Q1, w1)))
    a2 = np.einsum("nij,nj->ni", Q2, euler(I2, np.einsum("nji,nj->ni", Q2, w2)))
    wdot_c = np.abs(a2 - a1)
    B = contact.b_max(body(I1)) + contact.b_max(body(I2))
    G = contact.b_bound(body(I1)) + contact.b_bound(body(I2))
    scale = wmax**2
    # rounding of the direct float evaluation: w x I w cancels terms of size |w|^2 max(I)
    noise = 1e-14 * scale * sum(np.max(I) / np.min(I) for I in (I1, I2))
    assert np.all(wdot_c <= scale * G * (1 + 1e-12) + noise)
    assert np.all(wdot_c <= scale * B * (1 + 1e-12) + noise)
    assert G <= B / math.sqrt(3) * (1 + 1e-12)


def _mp_gyroscopic_norm(I, w):
    """|I^-1 (w x I w)| at 50 digits from the float inputs (no cancellation error)."""
    with mp.workdps(50):
        Im = [mp.mpf(float(x)) for x in I]
        u = [mp.mpf(float(x)) for x in w]
        n = mp.sqrt(sum(x * x for x in u))
        u = [x / n for x in u]
        Iu = [Im[k] * u[k] for k in range(3)]
        c = [u[1] * Iu[2] - u[2] * Iu[1], u[2] * Iu[0] - u[0] * Iu[2], u[0] * Iu[1] - u[1] * Iu[0]]
        return mp.sqrt(sum((c[k] / Im[k]) ** 2 for k in range(3)))


def _max_gyroscopic(I, seed=0):
    """max over unit w of |I^-1 (w x I w)| directly: 10000 random directions and Nelder-Mead from the
    4 best locate the maximum in float64; the candidates are then evaluated at 50 digits."""
    rng = np.random.default_rng(seed)
    w = rng.normal(size=(10000, 3))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    vals = np.linalg.norm(euler(I, w), axis=1)

    def unit(x):
        return np.array([np.sin(x[0]) * np.cos(x[1]), np.sin(x[0]) * np.sin(x[1]), np.cos(x[0])])

    cands = [w[i] for i in np.argsort(-vals)[:20]]
    for i in np.argsort(-vals)[:4]:
        x0 = [math.acos(max(-1.0, min(1.0, w[i, 2]))), math.atan2(w[i, 1], w[i, 0])]
        res = minimize(lambda x: -np.linalg.norm(euler(I, unit(x))), x0, method="Nelder-Mead",
                       options={"xatol": 1e-12, "fatol": 1e-18, "maxfev": 4000})
        cands.append(unit(res.x))
    return max(_mp_gyroscopic_norm(I, c) for c in cands)


@settings(max_examples=12)
@given(second_moments)
def test_b_bound_is_the_maximum_of_the_gyroscopic_term(s):
    I = inertia_from(s)
    G = contact.b_bound(body(I))
    B = contact.b_max(body(I))
    assert B / 2 * (1 - 1e-12) <= G <= B / math.sqrt(3) * (1 + 1e-12)
    found = _max_gyroscopic(I)
    assert found <= G * (1 + 1e-12) + 1e-30  # a bound: never exceeded
    assert found >= G * (1 - 1e-8)  # and attained (to the accuracy of the float search)


def test_b_bound_approaches_b_over_sqrt3_for_a_ribbon():
    ribbon = Box(100.0, 1.0, 0.01, density=1.0)
    assert contact.b_bound(ribbon) / contact.b_max(ribbon) > 0.577
    assert math.isclose(contact.b_bound(Ellipsoid(3.0, 2.0, 1.0, density=1.0)) / 0.8, 0.5, rel_tol=1e-12)


@given(st.floats(-3, 3), st.floats(0, 1), st.floats(0, 1))
def test_b_max_of_an_ellipsoid(log_a, fb, fc):
    a = 10.0**log_a
    b = a * (0.05 + 0.95 * fb)
    c = b * (0.05 + 0.95 * fc)
    e = Ellipsoid(a, b, c, density=1.0)
    assert math.isclose(dtcrit.b_max(e), (a * a - c * c) / (a * a + c * c), rel_tol=1e-12, abs_tol=1e-15)


def test_b_max_of_a_sphere_is_zero():
    assert dtcrit.b_max(Sphere(0.1, density=1000.0)) == 0.0
    assert contact.b_bound(Sphere(0.1, density=1000.0)) == 0.0


@pytest.mark.parametrize("label", ["A", "B", "C"])
def test_fig2_configurations_reach_half_of_eq53_and_no_more(label):
    """Direct evaluation in the Figure 2 orientations: max |wdot_c,k| = w_max^2 (|c1| + |c2|)/2 <= w_max^2 (B1+B2)/2."""
    e = Ellipsoid(3.0, 2.0, 1.0, density=1000.0)
    I = np.array(e.inertia)
    cfg = tips.FIG2[label]
    Q = [np.array(cfg.R1, dtype=float).T, np.array(cfg.R2, dtype=float).T]  # body -> global
    c = np.abs(np.array([(I[1] - I[2]) / I[0], (I[2] - I[0]) / I[1], (I[0] - I[1]) / I[2]]))
    B = dtcrit.b_max(e)
    rng = np.random.default_rng(5)
    wmax = 2.0
    best_all = 0.0
    for k in range(3):
        # the body axis of each particle that lies along global axis k carries the term on that axis
        ax = [int(np.argmax(np.abs(Qj[k]))) for Qj in Q]
        expected = wmax**2 * (c[ax[0]] + c[ax[1]]) / 2
        best = 0.0
        for s1 in (1, -1):
            for s2 in (1, -1):
                wl = []
                for j in range(2):
                    w = np.zeros(3)
                    others = [i for i in range(3) if i != ax[j]]
                    w[others] = wmax / math.sqrt(2) * np.array([1.0, s1 if j == 0 else s2])
                    wl.append(w)
                acc = Q[1] @ euler(I, wl[1]) - Q[0] @ euler(I, wl[0])
                best = max(best, abs(acc[k]))
        assert math.isclose(best, expected, rel_tol=1e-12)
        # and random velocities never exceed it
        w = rng.normal(size=(4000, 2, 3))
        w *= wmax * rng.uniform(0, 1, (4000, 2, 1)) / np.linalg.norm(w, axis=2, keepdims=True)
        acc = np.einsum("ij,nj->ni", Q[1], euler(I, w[:, 1])) - np.einsum("ij,nj->ni", Q[0], euler(I, w[:, 0]))
        assert np.max(np.abs(acc[:, k])) <= expected * (1 + 1e-12)
        best_all = max(best_all, best)
    assert best_all <= wmax**2 * B * (1 + 1e-12)  # Eq. (53) with B1 = B2 = B, loose by 2 here
    if label in ("A", "B"):
        assert math.isclose(best_all, wmax**2 * B, rel_tol=1e-12)
