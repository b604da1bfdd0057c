"""Schur-Cohn / Jury conditions: every root of a real polynomial strictly inside the unit circle.

For a monic real polynomial of degree n <= 3 the conditions are (Jury's table; complex pairs are
included, so this is the spectral-radius condition over *all* eigenvalues):

* p(1) > 0 and (-1)^n p(-1) > 0            (no real root crosses at lambda = +1 or -1);
* |a_0| < 1                                 (degree 2: the product of a complex pair);
* degree 3: 1 - a_0^2 > |a_0 a_2 - a_1|    (a complex pair crossing the circle).

Each condition is returned as ``(label, expr)`` meaning ``expr > 0``; all must hold.
"""
from __future__ import annotations

import sympy as sp

from dtcrit.symbolic.integrators import lam, monic_coefficients


def jury_conditions(poly: sp.Poly) -> list[tuple[str, sp.Expr]]:
    """Jury's conditions (degree 1-3) for every root of ``poly`` to lie inside the unit circle.

    Each condition is an expression that must be > 0: ``p(1)``, ``(-1)^n p(-1)`` and, from degree 2,
    ``1 -+ a0`` and, for degree 3, the two complex-pair conditions ``1 - a0^2 -+ (a0 a2 - a1)`` of the
    monic ``p = lambda^n + a_{n-1} lambda^{n-1} + ... + a0``.

    Parameters
    ----------
    poly : sympy.Poly
        Characteristic polynomial in ``lambda``, degree 1 to 3.

    Returns
    -------
    list of (str, sympy.Expr)
        (label, factored expression) pairs.
    """
    n = poly.degree()
    if n not in (1, 2, 3):
        raise NotImplementedError(f"Jury conditions implemented for degree 1-3, got {n}")
    a = monic_coefficients(poly)  # a[-1] = a_0
    monic = lam**n + sum(c * lam ** (n - 1 - i) for i, c in enumerate(a))
    conds = [
        ("p(+1) > 0: no real eigenvalue crosses at +1", sp.factor(monic.subs(lam, 1))),
        ("(-1)^n p(-1) > 0: no real eigenvalue crosses at -1", sp.factor((-1) ** n * monic.subs(lam, -1))),
    ]
    if n == 1:
        return conds
    a0 = a[-1]
    conds += [
        ("1 - a0 > 0: |a0| < 1 (upper)", sp.factor(1 - a0)),
        ("1 + a0 > 0: |a0| < 1 (lower)", sp.factor(1 + a0)),
    ]
    if n == 3:
        a2, a1 = a[0], a[1]
        conds += [
            ("1 - a0^2 - (a0 a2 - a1) > 0: complex pair inside", sp.factor(1 - a0**2 - (a0 * a2 - a1))),
            ("1 - a0^2 + (a0 a2 - a1) > 0: complex pair inside", sp.factor(1 - a0**2 + (a0 * a2 - a1))),
        ]
    return conds
