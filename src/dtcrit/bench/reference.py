"""High-precision references for the bench: the exact critical step and the paper's printed forms.

* ``dt_reference(integrator, k, c, A)`` -- the exact critical step for the exact float inputs at
  ``dps`` (>= 50) digits: the closed form of ``dtcrit.symbolic.closed_forms`` evaluated in
  mpmath, as ``dtcrit.symbolic.closed_forms.dt_crit_mp`` does, with the SymPy-to-mpmath
  functions built once per integrator instead of once per call (the bench needs thousands of
  references).  ``tests/bench/test_bench_kernels.py`` checks it against ``dt_crit_mp`` and against
  the exact Jury boundary ``dtcrit.symbolic.boundary.tau_crit_mp``.
* ``paper_form_reference(form, scene)`` -- each printed formula of the paper (and the CFL note)
  evaluated in mpmath at ``dps`` digits, transcribed from the seed text; the float64 evaluation
  of the same form is compared with it to show where a *form* loses digits.
* ``ulp_error(got, ref)`` -- |got - ref| in units in the last place of float64 at ``ref``.

SymPy is imported lazily, only when a reference is first built: this is the bench's reference
step, never timed, and nothing in the runtime imports it.
"""
from __future__ import annotations

import math
from functools import lru_cache

import mpmath as mp
import numpy as np

from dtcrit.mp_roots import balance_roots

DPS = 50
FLOAT_MAX_EXP = 1024  # a value >= 2**1024 is beyond float64
SUBNORMAL_ULP = mp.mpf(2) ** -1074


@lru_cache(maxsize=None)
def _pieces(name: str):
    """[(zeta_hi or None, kind, evaluator data)] for ``name``, built once (SymPy -> mpmath)."""
    import sympy as sp

    from dtcrit.symbolic.closed_forms import closed_pieces, eps
    from dtcrit.symbolic.integrators import zeta

    out = []
    for cp in closed_pieces(name):
        hi = None if cp.piece.zeta_hi == sp.oo else cp.piece.zeta_hi
        if cp.kind == "root":
            out.append((hi, "root", sp.lambdify(zeta, cp.tau_expr, modules="mpmath")))
        else:
            assert cp.cubic is not None and cp.cubic_large is not None  # a cubic piece carries both forms
            small = tuple(sp.lambdify(zeta, c, modules="mpmath") for c in cp.cubic)
            large = tuple(sp.lambdify(eps, c, modules="mpmath") for c in cp.cubic_large)
            out.append((hi, "cubic", (small, large)))
    return tuple(out)


def _positive_real_roots(coeffs):
    """Positive real roots of a monic polynomial, located by mpmath's ``polyroots`` at 30 digits
    (slow when roots cluster; used only when the float64 locator below is not conclusive).
    """
    with mp.workdps(30):
        roots = mp.polyroots([mp.mpf(c) for c in coeffs], maxsteps=400, extraprec=90)
        tol = mp.mpf(10) ** -20
        return [mp.re(r) for r in roots if abs(mp.im(r)) <= tol * (1 + abs(r)) and mp.re(r) > 0]


def _locate(coeffs, pick):
    """A float64 estimate of the wanted positive real root (``numpy.roots``), or None."""
    try:
        roots = np.roots([float(c) for c in coeffs])
    except (ValueError, np.linalg.LinAlgError, OverflowError):
        return None
    good = [r.real for r in roots if abs(r.imag) <= 1e-6 * abs(r) and r.real > 0]
    return pick(good) if good else None


def _smallest_positive_verified(a2, a1, a0, t, dps) -> bool:
    """True when ``t`` (a root of t^3 + a2 t^2 + a1 t + a0) is its smallest positive real root:
    the deflated quadratic t'^2 + (a2 + t) t' + (a1 + t (a2 + t)) has no real root in (0, t).
    """
    b1 = a2 + t
    b0 = a1 + t * b1
    disc = b1 * b1 - 4 * b0
    if disc < 0:
        return True
    s = mp.sqrt(disc)
    tol = mp.mpf(10) ** (-dps // 2) * t
    return all(not (0 < r < t - tol) for r in ((-b1 - s) / 2, (-b1 + s) / 2))


def _cubic_tau(funcs, z, dps):
    """Smallest positive root of the governing cubic in tau (as ``closed_forms._cubic_tau_mp``).

    Located in float64 (``numpy.roots`` on the cubic in tau for zeta < 1, on the cubic in
    y = 1/(zeta tau) for zeta >= 1, whose coefficients stay bounded), falling back to mpmath's
    ``polyroots``; polished by Newton at ``2 dps`` digits on the cubic in tau, and verified to be
    the *smallest* positive root by deflation.  Below zeta = 1e-6 the root is reached from the
    cubic's two-term balances instead (``dtcrit.mp_roots.balance_roots``).  ``tests/bench/test_bench_kernels.py`` checks it
    against ``dtcrit.symbolic.closed_forms.dt_crit_mp``.
    """
    small, large = funcs
    a2, a1, a0 = (f(z) for f in small)
    if z == 0:
        good = _positive_real_roots([mp.mpf(1), a2, a1, a0])
        return min(good) if good else mp.mpf(0)
    candidates = []
    if z < mp.mpf(10) ** -6:
        # tiny damping: the wanted root scales like a power of zeta (zeta for most schemes, 2 zeta^(1/3)
        # for adams-bashforth-2, whose undamped cubic is tau^3); located by scaled Newton (dtcrit.mp_roots.balance_roots)
        with mp.workdps(2 * dps):
            coeffs = [f(mp.mpf(z)) for f in small]
            found = balance_roots(coeffs, dps)
            if found and _smallest_positive_verified(*coeffs, min(found), dps):
                return +min(found)
    elif z < 1:
        est = _locate([1, a2, a1, a0], min)
        if est is not None:
            candidates.append(mp.mpf(est))
    else:
        e = 1 / (z * z)
        est = _locate([1] + [f(e) for f in large], max)
        if est is not None:
            candidates.append(1 / (z * mp.mpf(est)))
    with mp.workdps(2 * dps):
        a2, a1, a0 = (f(mp.mpf(z)) for f in small)
        cubic = lambda u: ((u + a2) * u + a1) * u + a0  # noqa: E731
        for t0 in candidates:
            try:
                t = mp.findroot(cubic, t0)
            except (ValueError, ZeroDivisionError):
                continue
            if t > 0 and _smallest_positive_verified(a2, a1, a0, t, dps):
                return +t
        # fallback: locate all roots at high precision
        if z < 1:
            good = _positive_real_roots([mp.mpf(1), a2, a1, a0])
            t = min(good) if good else None
        else:
            e = 1 / (mp.mpf(z) ** 2)
            good = _positive_real_roots([mp.mpf(1)] + [f(e) for f in large])
            t = 1 / (z * max(good)) if good else None
        if t is None:
            return mp.mpf(0)
        return +mp.findroot(cubic, t)


def tau_reference(name: str, z, dps: int = DPS):
    """tau_crit(zeta) = omega * dt_crit at ``dps`` digits (``z`` taken exactly).

    Parameters
    ----------
    name : str
        Name of the scheme.
    z : float or mpmath.mpf
        Damping ratio.
    dps : int
        Decimal digits.

    Returns
    -------
    mpmath.mpf
        tau_crit.
    """
    with mp.workdps(dps + 10):
        z = mp.mpf(z)
        for hi, kind, data in _pieces(name):
            if hi is not None and z > mp.mpf(_hi_value(name, hi, dps)):
                continue
            return +data(z) if kind == "root" else _cubic_tau(data, z, dps)
    raise AssertionError("unreachable: the last piece has no upper bound")


@lru_cache(maxsize=None)
def _hi_value(name: str, hi, dps: int):
    import sympy as sp

    return mp.mpf(sp.N(hi, dps + 20))


def _dt_at(name: str, k, c, A, dps: int):
    with mp.workdps(dps + 10):
        k, c, A = mp.mpf(k), mp.mpf(c), mp.mpf(A)
        w = mp.sqrt(k * A)
        return tau_reference(name, c * A / (2 * w), dps) / w


def _agreeing(evaluate, dps: int, limit: int = 1300):
    """``evaluate(d)`` at d = dps, dps + 40, ... (doubling) until two successive values agree to
    10^-dps relative: a cancellation inside the form (zeta^2 - 1 one ulp above critical damping,
    sqrt(zeta^2 + 1) - zeta at zeta = 1e290) only costs working digits, never a wrong reference.
    """
    d = dps
    prev = evaluate(d)
    while True:
        d = d + 40 if d == dps else 2 * d
        cur = evaluate(d)
        with mp.workdps(d):
            # two zeros may both be cancellation: only a non-zero agreement ends the loop early
            same = (mp.isnan(prev) and mp.isnan(cur)) or (
                cur != 0 and abs(cur - prev) <= mp.mpf(10) ** (-dps) * abs(cur))
        if same or d > limit:
            return cur
        prev = cur


def dt_reference(name: str, k, c, A, dps: int = DPS):
    """Exact critical step [s] for the exact float inputs, to ``dps`` digits (mpmath number);
    the working precision is raised until two evaluations agree (``_agreeing``).

    Parameters
    ----------
    name : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    dps : int
        Decimal digits.

    Returns
    -------
    mpmath.mpf
        The critical step [s].
    """
    return _agreeing(lambda d: _dt_at(name, k, c, A, d), dps)


def zeta_exact(k, c, A, dps: int = DPS):
    """Damping ratio c A / (2 sqrt(k A)) of the exact float inputs (mpmath number).

    Parameters
    ----------
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    dps : int
        Decimal digits.

    Returns
    -------
    mpmath.mpf
        The damping ratio.
    """
    with mp.workdps(dps + 10):
        k, c, A = mp.mpf(k), mp.mpf(c), mp.mpf(A)
        return c * A / (2 * mp.sqrt(k * A))


# --- the paper's printed forms at high precision ---------------------------------------------
# Each takes the scene's (k, c, A, m) as exact mpmath numbers; m is the particle mass of a
# two-identical-sphere scene (A = 7/m, Peng et al. 2020, Section 4.3) or None.

def _eq46(k, c, A, m):
    # Peng et al. 2020, Eq. (46), right-hand side: (sqrt(4 k A + c^2 A^2) + c A) / (k A)
    return (mp.sqrt(4 * k * A + c * c * A * A) + c * A) / (k * A)


def _eq34(k, c, A, m):
    # Eq. (34): 4 / sqrt(4 k A - c^2 A^2); not real beyond critical damping
    d = 4 * k * A - c * c * A * A
    return 4 / mp.sqrt(d) if d > 0 else mp.nan


def _eq36(k, c, A, m):
    # Eq. (36): pi / sqrt(2 k/m - c^2/(4 m^2)), m the particle mass (Silbert et al.)
    d = 2 * k / m - c * c / (4 * m * m)
    return mp.pi / mp.sqrt(d) if d > 0 else mp.nan


def _beta(k, c, m):
    return c / mp.sqrt(m * k)


def _eq58(k, c, A, m):
    # Eq. (58): dt sqrt(k/m) = 4 / sqrt(28 - 49 beta^2), returned as dt
    b = _beta(k, c, m)
    d = 28 - 49 * b * b
    return 4 / mp.sqrt(d) * mp.sqrt(m / k) if d > 0 else mp.nan


def _eq59(k, c, A, m):
    # Eq. (59): dt sqrt(k/m) = pi / sqrt(2 - beta^2/4), returned as dt
    b = _beta(k, c, m)
    d = 2 - b * b / 4
    return mp.pi / mp.sqrt(d) * mp.sqrt(m / k) if d > 0 else mp.nan


def _eq60(k, c, A, m):
    # Eq. (60): dt sqrt(k/m) = beta + sqrt(beta^2 + 4/7), returned as dt
    b = _beta(k, c, m)
    return (b + mp.sqrt(b * b + mp.mpf(4) / 7)) * mp.sqrt(m / k)


def _cfl(k, c, A, m):
    # CFL note (seed 004): dt = 2 sqrt(m/k) (sqrt(c^2/(4 k m) + 1) - c/(2 sqrt(k m))), m = 1/A
    mm = 1 / A
    return 2 * mp.sqrt(mm / k) * (mp.sqrt(c * c / (4 * k * mm) + 1) - c / (2 * mp.sqrt(k * mm)))


PAPER_FORMS_MP = {
    "eq46": _eq46,
    "eq34": _eq34,
    "eq36": _eq36,
    "eq58": _eq58,
    "eq59": _eq59,
    "eq60": _eq60,
    "cfl-note": _cfl,
}

NEEDS_MASS = frozenset({"eq36", "eq58", "eq59", "eq60"})


def paper_form_reference(form: str, k, c, A, m=None, dps: int = DPS):
    """The printed form ``form`` to ``dps`` digits for the exact float inputs (NaN where not real);
    the working precision is raised until two evaluations agree (``_agreeing``).

    Parameters
    ----------
    form : str
        Name of the printed form (``dtcrit.bench.paper_forms``).
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].
    m : float, optional
        Particle mass [kg].
    dps : int
        Decimal digits.

    Returns
    -------
    mpmath.mpf
        The form's value (NaN where not real).
    """

    def at(d):
        with mp.workdps(d + 10):
            args = [mp.mpf(v) for v in (k, c, A)] + [None if m is None else mp.mpf(m)]
            return +PAPER_FORMS_MP[form](*args)

    return _agreeing(at, dps)


# --- error measure -----------------------------------------------------------------------------

def ulp_at(ref) -> mp.mpf:
    """Unit in the last place of float64 at the real number ``ref`` (2**-1074 when subnormal).

    Parameters
    ----------
    ref : mpmath.mpf
        A real number.

    Returns
    -------
    mpmath.mpf
        The ulp.
    """
    if ref == 0:
        return SUBNORMAL_ULP
    _, e = mp.frexp(abs(ref))  # |ref| = m 2^e, m in [1/2, 1)
    return max(mp.ldexp(mp.mpf(1), int(e) - 53), SUBNORMAL_ULP)


def beyond_float64(ref) -> bool:
    """True when ``ref`` rounds to infinity in float64 (|ref| >= 2**1024 - half an ulp).

    Parameters
    ----------
    ref : mpmath.mpf
        A real number.

    Returns
    -------
    bool
        Whether it rounds to infinity.
    """
    return mp.isinf(ref) or abs(ref) >= mp.ldexp(mp.mpf(2) - mp.ldexp(1, -53), FLOAT_MAX_EXP - 1)


def ulp_error(got: float, ref) -> float:
    """|got - ref| / ulp(ref) as a float (inf when ``got`` is not finite or ``ref`` is 0 != got).

    Parameters
    ----------
    got : float
        A computed value.
    ref : mpmath.mpf
        The reference.

    Returns
    -------
    float
        The error in ulps of ``ref``.
    """
    if not math.isfinite(got):
        return math.inf
    if ref == 0:
        return 0.0 if got == 0.0 else math.inf
    with mp.workdps(DPS + 10):
        return float(abs(mp.mpf(got) - ref) / ulp_at(ref))


def to_float(ref) -> float:
    """Round an mpmath number to the nearest float64 (inf beyond the range).

    Parameters
    ----------
    ref : mpmath.mpf
        A real number.

    Returns
    -------
    float
        The nearest float64.
    """
    return float(ref)
