"""Amplification matrices and characteristic polynomials built from the integrators' update rules.

Each scheme in ``dtcrit.integrators.schemes`` is applied to SymPy symbols.  Its update is linear in the state,
so the Jacobian of one step with respect to the state is exactly the amplification matrix ``G``
(Peng et al. 2020, Eq. (40) for the printed scheme).  Nothing here is typed in per integrator.

Two variable sets are used:

* dimensional: step ``h``, ``K = k A`` and ``C = c A`` (Peng et al. 2020, Eq. (30));
* dimensionless: ``tau = omega h`` and ``zeta = C / (2 omega)`` with ``omega = sqrt(K)``.  The
  characteristic polynomial depends on ``(tau, zeta)`` only, so the critical step is
  ``dt = tau_crit(zeta) / omega``.
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from dtcrit.integrators.schemes import Integrator, LinearForce, lookup

h, K, C = sp.symbols("h K C", positive=True)
tau, zeta = sp.symbols("tau zeta", nonnegative=True)
lam = sp.Symbol("lambda")


def _integrator(name_or_obj) -> Integrator:
    return lookup(name_or_obj)


def amplification_matrix(integrator, dimensionless: bool = False) -> sp.Matrix:
    """``G`` with ``state_{n+1} = G state_n``, from one application of the update rule.

    The rule is linear in the state, so its Jacobian is ``G`` (Peng et al. 2020, Eqs. (38)-(40) for
    the printed scheme).

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or user-written scheme.
    dimensionless : bool
        True: in ``tau = omega dt`` and ``zeta`` (``K = 1``, ``C = 2 zeta``); False: in ``h``, ``K``, ``C``.

    Returns
    -------
    sympy.Matrix
        ``G`` (d x d).
    """
    integ = _integrator(integrator)
    state = sp.symbols(f"s0:{len(integ.state)}")
    if dimensionless:
        new = integ.step(state, tau, LinearForce(sp.Integer(1), 2 * zeta))
    else:
        new = integ.step(state, h, LinearForce(K, C))
    rows = [[sp.diff(sp.sympify(e), s) for s in state] for e in new]
    return sp.Matrix(rows).applyfunc(sp.cancel)


@lru_cache(maxsize=None)
def characteristic_polynomial(name: str, dimensionless: bool = True) -> sp.Poly:
    """det(lambda I - G) with roots at lambda = 0 removed and positive denominators cleared.

    Roots at zero never affect stability; removing them gives the smaller polynomial (for the
    velocity-Verlet family the 3x3 ``G`` has a zero eigenvalue from the stored acceleration).
    The result has a leading coefficient that is positive for every admissible (tau, zeta).
    """
    G = amplification_matrix(name, dimensionless)
    det = sp.cancel((lam * sp.eye(G.shape[0]) - G).det())
    num, _den = sp.fraction(sp.together(det))  # denominators are 1 + tau*zeta-like, positive
    poly = sp.Poly(sp.expand(num), lam)
    while poly.degree() > 0 and sp.simplify(poly.eval(0)) == 0:
        poly = sp.Poly(sp.cancel(poly.as_expr() / lam), lam)
    lead = poly.LC()
    if sp.Poly(lead, *(sorted(lead.free_symbols, key=str) or [tau])).is_ground and lead.is_negative:
        poly = -poly
    if poly.LC().is_Rational and poly.LC() != 1:  # a constant leading coefficient: the monic form
        poly = sp.Poly(poly.as_expr() / poly.LC(), lam)
    return poly


def monic_coefficients(poly: sp.Poly) -> list[sp.Expr]:
    """[a_{n-1}, ..., a_0] of the monic form lambda^n + a_{n-1} lambda^{n-1} + ... + a_0.

    Parameters
    ----------
    poly : sympy.Poly
        A polynomial in ``lambda``.

    Returns
    -------
    list of sympy.Expr
        The coefficients, divided by the leading one.
    """
    coeffs = poly.all_coeffs()
    return [sp.cancel(c / coeffs[0]) for c in coeffs[1:]]
