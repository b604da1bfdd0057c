"""The continuous 1-D impact of the CFL note (seed 004), ``d'' = -2 zeta d' - d`` in contact: the motion
per damping regime, the two separation conventions (geometric, force release), near-critical series
and the closed forms of contact duration and exit/entry speed.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

s = sp.Symbol("s", nonnegative=True)  # omega t
zeta = sp.Symbol("zeta", positive=True)  # damping ratio (zeta = 0 is the "undamped" regime)
w = sp.Symbol("w", positive=True)  # damped frequency / omega, underdamped: sqrt(1 - zeta^2)
mu = sp.Symbol("mu", positive=True)  # overdamped: sqrt(zeta^2 - 1)
phi = sp.Symbol("phi", nonnegative=True)  # entry phase in [0, 1)
psi = sp.Symbol("psi", nonnegative=True)  # exit phase in (0, 1]
n = sp.Symbol("n", integer=True, nonnegative=True)
N = sp.Symbol("N", integer=True, positive=True)
x, v = sp.symbols("x v", real=True)
u = sp.Symbol("u", real=True)  # 1 - zeta near critical damping

# Hertz: F = k_h d^(3/2)
k_h, m, v0 = sp.symbols("k_h m v0", positive=True)

CENTRAL_DIFFERENCE_FAMILY: tuple[str, ...] = (
    "symplectic-euler",
    "leapfrog",
    "leapfrog-centred",
    "velocity-verlet",
    "velocity-verlet-predicted",
)

# |1 - zeta| below which g(zeta) is evaluated from its Taylor series (the closed forms are 0/0 at 1)
SERIES_RADIUS = sp.Rational(1, 1000)
SERIES_ORDER = 6  # terms u^0 .. u^5: truncation error < 1e-18 relative inside SERIES_RADIUS


# ---------------------------------------------------------------------------------------------
# 1. The exact (continuous) impact
# ---------------------------------------------------------------------------------------------

def _solve_contact(stiff: sp.Expr, damp: sp.Expr) -> sp.Expr:
    """d(s) solving d'' + damp d' + stiff d = 0, d(0) = 0, d'(0) = 1 (SymPy's dsolve)."""
    d = sp.Function("d")
    ode = sp.Eq(d(s).diff(s, 2) + damp * d(s).diff(s) + stiff * d(s), 0)
    sol = sp.dsolve(ode, d(s), ics={d(0): 0, d(s).diff(s).subs(s, 0): 1})
    return sp.simplify(sol.rhs)


@lru_cache(maxsize=None)
def contact_motion(regime: str) -> sp.Expr:
    """Overlap d(s) during contact (Feng 2005 / CFL note, one-dimensional impact equation).

    ``regime``: "undamped" (zeta = 0), "underdamped" (in terms of w = sqrt(1 - zeta^2)),
    "critical" (zeta = 1), "overdamped" (in terms of mu = sqrt(zeta^2 - 1)).
    """
    if regime == "undamped":
        return _solve_contact(sp.Integer(1), sp.Integer(0))
    if regime == "underdamped":  # 1 = zeta^2 + w^2
        return _solve_contact(zeta**2 + w**2, 2 * zeta)
    if regime == "critical":
        return _solve_contact(sp.Integer(1), sp.Integer(2))
    if regime == "overdamped":  # 1 = zeta^2 - mu^2
        raw = _solve_contact(zeta**2 - mu**2, 2 * zeta)
        tidy = sp.exp(-zeta * s) * sp.sinh(mu * s) / mu
        if sp.simplify((raw - tidy).rewrite(sp.exp)) != 0:
            raise AssertionError("overdamped solution does not match exp(-zeta s) sinh(mu s)/mu")
        return tidy
    raise ValueError(f"unknown regime {regime!r}")


def _regime_subs(regime: str) -> dict:
    return {
        "undamped": {zeta: 0},
        "underdamped": {w: sp.sqrt(1 - zeta**2)},
        "critical": {zeta: 1},
        "overdamped": {mu: sp.sqrt(zeta**2 - 1)},
    }[regime]


def residual(regime: str) -> sp.Expr:
    """The residual d'' + 2 zeta d' + d of the regime's motion, with its frequency substituted (must be 0).

    Parameters
    ----------
    regime : str
        ``"undamped"``, ``"underdamped"``, ``"critical"`` or ``"overdamped"``.

    Returns
    -------
    sympy.Expr
        The residual, simplified.
    """
    d = contact_motion(regime)
    z = {"undamped": 0, "critical": 1}.get(regime, zeta)
    expr = (d.diff(s, 2) + 2 * z * d.diff(s) + d).subs(_regime_subs(regime))
    return sp.simplify(expr)


@lru_cache(maxsize=None)
def geometric_separation() -> tuple[sp.Expr, sp.Expr]:
    """(t_d, d'(t_d)): first return of d to 0 and the exit velocity, underdamped (CFL note).

    d = exp(-zeta s) sin(w s)/w vanishes where sin(w s) = 0, first at s = pi/w.
    """
    d = contact_motion("underdamped")
    zeros = sp.solve(sp.sin(w * s), s)
    first = min((z for z in zeros if z.is_positive), key=lambda e: e / (sp.pi / w))
    t_d = first.subs(_regime_subs("underdamped"))
    v_e = sp.simplify(d.diff(s).subs(s, first).subs(_regime_subs("underdamped")))
    return t_d, v_e


def no_geometric_separation() -> dict:
    """Critical and overdamped: d > 0 for every s > 0; {regime: (lim d, lim d', d)} as s -> oo.

    The overdamped d is returned in the decay rates a = zeta - mu > 0 and a + c = zeta + mu:
    (exp(-a s) - exp(-(a + c) s))/c, positive for s > 0.

    d = s exp(-s) (critical) and exp(-zeta s) sinh(mu s)/mu with zeta > mu (overdamped) are positive
    for s > 0, so the overlap never returns to 0: no geometric separation, exit velocity 0 in the limit.

    Returns
    -------
    dict
        ``{regime: (lim d, lim d', d)}`` for ``"critical"`` and ``"overdamped"``.
    """
    a_r, c_r = sp.symbols("a c", positive=True)  # overdamped decay rates a = zeta - mu, a + c = zeta + mu
    out = {}
    for regime in ("critical", "overdamped"):
        dd = contact_motion(regime)
        if regime == "overdamped":
            dd = sp.expand(dd.subs({zeta: a_r + c_r / 2, mu: c_r / 2}).rewrite(sp.exp))
        out[regime] = (sp.limit(dd, s, sp.oo), sp.limit(dd.diff(s), s, sp.oo), dd)
    return out


def compressive_force(regime: str) -> sp.Expr:
    """P(s) = d + 2 zeta d' = -d'' (contact force in units of k v0/omega; > 0 is compressive).

    Parameters
    ----------
    regime : str
        ``"undamped"``, ``"underdamped"``, ``"critical"`` or ``"overdamped"``.

    Returns
    -------
    sympy.Expr
        ``P(s)``.
    """
    d = contact_motion(regime)
    return sp.simplify(-d.diff(s, 2))


def g_underdamped() -> sp.Expr:
    """g(zeta) = arccos(zeta)/sqrt(1 - zeta^2) (zeta < 1): half the force-release time, ``s_f = 2 g``.

    Returns
    -------
    sympy.Expr
        ``g`` with the square root split as ``sqrt(1 - zeta) sqrt(1 + zeta)``.
    """
    return sp.acos(zeta) / (sp.sqrt(1 - zeta) * sp.sqrt(1 + zeta))


def g_overdamped() -> sp.Expr:
    """g(zeta) = arccosh(zeta)/sqrt(zeta^2 - 1) (zeta > 1): half the force-release time, ``s_f = 2 g``.

    Returns
    -------
    sympy.Expr
        ``g`` with the square root split as ``sqrt(zeta - 1) sqrt(zeta + 1)``.
    """
    return sp.acosh(zeta) / (sp.sqrt(zeta - 1) * sp.sqrt(zeta + 1))


def g_ode_residuals() -> tuple[sp.Expr, sp.Expr]:
    """(1 - zeta^2) g' - zeta g + 1 for both closed forms of g (both 0): g solves one linear ODE.

    Returns
    -------
    tuple of sympy.Expr
        The residuals of :func:`g_underdamped` and :func:`g_overdamped`.
    """
    p = sp.Symbol("p", positive=True)  # zeta = 1 - p (p < 1) and zeta = 1 + p
    out = []
    for g, z in ((g_underdamped(), 1 - p), (g_overdamped(), 1 + p)):
        res = ((1 - zeta**2) * sp.diff(g, zeta) - zeta * g + 1).subs(zeta, z)
        out.append(sp.simplify(sp.powsimp(sp.expand(res), force=False)))
    return tuple(out)


@lru_cache(maxsize=None)
def g_series() -> sp.Expr:
    """Taylor polynomial of g about zeta = 1 in u = 1 - zeta (terms u^0 .. u^5).

    g is the solution of (1 - zeta^2) g' = zeta g - 1 that is regular at zeta = 1 (both closed
    forms are); with zeta = 1 - u the ODE reads u (2 - u) dg/du + (1 - u) g - 1 = 0, and matching
    powers of u fixes every coefficient (c_0 = 1, c_k = 2k c_(k-1)/(2k + 1)).
    """
    c = sp.symbols(f"c0:{SERIES_ORDER}")
    poly = sum(ck * u**k for k, ck in enumerate(c))
    ode = sp.expand(u * (2 - u) * sp.diff(poly, u) + (1 - u) * poly - 1)
    eqs = [ode.coeff(u, k) for k in range(SERIES_ORDER)]
    sol = sp.solve(eqs, c, dict=True)[0]
    return sp.expand(poly.subs(sol))


@lru_cache(maxsize=None)
def force_release() -> dict:
    """Force-based separation: release time s_f (first zero of P) and exit velocity, per regime.

    Underdamped: P = exp(-zeta s) (2 zeta cos(w s) + (1 - 2 zeta^2) sin(w s)/w) is 2 zeta at s = 0
    and its zeros are pi/w apart; theta = 2 arccos(zeta) in (0, pi] is one (checked below), so it is
    the first: s_f = 2 arccos(zeta)/w.  Overdamped: tanh(mu s) = 2 zeta mu/(2 zeta^2 - 1) has the
    single root s_f = 2 arccosh(zeta)/mu.  Critical: P = (2 - s) exp(-s), s_f = 2.
    Returns {regime: (s_f, d'(s_f), d(s_f), P(s_f))}; the last must be 0.
    """
    out = {}
    for regime, s_f in (
        ("undamped", sp.pi),
        ("underdamped", 2 * sp.acos(zeta) / w),
        ("critical", sp.Integer(2)),
        ("overdamped", 2 * sp.acosh(zeta) / mu),
    ):
        d = contact_motion(regime)
        sub = _regime_subs(regime)
        vals = []
        for e in (d.diff(s), d, compressive_force(regime)):
            e = e.subs(s, s_f).subs(sub)
            vals.append(sp.simplify(sp.expand_trig(sp.simplify(e))))
        out[regime] = (s_f.subs(sub), *vals)
    return out


def force_release_time_expr() -> sp.Expr:
    """s_f = 2 g(zeta), piecewise with the series near zeta = 1 (no 0/0).

    Returns
    -------
    sympy.Piecewise
        The release time in units of ``1/omega``.
    """
    series = g_series().subs(u, 1 - zeta)
    g = sp.Piecewise(
        (series, sp.Abs(1 - zeta) < SERIES_RADIUS),
        (g_underdamped(), zeta < 1),
        (g_overdamped(), True),
    )
    return 2 * g


def geometric_duration_expr() -> sp.Expr:
    """Contact duration until the overlap returns to 0: ``pi/sqrt(1 - zeta^2)`` below critical damping, inf above.

    Returns
    -------
    sympy.Piecewise
        The duration in units of ``1/omega``.
    """
    t_d = geometric_separation()[0]
    t_d = t_d.subs(sp.sqrt(1 - zeta**2), sp.sqrt(1 - zeta) * sp.sqrt(1 + zeta))
    return sp.Piecewise((t_d, zeta < 1), (sp.oo, True))


def geometric_exit_ratio_expr() -> sp.Expr:
    """Exit speed over entry speed at geometric separation: ``exp(-zeta pi/w)`` below critical damping, 0 above.

    Returns
    -------
    sympy.Piecewise
        ``v_exit/v0``.
    """
    v_e = -geometric_separation()[1]
    v_e = v_e.subs(sp.sqrt(1 - zeta**2), sp.sqrt(1 - zeta) * sp.sqrt(1 + zeta))
    return sp.Piecewise((v_e, zeta < 1), (0, True))
