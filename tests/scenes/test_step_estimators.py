"""The side-by-side estimates and the contact-law conversions, each against an independent route:
the Rayleigh equation (mpmath), time integration of the Hertz and spring-dashpot collisions (SciPy,
tight tolerances), and the eigenvalues of a two-body spring system."""
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from dtcrit.physics import rules_of_thumb as est
from dtcrit.physics.damping_conventions import damping_ratio_from_restitution
from dtcrit.scenes.laws import hertz_max_overlap, resolve_pair
from dtcrit.scenes.scene import parse_scene



def rayleigh_ratio_exact(nu):
    """c_R / c_S: root in (0, 1) of (2 - x^2)^2 = 4 sqrt(1 - x^2) sqrt(1 - kappa x^2), kappa = c_S^2/c_P^2."""
    with mp.workdps(40):
        nu = mp.mpf(nu)
        kappa = (1 - 2 * nu) / (2 * (1 - nu))
        f = lambda x: (2 - x**2) ** 2 - 4 * mp.sqrt(1 - x**2) * mp.sqrt(1 - kappa * x**2)  # noqa: E731
        return mp.findroot(f, (mp.mpf("0.8"), mp.mpf("0.99")), solver="anderson")


@pytest.mark.parametrize("nu", [0.0, 0.1, 0.2, 0.25, 0.3, 0.4, 0.49])
def test_rayleigh_time_fit_is_within_0_3_percent_of_the_rayleigh_root(nu):
    """T_R = pi R / c_R with c_R = x sqrt(G/rho); the code's fit replaces x by 0.1631 nu + 0.8766."""
    R, rho, E = 1e-3, 2500.0, 7e10
    G = E / (2 * (1 + nu))
    exact = math.pi * R / (float(rayleigh_ratio_exact(nu)) * math.sqrt(G / rho))
    assert est.rayleigh_time(R, rho, E, nu) == pytest.approx(exact, rel=3e-3)


def _hertz_collision(m_star, e_star, r_star, v):
    """Integrate m* d'' = -(4/3) E* sqrt(R*) d^(3/2) from d = 0, d' = v to separation."""
    K = 4.0 / 3.0 * e_star * math.sqrt(r_star)
    scale_t = (m_star**2 / (r_star * e_star**2 * v)) ** 0.2

    def rhs(t, y):
        return [y[1], -K * max(y[0], 0.0) ** 1.5 / m_star]

    def out(t, y):
        return y[0]

    out.terminal, out.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 20 * scale_t), [0.0, v], events=out, rtol=1e-11, atol=1e-14 * v * scale_t,
                    dense_output=True, max_step=scale_t / 50)
    t_end = sol.t_events[0][0]
    ts = np.linspace(0, t_end, 4001)
    return t_end, float(np.max(sol.sol(ts)[0]))


@settings(max_examples=8)
@given(log_m=st.floats(-9, 0), log_e=st.floats(7, 11), log_r=st.floats(-4, -1), log_v=st.floats(-2, 1))
def test_hertz_contact_time_and_overlap_against_time_integration(log_m, log_e, log_r, log_v):
    m, E, R, v = 10**log_m, 10**log_e, 10**log_r, 10**log_v
    t_end, d_max = _hertz_collision(m, E, R, v)
    assert est.hertz_contact_time(m, R, E, v) == pytest.approx(t_end, rel=2e-3)  # 2.87 vs 2.868...
    assert hertz_max_overlap(m, E, R, v) == pytest.approx(d_max, rel=1e-5)


def test_hertz_tangent_stiffness_is_the_derivative_of_the_force():
    s = parse_scene("""
integrator = "velocity-verlet"
[[particle]]
shape = "sphere"
radius = 1e-3
density = 2500.0
youngs_modulus = 6.3e10
poisson_ratio = 0.22
[contact]
model = "hertz"
velocity = 1.0
""")
    pc = resolve_pair(s, 1, 1)
    E, nu = 6.3e10, 0.22
    assert pc.e_star == pytest.approx(E / (2 * (1 - nu**2)), rel=1e-14)
    G = E / (2 * (1 + nu))
    assert pc.g_star == pytest.approx(G / (2 * (2 - nu)), rel=1e-14)
    assert pc.r_star == pytest.approx(0.5e-3, rel=1e-15)
    F = lambda d: 4 / 3 * pc.e_star * math.sqrt(pc.r_star) * d**1.5  # noqa: E731
    h = pc.delta_max * 1e-5
    assert pc.kn == pytest.approx((F(pc.delta_max + h) - F(pc.delta_max - h)) / (2 * h), rel=1e-8)
    assert pc.ks / pc.kn == pytest.approx(4 * pc.g_star / pc.e_star, rel=1e-14)  # Mindlin 8 G* a / (2 E* a)


def _linear_collision(k, c, m):
    def rhs(t, y):
        return [y[1], -(k * y[0] + c * y[1]) / m]

    def out(t, y):
        return y[0]

    out.terminal, out.direction = True, -1
    T = math.pi * math.sqrt(m / k)
    sol = solve_ivp(rhs, (0, 50 * T), [0.0, 1.0], events=out, rtol=1e-12, atol=1e-15, max_step=T / 100)
    return sol.t_events[0][0], -sol.y_events[0][0][1]


@settings(max_examples=10)
@given(e=st.floats(0.05, 0.99), log_k=st.floats(0, 10), log_m=st.floats(-6, 3))
def test_restitution_damping_and_collision_time_against_time_integration(e, log_k, log_m):
    """A linear spring-dashpot with zeta from e returns with speed ratio e after t_c."""
    k, m = 10**log_k, 10**log_m
    zeta = damping_ratio_from_restitution(e)
    c = 2 * zeta * math.sqrt(k * m)
    t_c, v_out = _linear_collision(k, c, m)
    assert v_out == pytest.approx(e, rel=1e-7)
    assert est.damped_collision_time(k, c, m) == pytest.approx(t_c, rel=1e-7)


def test_collision_time_is_none_when_not_underdamped():
    assert est.damped_collision_time(1.0, 2.0, 1.0) is None
    assert est.damped_collision_time(1.0, 3.0, 1.0) is None


@settings(max_examples=20)
@given(log_m=st.floats(-6, 4), log_k=st.floats(0, 10))
def test_diagonal_stiffness_estimate_is_exact_for_two_equal_bodies_and_one_spring(log_m, log_k):
    """sqrt(2) sqrt(m/K) = 2/omega_max of two masses m joined by one spring K (eigenvalues of M^-1 K)."""
    m, k = 10**log_m, 10**log_k
    Kmat = np.array([[k, -k], [-k, k]])
    omega_max = math.sqrt(np.linalg.eigvalsh(Kmat / m)[-1])
    assert est.diagonal_stiffness_step(m, 1e30, k, 1.0) == pytest.approx(2 / omega_max, rel=1e-12)


@settings(max_examples=30)
@given(e=st.floats(1e-6, 1.0))
def test_damping_ratio_from_restitution_is_monotone_and_bounded(e):
    z = damping_ratio_from_restitution(e)
    assert 0.0 <= z < 1.0
    assert damping_ratio_from_restitution(min(1.0, e * 1.01)) <= z


def test_yade_stepper_as_it_runs():
    """YADE's GlobalStiffnessTimeStepper: 1.41044 x 0.8 x sqrt(min(m/K_ii, I/K_rot_ii)), its source's constant and
    default safety, for one contact per body (K_ii = max(kn, ks), K_rot = ks R^2 for a sphere)."""
    import math

    from dtcrit.scenes.timestep import critical_step

    r, rho, kn, ks = 0.001, 2500.0, 1e5, 4e4
    m = rho * 4 / 3 * math.pi * r**3
    s = parse_scene(f'integrator = "leapfrog"\n[[particle]]\nshape = "sphere"\nradius = {r!r}\ndensity = {rho!r}\n'
                    f'[contact]\nmodel = "linear"\nkn = {kn!r}\nks = {ks!r}\n')
    got = {e.estimate.name: e.estimate.dt for e in critical_step(s).estimates}
    expect = 1.41044 * 0.8 * math.sqrt(min(m / max(kn, ks), 0.4 * m * r * r / (ks * r * r)))
    assert got["yade_gsts"] == pytest.approx(expect, rel=1e-14)
    assert got["yade_gsts"] / got["diagonal_stiffness"] == pytest.approx(1.41044 * 0.8 / math.sqrt(2), rel=1e-14)
