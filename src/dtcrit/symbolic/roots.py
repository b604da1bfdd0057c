"""Eigenvalues of the amplification matrices: the roots of the characteristic polynomials.

The characteristic polynomial of each integrator is ``dtcrit.symbolic.integrators.
characteristic_polynomial(name)`` (det(lambda I - G) in ``tau = omega dt`` and ``zeta``, with the
structural zero eigenvalues removed).  Its roots are written here in closed form:

* degree 2 (forward Euler, symplectic Euler, both leapfrogs, velocity Verlet): the textbook
  quadratic formula and the cancellation-free form (``q = -(b + s sqrt(D))/2``, roots ``q/a`` and
  ``c/q``), with the discriminant ``D`` factored symbolically;
* degree 3 (the printed scheme of Peng et al. 2020, Eq. (40), and velocity Verlet with predicted
  damping velocity): Cardano's form exactly as the paper prints it (Eqs. (42)-(43)), and the
  numerically sound form (Viete's trigonometric form when the three roots are real, the
  hyperbolic form when one is real, both written with the symbolically factored discriminant so
  that no ``acos``/``acosh`` is taken of a rounded number near 1).

The paper's own route (Eqs. (40)-(43) in the dimensional variables ``dt``, ``K_j``, ``C_j``) is
transcribed in ``dtcrit.symbolic.paper_cardano``.

Every function returns SymPy expressions; ``dtcrit.symbolic.roots_codegen`` emits the numeric
kernels (``dtcrit._generated.eigenvalues``).
"""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from dtcrit.integrators.schemes import lookup
from dtcrit.symbolic.integrators import characteristic_polynomial, tau, zeta

OMEGA3 = sp.Rational(-1, 2) + sp.sqrt(3) * sp.I / 2  # primitive cube root of unity


def degree(name: str) -> int:
    """Degree in lambda of the scheme's characteristic polynomial (zero roots removed).

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    int
        The degree.
    """
    return characteristic_polynomial(name).degree()


def structural_zero_eigenvalues(name: str) -> int:
    """Number of zero eigenvalues of ``G`` removed from its characteristic polynomial.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    int
        The count.
    """
    return len(lookup(name).state) - degree(name)


def dimensional_polynomial(name: str) -> sp.Poly:
    """det(lambda I - G) in the step ``h`` and the rates ``K = k A``, ``C = c A`` (zero roots removed).

    For ``paper-eq40`` this is minus the paper's Eq. (41) with ``K_j = -K``, ``C_j = -C``
    (``check_paper_cardano``).

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    sympy.Poly
        The polynomial in ``lambda``.
    """
    return characteristic_polynomial(name, dimensionless=False)


def coefficients(name: str) -> tuple[sp.Expr, ...]:
    """(c_n, ..., c_0) of the characteristic polynomial in lambda, each expanded in (tau, zeta).

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of sympy.Expr
        The coefficients.
    """
    return tuple(sp.expand(c) for c in characteristic_polynomial(name).all_coeffs())


def monic_coefficients(name: str) -> tuple[sp.Expr, ...]:
    """(a_{n-1}, ..., a_0) of the monic polynomial (only used for leading coefficient 1 here).

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of sympy.Expr
        The coefficients.
    """
    c = coefficients(name)
    return tuple(sp.expand(sp.cancel(x / c[0])) for x in c[1:])


@lru_cache(maxsize=None)
def discriminant(name: str) -> sp.Expr:
    """Discriminant of the characteristic polynomial in lambda, factored over the rationals.

    Degree 2: ``b^2 - 4 a c``; degree 3 (monic): ``-4 p^3 - 27 q^2`` of the depressed cubic
    (the product of the squared root differences).  Factoring removes the spurious
    cancellations of the expanded form (e.g. ``tau^2 (zeta - 1)(zeta + 1)`` for forward Euler).
    """
    c = coefficients(name)
    if len(c) == 3:
        a, b, cc = c
        return sp.factor(sp.expand(b**2 - 4 * a * cc))
    if len(c) == 4:
        if c[0] != 1:
            raise NotImplementedError(f"{name}: non-monic cubic")
        p, q = depressed(name)[1:]
        return sp.factor(sp.expand(-4 * p**3 - 27 * q**2))
    raise NotImplementedError(f"{name}: degree {len(c) - 1}")


def discriminant_factors(name: str) -> tuple[sp.Rational, list[tuple[sp.Expr, int]]]:
    """(constant, [(irreducible factor, multiplicity), ...]) of ``discriminant(name)``.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple
        The rational constant and the list of (factor, multiplicity).
    """
    const, factors = sp.factor_list(discriminant(name), tau, zeta)
    return sp.Rational(const), [(f, m) for f, m in factors]


def sqrt_abs_discriminant(name: str) -> sp.Expr:
    """sqrt(|Disc|) as a product over the factors: ``|f|^(m//2)`` times ``sqrt(|f|)`` for odd ``m``.

    Evaluated factor by factor it neither overflows before the root is taken nor loses the
    exactly cancelled parts (a factor ``tau^2`` stays a factor).  The *sign* of the discriminant
    is the sign of the factored product.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    sympy.Expr
        ``sqrt(|Disc|)`` in (tau, zeta).
    """
    const, factors = discriminant_factors(name)
    out = sp.sqrt(abs(const))
    for f, m in factors:
        if m // 2:
            out *= sp.Abs(f) ** (m // 2)
        if m % 2:
            out *= sp.sqrt(sp.Abs(f))
    return out


# ---------------------------------------------------------------- quadratics


def quadratic_roots_textbook(name: str) -> tuple[sp.Expr, sp.Expr]:
    """(-b +- sqrt(b^2 - 4 a c)) / (2 a): the schoolbook form (cancels for |4 a c| << b^2).

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of sympy.Expr
        The two roots.
    """
    a, b, c = coefficients(name)
    s = sp.sqrt(sp.expand(b**2 - 4 * a * c))
    return ((-b + s) / (2 * a), (-b - s) / (2 * a))


def quadratic_roots_sound(name: str, branch_sign: int) -> tuple[sp.Expr, sp.Expr]:
    """Cancellation-free roots ``q/a`` and ``c/q`` with ``q = -(b + s sqrt(D))/2``.

    ``branch_sign`` is ``s``: the numeric kernel takes ``s = sgn(b)`` (+1 at 0) for real roots, so
    that ``b`` and ``s sqrt(D)`` never cancel; for a complex pair there is no cancellation either
    way.  ``D`` is the factored discriminant.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).
    branch_sign : int
        ``s``, +1 or -1.

    Returns
    -------
    tuple of sympy.Expr
        The two roots.
    """
    a, b, c = coefficients(name)
    q = -(b + branch_sign * sp.sqrt(discriminant(name))) / 2
    return (q / a, c / q)


# ---------------------------------------------------------------- cubics


@lru_cache(maxsize=None)
def depressed(name: str) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(shift, p, q): lambda = t - shift turns the monic cubic into t^3 + p t + q.

    ``p`` and ``q`` are expanded polynomials in (tau, zeta), so the constant parts of
    ``a1 - a2^2/3`` and ``2 a2^3/27 - a2 a1/3 + a0`` cancel exactly (e.g. ``p = 2 tau zeta - 1/3``
    and ``q = tau^2 - 2 tau zeta/3 + 2/27`` for Eq. (40)).
    """
    a2, a1, a0 = monic_coefficients(name)
    shift = a2 / 3
    p = sp.expand(a1 - a2**2 / 3)
    q = sp.expand(2 * a2**3 / 27 - a2 * a1 / 3 + a0)
    return shift, p, q


def cardano_roots(name: str) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Cardano's form: ``t = u + v``, ``u^3 = -q/2 + sqrt(q^2/4 + p^3/27)``, ``v = -p/(3u)``.

    With the principal cube root ``u`` and ``v`` tied to it, the three roots are
    ``u + v``, ``w u + w^2 v`` and ``w^2 u + w v`` (``w = exp(2 pi i/3)``), minus the shift.
    Undefined where ``u = 0`` (``p = 0`` and ``q >= 0``).  This is the structure of Eqs. (42)-(43)
    (``D = 3 * 2^(1/3) u`` there).

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of sympy.Expr
        The three roots in lambda.
    """
    shift, p, q = depressed(name)
    u = sp.Pow(-q / 2 + sp.sqrt(q**2 / 4 + p**3 / 27), sp.Rational(1, 3))
    v = -p / (3 * u)
    w, w2 = OMEGA3, sp.conjugate(OMEGA3)
    return (u + v - shift, w * u + w2 * v - shift, w2 * u + w * v - shift)


def trigonometric_roots(name: str) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """Viete's trigonometric form, valid where the discriminant is >= 0 (three real roots).

    ``t_k = 2 sqrt(-p/3) cos(theta/3 - 2 pi k/3)`` with ``theta = atan2(sqrt(Disc), -3 sqrt(3) q)``;
    the usual ``theta = acos((3q/2p) sqrt(-3/p))`` rewritten through ``sin theta = sqrt(Disc) /
    (2 |p|^(3/2))``, so the angle stays accurate when two roots nearly coincide.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of sympy.Expr
        The three real roots in lambda.
    """
    shift, p, q = depressed(name)
    theta = sp.atan2(sp.sqrt(discriminant(name)), -3 * sp.sqrt(3) * q)
    r = 2 * sp.sqrt(-p / 3)
    return tuple(r * sp.cos(theta / 3 - 2 * sp.pi * k / 3) - shift for k in range(3))


def hyperbolic_real_root(name: str) -> sp.Expr:
    """The real root where the discriminant is < 0 (one real root, a complex pair).

    Hyperbolic forms: ``t = -2 sgn(q) sqrt(|p|/3) sinh(phi/3)`` (p > 0) or ``cosh(phi/3)`` (p < 0)
    with ``phi = log((3 sqrt(3)|q| + sqrt(-Disc)) / (2 |p|^(3/2)))`` (= asinh / acosh of the usual
    argument).  With ``E = ((3 sqrt(3)|q| + sqrt(-Disc))/2)^(1/3)``, ``exp(phi/3) = E/sqrt(|p|)`` and
    both cases become ``t = -sgn(q) (E - p/E)/sqrt(3)``, which also holds at ``p = 0``: no division
    by ``|p|`` and no cancellation inside ``E``.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    sympy.Expr
        The real root in lambda.
    """
    shift, p, q = depressed(name)
    E = sp.cbrt((3 * sp.sqrt(3) * sp.Abs(q) + sp.sqrt(-discriminant(name))) / 2)
    sgn = sp.Piecewise((-1, q < 0), (1, True))
    return -sgn * (E - p / E) / sp.sqrt(3) - shift


def pair_from_isolated_root(name: str, r: sp.Expr, t_r: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """The two other roots given one root ``r = t_r - shift`` (used symbolically and numerically).

    Sum ``sigma = -(a2 + r)`` and product ``pi = -a0/r`` of the other two; their half-difference
    is ``sqrt(Disc) / (2 P'(r))`` with ``P'(r) = 3 t_r^2 + p`` (``Disc = (r - l2)^2 (r - l3)^2
    (l2 - l3)^2`` and ``P'(r) = (r - l2)(r - l3)``), so a nearly double pair is split accurately.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).
    r : sympy.Expr
        The known root in lambda.
    t_r : sympy.Expr
        The same root in the depressed variable ``t``.

    Returns
    -------
    tuple of sympy.Expr
        The two other roots.
    """
    a2 = monic_coefficients(name)[0]
    p = depressed(name)[1]
    sigma = -(a2 + r)
    half = sp.sqrt(discriminant(name)) / (2 * (3 * t_r**2 + p))
    return (sigma / 2 + half, sigma / 2 - half)
