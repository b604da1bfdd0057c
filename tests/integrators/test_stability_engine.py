"""The exact critical steps against direct computation: spectral radius (mpmath, NumPy),
time-stepping, high-precision references in ulps, and the anchors (Peng et al. 2020, Section 4)."""
import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import dtcrit
from dtcrit.errors import InputError
from dtcrit.integrators.schemes import NAMES
from dtcrit.integrators.simulate import run
from dtcrit.integrators.stability import critical_dt, critical_dt_array
from dtcrit.symbolic.closed_forms import dt_crit_mp

from support.amplification import spectral_radius_mp, spectral_radius_np
from support.strategies import log_uniform

zetas = st.one_of(st.just(0.0), log_uniform(-6, 3))


def _scaled(name, k, c, A):
    """(tau*, zeta) at 60 digits for the library's dt and the exact float inputs."""
    r = critical_dt(name, k, c, A)
    with mp.workdps(60):
        w = mp.sqrt(mp.mpf(k) * mp.mpf(A))
        return r, mp.mpf(r.dt) * w, mp.mpf(c) * mp.mpf(A) / (2 * w)


@settings(max_examples=40)
@given(name=st.sampled_from(NAMES), log_k=st.floats(-6, 12), log_A=st.floats(-6, 12), zeta=zetas)
def test_spectral_radius_brackets_the_critical_step(name, log_k, log_A, zeta):
    """rho <= 1 at dt (1 - 1e-6) and rho > 1 at dt (1 + 1e-6), all eigenvalues, 50 digits.

    k A spans 1e-12 ... 1e24 s^-2; zeta spans 0 and 1e-6 ... 1e3."""
    k, A = 10.0**log_k, 10.0**log_A
    c = 2.0 * zeta * math.sqrt(k / A)
    r, tau, z = _scaled(name, k, c, A)
    with mp.workdps(50):
        tol = mp.mpf(10) ** -40
        if r.dt == 0.0:
            for t in np.logspace(-8, 1, 10):
                assert spectral_radius_mp(name, t, z) > 1 + tol, (name, t, z)
            return
        below = spectral_radius_mp(name, tau * (1 - mp.mpf(10) ** -6), z)
        above = spectral_radius_mp(name, tau * (1 + mp.mpf(10) ** -6), z)
        assert below <= 1 + tol, (name, float(tau), float(z), below)
        assert above > 1 + tol, (name, float(tau), float(z), above)


@settings(max_examples=40)
@given(name=st.sampled_from(NAMES), zeta=zetas, rel=st.sampled_from([0.5, 0.9, 0.999]))
def test_numpy_eigvals_agree_inside_the_stable_range(name, zeta, rel):
    """NumPy's eigvals (float64) agree with mpmath on the spectral radius inside the range."""
    r = critical_dt(name, 1.0, 2.0 * zeta, 1.0)
    assume(r.dt != 0.0)
    t = r.dt * rel
    assert spectral_radius_np(name, t, zeta) == pytest.approx(float(spectral_radius_mp(name, t, zeta)), abs=1e-9)
    assert spectral_radius_np(name, t, zeta) <= 1 + 1e-9


@settings(max_examples=60)
@given(
    name=st.sampled_from(NAMES),
    log_k=st.floats(-300, 300),
    log_A=st.floats(-300, 300),
    zeta=st.one_of(st.just(0.0), log_uniform(-12, 12)),
)
def test_within_4_ulp_of_the_50_digit_reference(name, log_k, log_A, zeta):
    """Across the float64 range (k A from 1e-600 to 1e600 never formed explicitly)."""
    k, A = 10.0**log_k, 10.0**log_A
    with mp.workdps(30):
        c = float(2 * mp.mpf(zeta) * mp.sqrt(mp.mpf(k) / mp.mpf(A)))
    assume(math.isfinite(c) and c < 1e300 and not (zeta > 0 and c == 0.0))
    ref = dt_crit_mp(name, k, c, A)
    got = critical_dt(name, k, c, A).dt
    if ref == 0:
        assert got == 0.0
        return
    assume(1e-300 < float(ref) < 1e300)  # else the answer itself is outside float64's normal range
    ulp = abs(mp.mpf(got) - ref) / np.spacing(float(ref))
    assert ulp <= 4, (name, k, c, A, float(ulp))


def test_vectorised_equals_scalar():
    rng = np.random.default_rng(1)
    k = 10.0 ** rng.uniform(-6, 12, 200)
    A = 10.0 ** rng.uniform(-6, 12, 200)
    c = 2 * 10.0 ** rng.uniform(-6, 3, 200) * np.sqrt(k / A)
    c[:20] = 0.0
    for name in NAMES:
        vec = critical_dt_array(name, k, c, A)
        assert np.array_equal(vec, [critical_dt(name, *x).dt for x in zip(k, c, A)])


# Time-stepping the integrators themselves: bounded just below, growing just above.
SIM_CASES = [(n, z) for n in NAMES for z in (0.0, 0.05, 0.3, 1.0, 3.0, 30.0)]


@pytest.mark.parametrize("name,zeta", SIM_CASES)
def test_time_stepping_bounded_below_and_growing_above(name, zeta):
    r = critical_dt(name, 1.0, 2.0 * zeta, 1.0)  # omega = 1: dt is tau
    if r.dt == 0.0:
        # unstable for every dt: grows even at a small step
        assert spectral_radius_mp(name, 0.01, zeta) > 1
        rho = float(spectral_radius_mp(name, 0.5, zeta))
        n = int(min(200_000, max(2_000, 8 * math.log(10) / math.log(rho))))
        assert run(name, 0.5, zeta, n).growth > 100
        return
    rho_above = float(spectral_radius_mp(name, 1.02 * r.dt, zeta))
    n = int(min(200_000, max(2_000, 8 * math.log(10) / math.log(rho_above))))
    assert run(name, 1.02 * r.dt, zeta, n).growth > 100, (name, zeta, n)
    below = run(name, 0.98 * r.dt, zeta, n)
    assert below.growth <= 1.5, (name, zeta, below.growth)


def test_undamped_central_difference_anchor():
    """Undamped central difference: omega dt = 2 (Peng et al. 2020, Eq. (35))."""
    for name in ("leapfrog", "leapfrog-centred", "velocity-verlet", "symplectic-euler", "velocity-verlet-predicted"):
        for k, A in ((1.0, 1.0), (4.0, 1.0), (1e10, 7e-3), (3.7e-5, 2.2e8)):
            r = critical_dt(name, k, 0.0, A)
            assert r.omega_dt == pytest.approx(2.0, rel=4e-16)


def test_two_sphere_alpha_anchor():
    """A = 7/m gives dt = (2/sqrt 7) sqrt(m/k) (Peng et al. 2020, Eq. (49)), alpha checked at 60 digits."""
    with mp.workdps(60):
        alpha = 2 / mp.sqrt(7)
        for m, k in ((1.0, 1e10), (2.5e-9, 3e5), (7e3, 1e12)):
            dt = critical_dt("velocity-verlet", k, 0.0, 7.0 / m).dt
            got = mp.mpf(dt) * mp.sqrt(mp.mpf(k) / mp.mpf(m))
            assert abs(got - alpha) < 4 * mp.mpf(2) ** -52 * alpha


def test_eq46_overestimates_every_damped_integrator():
    """The printed Eq. (46) exceeds the verified bound of every scheme once zeta > 0."""
    for name in NAMES:
        for zeta in (0.01, 0.5, 2.0, 100.0):
            c = 2 * zeta
            assert dtcrit.paper_eq46(1.0, c, 1.0) > critical_dt(name, 1.0, c, 1.0).dt
            rho = spectral_radius_mp(name, dtcrit.paper_eq46(1.0, c, 1.0), zeta)
            assert rho > 1


def test_unstable_schemes_report_zero_with_a_reason():
    for name in ("forward-euler", "paper-eq40", "extended-taylor", "adams-bashforth-2"):
        r = critical_dt(name, 1e10, 0.0, 7e-3)
        assert r.dt == 0.0 and "unstable" in r.reason and r.regime == "undamped"


@pytest.mark.parametrize(
    "args,key",
    [
        (("nope", 1.0, 0.0, 1.0), "integrator"),
        (("leapfrog", -1.0, 0.0, 1.0), "k"),
        (("leapfrog", 0.0, 0.0, 1.0), "k"),
        (("leapfrog", float("nan"), 0.0, 1.0), "k"),
        (("leapfrog", 1.0, -1.0, 1.0), "c"),
        (("leapfrog", 1.0, float("inf"), 1.0), "c"),
        (("leapfrog", 1.0, 0.0, 0.0), "A"),
        (("leapfrog", 1.0, 0.0, "x"), "A"),
    ],
)
def test_bad_input_names_the_argument(args, key):
    with pytest.raises(InputError) as info:
        critical_dt(*args)
    assert info.value.key == key


def test_unknown_integrator_suggests_nearest():
    with pytest.raises(InputError, match="did you mean 'leapfrog'"):
        critical_dt("leapfrg", 1.0, 0.0, 1.0)
