"""The labelled comparison formulas of Peng et al. 2020, Section 4 and 6.1, derived, not typed.

* Eq. (46): the root of the "real eigenvalue at -1" factor of the Eq. (40) scheme's Jury
  conditions (``tau^2 - 4 zeta tau - 4``), i.e. where the paper's Eq. (44) puts the boundary;
* Eq. (34)/(35): Belytschko's criterion dt = 2/omega_d with the damped frequency of Eq. (33),
  from the roots of the characteristic equation (31);
* Eq. (36): Silbert et al.'s collision time, with the paper's mass convention;
* Eq. (37): the critical damping coefficient, where the discriminant of Eq. (31) vanishes;
* Eqs. (58)-(60): the beta forms for identical spheres, obtained by substituting A = 7/m,
  c = beta sqrt(m k) into the three formulas above.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from dtcrit.symbolic.boundary import boundary_factors
from dtcrit.symbolic.integrators import tau, zeta

k, c, A, m, beta = sp.symbols("k c A m beta", positive=True)
s = sp.Symbol("s")


@lru_cache(maxsize=None)
def eq46() -> sp.Expr:
    """The step dt of the paper's Eq. (46) as a function of k, c, A (positive root of the lambda=-1 factor)."""
    factor = next(f for f in boundary_factors("paper-eq40") if f.condition.startswith("(-1)^n p(-1)"))
    roots = sp.solve(factor.poly.as_expr(), tau)
    positive = [r for r in roots if sp.N(r.subs(zeta, 1)) > 0]
    assert len(positive) == 1
    w = sp.sqrt(k * A)
    return sp.simplify(positive[0].subs(zeta, c * A / (2 * w)) / w)


@lru_cache(maxsize=None)
def characteristic_roots() -> list[sp.Expr]:
    """Roots of s^2 + c A s + k A = 0 (Eq. (31)), i.e. Eq. (32)."""
    return sp.solve(s**2 + c * A * s + k * A, s)


@lru_cache(maxsize=None)
def omega_damped() -> sp.Expr:
    """Imaginary part of the underdamped roots of Eq. (31): Eq. (33).

    For complex roots r1, r2 = -cA/2 +- i omega_d, (r1 - r2)^2 = -4 omega_d^2.
    """
    r1, r2 = characteristic_roots()
    return sp.sqrt(-sp.expand((r1 - r2) ** 2)) / 2


def eq34() -> sp.Expr:
    """Belytschko: dt = 2/omega_max, Eqs. (28) and (33)-(34) (underdamped only).

    Returns
    -------
    sympy.Expr
        ``dt(k, c, A)``.
    """
    return 2 / omega_damped()


def eq36() -> sp.Expr:
    """Silbert et al.'s collision time as printed, Eq. (36) (m the particle mass).

    Returns
    -------
    sympy.Expr
        ``dt(k_n, c_n, m)``.
    """
    return sp.pi / sp.sqrt(2 * k / m - c**2 / (4 * m**2))


def eq37() -> sp.Expr:
    """Critical damping coefficient: the discriminant of Eq. (31) vanishes, Eq. (37).

    Returns
    -------
    sympy.Expr
        ``c_crit(k, A)``.
    """
    sols = sp.solve(sp.Eq((c * A) ** 2 - 4 * k * A, 0), c)
    return [x for x in sols if x.is_positive is not False][0]


def beta_form(dt_expr: sp.Expr) -> sp.Expr:
    """The scaled step dt * sqrt(k/m) for identical spheres: A = 7/m, c = beta sqrt(m k) (Eqs. (58)-(60)).

    Parameters
    ----------
    dt_expr : sympy.Expr
        A step ``dt(k, c, A)``.

    Returns
    -------
    sympy.Expr
        The step in units of ``sqrt(m/k)``, as a function of ``beta``.
    """
    e = dt_expr.subs({A: 7 / m}).subs({c: beta * sp.sqrt(m * k)}) * sp.sqrt(k / m)
    return sp.simplify(e)
