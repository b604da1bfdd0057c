"""The critical step of one contact direction as a SymPy expression (Peng et al. 2020, Eqs. (29)-(30)).

One direction ``j = n, s`` has omega_j = sqrt(k_j A), zeta_j = c_j A / (2 omega_j) and
dt_j = tau(zeta_j) / omega_j, tau the exact dimensionless critical step of the integrator from
``dtcrit.symbolic.closed_forms`` (its piecewise closed form or the root of its cubic).
:func:`direction_kernel` writes it in placeholders of the direction's rates, which
``dtcrit.codegen.kernel`` replaces per direction; :func:`undamped_tau` is the constant tau at zeta = 0.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from dtcrit.codegen.functions import cubic_positive_root
from dtcrit.symbolic.closed_forms import closed_pieces, eps, gamma, omega
from dtcrit.symbolic.emit import rewrite_for_printing
from dtcrit.symbolic.integrators import zeta as zeta_sym


def _pos(name: str) -> sp.Symbol:
    return sp.Symbol(name, positive=True)


# placeholders of one direction's rates, replaced per direction
OMEGA, GAMMA, KA, ZETA, EPS = (_pos(n) for n in ("OMEGA", "GAMMA", "KA", "ZETA", "EPS"))

ZETA_SCALED = sp.Rational(1, 2)
"""Below this damping ratio a cubic piece multiplies its root by omega/(k A) instead of dividing
by omega (equal in exact arithmetic; fewer correlated roundings where dt ~ gamma/(k A))."""


@lru_cache(maxsize=None)
def undamped_tau(integrator: str) -> sp.Expr:
    """tau_crit(0) = omega dt_crit at zeta = 0 (Peng et al. 2020, Eq. (30) undamped; a number).

    Parameters
    ----------
    integrator : str
        Integrator name (``dtcrit.integrators.schemes``).

    Returns
    -------
    sympy.Expr
        The smallest positive root of the boundary cubic at zeta = 0 (0 if none), or the closed form at zeta = 0.
    """
    cp = closed_pieces(integrator)[0]
    if cp.kind == "cubic":  # smallest positive real root of the cubic at zeta = 0, or 0 if none
        t = sp.Symbol("t")
        if cp.cubic is None:  # pragma: no cover - a cubic piece carries its cubic
            raise ValueError(f"'{integrator}': a cubic piece without its cubic")
        a2, a1, a0 = (c.subs(zeta_sym, 0) for c in cp.cubic)
        positive = [r for r in sp.Poly(t**3 + a2 * t**2 + a1 * t + a0, t).real_roots() if r > 0]
        return min(positive) if positive else sp.Integer(0)
    if cp.tau_expr is None:  # pragma: no cover - a closed-form piece carries its tau
        raise ValueError(f"'{integrator}': a closed-form piece without its tau")
    return sp.simplify(cp.tau_expr.subs(zeta_sym, 0))


@lru_cache(maxsize=None)
def direction_kernel(integrator: str) -> sp.Expr:
    """Step dt of one direction in the placeholders OMEGA = sqrt(k A), GAMMA = c A/2, KA = k A,
    ZETA = GAMMA/OMEGA and EPS = 1/ZETA^2 (Peng et al. 2020, Eqs. (29)-(30)).

    Built piece by piece from ``dtcrit.symbolic.closed_forms.closed_pieces`` (the exact boundary of
    the integrator): closed-form pieces as derived, with sqrt(x^2 + y^2) as ``hypot`` and omega^2
    as k A itself; a cubic piece as the root of the cubic in tau (zeta <= 1) or in
    y = 1/(zeta tau) (zeta > 1), whose coefficients are polynomials in the *ratios* zeta and
    eps = 1/zeta^2, so nothing overflows for any k, c, A in the float range.

    Parameters
    ----------
    integrator : str
        Integrator name (``dtcrit.integrators.schemes``).

    Returns
    -------
    sympy.Expr
        dt [s] of one direction in the placeholders (a ``Piecewise`` over the boundary's pieces).
    """
    branches = []
    for cp in closed_pieces(integrator):
        if cp.kind == "root":
            e = rewrite_for_printing(cp.dt_expr).subs(omega**2, KA).xreplace({omega: OMEGA, gamma: GAMMA})
        else:
            if cp.cubic is None or cp.cubic_large is None:  # pragma: no cover - a cubic piece carries both
                raise ValueError(f"'{integrator}': a cubic piece without its cubics")
            a2, a1, a0 = (c.subs(zeta_sym, ZETA) for c in cp.cubic)
            b2, b1, b0 = (c.subs(eps, EPS) for c in cp.cubic_large)
            # zeta <= 1/2, where dt ~ tau(zeta)/omega ~ gamma/(k A): the factor 1/omega is taken as
            # omega/(k A), whose rounding error cancels the one omega passes on through zeta
            scale = sp.Piecewise((OMEGA / KA, sp.Le(ZETA, ZETA_SCALED)), (1 / OMEGA, True))
            small = cubic_positive_root(a2, a1, a0, sp.false) * scale
            large = 1 / (GAMMA * cubic_positive_root(b2, b1, b0, sp.true))
            e = sp.Piecewise((small, sp.Le(GAMMA, OMEGA)), (large, True))
        hi = cp.piece.zeta_hi
        branches.append((e, sp.true if hi == sp.oo else sp.Le(GAMMA, hi * OMEGA)))
    if len(branches) == 1:
        return branches[0][0]
    branches[-1] = (branches[-1][0], sp.true)
    return sp.Piecewise(*branches)
