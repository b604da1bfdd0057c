"""Producer of ``dtcrit/_generated/eigenvalues.py``: every eigenvalue of every amplification matrix.

For each integrator of ``dtcrit.integrators.schemes`` the kernel ``eigenvalues_<name>(tau, zeta)`` returns the
roots of its characteristic polynomial (``dtcrit.symbolic.roots``) as a complex array of shape
``(degree,) + broadcast shape``, in the numerically sound form:

* degree 2: ``q = -(b + sgn(b) sqrt(D))/2``, roots ``q/a`` and ``c/q`` (real), or
  ``-b/(2a) +- i sqrt(-D)/(2a)`` (complex pair);
* degree 3: the isolated real root from Viete's trigonometric form (three real roots) or the
  hyperbolic form (one real root), polished by Newton's method on the cubic; the other two from
  the deflated sum and product and the split ``sqrt(|Disc|) / (2 P'(r))``.

Everything that cancels exactly (the depressed coefficients, the discriminant's factors) is done
symbolically; the kernels receive the factored discriminant, each non-monomial factor evaluated in
double-double arithmetic, so that a nearly double pair of eigenvalues is still split to full
precision (a plain evaluation, like an eigen-solver, loses half the digits there).  ``eigenvalues_cardano_paper_eq40``
evaluates the paper's own route, Peng et al. 2020, Eqs. (42)-(43), literally in complex float64,
for comparison of accuracy.
"""
from __future__ import annotations

import sympy as sp

from dtcrit.integrators.schemes import NAMES
from dtcrit.symbolic import paper_cardano as PC
from dtcrit.symbolic import roots as R
from dtcrit.symbolic.emit import Kernel, python_module
from dtcrit.symbolic.integrators import tau, zeta

QUADRATIC = sp.Function("_quadratic_roots")
CUBIC = sp.Function("_cubic_roots")
STACK = sp.Function("_stack")
CSQRT = sp.Function("_csqrt")
CCBRT = sp.Function("_ccbrt")
DD_POLY = sp.Function("_dd_poly")

# the kernels call the sound root forms and double-double polynomials of dtcrit.numerics
PREAMBLE = """\
from dtcrit.numerics.eft import dd_polynomial as _dd_poly
from dtcrit.numerics.polynomial_roots import cubic_roots as _cubic_roots
from dtcrit.numerics.polynomial_roots import principal_cbrt as _ccbrt
from dtcrit.numerics.polynomial_roots import principal_sqrt as _csqrt
from dtcrit.numerics.polynomial_roots import quadratic_roots as _quadratic_roots
from dtcrit.numerics.polynomial_roots import stack_roots as _stack
"""


def py_name(integrator: str) -> str:
    """Name of the emitted eigenvalue kernel of an integrator.

    Parameters
    ----------
    integrator : str
        Name of the integrator.

    Returns
    -------
    str
        ``eigenvalues_<name>`` with dashes as underscores.
    """
    return "eigenvalues_" + integrator.replace("-", "_")


def dd_factor(f: sp.Expr) -> sp.Expr:
    """A polynomial factor of the discriminant, evaluated in double-double unless it is a monomial.

    Parameters
    ----------
    f : sympy.Expr
        A polynomial in tau and zeta.

    Returns
    -------
    sympy.Expr
        ``f`` itself (a monomial) or a call of ``_dd_poly`` (``dtcrit.numerics.eft.dd_polynomial``).
    """
    poly = sp.Poly(f, tau, zeta)
    if len(poly.terms()) == 1:
        return f
    if any(not c.is_Integer for c in poly.coeffs()):
        return dd_rational(f)
    terms = [sp.Tuple(sp.Integer(c), i, j) for (i, j), c in sorted(poly.terms())]
    return DD_POLY(sp.Tuple(*terms), tau, zeta)


def dd_rational(f: sp.Expr) -> sp.Expr:
    """A polynomial with rational coefficients as (integer polynomial in double-double) / denominator.

    Parameters
    ----------
    f : sympy.Expr
        A polynomial in tau and zeta with rational coefficients.

    Returns
    -------
    sympy.Expr
        The double-double evaluation of the integer polynomial divided by the common denominator.
    """
    poly = sp.Poly(f, tau, zeta)
    den = sp.ilcm(*[sp.Rational(c).q for c in poly.coeffs()])
    return dd_factor(sp.expand(f * den)) / den


def discriminant_numeric(name: str) -> tuple[sp.Expr, sp.Expr]:
    """(Disc, sqrt(|Disc|)) for the kernels: factor by factor, near-zero factors in double-double.

    Parameters
    ----------
    name : str
        Name of the integrator.

    Returns
    -------
    tuple of sympy.Expr
        ``(Disc, sqrt(|Disc|))`` built from the factors.
    """
    const, factors = R.discriminant_factors(name)
    disc = const
    sad = sp.sqrt(abs(const))
    for f, m in factors:
        g = dd_factor(f)
        disc *= g**m
        if m // 2:
            sad *= sp.Abs(g) ** (m // 2)
        if m % 2:
            sad *= sp.sqrt(sp.Abs(g))
    return disc, sad


def discriminant_scale(name: str) -> sp.Expr:
    """The discriminant with every coefficient replaced by its absolute value: the size of the terms
    that cancel in it, from which the kernel bounds the double-double rounding error.

    Parameters
    ----------
    name : str
        Name of the integrator.

    Returns
    -------
    sympy.Expr
        The discriminant with absolute coefficients.
    """
    const, factors = R.discriminant_factors(name)
    out = abs(const)
    for f, m in factors:
        poly = sp.Poly(f, tau, zeta)
        out *= sum(abs(c) * tau**i * zeta**j for (i, j), c in poly.terms()) ** m
    return out


def kernel_expr(name: str) -> sp.Expr:
    """The sound-form eigenvalue kernel of one integrator, as a call of a preamble helper.

    Parameters
    ----------
    name : str
        Name of the integrator.

    Returns
    -------
    sympy.Expr
        A call of ``_quadratic_roots`` or ``_cubic_roots`` (``dtcrit.numerics.polynomial_roots``).
    """
    disc, sad = discriminant_numeric(name)
    if R.degree(name) == 2:
        a, b, c = R.coefficients(name)
        # b and c in double-double: as written they cancel where a root is small (forward Euler's
        # c = tau^2 - 2 tau zeta + 1 = (1 - tau)^2 at zeta = 1, tau near 1)
        return QUADRATIC(a, dd_rational(b), dd_rational(c), disc, sad)
    if R.degree(name) == 3:
        a2, a1, a0 = R.monic_coefficients(name)
        _shift, p, q = R.depressed(name)
        return CUBIC(a2, a1, a0, dd_rational(p), dd_rational(q), disc, sad, discriminant_scale(name))
    raise NotImplementedError(name)


def cardano_paper_eq40_expr() -> sp.Expr:
    """Eqs. (42)-(43) literally (complex principal roots), with C_j dt = -2 zeta tau, K_j dt^2 = -tau^2.

    Returns
    -------
    sympy.Expr
        A call of ``_stack`` on the three roots in tau and zeta.
    """
    N = -9 * PC.Cj * PC.dt + 27 * PC.Kj * PC.dt**2 - 2
    M = 3 * PC.Cj * PC.dt + 1
    D = CCBRT(CSQRT(N**2 - 4 * M**3) + N)
    # no expansion: the differences are evaluated as printed, cancellation included
    return STACK(*[r.subs(PC.PAPER_TO_DIMENSIONLESS) for r in PC.paper_eq42_roots(D)])


ARGS = (
    (tau, "omega*dt, dimensionless step (omega = sqrt(k*A))"),
    (zeta, "c*A/(2*omega), damping ratio"),
)


def kernels() -> list[Kernel]:
    """The eigenvalue kernels of every integrator and the paper's Cardano route (Eqs. (42)-(43)).

    Returns
    -------
    list of Kernel
        One eigenvalue kernel per integrator, then the paper's Cardano route.
    """
    out = []
    for n in NAMES:
        deg = R.degree(n)
        form = "quadratic (cancellation-free)" if deg == 2 else "cubic (trigonometric / hyperbolic, isolated root first)"
        zeros = R.structural_zero_eigenvalues(n)
        extra = f" The amplification matrix has {zeros} further eigenvalue(s) equal to 0." if zeros else ""
        out.append(
            Kernel(
                py_name(n),
                ARGS,
                kernel_expr(n),
                f"Eigenvalues of the '{n}' amplification matrix: roots of its characteristic polynomial, {form}.\n\n"
                f"    Polynomial: {sp.sstr(R.characteristic_polynomial(n).as_expr())}.{extra}\n"
                "    Peng et al. 2020, Eqs. (40)-(42) for the method; derived by dtcrit.symbolic.roots.",
                cse=True,
                returns=f"complex array of shape ({deg},) + broadcast shape of (tau, zeta)",
            )
        )
    out.append(
        Kernel(
            "eigenvalues_cardano_paper_eq40",
            ARGS,
            cardano_paper_eq40_expr(),
            "The three eigenvalues of Eq. (40) by the paper's own route, Peng et al. 2020, Eqs. (42)-(43),\n\n"
            "    in complex float64 with principal square and cube roots.  For comparison only: it divides by\n"
            "    D, which vanishes on tau*zeta = 1/6 (zeta <= sqrt(3)/2), and loses digits near that curve and\n"
            "    near double roots; use eigenvalues_paper_eq40.",
            cse=True,
            returns="complex array of shape (3,) + broadcast shape (NaN where D = 0)",
        )
    )
    return out


def postamble() -> str:
    """The tables and the spectral radius appended to ``eigenvalues.py``.

    Returns
    -------
    str
        ``EIGENVALUE_KERNELS``, ``STRUCTURAL_ZERO_EIGENVALUES`` and ``spectral_radius``.
    """
    lines = ["EIGENVALUE_KERNELS = {"]
    lines += [f"    {n!r}: {py_name(n)}," for n in NAMES]
    lines += ["}", "", "# zero eigenvalues of the amplification matrix left out of its characteristic polynomial"]
    lines += ["STRUCTURAL_ZERO_EIGENVALUES = {"]
    lines += [f"    {n!r}: {R.structural_zero_eigenvalues(n)}," for n in NAMES]
    lines += ["}", ""]
    lines += [
        "",
        "def spectral_radius(integrator, tau, zeta):",
        '    """max |lambda| over all eigenvalues of the amplification matrix (vectorised)."""',
        "    return np.max(np.abs(EIGENVALUE_KERNELS[integrator](tau, zeta)), axis=0)",
    ]
    return "\n".join(lines)


def generated_files() -> dict[str, str]:
    """The files this producer writes under ``dtcrit/_generated`` (``dtcrit.symbolic.regenerate``).

    Returns
    -------
    dict of str to str
        ``{"eigenvalues.py": text}``.
    """
    text = python_module(
        "dtcrit.symbolic.roots_codegen",
        "Eigenvalues of the integrators' amplification matrices (numerically sound closed forms) and the\n"
        "paper's Cardano route (Peng et al. 2020, Eqs. (42)-(43)) for comparison.",
        kernels(),
        preamble=PREAMBLE,
        postamble=postamble(),
    )
    return {"eigenvalues.py": text}
