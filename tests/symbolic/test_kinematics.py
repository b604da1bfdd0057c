"""Symbolic contact kinematics (Peng et al. 2020, Eqs 1-26, 49) against independent evaluations.

The derived Figure 2 matrices and velocity terms are compared with a direct numerical evaluation of
the rigid-body equations written out here (cross products, a linear solve of Euler's equations),
in float64 and with mpmath at 50 digits, for random rotations of the whole pair.
"""
import functools

import mpmath as mp
import numpy as np
import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from dtcrit._generated import contact as gen
from dtcrit.symbolic import coefficient_forms as cforms
from dtcrit.symbolic import kinematics as kin
from dtcrit.symbolic import candidate_scores as scores
from dtcrit.symbolic import quaternions as quat
from dtcrit.symbolic import tip_configurations as tips

# ---------------------------------------------------------------------------------- helpers

decades = st.floats(min_value=-6.0, max_value=6.0)


def quaternion_strategy():
    return st.tuples(*[st.floats(-1.0, 1.0)] * 4).filter(lambda q: sum(c * c for c in q) > 1e-3)


def direct_float(m, I, R, r, w_global, F):
    """xdd_c and wdot_c for two particles by the rigid-body equations, written out independently.

    m, I (3x3 local), R (paper convention, global -> local), r (global arm), w_global: pairs.
    """
    xdd = np.zeros(3)
    wdot = np.zeros(3)
    for j, sign in ((0, -1.0), (1, 1.0)):
        moment_global = sign * np.cross(r[j], F)
        wl = R[j] @ w_global[j]
        wdot_local = np.linalg.solve(I[j], R[j] @ moment_global - np.cross(wl, I[j] @ wl))
        wdot_global = R[j].T @ wdot_local
        acc = np.cross(wdot_global, r[j]) + np.cross(w_global[j], np.cross(w_global[j], r[j])) + sign * F / m[j]
        xdd += sign * acc
        wdot += sign * wdot_global
    return xdd, wdot


def _mp_cross(a, b):
    return mp.matrix([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def direct_mp(m, I, R, r, w_global, F):
    xdd = mp.matrix(3, 1)
    for j, sign in ((0, -1), (1, 1)):
        moment_global = sign * _mp_cross(r[j], F)
        wl = R[j] * w_global[j]
        wdot_local = mp.lu_solve(I[j], R[j] * moment_global - _mp_cross(wl, I[j] * wl))
        wdot_global = R[j].T * wdot_local
        acc = _mp_cross(wdot_global, r[j]) + _mp_cross(w_global[j], _mp_cross(w_global[j], r[j])) + sign * F / m[j]
        xdd += sign * acc
    return xdd


@functools.lru_cache(maxsize=None)
def fig2_functions(label):
    """Derived A, Omega (global omega) and wdot_c of one configuration as NumPy and mpmath functions."""
    d = tips.fig2_symbolic(label, False)
    syms = sorted(set().union(*[e.free_symbols for part in d.values() for e in part]), key=str)
    return syms, {k: sp.lambdify(syms, v, modules="numpy") for k, v in d.items()}, {
        k: sp.lambdify(syms, v, modules="mpmath") for k, v in d.items()}


def _values(data, label):
    """Random physical parameters over many decades for one configuration."""
    syms, _, _ = fig2_functions(label)
    vals = {}
    for ps in (tips.P1, tips.P2):
        scale = 10.0 ** data.draw(decades)
        m = 10.0 ** data.draw(decades)
        a, b, c = sorted((scale * (1 + data.draw(st.floats(0, 3))) for _ in range(3)), reverse=True)
        base = m * scale**2
        ixx, iyy, izz = sorted((base * 10.0 ** data.draw(st.floats(-1, 1)) for _ in range(3)))
        vals.update({ps.m: m, ps.Ixx: ixx, ps.Iyy: iyy, ps.Izz: izz})
        vals.update(dict(zip(ps.half_lengths, (a, b, c))))
        vals.update({w: data.draw(st.floats(-3, 3)) for w in ps.w})
    return [vals[s] for s in syms], vals


# ---------------------------------------------------------------------------------- convention


def test_rotation_convention_is_self_consistent():
    assert all(quat.check_rotation_convention().values())


@given(quaternion_strategy())
def test_eq7_kernel_is_the_rotation_of_the_quaternion(q):
    q = np.array(q) / np.linalg.norm(q)
    R = np.array([float(x) for x in gen.rotation_matrix(*q)]).reshape(3, 3)
    reference = Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_matrix()  # scalar-last convention
    np.testing.assert_allclose(R, reference, atol=1e-14)


def test_quaternions_of_the_configurations_reproduce_their_matrices():
    """The configurations' quaternions are orientations body to world: their Eq. (7) matrices are the
    transposes of the paper's R_i (global -> local, Eq. 5)."""
    for cfg in tips.FIG2.values():
        q1, q2 = cfg.quaternions()
        assert quat.quaternion_rotation_matrix(q1) == sp.Matrix(cfg.R1).T
        assert quat.quaternion_rotation_matrix(q2) == sp.Matrix(cfg.R2).T
        assert sum(c**2 for c in q2) == 1


# ---------------------------------------------------------------------------------- general results


def test_arm_term_equals_closed_form_for_general_inertia():
    r = sp.symbols("r_x r_y r_z", real=True)
    I = kin.inertia_tensor(*sp.symbols("I_xx I_yy I_zz I_xy I_xz I_yz", real=True))
    assert cforms.check_arm_term_closed_form(r, I)


def test_two_spheres_give_7_over_m_through_the_general_kinematics():
    res = cforms.sphere_pair_check()
    m = res["m"]
    assert res["residual"] == sp.zeros(3, 3)
    assert res["eigen_along_n"] == sp.zeros(3, 1) and res["eigen_across_n"] == sp.zeros(3, 1)
    assert res["trace_times_m"] == 16  # eigenvalues 2/m, 7/m, 7/m
    assert res["lambda_max"] == 7 / m
    assert sp.simplify(res["a_max_eq26"] - 7 / m) == 0


def test_eq26_dominates_the_fig2_diagonals_under_assumption_3():
    for label in tips.FIG2:
        assert all(tips.eq26_dominates(label).values())


def test_nonnegativity_certificate_rejects_a_negative_quantity():
    assert not tips.nonnegativity_certificate(tips.P1.Ixx - tips.P1.Izz)


def test_library_configurations_are_the_best_reconstructions():
    cands = tips.candidate_configurations()
    for label, cfg in tips.FIG2.items():
        best = [cands[s.index] for s in scores.best_candidates(label)]
        assert any(c.arm1 == cfg.arm1 and c.arm2 == cfg.arm2 and sp.Matrix(c.R2) == sp.Matrix(cfg.R2) for c in best)
    assert not tips.FIG2["A"].normals_opposite()
    assert tips.FIG2["B"].normals_opposite() and tips.FIG2["C"].normals_opposite()


# ---------------------------------------------------------------------------------- numeric checks


@pytest.mark.parametrize("label", ["A", "B", "C"])
@given(data=st.data(), q=quaternion_strategy())
def test_fig2_terms_match_direct_float_evaluation(label, data, q):
    args, vals = _values(data, label)
    _, fn, _ = fig2_functions(label)
    A = np.array(fn["A"](*args), dtype=float)
    Om = np.array(fn["Omega"](*args), dtype=float).ravel()
    wd = np.array(fn["wdot_c"](*args), dtype=float).ravel()
    Q = Rotation.from_quat(np.array(q) / np.linalg.norm(q)).as_matrix()  # turn the whole pair
    cfg = tips.FIG2[label]
    m, I, R, r, w = [], [], [], [], []
    for ps, Rj, j in ((tips.P1, cfg.R1, 1), (tips.P2, cfg.R2, 2)):
        m.append(vals[ps.m])
        I.append(np.diag([vals[ps.Ixx], vals[ps.Iyy], vals[ps.Izz]]))
        R.append(np.array(Rj, dtype=float) @ Q.T)
        r.append(Q @ np.array(cfg.arm_global(j).subs(vals), dtype=float).ravel())
        w.append(Q @ np.array([vals[x] for x in ps.w]))
    x0, wd0 = direct_float(m, I, R, r, w, np.zeros(3))
    still = [np.zeros(3), np.zeros(3)]  # the force coefficient does not depend on w: take w = 0
    A_direct = np.column_stack([direct_float(m, I, R, r, still, e)[0] for e in np.eye(3)])
    scale = np.max(np.abs(A))
    np.testing.assert_allclose(A_direct, Q @ A @ Q.T, rtol=0, atol=1e-12 * scale)
    # natural size of the velocity terms: |w|^2 times arm (and inertia ratios) of each particle
    ratio = [np.max(np.diag(Ij)) / np.min(np.diag(Ij)) for Ij in I]
    wd_scale = sum(rj * float(wj @ wj) for rj, wj in zip(ratio, w)) + 1e-300
    om_scale = sum(rj * float(wj @ wj) * np.linalg.norm(aj) for rj, wj, aj in zip(ratio, w, r)) + 1e-300
    np.testing.assert_allclose(x0, Q @ Om, rtol=0, atol=1e-12 * om_scale)
    np.testing.assert_allclose(wd0, Q @ wd, rtol=0, atol=1e-12 * wd_scale)


@pytest.mark.parametrize("label", ["A", "B", "C"])
@given(data=st.data(), q=quaternion_strategy())
def test_fig2_coefficient_matrix_matches_direct_mpmath_50_digits(label, data, q):
    args, vals = _values(data, label)
    _, _, fmp = fig2_functions(label)
    with mp.workdps(50):
        args_mp = [mp.mpf(x) for x in args]
        A = mp.matrix(fmp["A"](*args_mp))
        qq = [mp.mpf(x) for x in q]
        norm = mp.sqrt(sum(x * x for x in qq))
        qq = [x / norm for x in qq]
        # whole-pair rotation from Eq. (7) evaluated in mpmath (active matrix of the quaternion)
        Q = mp.matrix(quat.quaternion_rotation_matrix(qq).evalf(60).tolist())
        cfg = tips.FIG2[label]
        m, I, R, r, w = [], [], [], [], []
        for ps, Rj, j in ((tips.P1, cfg.R1, 1), (tips.P2, cfg.R2, 2)):
            m.append(mp.mpf(vals[ps.m]))
            I.append(mp.diag([mp.mpf(vals[ps.Ixx]), mp.mpf(vals[ps.Iyy]), mp.mpf(vals[ps.Izz])]))
            R.append(mp.matrix(sp.Matrix(Rj).tolist()) * Q.T)
            r.append(Q * mp.matrix([mp.mpf(float(x)) for x in cfg.arm_global(j).subs(vals)]))
            w.append(mp.matrix(3, 1))
        x0 = direct_mp(m, I, R, r, w, mp.matrix(3, 1))
        cols = []
        for k in range(3):
            e = mp.matrix(3, 1)
            e[k] = 1
            cols.append(direct_mp(m, I, R, r, w, e) - x0)
        expected = Q * A * Q.T
        scale = max(abs(x) for x in A)
        for i in range(3):
            for k in range(3):
                assert abs(cols[k][i] - expected[i, k]) <= mp.mpf(10) ** -40 * scale


@given(st.tuples(*[st.floats(-3, 3)] * 3), st.tuples(*[decades] * 3))
def test_generated_arm_term_is_the_rotational_part(r, logs):
    I = 10.0 ** np.array(logs)
    T = np.array([float(x) for x in gen.arm_term(*r, *I)])
    M = np.array([[T[0], T[3], T[4]], [T[3], T[1], T[5]], [T[4], T[5], T[2]]])
    # direct: unit force columns, torque r x F, angular acceleration I^-1 torque, acceleration alpha x r
    direct = np.column_stack([np.cross((np.cross(r, e) / I), r) for e in np.eye(3)])
    np.testing.assert_allclose(M, direct, rtol=1e-13, atol=1e-15 * np.max(np.abs(direct)))


@given(st.tuples(*[decades] * 3), st.tuples(*[st.floats(-5, 5)] * 3))
def test_generated_gyroscopic_coefficients_match_euler(logs, w):
    I = 10.0 ** np.array(logs)
    w = np.array(w)
    c = np.array([float(x) for x in gen.gyroscopic_coefficients(*I)])
    direct = -np.cross(w, I * w) / I
    mine = c * np.array([w[1] * w[2], w[2] * w[0], w[0] * w[1]])
    scale = float(w @ w) * np.max(I) / np.min(I)  # size of the terms that cancel in w x I w
    np.testing.assert_allclose(mine, direct, rtol=0, atol=1e-14 * scale + 1e-300)
