"""A kernel evaluated at 50 digits with mpmath, the reference the emitted C, NumPy and Fortran are
checked against in ulps (tests/test_codegen_*.py).
"""
from __future__ import annotations

from functools import lru_cache
from typing import Any

import mpmath as mp
import sympy as sp

from dtcrit.codegen.kernel import ContactKernel
from dtcrit.numerics.reference import mp_cubic_positive_root  # the cubic root's 50-digit reference


def _mp_max(*xs):
    return max(xs)


def _mp_min(*xs):
    return min(xs)


_MP_FUNCTIONS: dict[str, Any] = {"cubic_positive_root": mp_cubic_positive_root, "hypot": mp.hypot, "Max": _mp_max,
                                  "Min": _mp_min}
_MP_MODULES = [_MP_FUNCTIONS, "mpmath"]


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
    modules = [{**_MP_FUNCTIONS, "critical_step": _mp_step(kernel.structure.integrator),
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

    Parameters
    ----------
    kernel : ContactKernel
        The kernel to evaluate.
    values : sequence of float or dict of str to float
        The argument values, taken as exact.
    dps : int, optional
        Decimal digits of the result.

    Returns
    -------
    mpmath.mpf
        The critical step [s] at ``dps`` digits.
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
