"""Eigenvalues of the amplification matrices: symbolic roots and generated kernels against direct
eigen-solves of the matrix built numerically from each integrator's update rule.

References: ``mpmath.eig`` at 50 digits and ``numpy.linalg.eigvals`` of the matrix obtained by
applying ``dtcrit.integrators.schemes`` to the unit state vectors (``support.amplification``): no polynomial,
no closed form on that side.  Error measure: ``|lambda - lambda_ref| / max(1, |lambda_ref|)`` for
the best matching of the roots (normwise, the scale of the polynomial's coefficients).
"""
import itertools
import math
import subprocess
import sys
from functools import lru_cache

import mpmath as mp
import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from dtcrit._generated import eigenvalues as gen
from dtcrit.integrators.schemes import INTEGRATORS, NAMES
from dtcrit.integrators.stability import critical_dt
from dtcrit.symbolic import paper_cardano as PC
from dtcrit.symbolic import roots as R
from dtcrit.symbolic.integrators import tau, zeta

from support.amplification import matrix_float, matrix_mp
from support.strategies import log_uniform

SOUND_TOL = 2e-15  # measured worst 4.1e-16 over 3000 random points and the edge cases below
NUMPY_TOL = 1e-6  # eigvals loses half the digits next to a double eigenvalue (measured 3e-8)
CARDANO_TOL_AWAY = 1e-7  # |1 - 6 tau zeta| >= 0.1: measured worst 3.5e-9 on a 1.5e6-point grid

taus = log_uniform(-8, math.log10(4.0))
zetas = st.one_of(st.just(0.0), log_uniform(-6, 3))


def _drop_structural_zeros(name, values):
    values = list(values)
    for _ in range(gen.STRUCTURAL_ZERO_EIGENVALUES[name]):
        values.pop(min(range(len(values)), key=lambda i: abs(values[i])))
    return values


def eig_mp(name, t, z, dps=50):
    """All eigenvalues (mpmath, ``dps`` digits) of the numerically built matrix, zeros removed."""
    with mp.workdps(dps):
        ev, _ = mp.eig(matrix_mp(name, t, z))
        return _drop_structural_zeros(name, [mp.mpc(v) for v in ev])


def eig_np(name, t, z):
    return _drop_structural_zeros(name, np.linalg.eigvals(matrix_float(name, t, z)))


def match_error(got, ref):
    """Smallest over root matchings of the largest |got - ref| / max(1, |ref|)."""
    got, ref = list(got), list(ref)
    assert len(got) == len(ref)
    best = math.inf
    with mp.workdps(90):
        for perm in itertools.permutations(range(len(ref))):
            e = max(abs(mp.mpc(got[i]) - ref[j]) / max(1, abs(ref[j])) for i, j in enumerate(perm))
            best = min(best, float(e))
    return best


# ------------------------------------------------------------------ generated kernels


@settings(max_examples=60)
@given(name=st.sampled_from(NAMES), t=taus, z=zetas)
@example(name="velocity-verlet-predicted", t=1.0, z=0.0)  # a0 = 0: a zero eigenvalue
@example(name="paper-eq40", t=1.0, z=0.5)  # a0 = tau^2 - 2 tau zeta = 0
@example(name="forward-euler", t=0.5, z=2.0)  # b = 2 tau zeta - 2 = 0
@example(name="velocity-verlet-predicted", t=0.5, z=0.5)  # a1 = 1 - 4 tau zeta = 0
@example(name="symplectic-euler", t=1.0, z=0.5)  # double eigenvalue 0 (b = c = 0)
@example(name="leapfrog-centred", t=2.0, z=0.0)  # double eigenvalue -1
@example(name="forward-euler", t=0.3, z=1.0)  # critically damped: double eigenvalue
@example(name="forward-euler", t=10.0 ** 0.0078125, z=1.0)  # c = (1 - tau)^2 cancels as written
def test_sound_kernels_match_mpmath_eig(name, t, z):
    """Every root, complex pairs included, within SOUND_TOL of a 50-digit eigen-solve; never NaN."""
    got = gen.EIGENVALUE_KERNELS[name](t, z)
    assert got.shape == (R.degree(name),)
    assert np.all(np.isfinite(got))
    assert match_error(got, eig_mp(name, t, z)) <= SOUND_TOL


@settings(max_examples=60)
@given(name=st.sampled_from(NAMES), t=taus, z=zetas)
def test_numpy_eigvals_agree(name, t, z):
    """NumPy's eigvals of the float matrix agrees with the 50-digit reference and the kernel."""
    ref = eig_mp(name, t, z)
    assert match_error(eig_np(name, t, z), ref) <= NUMPY_TOL
    assert match_error(eig_np(name, t, z), [mp.mpc(v) for v in gen.EIGENVALUE_KERNELS[name](t, z)]) <= NUMPY_TOL


def _double_root_points():
    """(name, tau, zeta) next to a double eigenvalue: float neighbours of discriminant zeros."""
    out = []
    for name in ("paper-eq40", "symplectic-euler", "leapfrog-centred", "velocity-verlet-predicted"):
        const, factors = R.discriminant_factors(name)
        f = next(f for f, _ in factors if f.has(zeta) and f.has(tau))
        for z in (0.0, 1e-6, 0.1, 2.0, 1e3):
            poly = sp.Poly(f.subs(zeta, sp.Rational(z)), tau)
            for r in poly.nroots(n=30, maxsteps=500):
                if r.is_real and 1e-8 <= r <= 4:
                    t0 = float(r)
                    out += [(name, t0, z), (name, float(np.nextafter(t0, 0)), z), (name, t0 * (1 + 1e-9), z)]
    return out


@pytest.mark.parametrize("name,t,z", _double_root_points())
def test_double_eigenvalues_split_to_full_precision(name, t, z):
    """Next to a double eigenvalue the pair is split from the double-double discriminant.

    An eigen-solver (and a plain evaluation of the discriminant) loses half the digits here; the
    kernel keeps the normwise error within SOUND_TOL.
    """
    assert match_error(gen.EIGENVALUE_KERNELS[name](t, z), eig_mp(name, t, z)) <= SOUND_TOL


def test_triple_eigenvalue_of_eq40():
    """Eq. (40) has a triple eigenvalue 2/3 at tau = 1/sqrt(27), zeta = sqrt(27)/6 (p = q = 0).

    There the factored discriminant is below its own rounding error; the kernel switches to
    -4p^3 - 27q^2 from the double-double p, q.  All float neighbours stay within SOUND_TOL.
    """
    t0, z0 = 1 / math.sqrt(27), math.sqrt(27) / 6
    for t in (float(np.nextafter(t0, 0)), t0, float(np.nextafter(t0, 1)), t0 * (1 + 1e-9), t0 * (1 - 1e-6)):
        for z in (float(np.nextafter(z0, 0)), z0, float(np.nextafter(z0, 1)), z0 * (1 + 1e-8)):
            assert match_error(gen.eigenvalues_paper_eq40(t, z), eig_mp("paper-eq40", t, z)) <= SOUND_TOL


def test_structural_zero_eigenvalues():
    """The matrix's spectrum is the kernel's roots plus the removed zeros (50 digits)."""
    for name in NAMES:
        n = len(INTEGRATORS[name].state)
        assert R.degree(name) + gen.STRUCTURAL_ZERO_EIGENVALUES[name] == n
        with mp.workdps(50):
            ev, _ = mp.eig(matrix_mp(name, 0.7, 0.3))
            zeros = sorted(abs(v) for v in ev)[: gen.STRUCTURAL_ZERO_EIGENVALUES[name]]
            assert all(v < mp.mpf(10) ** -40 for v in zeros)


def test_vectorised_equals_scalar():
    rng = np.random.default_rng(7)
    t = 10.0 ** rng.uniform(-8, math.log10(4), 50)
    z = np.where(rng.uniform(size=50) < 0.2, 0.0, 10.0 ** rng.uniform(-6, 3, 50))
    for name, kernel in gen.EIGENVALUE_KERNELS.items():
        vec = kernel(t, z)
        assert vec.shape == (R.degree(name), 50) and vec.dtype == complex
        for i in (0, 17, 49):
            assert np.array_equal(vec[:, i], kernel(t[i], z[i]))
        grid = kernel(t[:5, None], z[None, :3])
        assert grid.shape == (R.degree(name), 5, 3)


@settings(max_examples=60)
@given(name=st.sampled_from(NAMES), z=st.one_of(st.just(0.0), log_uniform(-4, 3)))
def test_spectral_radius_is_one_at_the_exact_critical_step(name, z):
    """Two independent routes meet: the roots (this module) and the Jury boundary (critical_steps).

    rho(tau*) = 1 to rounding, rho <= 1 just below and > 1 just above (1e-6 relative).
    """
    t_star = critical_dt(name, 1.0, 2.0 * z, 1.0).dt  # omega = 1: dt is tau
    if t_star == 0.0:
        assert gen.spectral_radius(name, 1e-3, z) > 1.0
        return
    assert abs(gen.spectral_radius(name, t_star, z) - 1.0) <= 1e-12
    assert gen.spectral_radius(name, t_star * (1 - 1e-6), z) <= 1.0
    assert gen.spectral_radius(name, t_star * (1 + 1e-6), z) > 1.0


# ------------------------------------------------------------------ the paper's Cardano route


def _away_from_singular_curve(t, z):
    return abs(1.0 - 6.0 * t * z) >= 0.1


@settings(max_examples=60)
@given(t=taus, z=zetas)
def test_cardano_float64_away_from_its_singular_curve(t, z):
    """Eqs. (42)-(43) in float64 lose up to ~8 digits but stay within CARDANO_TOL_AWAY there."""
    assume(_away_from_singular_curve(t, z))
    got = gen.eigenvalues_cardano_paper_eq40(t, z)
    assert np.all(np.isfinite(got))
    assert match_error(got, eig_mp("paper-eq40", t, z)) <= CARDANO_TOL_AWAY


@pytest.mark.parametrize("z,gap", [(0.1, 1e-4), (0.5, 1e-4), (0.8, 1e-5)])
def test_cardano_float64_fails_next_to_tau_zeta_one_sixth(z, gap):
    """On tau zeta = 1/6 (zeta < sqrt(3)/2) D of Eq. (43) vanishes: N + sqrt(N^2 - 4M^3) with N < 0
    and M = 1 - 6 tau zeta -> 0 cancels completely in float64 (NaN), and digits are lost well
    before (error > 1e-6 at 1 - 6 tau zeta = -gap; measured 2e-2, 3e-5, 4e-5); the sound kernel is
    unaffected."""
    with np.errstate(all="ignore"):
        t = (1 + 1e-6) / (6 * z)
        assert not np.all(np.isfinite(gen.eigenvalues_cardano_paper_eq40(t, z)))
        assert match_error(gen.eigenvalues_paper_eq40(t, z), eig_mp("paper-eq40", t, z)) <= SOUND_TOL
        t = (1 + gap) / (6 * z)
        ref = eig_mp("paper-eq40", t, z)
        assert match_error(gen.eigenvalues_cardano_paper_eq40(t, z), ref) > 1e-6
        assert match_error(gen.eigenvalues_paper_eq40(t, z), ref) <= SOUND_TOL


# ------------------------------------------------------------------ symbolic forms at 50 digits


@lru_cache(maxsize=None)
def _mp_function(key):
    name, form = key
    if form == "cardano":
        exprs = R.cardano_roots(name)
    elif form == "trig":
        exprs = R.trigonometric_roots(name)
    elif form == "hyperbolic":
        r = R.hyperbolic_real_root(name)
        shift, _p, _q = R.depressed(name)
        exprs = (r,) + R.pair_from_isolated_root(name, r, r + shift)
    elif form == "textbook":
        exprs = R.quadratic_roots_textbook(name)
    elif form in ("sound+", "sound-"):
        exprs = R.quadratic_roots_sound(name, 1 if form == "sound+" else -1)
    elif form == "disc":
        exprs = (R.discriminant(name),)
    else:
        raise KeyError(form)
    return sp.lambdify((tau, zeta), list(exprs), modules="mpmath")


def symbolic_roots_mp(name, form, t, z):
    with mp.workdps(60):
        return [mp.mpc(v) for v in _mp_function((name, form))(mp.mpf(t), mp.mpf(z))]


@settings(max_examples=30)
@given(name=st.sampled_from(NAMES), t=taus, z=zetas)
@example(name="forward-euler", t=1.0, z=1.0)  # double root; sound form with q = 0 would be 0/0
@example(name="symplectic-euler", t=1.0, z=0.5)  # b = c = 0: double root at 0
def test_symbolic_roots_at_high_precision(name, t, z):
    """Every symbolic form, evaluated in mpmath (60 digits), equals a 90-digit eigen-solve to 1e-28.

    (At an exact double or triple eigenvalue the eigen-solve itself is only good to the square or
    cube root of its precision, hence 90 digits for a 1e-28 tolerance.)
    Cubics: Cardano's form everywhere (its singular set u = 0 has measure zero), the trigonometric
    form where the discriminant is >= 0, the hyperbolic form (with the deflated pair) where < 0.
    Quadratics: the textbook form and the cancellation-free form with the kernel's branch sign.
    """
    ref = eig_mp(name, t, z, dps=90)
    tol = 1e-28
    disc = symbolic_roots_mp(name, "disc", t, z)[0].real
    if R.degree(name) == 3:
        forms = ["cardano", "trig" if disc >= 0 else "hyperbolic"]
    else:
        b = float(R.coefficients(name)[1].subs({tau: t, zeta: z}))
        forms = ["textbook", "sound+" if b >= 0 or disc < 0 else "sound-"]
    for form in forms:
        try:
            got = symbolic_roots_mp(name, form, t, z)
        except ZeroDivisionError:
            # only the sound form's c/q with q = 0, i.e. b = 0 and D = 0: both roots are 0
            assert form.startswith("sound") and all(abs(v) < 1e-28 for v in ref), form
            continue
        assert match_error(got, ref) <= tol, form


def test_paper_equations_41_to_43_are_cardano_for_eq40():
    """Eq. (41) is -det(lambda I - G) of Eq. (40) with K_j = -kA, C_j = -cA, and Eqs. (42)-(43) are
    Cardano's roots: u v = -p/3 and u^3 + v^3 = -q for u = D/(3 2^(1/3)), v = 2^(1/3)(3 C_j dt + 1)/(3D),
    shift 2/3 (symbolic identities)."""
    check = PC.check_paper_cardano()
    assert check.eq41_equals_library and check.uv_product and check.u3_plus_v3 and check.shift_is_two_thirds


@pytest.mark.parametrize("t,z", [(0.05, 0.0), (0.5, 0.3), (1.7, 2.0), (3.9, 0.01), (1e-6, 10.0)])
def test_paper_eq42_numerically_at_50_digits(t, z):
    """The transcribed Eq. (42)-(43), at 50 digits, are the eigenvalues of the numeric Eq. (40) matrix."""
    exprs = [PC.to_dimensionless(e) for e in PC.paper_eq42_roots()]
    f = sp.lambdify((tau, zeta, PC.dt), exprs, modules="mpmath")
    with mp.workdps(60):
        got = [mp.mpc(v) for v in f(mp.mpf(t), mp.mpf(z), mp.mpf(1))]
    assert match_error(got, eig_mp("paper-eq40", t, z, dps=60)) <= 1e-40


def test_runtime_module_does_not_import_sympy():
    code = "import sys, dtcrit._generated.eigenvalues as e; e.spectral_radius('leapfrog', 1.0, 0.1); print('sympy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
