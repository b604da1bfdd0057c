"""Emitted C (compiled with the system cc, called through ctypes), NumPy (imported) and Fortran
(compiled with gfortran when present) agree with a 50-digit mpmath evaluation of the symbolic
kernel within 4 ulp, over parameters drawn across many decades, and the C and Fortran kernels
agree with each other (the same operations in the same order); the symbolic kernel itself agrees
with the stability engine's independent 50-digit reference (dtcrit.symbolic.closed_forms)."""
import math

import mpmath as mp
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dtcrit.codegen import KernelStructure, evaluate_mp, general_structure
from dtcrit.codegen.direction import direction_kernel
from dtcrit.integrators.schemes import NAMES
from dtcrit.symbolic.closed_forms import dt_crit_mp, tau_crit_closed_mp

from support.codegen import GFORTRAN, c_function, fortran_function, kernel_for, numpy_function
from support.precision import ulps
from support.strategies import log_uniform as decades


# every integrator in the general form; the specialised forms for two of them
CASES = [(n, "general") for n in NAMES] + [
    (n, v) for n in ("velocity-verlet", "paper-eq40") for v in ("identical-general-damped", "spheres-damped", "sphere-general-rotation")
] + [("velocity-verlet", "spheres-damped-normal")]
STRUCTURES = {
    "general": lambda n: general_structure(n),
    "identical-general-damped": lambda n: KernelStructure(n, True, ("general",), True, True, False),
    "spheres-damped": lambda n: KernelStructure(n, True, ("sphere",), True, True, False),
    "spheres-damped-normal": lambda n: KernelStructure(n, True, ("sphere",), True, False, False),
    "sphere-general-rotation": lambda n: KernelStructure(n, False, ("sphere", "general"), True, True, True),
}
ILL_CONDITIONED = 0.05  # forward-euler: |zeta - 1| below this is excluded here (see the test below)


@st.composite
def parameters(draw, kernel, zeta_strategy):
    """Argument values for ``kernel``: masses, moments, arms, stiffnesses over many decades; the
    damping coefficients are drawn through their damping ratio so all regimes occur."""
    names = [a.name for a in kernel.arguments]
    v = {}
    for suffix in ("", "1", "2"):
        if f"m{suffix}" not in names:
            continue
        m = draw(decades(-9, 6))
        v[f"m{suffix}"] = m
        if f"I_xx{suffix}" in names:
            size = draw(decades(-4, 1))
            v[f"I_xx{suffix}"] = m * size**2 * draw(st.floats(0.05, 0.4))
            v[f"r{suffix}"] = size * draw(st.floats(0.2, 3.0))
            if f"I_yy{suffix}" in names:
                v[f"I_yy{suffix}"] = v[f"I_xx{suffix}"] * draw(st.floats(1.0, 4.0))
                v[f"I_zz{suffix}"] = v[f"I_yy{suffix}"] * draw(st.floats(1.0, 4.0))
    v["kn"] = draw(decades(-2, 12))
    v["ks"] = v["kn"] * draw(st.floats(0.05, 1.5))
    A = sum(1.0 / v[k] for k in v if k.startswith("m"))
    if "m" in v:
        A = 2.0 / v["m"]
    for s in ("", "1", "2"):
        if f"I_xx{s}" in v:
            A += v[f"r{s}"] ** 2 / v[f"I_xx{s}"] * (2 if s == "" else 1)
    zetas = {}
    for j in ("n", "s"):
        if f"c{j}" in names:
            zetas[j] = draw(zeta_strategy)
            v[f"c{j}"] = 2.0 * zetas[j] * math.sqrt(v[f"k{j}"] / A)
    if "omega_max" in names:
        v["omega_max"] = draw(decades(-3, 6))
    return [v[n] for n in names], zetas


def zeta_values(integrator):
    base = st.one_of(st.just(0.0), decades(-6, 3), st.floats(0.05, 5.0))
    if integrator == "forward-euler":
        return base.filter(lambda z: abs(z - 1.0) >= ILL_CONDITIONED)
    return base


@given(data=st.data(), case=st.sampled_from(CASES))
def test_c_and_numpy_within_4_ulp_of_50_digits(data, case):
    integrator, variant = case
    kernel = kernel_for(STRUCTURES[variant](integrator))
    args, _ = data.draw(parameters(kernel, zeta_values(integrator)))
    ref = evaluate_mp(kernel, args, dps=50)
    assume(float(ref) > 0.0)
    got_c = c_function(kernel)(*args)
    got_np = numpy_function(kernel)(*args)
    assert ulps(got_c, ref) <= 4, (integrator, variant, args, got_c, float(ref))
    assert ulps(got_np, ref) <= 4, (integrator, variant, args, got_np, float(ref))


@settings(max_examples=40)
@given(data=st.data(), case=st.sampled_from(CASES))
def test_fortran_within_4_ulp_of_50_digits_and_of_the_c(data, case):
    integrator, variant = case
    kernel = kernel_for(STRUCTURES[variant](integrator))
    f = fortran_function(kernel)  # skips with the stated reason when gfortran is absent
    args, _ = data.draw(parameters(kernel, zeta_values(integrator)))
    ref = evaluate_mp(kernel, args, dps=50)
    got_f, got_c = f(*args), c_function(kernel)(*args)
    assert ulps(got_f, ref) <= 4, (integrator, variant, args, got_f, float(ref))
    # same statements, same order, same libm: at most the last bit apart (bitwise equal where observed)
    assert ulps(got_f, got_c) <= 1, (integrator, variant, args, got_f, got_c)


@settings(max_examples=10)
@given(data=st.data(), integrator=st.sampled_from(["paper-eq40", "velocity-verlet", "forward-euler"]))
def test_fortran_does_not_depend_on_the_default_real_kinds(data, integrator):
    """Every literal has kind c_double: with gfortran's -fdefault-real-8 (which turns a d0 literal
    into quad precision) the module compiles and gives bit-for-bit the same steps."""
    kernel = kernel_for(general_structure(integrator))
    plain, widened = fortran_function(kernel), fortran_function(kernel, extra_flags=("-fdefault-real-8",))
    args, _ = data.draw(parameters(kernel, zeta_values(integrator)))
    assert widened(*args) == plain(*args)


@settings(max_examples=30)
@given(zeta=st.floats(1.0 - ILL_CONDITIONED, 1.0 + ILL_CONDITIONED), log_k=st.floats(-2, 10), log_m=st.floats(-6, 4))
def test_forward_euler_near_critical_damping_is_as_accurate_as_its_conditioning_allows(zeta, log_k, log_m):
    """Near zeta = 1 the forward-Euler step omega*dt = 2/(zeta + sqrt(zeta^2 - 1)) has an infinite
    slope (a square-root branch point), so the few-u rounding of the computed zeta is amplified
    without bound.  The emitted code must stay within 4 ulp plus the exact change of the 50-digit
    result under a relative perturbation of zeta by 4u (u = 2^-53), evaluated at both signs."""
    kernel = kernel_for(KernelStructure("forward-euler", True, ("sphere",), True, True, False))
    m, k = 10.0**log_m, 10.0**log_k
    c = 2.0 * zeta * math.sqrt(k * m / 7.0)
    args = [m, k, k, c, c]
    ref = evaluate_mp(kernel, args, dps=50)
    with mp.workdps(50):
        z = mp.mpf(c) * 7 / mp.mpf(m) / (2 * mp.sqrt(mp.mpf(k) * 7 / mp.mpf(m)))
        tau = lambda x: tau_crit_closed_mp("forward-euler", x, 50)  # noqa: E731
        d = 4 * mp.mpf(2) ** -53
        change = max(abs(tau(z * (1 + s * d)) / tau(z) - 1) for s in (-1, 1))
    allowed = 4 + float(change) * float(ref) / math.ulp(float(ref))
    assert ulps(c_function(kernel)(*args), ref) <= allowed
    assert ulps(numpy_function(kernel)(*args), ref) <= allowed


@given(integrator=st.sampled_from(NAMES), log_k=st.floats(-100, 100), log_A=st.floats(-100, 100),
       zeta=st.one_of(st.just(0.0), decades(-8, 8)))
def test_direction_kernel_matches_the_stability_engine_reference(integrator, log_k, log_A, zeta):
    """The per-direction expression assembled here (hypot, k A for omega^2, ratio-form cubic
    coefficients) equals dtcrit.symbolic.closed_forms.dt_crit_mp, an independent 50-digit route."""
    from dtcrit.codegen.direction import EPS, GAMMA, KA, OMEGA, ZETA
    from dtcrit.codegen.kernel_mp import _MP_MODULES
    import sympy as sp

    k, A = 10.0**log_k, 10.0**log_A
    with mp.workdps(60):
        c = 2 * mp.mpf(zeta) * mp.sqrt(mp.mpf(k) / mp.mpf(A))
        w, g = mp.sqrt(mp.mpf(k) * mp.mpf(A)), c * mp.mpf(A) / 2
        expr = direction_kernel(integrator)
        f = sp.lambdify([OMEGA, GAMMA, KA, ZETA, EPS], expr, modules=_MP_MODULES)
        got = f(w, g, w * w, g / w, (w / g) ** 2 if g > 0 else mp.inf)
        ref = dt_crit_mp(integrator, mp.mpf(k), c, mp.mpf(A), dps=50)
        if ref == 0:
            assert got == 0
        else:
            assert abs(got / ref - 1) < mp.mpf(10) ** -40, (integrator, k, A, zeta)


def test_extreme_scales_do_not_overflow():
    """Heavy damping with huge rates: the cubic coefficients use the ratios zeta and eps only."""
    for integrator in ("paper-eq40", "velocity-verlet", "forward-euler"):
        kernel = kernel_for(KernelStructure(integrator, True, ("sphere",), True, True, False))
        for m, k, zeta in ((1e-30, 1e30, 1e12), (1e30, 1e-30, 1e-12), (1.0, 1.0, 1e150), (1e-150, 1e150, 1e-100)):
            c = 2.0 * zeta * math.sqrt(k * m / 7.0)
            args = [m, k, k, c, c]
            ref = evaluate_mp(kernel, args, dps=50)
            functions = [c_function(kernel), numpy_function(kernel)] + ([fortran_function(kernel)] if GFORTRAN else [])
            for f in functions:
                got = f(*args)
                assert math.isfinite(got) and ulps(got, ref) <= 4, (integrator, m, k, zeta, got, float(ref))
