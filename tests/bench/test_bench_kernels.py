"""dtcrit.bench's own kernels against independent references (no bench run needed).

* the fused closed forms (dtcrit.bench.fused) within 4 ulp of the 50-digit reference over many
  decades, near critical damping and at the float64 edges -- or refusing (InputError);
* the emitted C kernel equal to the generated NumPy kernel (same expression, same libm);
* the bench's reference against dtcrit.symbolic.closed_forms.dt_crit_mp and against the exact
  Jury boundary (dtcrit.symbolic.boundary.tau_crit_mp), and the paper-form references against
  plain mpmath at high precision;
* the bisection, the classification of outcomes and the float64 transcriptions of the printed forms.
"""
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dtcrit.bench import reference as ref
from dtcrit.bench.bisection import bisect_tau, bisect_tau_scalar
from dtcrit.bench.fused import critical_dt_fused
from dtcrit.bench.runner import classify
from dtcrit.errors import InputError
from dtcrit.integrators.schemes import NAMES
from dtcrit.integrators.stability import critical_dt_array

log_uniform = lambda lo, hi: st.floats(lo, hi).map(lambda e: 10.0**e)  # noqa: E731
near_one = st.tuples(st.sampled_from([-1.0, 1.0]), st.floats(-16, -1)).map(lambda t: 1.0 + t[0] * 10.0 ** t[1])
zetas = st.one_of(st.just(0.0), log_uniform(-12, 12), near_one, st.floats(0.2, 1.5))


def _inputs(log_k, log_A, zeta):
    k, A = 10.0**log_k, 10.0**log_A
    with mp.workdps(30):
        c = float(2 * mp.mpf(zeta) * mp.sqrt(mp.mpf(k) / mp.mpf(A)))
    return k, c, A


@settings(max_examples=60)
@given(name=st.sampled_from(NAMES), log_k=st.floats(-300, 300), log_A=st.floats(-300, 300), zeta=zetas)
def test_fused_within_4_ulp_or_refuses(name, log_k, log_A, zeta):
    """Across the float64 range (k A from 1e-600 to 1e600, never formed), zeta from 0 to 1e12 and
    within 1e-16 of critical: the fused form is within 4 ulp of the reference or refuses."""
    k, c, A = _inputs(log_k, log_A, zeta)
    assume(math.isfinite(c))
    r = ref.dt_reference(name, k, c, A)
    representable = r == 0 or (ref.SUBNORMAL_ULP / 2 <= r and not ref.beyond_float64(r))
    try:
        got = float(critical_dt_fused(name, [k], [c], [A])[0])
    except InputError:
        assert not representable, (name, k, c, A, float(r))
        return
    assert representable, (name, k, c, A, got)
    assert ref.ulp_error(got, r) <= 4, (name, k, c, A, ref.ulp_error(got, r))


@settings(max_examples=40)
@given(name=st.sampled_from(NAMES), log_k=st.floats(-8, 14), log_A=st.floats(-8, 14), zeta=zetas)
def test_fused_batch_equals_fused_scalars(name, log_k, log_A, zeta):
    """Chunking and the fast path do not change a value by more than the 4-ulp budget allows."""
    k, c, A = _inputs(log_k, log_A, zeta)
    rng = np.random.default_rng(int(abs(log_k) * 1000) % 2**32)
    ks = k * 10.0 ** rng.uniform(-3, 3, 3000)
    As = A * 10.0 ** rng.uniform(-3, 3, 3000)
    cs = c * np.sqrt(As / A) * np.sqrt(ks / k)
    batch = critical_dt_fused(name, ks, cs, As, chunk=1024)
    ones = np.array([critical_dt_fused(name, [a], [b], [d])[0] for a, b, d in zip(ks[:20], cs[:20], As[:20])])
    assert np.all(np.abs(batch[:20] - ones) <= 8 * np.spacing(ones))


def test_fused_near_critical_forward_euler_is_exact_where_generated_loses_digits():
    """zeta = 1 + 1e-8 (1 mm steel balls): the fused residual keeps every digit."""
    from dtcrit.bench.suite import SUITE

    case = next(c for c in SUITE if c.name == "zeta-1+1e-8")
    r = ref.dt_reference("forward-euler", case.k, case.c, case.A)
    fused = float(critical_dt_fused("forward-euler", [case.k], [case.c], [case.A])[0])
    assert ref.ulp_error(fused, r) <= 2


@pytest.mark.parametrize("k,c,A,where", [(1e-310, 0.0, 1e-310, "beyond"), (1e300, 1e300, 1e300, "below"),
                                         (1e300, 5e-324, 1.0, "below")])
def test_fused_refuses_steps_outside_float64(k, c, A, where):
    with pytest.raises(InputError, match=where):
        critical_dt_fused("forward-euler" if c == 5e-324 else "velocity-verlet", [k], [c], [A])


def test_fused_keeps_zero_for_schemes_without_a_stable_step():
    assert critical_dt_fused("forward-euler", [1e10], [0.0], [7e-3])[0] == 0.0
    assert critical_dt_fused("paper-eq40", [1e10], [0.0], [7e-3])[0] == 0.0


@settings(max_examples=40)
@given(name=st.sampled_from(NAMES), log_k=st.floats(-300, 300), log_A=st.floats(-300, 300), zeta=zetas)
def test_emitted_c_equals_generated_numpy(name, log_k, log_A, zeta):
    """The C kernel prints the same expression as the NumPy one, with the same scaling."""
    from dtcrit.bench.c_kernel import compiler, critical_dt_c

    if compiler() is None:
        pytest.skip("no C compiler")
    k, c, A = _inputs(log_k, log_A, zeta)
    assume(math.isfinite(c))
    with np.errstate(all="ignore"):
        a = float(critical_dt_c(name, [k], [c], [A])[0])
        b = float(critical_dt_array(name, [k], [c], [A])[0])
    if math.isnan(b) or math.isinf(b) or b == 0:
        assert a == b or (math.isnan(a) and math.isnan(b))
    else:
        assert abs(a - b) <= 2 * np.spacing(b), (name, k, c, A, a, b)


CROSS = [(1.0, 0.0, 1.0), (1e10, 3.0, 7e-3), (4.0, 4.0, 1.0), (4.0, 4.0 * (1 + 2.0**-52), 1.0),
         (1e-300, 6.0, 1e-300), (1e300, 1e3, 1e300), (1.0, 1e8, 1.0), (1.0, 2e-7, 1.0), (2.5, 1.1, 0.7)]


@pytest.mark.parametrize("name", NAMES)
def test_reference_equals_dt_crit_mp(name):
    """The bench's cached reference is the closed form of dtcrit.symbolic at >= 50 digits."""
    from dtcrit.symbolic.closed_forms import dt_crit_mp

    for k, c, A in CROSS:
        a, b = ref.dt_reference(name, k, c, A), dt_crit_mp(name, k, c, A)
        with mp.workdps(60):
            assert (a == b == 0) or abs(a - b) <= mp.mpf(10) ** -45 * abs(b), (name, k, c, A)


@pytest.mark.parametrize("name", ["paper-eq40", "forward-euler", "velocity-verlet-predicted"])
def test_reference_equals_exact_jury_boundary(name):
    """Independent route: the boundary found from the Jury conditions between all roots of every
    boundary factor (dtcrit.symbolic.boundary.tau_crit_mp), no closed form involved."""
    from dtcrit.symbolic.boundary import tau_crit_mp

    for z in (0.25, 0.75, 1.0, 3.0):
        t_exact, _ = tau_crit_mp(name, z, dps=40)
        t_ref = ref.tau_reference(name, z)
        with mp.workdps(40):
            assert abs(t_ref - t_exact) <= mp.mpf(10) ** -30 * max(abs(t_exact), 1), (name, z)


def test_paper_form_reference_survives_cancellation():
    """The CFL note's sqrt(zeta^2 + 1) - zeta at zeta = 5e289 needs ~600 digits; the reference
    raises its precision until it agrees with the cancellation-free 1/(zeta + sqrt(zeta^2 + 1))."""
    k, c, A = 1e-100, 1e160, 1e160
    got = ref.paper_form_reference("cfl-note", k, c, A)
    with mp.workdps(50):
        kk, cc, AA = mp.mpf(k), mp.mpf(c), mp.mpf(A)
        w = mp.sqrt(kk * AA)
        z = cc * AA / (2 * w)
        expect = 2 / (w * (z + mp.sqrt(z * z + 1)))
        assert abs(got - expect) <= mp.mpf(10) ** -45 * expect


def test_ulp_measure():
    assert ref.ulp_error(1.0, mp.mpf(1)) == 0.0
    assert ref.ulp_error(1.0 + 2.0**-52, mp.mpf(1)) == pytest.approx(1.0)
    assert ref.ulp_error(5e-324, mp.mpf(0)) == math.inf
    assert ref.ulp_error(0.0, mp.mpf(2) ** -1080) < 0.5  # below the subnormals: 0 is the nearest float
    assert ref.beyond_float64(mp.mpf(2) ** 1024) and not ref.beyond_float64(mp.mpf(1.7e308))


def test_bisection_finds_adjacent_floats_at_any_magnitude():
    for t_star in (3.0, 1.234e-12, 2.0**-1000, 0.0):
        lo, hi = bisect_tau(lambda t: t <= t_star, 1)
        assert lo[0] <= t_star < hi[0] and (hi[0] == np.nextafter(lo[0], 5.0))
        slo, shi = bisect_tau_scalar(lambda t: t <= t_star)
        assert (slo, shi) == (lo[0], hi[0])


def test_classify():
    assert classify(1.0, mp.mpf(1))["outcome"] == "ok"
    lost = classify(1.0 + 1e-10, mp.mpf(1))
    assert lost["outcome"] == "digits_lost" and 5 < lost["digits_lost"] < 7
    assert classify(float("nan"), mp.mpf(1))["outcome"] == "failed"
    assert classify(float("inf"), mp.mpf(2) ** 1030)["outcome"] == "failed"
    assert "should refuse" in classify(0.0, mp.mpf(10) ** -600)["note"]
    assert classify(None, mp.mpf(1), InputError("k", "x"))["outcome"] == "refused"
    assert classify(1e-14, mp.mpf(0))["outcome"] == "failed"


def test_printed_forms_transcribed_as_in_the_seed():
    """Float64 transcriptions against plain mpmath at an ordinary point (Eqs. 34, 36, 46, 58-60, CFL)."""
    from dtcrit.bench.paper_forms import PAPER_FORMS

    k, c, m = 1e7, 2.0, 7.0 * 2.0**-18  # A = 7/m = 2^18 exactly
    A = 2.0**18
    for name, key, fn, _ in PAPER_FORMS:
        got = float(np.asarray(fn(np.array([k]), np.array([c]), np.array([A]), np.array([m])))[0])
        expect = ref.paper_form_reference(key, k, c, A, m)
        assert ref.ulp_error(got, expect) <= 8, name
    with mp.workdps(40):  # Eq. (60) is Eq. (46) for two identical spheres (A = 7/m)
        assert abs(ref.paper_form_reference("eq60", k, c, A, m) - ref.paper_form_reference("eq46", k, c, A, m)) \
            <= mp.mpf(10) ** -30 * ref.paper_form_reference("eq46", k, c, A, m)
