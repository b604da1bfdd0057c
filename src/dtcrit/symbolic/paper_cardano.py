"""The paper's Cardano route for its printed scheme, Peng et al. 2020, Eqs. (40)-(43).

The roots of the printed scheme's characteristic polynomial are transcribed in the dimensional
variables of Eq. (41) (``dt``, ``K_j = -k A``, ``C_j = -c A``) by ``paper_eq41_determinant`` and
``paper_eq42_roots``; in the dimensionless variables these depend on ``C_j dt = -2 zeta tau`` and
``K_j dt^2 = -tau^2`` only (``to_dimensionless``).  ``check_paper_cardano`` shows symbolically that
they are Cardano's roots of the library's polynomial (``dtcrit.symbolic.roots``).
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from dtcrit.symbolic.integrators import lam, tau, zeta
from dtcrit.symbolic.roots import dimensional_polynomial

# The paper's dimensional symbols (Eq. (40)): K_j = -k A < 0, C_j = -c A <= 0, dt > 0.
dt = sp.Symbol("Delta_t", positive=True)
Kj = sp.Symbol("K_j", negative=True)
Cj = sp.Symbol("C_j", nonpositive=True)


def paper_eq40_matrix() -> sp.Matrix:
    """Eq. (40) as printed: [[1, dt, 0], [0, 1, dt], [K_j, C_j, 0]].

    Returns
    -------
    sympy.Matrix
        The printed amplification matrix.
    """
    return sp.Matrix([[1, dt, 0], [0, 1, dt], [Kj, Cj, 0]])


def paper_eq41_determinant() -> sp.Expr:
    """Eq. (41) as printed: det([[1 - lambda, dt, 0], [0, 1 - lambda, dt], [K_j, C_j, -lambda]]).

    Returns
    -------
    sympy.Expr
        The determinant, expanded.
    """
    M = sp.Matrix([[1 - lam, dt, 0], [0, 1 - lam, dt], [Kj, Cj, -lam]])
    return sp.expand(M.det())


def paper_eq43_D() -> sp.Expr:
    """Eq. (43), with the extraction fix (the inner square root ends after ``(3 C_j dt + 1)^3``).

    Returns
    -------
    sympy.Expr
        ``D(dt, K_j, C_j)``.
    """
    N = -9 * Cj * dt + 27 * Kj * dt**2 - 2
    return sp.Pow(sp.sqrt(N**2 - 4 * (3 * Cj * dt + 1) ** 3) + N, sp.Rational(1, 3))


def paper_eq42_roots(D: sp.Expr | None = None) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Eq. (42) as printed (in dt, K_j, C_j); ``D`` defaults to Eq. (43).

    Parameters
    ----------
    D : sympy.Expr, optional
        The ``D`` to use (:func:`paper_eq43_D` when None).

    Returns
    -------
    tuple of sympy.Expr
        The three printed roots.
    """
    D = paper_eq43_D() if D is None else D
    c2 = sp.cbrt(2)
    M = 3 * Cj * dt + 1
    s3i = sp.sqrt(3) * sp.I
    return (
        D / (3 * c2) + c2 * M / (3 * D) + sp.Rational(2, 3),
        (s3i - 1) * D / (6 * c2) - (1 + s3i) * M / (3 * 2 ** sp.Rational(2, 3) * D) + sp.Rational(2, 3),
        (-s3i - 1) * D / (6 * c2) - (1 - s3i) * M / (3 * 2 ** sp.Rational(2, 3) * D) + sp.Rational(2, 3),
    )


PAPER_TO_DIMENSIONLESS = {Cj: -2 * zeta * tau / dt, Kj: -(tau**2) / dt**2}
"""K_j = -k A = -omega^2 and C_j = -c A = -2 zeta omega with tau = omega dt."""


def to_dimensionless(expr: sp.Expr) -> sp.Expr:
    """Rewrite an expression in (dt, K_j, C_j) in (tau, zeta).

    Parameters
    ----------
    expr : sympy.Expr
        An expression in the printed symbols.

    Returns
    -------
    sympy.Expr
        The same with ``K_j = -omega^2 = -tau^2/dt^2`` and ``C_j = -2 zeta omega = -2 zeta tau/dt``.
    """
    return expr.subs(PAPER_TO_DIMENSIONLESS)


@dataclass(frozen=True)
class CardanoCheck:
    """Symbolic identities showing that Eq. (42) with Eq. (43) are Cardano's roots of Eq. (41).

    Parameters
    ----------
    eq41_equals_library : bool
        The printed determinant equals -(library ``det(lambda I - G)``) with ``K_j = -K``, ``C_j = -C``.
    uv_product : bool
        ``u v = -p/3`` with ``u = D/(3 2^(1/3))``, ``v = 2^(1/3)(3 C_j dt + 1)/(3 D)``.
    u3_plus_v3 : bool
        ``u^3 + v^3 = -q`` (after rationalising ``1/D^3``).
    shift_is_two_thirds : bool
        The shift of the printed roots is 2/3, the depressed cubic's ``a2/3``.
    """

    eq41_equals_library: bool  # printed det == -(library det(lambda I - G)) with K_j = -K, C_j = -C
    uv_product: bool  # u v = -p/3 with u = D/(3 2^(1/3)), v = 2^(1/3)(3 C_j dt + 1)/(3 D)
    u3_plus_v3: bool  # u^3 + v^3 = -q (after rationalising 1/D^3)
    shift_is_two_thirds: bool


def check_paper_cardano() -> CardanoCheck:
    """Verify Eqs. (41)-(43) symbolically against the library's polynomial for ``paper-eq40``.

    Returns
    -------
    CardanoCheck
        The identities (all True when the printed route is Cardano's).
    """
    from dtcrit.symbolic.integrators import C, K, h

    lib = dimensional_polynomial("paper-eq40").as_expr()
    printed = paper_eq41_determinant().subs({Kj: -K, Cj: -C, dt: h})
    eq41_ok = sp.expand(printed + lib) == 0
    # the monic form of the printed determinant, in the paper's variables
    mon = sp.Poly(-paper_eq41_determinant(), lam)
    a2, a1, a0 = (sp.expand(c) for c in mon.all_coeffs()[1:])
    p = sp.expand(a1 - a2**2 / 3)
    q = sp.expand(2 * a2**3 / 27 - a2 * a1 / 3 + a0)
    Dsym = sp.Symbol("D", nonzero=True)
    M = 3 * Cj * dt + 1
    u = Dsym / (3 * sp.cbrt(2))
    v = sp.cbrt(2) * M / (3 * Dsym)
    uv_ok = sp.simplify(u * v + p / 3) == 0
    # D^3 = N + S with S^2 = N^2 - 4 M^3, so 1/D^3 = (N - S)/(4 M^3)
    N = -9 * Cj * dt + 27 * Kj * dt**2 - 2
    S = sp.Symbol("S")
    u3 = (N + S) / 54
    v3 = 2 * M**3 * (N - S) / (4 * M**3) / 27
    u3v3_ok = sp.expand(u3 + v3 + q) == 0
    shift_ok = sp.simplify(-a2 / 3 - sp.Rational(2, 3)) == 0
    return CardanoCheck(eq41_ok, uv_ok, u3v3_ok, shift_ok)
