"""The exact impact (CFL note; Feng 2005) against high-accuracy integration and 50-digit evaluation.

* closed forms (geometric separation, force-based release, Hertz) vs ``scipy.integrate.solve_ivp``
  (DOP853, rtol 1e-12) with event detection;
* the generated float kernels vs the same formulas evaluated by mpmath at 50 digits, over damping
  ratios spanning many decades and approaching 1 from both sides (series branch, no 0/0).
"""
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import dtcrit.impact as imp
from dtcrit._generated import impact as gen
from dtcrit.errors import InputError

RTOL_ODE = 1e-12
ATOL_ODE = 1e-14


def _contact_rhs(zeta):
    return lambda s, y: [y[1], -2.0 * zeta * y[1] - y[0]]


def _integrate_until(zeta, event, s_max):
    event.terminal = True
    event.direction = -1
    sol = solve_ivp(
        _contact_rhs(zeta), (0.0, s_max), [0.0, 1.0], method="DOP853", rtol=RTOL_ODE, atol=ATOL_ODE,
        events=event, dense_output=True,
    )
    return sol


def _geometric_event(s, y):
    return y[0] if s > 0 else 1.0


def _force_event_for(zeta):
    def ev(s, y):
        return y[0] + 2.0 * zeta * y[1] if s > 0 else 1.0

    return ev


@pytest.mark.parametrize("zeta", [0.0, 0.01, 0.05, 0.2, 0.5, 1 / math.sqrt(2), 0.9, 0.98])
def test_geometric_separation_matches_integration(zeta):
    """t_d = pi/sqrt(1 - zeta^2) and v_e/v0 = exp(-zeta pi/sqrt(1 - zeta^2)) (CFL note)."""
    sol = _integrate_until(zeta, _geometric_event, 200.0)
    assert sol.t_events[0].size == 1
    s_d = sol.t_events[0][0]
    v_e = -sol.y_events[0][0][1]
    ex = imp.exact_impact(zeta)
    assert ex.duration == pytest.approx(s_d, rel=1e-9)
    assert ex.exit_ratio == pytest.approx(v_e, rel=1e-8, abs=1e-13)
    # and the CFL note's printed formulas, typed in independently
    assert ex.duration == pytest.approx(math.pi / math.sqrt(1 - zeta**2), rel=1e-14)
    assert ex.exit_ratio == pytest.approx(math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2)), rel=1e-13)


@pytest.mark.parametrize("zeta", [1.0, 1.2, 3.0, 10.0])
def test_no_geometric_separation_when_not_underdamped(zeta):
    """zeta >= 1: the overlap stays positive (no event), speed decays; reported as inf / 0."""
    slow = zeta - math.sqrt(zeta**2 - 1)  # slowest decay rate: stop while d >> the tolerances
    s_max = min(80.0, 18.0 / slow)
    sol = _integrate_until(zeta, _geometric_event, s_max)
    assert sol.t_events[0].size == 0
    s = np.linspace(1e-6, s_max, 4001)
    assert np.all(sol.sol(s)[0] > 0)
    ex = imp.exact_impact(zeta)
    assert ex.duration == math.inf and ex.exit_ratio == 0.0 and not ex.separates


@pytest.mark.parametrize(
    "zeta", [0.0, 0.01, 0.2, 0.5, 1 / math.sqrt(2), 0.9, 0.9995, 1.0, 1.0004, 1.3, 3.0, 20.0]
)
def test_force_release_matches_integration(zeta):
    """Force-based release: first zero of k d + c d'; exit speed exp(-zeta s_f); overlap left 2 zeta e^(-zeta s_f)."""
    sol = _integrate_until(zeta, _force_event_for(zeta), 200.0)
    assert sol.t_events[0].size == 1
    s_f = sol.t_events[0][0]
    d_f, v_f = sol.y_events[0][0]
    ex = imp.exact_impact(zeta)
    assert ex.force_release_time == pytest.approx(s_f, rel=1e-9)
    assert ex.force_exit_ratio == pytest.approx(-v_f, rel=1e-8)
    assert ex.force_release_overlap == pytest.approx(d_f, rel=1e-8, abs=1e-14)


@pytest.mark.parametrize("zeta", [0.3, 300.0, 5000.0])
def test_force_release_by_mpmath_taylor_integration(zeta):
    """Stiff large damping (DOP853's event location loses digits there): mpmath's Taylor-series ODE
    solver at 30 digits, release located by bracketing root finding."""
    with mp.workdps(30):
        z = mp.mpf(zeta)
        f = mp.odefun(lambda s, y: [y[1], -2 * z * y[1] - y[0]], 0, [mp.mpf(0), mp.mpf(1)])
        ex = imp.exact_impact(zeta)
        guess = mp.mpf(ex.force_release_time)
        s_f = mp.findroot(lambda s: f(s)[0] + 2 * z * f(s)[1], (guess * 0.9, guess * 1.1), solver="illinois")
        assert abs(s_f - guess) / s_f < 1e-14
        assert abs(-f(s_f)[1] - mp.mpf(ex.force_exit_ratio)) / mp.mpf(ex.force_exit_ratio) < 1e-13


def _mp_g(z):
    z = mp.mpf(z)
    if z == 1:
        return mp.mpf(1)
    if z < 1:
        return mp.acos(z) / mp.sqrt(1 - z * z)
    return mp.acosh(z) / mp.sqrt(z * z - 1)


def _mp_exact(z):
    with mp.workdps(50):
        zz = mp.mpf(z)
        g = _mp_g(zz)
        s_f = 2 * g
        out = {
            "force_release_time": s_f,
            "force_exit_ratio": mp.e ** (-zz * s_f),
            "force_release_overlap": 2 * zz * mp.e ** (-zz * s_f),
        }
        if zz < 1:
            w = mp.sqrt(1 - zz * zz)
            out["duration"] = mp.pi / w
            out["exit_ratio"] = mp.e ** (-zz * mp.pi / w)
        else:
            out["duration"] = mp.inf
            out["exit_ratio"] = mp.mpf(0)
        return out


zetas_wide = st.one_of(
    st.just(0.0),
    st.floats(-10, 10).map(lambda e: 10.0**e),
    st.floats(-15.5, -0.5).map(lambda e: 1.0 - 10.0**e),
    st.floats(-15.5, -0.5).map(lambda e: 1.0 + 10.0**e),
    st.just(1.0),
)


@given(zeta=zetas_wide)
def test_kernels_match_50_digit_evaluation(zeta):
    """Every generated kernel within a few ulps (scaled by the exponent's size) of mpmath at 50 digits.

    zeta spans 0, 1e-10 ... 1e10 and 1 -+ 3e-16 ... 1 -+ 0.3 (the series branch near 1)."""
    ex = imp.exact_impact(zeta)
    ref = _mp_exact(zeta)
    for key, value in ref.items():
        got = getattr(ex, key)
        if value == mp.inf:
            assert got == math.inf, key
            continue
        if value == 0:
            assert got == 0.0, key
            continue
        if value < mp.mpf(10) ** -300:  # below the float64 normal range: must underflow to ~0
            assert got < 1e-290, (key, got)
            continue
        # exp(-a): relative error ~ |a| * eps from the rounding of a; allow 8 eps (1 + |a|)
        scale = 1.0 + abs(float(mp.log(value))) if "ratio" in key or "overlap" in key else 1.0
        rel = abs(mp.mpf(got) - value) / value
        assert rel < 8 * 2.0**-52 * scale, (key, zeta, got, value, float(rel))


def test_exact_limits_and_identities():
    assert imp.exact_impact(0.0).exit_ratio == 1.0
    assert imp.exact_impact(0.0).force_release_time == pytest.approx(math.pi, rel=1e-15)
    assert imp.exact_impact(1.0).force_release_time == pytest.approx(2.0, rel=1e-15)
    assert imp.exact_impact(1.0).force_exit_ratio == pytest.approx(math.exp(-2.0), rel=1e-15)
    # large zeta: s_f ~ 2 ln(2 zeta)/zeta, ratio ~ 1/(4 zeta^2)
    big = imp.exact_impact(1e8)
    assert big.force_exit_ratio == pytest.approx(1 / (4e16), rel=1e-6)
    # force-based release always loses less speed than... the geometric exit (no tensile phase)
    for z in (0.01, 0.1, 0.3, 0.6, 0.9):
        e = imp.exact_impact(z)
        assert e.force_exit_ratio > e.exit_ratio
        assert e.force_release_time < e.duration


@pytest.mark.parametrize("bad", [-0.1, float("nan"), float("inf"), "x", None])
def test_bad_zeta(bad):
    with pytest.raises(InputError) as info:
        imp.exact_impact(bad)
    assert info.value.key == "zeta"


# ----------------------------------------------------------------------------------------------
# Hertz
# ----------------------------------------------------------------------------------------------

def test_hertz_duration_factor_is_the_beta_integral():
    """(4/5) B(2/5, 1/2) = 2 int_0^1 (1 - u^(5/2))^(-1/2) du, by 50-digit quadrature."""
    with mp.workdps(50):
        quad = 2 * mp.quad(lambda u: 1 / mp.sqrt(1 - u ** mp.mpf(2.5)), [0, 0.5, 0.9, 0.99, 1])
        assert abs(quad - mp.mpf(gen.HERTZ_DURATION_FACTOR)) < 1e-15
        # and the duration in tangent-frequency units: factor * omega_t dmax / v0 = factor * sqrt(15/8)
        assert abs(quad * mp.sqrt(mp.mpf(15) / 8) - mp.mpf(gen.HERTZ_SCALED_DURATION)) < 1e-14


def test_hertz_scaled_problem_by_integration():
    """u'' = -(2/3) u^(3/2), u(0) = 0, u'(0) = sqrt(8/15): max overlap 1, duration, exit speed."""
    c, v0 = gen.HERTZ_SCALED_COEFFICIENT, gen.HERTZ_SCALED_SPEED

    def rhs(s, y):
        return [y[1], -c * max(y[0], 0.0) ** 1.5]

    def ev(s, y):
        return y[0] if s > 0 else 1.0

    ev.terminal, ev.direction = True, -1

    def top(s, y):
        return y[1]

    sol = solve_ivp(rhs, (0, 20), [0.0, v0], method="DOP853", rtol=1e-12, atol=1e-14, events=[ev, top])
    assert sol.t_events[0][0] == pytest.approx(gen.HERTZ_SCALED_DURATION, rel=1e-8)
    assert sol.y_events[0][0][1] == pytest.approx(-v0, rel=1e-9)
    assert sol.y_events[1][0][0] == pytest.approx(1.0, rel=1e-9)
    assert imp.hertz_exact().duration == gen.HERTZ_SCALED_DURATION


@given(
    k_h=st.floats(0, 14).map(lambda e: 10.0**e),
    m=st.floats(-12, 3).map(lambda e: 10.0**e),
    v0=st.floats(-4, 3).map(lambda e: 10.0**e),
)
def test_hertz_dimensional_kernels(k_h, m, v0):
    """Energy balance, duration and tangent frequency in SI units vs 50-digit evaluation."""
    got = imp.hertz_dimensional(k_h, m, v0)
    with mp.workdps(50):
        K, M, V = mp.mpf(k_h), mp.mpf(m), mp.mpf(v0)
        dmax = (5 * M * V**2 / (4 * K)) ** (mp.mpf(2) / 5)
        # energy: m v0^2/2 = (2/5) k_h dmax^(5/2)
        assert abs(M * V**2 / 2 - mp.mpf(2) / 5 * K * dmax ** mp.mpf(2.5)) / (M * V**2) < 1e-40
        dur = 2 * dmax / V * mp.quad(lambda u: 1 / mp.sqrt(1 - u ** mp.mpf(2.5)), [0, 0.5, 0.9, 1])
        om = mp.sqrt(mp.mpf(1.5) * K * mp.sqrt(dmax) / M)
        for key, ref in (("max_overlap", dmax), ("duration", dur), ("tangent_omega", om)):
            assert abs(mp.mpf(got[key]) - ref) / ref < 1e-13, key


def test_hertz_dimensional_by_integration():
    k_h, m, v0 = 3.7e9, 2.0e-4, 0.8
    got = imp.hertz_dimensional(k_h, m, v0)

    def rhs(t, y):
        return [y[1], -k_h / m * max(y[0], 0.0) ** 1.5]

    def ev(t, y):
        return y[0] if t > 0 else 1.0

    ev.terminal, ev.direction = True, -1
    T = got["duration"]
    sol = solve_ivp(rhs, (0, 3 * T), [0.0, v0], method="DOP853", rtol=1e-12, atol=1e-20, events=ev, dense_output=True)
    assert sol.t_events[0][0] == pytest.approx(T, rel=1e-8)
    assert sol.sol(T / 2)[0] == pytest.approx(got["max_overlap"], rel=1e-8)


@pytest.mark.parametrize("key,args", [("k_h", (0.0, 1.0, 1.0)), ("m", (1.0, -1.0, 1.0)), ("v0", (1.0, 1.0, float("nan")))])
def test_hertz_bad_input(key, args):
    with pytest.raises(InputError) as info:
        imp.hertz_dimensional(*args)
    assert info.value.key == key
