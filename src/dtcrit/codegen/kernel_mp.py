"""A kernel evaluated at 50 digits with mpmath, the reference the emitted C, NumPy and Fortran are
checked against in ulps (tests/test_codegen_*.py).
"""
from __future__ import annotations

from functools import lru_cache

import mpmath as mp
import sympy as sp

from dtcrit.codegen.kernel import ContactKernel


# ----------------------------------------------------------------------------------------------
# High-precision evaluation (the reference the emitted code is tested against)
# ----------------------------------------------------------------------------------------------
def mp_cubic_positive_root(a2, a1, a0, largest) -> mp.mpf:
    """Smallest (largest if ``largest``) positive real root of t^3 + a2 t^2 + a1 t + a0, at the
    working precision (mpmath ``polyroots`` with extra precision on the cubic with its exact roots at 0
    deflated, then Newton steps at twice the precision); 0 if none.
    """
    dps = mp.mp.dps
    coeffs = [mp.mpf(1), mp.mpf(a2), mp.mpf(a1), mp.mpf(a0)]
    poly = list(coeffs)
    while len(poly) > 1 and poly[-1] == 0:
        # an exact root at 0 is not positive: deflate it (adams-bashforth-2 undamped is t^3, whose
        # clustered polyroots values would otherwise pass as a positive root of size 1e-143)
        poly.pop()
    if len(poly) == 1:
        return mp.mpf(0)
    nonzero = [abs(c) for c in coeffs if c != 0]
    spread_bits = int(mp.log(max(nonzero) / min(nonzero), 2)) if len(nonzero) > 1 else 0
    extra = min(spread_bits, 256)  # widely spread coefficients: more bits for the root iteration
    with mp.workdps(2 * dps + 20):
        roots = mp.polyroots(poly, maxsteps=2000, extraprec=8 * dps + 4 * extra)
        scale = 1 + max(abs(r) for r in roots)
        good = [mp.re(r) for r in roots if abs(mp.im(r)) <= mp.mpf(10) ** (-dps) * scale and mp.re(r) > 0]
        if not good:
            return mp.mpf(0)
        t = max(good) if bool(largest) else min(good)
        for _ in range(8):  # Newton polish at the raised precision (quadratic from polyroots' value)
            f = ((t + coeffs[1]) * t + coeffs[2]) * t + coeffs[3]
            df = (3 * t + 2 * coeffs[1]) * t + coeffs[2]
            if df == 0:
                break
            t -= f / df
    return +mp.re(t)


def _mp_max(*xs):
    return max(xs)


def _mp_min(*xs):
    return min(xs)


_MP_MODULES = [
    {"cubic_positive_root": mp_cubic_positive_root, "hypot": mp.hypot, "Max": _mp_max, "Min": _mp_min},
    "mpmath",
]


def _mp_step(integrator: str):
    """critical_step(k, c, A) at high precision: the closed form of dtcrit.symbolic (dt_crit_mp)."""
    from dtcrit.symbolic.closed_forms import dt_crit_mp

    def step(k, c, A):
        return dt_crit_mp(integrator, k, c, A, dps=mp.mp.dps)

    return step


@lru_cache(maxsize=64)
def _step_functions(kernel: ContactKernel):
    known = list(kernel.symbols)
    funcs = []
    modules = [{**_MP_MODULES[0], "critical_step": _mp_step(kernel.structure.integrator),
                "critical_step_undamped": (lambda f: lambda k, A: f(k, 0, A))(_mp_step(kernel.structure.integrator)), "is_nan": mp.isnan, "is_negative": lambda x: x < 0}, "mpmath"]
    from dtcrit.symbolic.careful_forms import is_nan

    for s, e in kernel.steps:
        e = e.replace(is_nan, lambda *a: sp.false)  # the reference takes finite arguments: no NaN to test for
        funcs.append((s, tuple(known), sp.lambdify(known, e, modules=modules)))
        known.append(s)
    return funcs


def evaluate_mp(kernel: ContactKernel, values, dps: int = 50) -> mp.mpf:
    """The kernel's result at ``dps`` digits for argument values taken as exact (floats are exact).

    ``values``: a sequence in argument order or a mapping from argument name to value.
    """
    if isinstance(values, dict):
        values = [values[a.name] for a in kernel.arguments]
    with mp.workdps(dps + 20):
        env = [mp.mpf(v) for v in values]
        for _, _, f in _step_functions(kernel):
            try:
                env.append(f(*env))
            except ZeroDivisionError:  # x/0 with x > 0 (e.g. eps = 1/zeta^2 at zeta = 0): +inf, as in IEEE
                env.append(mp.inf)
        return +env[-1]
