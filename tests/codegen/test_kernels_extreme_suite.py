"""The emitted careful step dt(k, c, A) of every integrator, in every language that runs here (C with the
system compiler, Fortran with gfortran, NumPy), on the whole extreme-case suite of ``dtcrit bench``:

* within 4 ulp of the 50-digit reference (``dtcrit.bench.reference``: the closed form of dtcrit.symbolic in
  mpmath, from the exact float inputs) wherever the step is a float64 number;
* +inf where the exact step lies beyond float64 and 0 where it lies below it (no positive float64 step is
  stable), 0 exactly where no step is stable;
* NaN for a NaN or negative input, in every argument position;
* the per-contact kernels of ``dtcrit codegen`` give NaN when one stiffness is negative or NaN (``fmin``
  and Fortran's ``min`` would drop it and return the other direction's step);
* emitted files end with a newline.

This replaces the strict xfail on the bare C kernel's limits that ``tests/bench/test_bench.py`` carried.
"""
import ctypes
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dtcrit.bench import reference as ref
from dtcrit.bench.suite import SUITE
from dtcrit.codegen import KernelStructure, general_structure, render
from dtcrit.codegen.render import render_step
from dtcrit.integrators.schemes import NAMES

from support.codegen import CC, C_FLAGS, GFORTRAN, _build, fortran_library, import_emitted, kernel_for
from support.precision import ulps

NAME = "dtcrit_step"


def _c(integrator):
    src = render_step(integrator, "c", NAME)
    lib = _build(src, ".c", lambda s, o: [CC, *C_FLAGS, "-O2", "-shared", "-fPIC", "-o", str(o), str(s), "-lm"])
    f = getattr(ctypes.CDLL(str(lib)), NAME)
    f.restype, f.argtypes = ctypes.c_double, [ctypes.c_double] * 3
    return f


def _fortran(integrator):
    lib = fortran_library(render_step(integrator, "fortran", NAME))
    f = getattr(ctypes.CDLL(str(lib)), NAME)
    f.restype, f.argtypes = ctypes.c_double, [ctypes.c_double] * 3
    return f


def _numpy(integrator):
    return import_emitted(render_step(integrator, "numpy", NAME), NAME, prefix="step")


LANGS = {"c": _c, "fortran": _fortran, "numpy": _numpy}
_CACHE: dict = {}


def step_function(lang, integrator):
    if (lang, integrator) not in _CACHE:
        _CACHE[(lang, integrator)] = LANGS[lang](integrator)
    return _CACHE[(lang, integrator)]


def expected_outcome(r):
    if r == 0:
        return "zero"
    if ref.beyond_float64(r):
        return "inf"
    if r < ref.SUBNORMAL_ULP / 2:
        return "below"
    return "value"


@pytest.mark.parametrize("lang", sorted(LANGS))
@pytest.mark.parametrize("integrator", NAMES)
def test_whole_extreme_suite_within_4_ulp(lang, integrator):
    f = step_function(lang, integrator)
    bad, worst = [], 0.0
    for case in SUITE:
        r = ref.dt_reference(integrator, case.k, case.c, case.A)
        got = f(case.k, case.c, case.A)
        kind = expected_outcome(r)
        if kind == "value":
            u = ulps(got, r)
            worst = max(worst, u)
            if not u <= 4:
                bad.append((case.name, got, float(r), u))
        elif kind == "inf" and got != math.inf:
            bad.append((case.name, got, "beyond float64: inf expected"))
        elif kind in ("zero", "below") and got != 0.0:
            bad.append((case.name, got, f"{kind}: 0 expected"))
    assert not bad, (lang, integrator, bad)
    assert worst <= 4


@settings(max_examples=60, deadline=None)
@given(log_k=st.floats(-300, 300), log_A=st.floats(-300, 300), log_zeta=st.floats(-480, -3), lang=st.sampled_from(sorted(LANGS)))
def test_adams_bashforth_2_tiny_damping_within_4_ulp(log_k, log_A, log_zeta, lang):
    """The cubic whose undamped form is tau^3: omega dt ~ 2 zeta^(1/3), so the step stays in float64 while
    zeta (and c/k) underflow; across the leading-order branch (zeta <= 2^-94) and the root of the cubic."""
    k, A = 10.0**log_k, 10.0**log_A
    c = 2.0 * math.sqrt(k) * (10.0 ** (log_zeta / 2)) * (10.0 ** (log_zeta / 2)) / math.sqrt(A)
    assume(0.0 < c < math.inf)
    r = ref.dt_reference("adams-bashforth-2", k, c, A)
    assume(expected_outcome(r) == "value")
    got = step_function(lang, "adams-bashforth-2")(k, c, A)
    assert ulps(got, r) <= 4, (lang, k, c, A, got, float(r))


BAD_INPUTS = [(math.nan, 1.0, 1.0), (1.0, math.nan, 1.0), (1.0, 1.0, math.nan), (-1.0, 1.0, 1.0), (1.0, -1.0, 1.0),
              (1.0, 1.0, -1.0), (-4.0, 4.0, 1.0), (1e10, math.nan, 1e-300), (math.nan, 0.0, 1.0), (1.0, 0.0, -0.5)]


@pytest.mark.parametrize("lang", sorted(LANGS))
@pytest.mark.parametrize("integrator", NAMES)
def test_nan_in_gives_nan_out(lang, integrator):
    f = step_function(lang, integrator)
    got = [f(*x) for x in BAD_INPUTS]
    assert all(math.isnan(g) for g in got), (lang, integrator, list(zip(BAD_INPUTS, got)))
    assert f(4.0, 1.0, 1.0) > 0  # and a valid input is a step


def test_numpy_step_is_elementwise_on_arrays():
    f = step_function("numpy", "velocity-verlet")  # scalar wrapper; the module function takes arrays
    src = render_step("velocity-verlet", "numpy", NAME)
    namespace: dict = {}
    exec(compile(src, "step.py", "exec"), namespace)
    k = np.array([1e10, math.nan, 4.0])
    got = namespace[NAME](k, np.array([1.0, 1.0, 4.0]), np.array([7e-3, 1.0, 1.0]))
    assert got.shape == (3,) and math.isnan(got[1])
    assert got[0] == f(1e10, 1.0, 7e-3) and got[2] == f(4.0, 4.0, 1.0)


def _contact_functions(kernel):
    from support.codegen import c_function, fortran_function, numpy_function

    return [c_function(kernel), numpy_function(kernel)] + ([fortran_function(kernel)] if GFORTRAN else [])


@pytest.mark.parametrize("integrator", ["velocity-verlet", "forward-euler", "paper-eq40", "leapfrog-centred"])
def test_contact_kernel_propagates_nan(integrator):
    """A negative or NaN normal stiffness (or any NaN) gives NaN, not the other direction's step."""
    for structure in (general_structure(integrator), KernelStructure(integrator, True, ("sphere",), True, True, False)):
        kernel = kernel_for(structure)
        names = [a.name for a in kernel.arguments]
        base = {"kn": 1e6, "ks": 5e5, "cn": 0.2, "cs": 0.1, "omega_max": 1.0}
        for a in names:
            base.setdefault(a, 2.0 if a.startswith("I_zz") else 1.5 if a.startswith("I_yy") else 1.0)
        for f in _contact_functions(kernel):
            assert f(*[base[n] for n in names]) > 0
            for key, value in [("kn", -1e6), ("kn", math.nan)] + [(n, math.nan) for n in names]:
                args = dict(base, **{key: value})
                got = f(*[args[n] for n in names])
                assert math.isnan(got), (integrator, structure, key, value, got)


def test_undamped_contact_kernel_propagates_nan():
    kernel = kernel_for(KernelStructure("velocity-verlet", True, ("sphere",), False, False, False))
    for f in _contact_functions(kernel):
        assert math.isnan(f(1.0, -1e6, 1e6)) and math.isnan(f(1.0, 1e6, math.nan)) and f(1.0, 1e6, 1e6) > 0


@pytest.mark.parametrize("lang", sorted(LANGS))
def test_emitted_files_end_with_a_newline(lang):
    for integrator in NAMES:
        assert render_step(integrator, lang, NAME).endswith("\n")
        text = render(kernel_for(general_structure(integrator)), lang)
        assert text.endswith("\n") and not text.endswith("\n\n")
