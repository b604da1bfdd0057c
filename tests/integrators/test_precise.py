"""dtcrit.integrators.precise evaluates the *derived* closed forms: symbolic identities, and ulps where it matters.

The careful forms (forward Euler's error-free residual, the Eq. (40) cubic's identity) are checked
against the closed forms produced by dtcrit.symbolic, and numerically against 50-digit references
at the inputs that defeat a naive evaluation (zeta -> 1 for forward Euler; rates beyond float64).
"""
import mpmath as mp
import numpy as np
import pytest
import sympy as sp

from dtcrit.integrators import precise, precise_eq40
from dtcrit.integrators.stability import critical_dt_array
from dtcrit.symbolic.closed_forms import closed_pieces, dt_crit_mp
from dtcrit.symbolic.integrators import tau, zeta

k, A, z = sp.symbols("k A z", positive=True)


def _dt(tau_expr, c):
    """dt = tau(zeta)/omega with omega = sqrt(k A), zeta = c A/(2 omega)."""
    w = sp.sqrt(k * A)
    return tau_expr.subs(zeta, c * A / (2 * w)) / w


def test_forward_euler_forms_are_the_derived_pieces():
    under, over = closed_pieces("forward-euler")
    c_under = 2 * z * sp.sqrt(k / A)  # zeta = z
    assert sp.simplify(_dt(under.tau_expr, c_under) - c_under / k) == 0  # dt = c/k for zeta <= 1
    zz = 1 + z  # zeta > 1
    c_over = 2 * zz * sp.sqrt(k / A)
    residual = c_over**2 * A - 4 * k  # R = c^2 A - 4k
    careful = 4 / (c_over * A + sp.sqrt(A * residual))
    assert sp.simplify(_dt(over.tau_expr, c_over) - careful) == 0


def test_paper_eq40_identity_follows_from_the_derived_cubic():
    (piece,) = closed_pieces("paper-eq40")
    g = tau**3 + sum(coef * tau ** (2 - i) for i, coef in enumerate(piece.cubic))
    assert sp.expand(g - (tau * (tau - 2 * zeta) ** 2 + 2 * (tau - zeta))) == 0
    # g(tau) = 0  <=>  tau = zeta / (1 + (tau - 2 zeta)^2 / 2)
    assert sp.expand(2 * (zeta - tau * (1 + (tau - 2 * zeta) ** 2 / 2)) + g) == 0


@pytest.mark.parametrize("dz", [1e-16, 1e-12, 1e-8, 1e-4, -1e-8, -1e-4])
def test_forward_euler_near_critical_damping_within_4_ulp(dz):
    for k_, A_ in ((1.0, 1.0), (3.3e7, 2.9e-3), (1e-200, 1e150)):
        with mp.workdps(40):
            c_ = float(2 * (1 + mp.mpf(dz)) * mp.sqrt(mp.mpf(k_) / mp.mpf(A_)))
        ref = dt_crit_mp("forward-euler", k_, c_, A_)
        got = float(critical_dt_array("forward-euler", k_, c_, A_))
        assert abs(mp.mpf(got) - ref) / np.spacing(float(ref)) <= 4, (dz, k_, A_)


def test_scaling_by_the_larger_rate_keeps_huge_damping_ratios():
    # zeta ~ 1e305: gamma/omega beyond float64 if scaled by omega alone
    k_, c_, A_ = 1e-300, 1e300, 1e-10
    for name in ("velocity-verlet", "forward-euler", "paper-eq40"):
        ref = dt_crit_mp(name, k_, c_, A_)
        got = float(critical_dt_array(name, k_, c_, A_))
        assert abs(mp.mpf(got) - ref) / np.spacing(float(ref)) <= 4, name
    assert precise.scaled_closed_form("velocity-verlet", k_, c_, A_) > 0


def test_paper_eq40_bounded_cubic_is_the_derived_cubic():
    """tau = zeta m r with w = 2 zeta^2/(1 + 2 zeta^2), m = 1 - w turns the derived cubic into a multiple
    of the runtime's h(r) (``precise_eq40.eq40_bounded_cubic``), and dt = tau/omega = (c/2) r/(k + c^2 A/2)."""
    (piece,) = closed_pieces("paper-eq40")
    g = tau**3 + sum(coef * tau ** (2 - i) for i, coef in enumerate(piece.cubic))
    w, r, d, cc = sp.symbols("w r delta c", positive=True)
    m = 1 - w
    s = w / (2 * m)  # zeta^2
    c3, c2, c1, c0 = precise_eq40.eq40_bounded_cubic(w, m)
    h = sp.nsimplify(sp.expand(c3 * d**3 + c2 * d**2 + c1 * d + c0)).subs(d, r - 1)
    zeta_pos = sp.sqrt(s)
    cubic_in_r = sp.expand(g.subs(tau, zeta_pos * m * r).subs(zeta, zeta_pos))
    assert sp.simplify(cubic_in_r / h - cubic_in_r.subs(r, 2) / h.subs(r, 2)) == 0  # a multiple of h
    assert sp.simplify(cubic_in_r.subs(r, 2) / h.subs(r, 2)) != 0
    # dt = tau/omega with omega = sqrt(k A), zeta = c A / (2 omega), m = 2k/(2k + c^2 A)
    w_ = cc**2 * A / (2 * k + cc**2 * A)
    om = sp.sqrt(k * A)
    z_ = cc * A / (2 * om)
    assert sp.simplify(z_**2 - (w / (2 * m)).subs(w, w_)) == 0
    assert sp.simplify(z_ * (1 - w_) * r / om - (cc / 2) * r / (k + cc**2 * A / 2)) == 0


def test_paper_eq40_bounded_root_is_the_only_one_in_its_bracket():
    """h < 0 on [0, 1], h(3/2) > 0 and h' >= 1/4 on [1, 3/2] for every w in [0, 1]: the root in (1, 3/2)
    is the smallest positive root (tau = zeta m r is increasing in r)."""
    w, r = sp.symbols("w r", real=True)
    c3, c2, c1, c0 = precise_eq40.eq40_bounded_cubic(w, 1 - w)
    a, b = sp.nsimplify(sp.expand(w * (1 - w))), sp.nsimplify(sp.expand(w * (1 - w) ** 2 / 4))
    h = sp.expand(b * r**3 - a * r**2 + r - 1)
    assert sp.expand(sp.nsimplify(sp.expand(c3 * (r - 1) ** 3 + c2 * (r - 1) ** 2 + c1 * (r - 1) + c0)) - h) == 0
    # on [0, 1]: h = (r - 1) - a r^2 (1 - m r/4) with a >= 0 and m r/4 < 1
    assert sp.expand(h - ((r - 1) - a * r**2 * (1 - (1 - w) * r / 4))) == 0
    h32 = sp.Poly(sp.expand(h.subs(r, sp.Rational(3, 2))), w)
    assert not [x for x in h32.real_roots() if 0 <= x <= 1] and h32.eval(sp.Rational(1, 2)) > 0
    # h' = 1 - 2 a r + 3 b r^2 >= 1 - 2 (1/4)(3/2) = 1/4, as 0 <= a <= 1/4 and b >= 0
    assert sp.expand(sp.diff(h, r) - (1 - 2 * a * r + 3 * b * r**2)) == 0
    assert sp.maximum(a, w, sp.Interval(0, 1)) == sp.Rational(1, 4)


def _case_ulps(name, k_, c_, A_, dt):
    from dtcrit.bench import reference as ref

    r = ref.dt_reference(name, k_, c_, A_)
    return 0.0 if (r == 0 and dt == 0) else ref.ulp_error(float(dt), r)


@pytest.mark.parametrize("name", ["forward-euler", "paper-eq40"])
def test_fast_path_within_4_ulp_on_each_suite_case_and_inside_a_fast_chunk(name):
    """Each case of the bench's extreme suite alone (the fast path wherever its rates allow) and
    embedded in a chunk of ordinary scenes: within 4 ulp, or refused where float64 cannot hold the step."""
    from dtcrit.bench import reference as ref
    from dtcrit.bench.suite import SUITE
    from dtcrit.errors import InputError

    filler_k, filler_c, filler_A = np.full(63, 1e7), np.full(63, 0.3), np.full(63, 7e3)
    for case in SUITE:
        r = ref.dt_reference(name, case.k, case.c, case.A)
        representable = r == 0 or (ref.SUBNORMAL_ULP / 2 <= r and not ref.beyond_float64(r))
        for ks, cs, As in (([case.k], [case.c], [case.A]),
                           (np.r_[filler_k, case.k], np.r_[filler_c, case.c], np.r_[filler_A, case.A])):
            try:
                got = critical_dt_array(name, ks, cs, As)[-1]
            except InputError:
                assert not representable, (name, case.name)
                continue
            assert representable, (name, case.name, got)
            assert _case_ulps(name, case.k, case.c, case.A, got) <= 4, (name, case.name)


@pytest.mark.parametrize("k_,A_", [(2.0**-1000, 2.0**300), (1e-300, 1e100), (1e300, 1e-290), (2.0**-900, 2.0**380)])
def test_forward_euler_near_critical_where_c_squared_underflows(k_, A_):
    """Near-critical scenes whose c^2 lies below float64 (an unscaled error-free product would lose
    the residual): the exact residual is then summed on mantissas (``forward_euler_exact``)."""
    for dz in (1e-8, -1e-8, 1e-3, 0.05, -0.05):
        with mp.workdps(40):
            c_ = float(2 * (1 + mp.mpf(dz)) * mp.sqrt(mp.mpf(k_) / mp.mpf(A_)))
        got = critical_dt_array("forward-euler", [k_, 1.0], [c_, 1.0], [A_, 1.0])[0]
        assert _case_ulps("forward-euler", k_, c_, A_, got) <= 4, (k_, A_, dz)


def test_fast_steps_flag_a_damped_step_that_underflows():
    dt, checked = precise.fast_steps("forward-euler", [1e300, 1e7], [5e-324, 0.0], [1.0, 7e3])
    assert not checked and dt[0] == 0.0 and dt[1] == 0.0
    dt, checked = precise.fast_steps("paper-eq40", [1e7, 1e7], [0.3, 0.0], [7e3, 7e3])
    assert checked and dt[0] > 0 and dt[1] == 0.0


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=80)
@given(name=st.sampled_from(["forward-euler", "paper-eq40"]), log_k=st.floats(-12, 24), log_A=st.floats(-8, 18),
       zeta_=st.one_of(st.floats(-6, 6).map(lambda e: 10.0**e), st.floats(0.05, 3.0),
                       st.tuples(st.sampled_from([-1.0, 1.0]), st.floats(-16, -1)).map(lambda t: 1 + t[0] * 10.0 ** t[1])))
def test_fast_path_within_4_ulp_over_many_decades(name, log_k, log_A, zeta_):
    """The chunked fast path (rates in range) over 36 decades of k A and 12 of zeta, and near critical."""
    k_, A_ = 10.0**log_k, 10.0**log_A
    with mp.workdps(30):
        c_ = float(2 * mp.mpf(zeta_) * mp.sqrt(mp.mpf(k_) / mp.mpf(A_)))
    dt, checked = precise.fast_steps(name, [k_], [c_], [A_])
    assert checked
    assert _case_ulps(name, k_, c_, A_, dt[0]) <= 4, (name, k_, c_, A_)
