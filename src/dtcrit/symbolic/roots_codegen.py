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
from dtcrit.symbolic import roots as R
from dtcrit.symbolic.emit import Kernel, python_module
from dtcrit.symbolic.integrators import tau, zeta

QUADRATIC = sp.Function("_quadratic_roots")
CUBIC = sp.Function("_cubic_roots")
STACK = sp.Function("_stack")
CSQRT = sp.Function("_csqrt")
CCBRT = sp.Function("_ccbrt")
DD_POLY = sp.Function("_dd_poly")

PREAMBLE = '''
_EPS = np.finfo(float).eps


def _stack(*roots):
    """Complex array of shape (number of roots,) + broadcast shape."""
    return np.stack(np.broadcast_arrays(*(np.asarray(r, dtype=complex) for r in roots)))


def _csqrt(x):
    """Principal complex square root (a negative real gives +i sqrt(-x))."""
    return np.sqrt(np.asarray(x, dtype=complex))


def _ccbrt(x):
    """Principal complex cube root, as a general-purpose complex power would take it."""
    return np.power(np.asarray(x, dtype=complex), 1.0 / 3.0)


_SPLITTER = 134217729.0  # 2^27 + 1, Dekker's splitting constant


def _two_sum(a, b):
    """s + e = a + b exactly (Knuth)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def _two_prod(a, b):
    """p + e = a * b exactly (Dekker; |a|, |b| well below 1e300)."""
    p = a * b
    c = _SPLITTER * a
    ah = c - (c - a)
    al = a - ah
    c = _SPLITTER * b
    bh = c - (c - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def _dd_poly(terms, tau, zeta):
    """sum(c tau^i zeta^j for (c, i, j) in terms) in double-double arithmetic, rounded once.

    The integer coefficients are exact; every product and sum keeps its rounding error, so the
    result has a relative error of about 1e-16 even where the terms cancel to many digits (the
    factors of a discriminant near a double root).
    """
    tau, zeta = np.broadcast_arrays(np.asarray(tau, dtype=float), np.asarray(zeta, dtype=float))
    hi = np.zeros(tau.shape)
    lo = np.zeros(tau.shape)
    for c, i, j in terms:
        th = np.full(tau.shape, float(c))
        tl = np.zeros(tau.shape)
        for x in (tau,) * i + (zeta,) * j:
            p, e = _two_prod(th, x)
            th, tl = _two_sum(p, e + tl * x)
        s, e = _two_sum(hi, th)
        hi, lo = _two_sum(s, e + lo + tl)
    return hi + lo


def _sgn(x):
    """Sign with sgn(0) = +1."""
    return np.where(x < 0, -1.0, 1.0)


def _quadratic_roots(a, b, c, disc, sqrt_abs_disc):
    """Both roots of a l^2 + b l + c (a > 0) without cancellation.

    ``disc`` is the discriminant b^2 - 4ac evaluated from its factored form (only its sign is
    used) and ``sqrt_abs_disc`` = sqrt(|disc|), also from the factors.  Real roots:
    q = -(b + sgn(b) sqrt(D))/2, roots q/a and c/q; complex pair: -b/(2a) +- i sqrt(-D)/(2a).
    """
    a, b, c, disc, s = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a, b, c, disc, sqrt_abs_disc)))
    with np.errstate(all="ignore"):
        q = -(b + _sgn(b) * s) / 2.0
        big = q / a
        small = np.where(q != 0, c / np.where(q != 0, q, 1.0), 0.0)
        re = -b / (2.0 * a)
        im = s / (2.0 * a)
    real = disc >= 0
    return _stack(np.where(real, big, re + 1j * im), np.where(real, small, re - 1j * im))


def _cubic_roots(a2, a1, a0, p, q, disc, sqrt_abs_disc, disc_scale):
    """The three roots of l^3 + a2 l^2 + a1 l + a0, the isolated real root first.

    ``p``, ``q``: the depressed cubic t^3 + p t + q (l = t - a2/3), expanded symbolically and
    evaluated in double-double; ``disc`` = -4p^3 - 27q^2 from its factored form (double-double
    factors), ``sqrt_abs_disc`` = sqrt(|disc|), and ``disc_scale`` the same product with absolute
    coefficients.  Near a triple root the factored value is below its rounding error
    (~ eps^2 disc_scale); there -4p^3 - 27q^2 from the accurate p and q is used instead, whichever
    has the smaller error bound.

    1. The isolated real root t_r (the one farthest from the other two):
       disc >= 0: Viete, t = 2 sqrt(-p/3) cos(theta/3 - 2 pi k/3), theta = atan2(sqrt(disc),
       -3 sqrt(3) q), k = 0 if theta <= pi/2 else k = 2;
       disc < 0: hyperbolic form, t = -sgn(q) (E - p/E)/sqrt(3), E = ((3 sqrt(3)|q| + sqrt(-disc))/2)^(1/3)
       (= -2 sgn(q) sqrt(|p|/3) sinh or cosh of asinh/acosh(...)/3, written without 1/|p|).
    2. Two Newton steps on the cubic for r = t_r - a2/3, each taken only where its rounding
       error bound is below that of the closed form and it reduces |P|.
    3. Deflation: sum and product of the other two from whichever of (-(a2 + r), a1 - r sigma) and
       ((a1 - pi)/r, -a0/r) has the smaller error estimate (rounding plus the last Newton step).
    4. The other two roots sigma/2 +- d, d = sqrt(|disc|) / (2 P'(r)), P'(r) = 3 t_r^2 + p > 0;
       real: the larger from sigma/2 + sgn(sigma) d, the smaller as pi / larger.
    """
    a2, a1, a0, p, q, disc, sad, scale = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (a2, a1, a0, p, q, disc, sqrt_abs_disc, disc_scale))
    )
    with np.errstate(all="ignore"):
        disc_pq = -4.0 * p**3 - 27.0 * q * q
        use_pq = 8.0 * _EPS * (4.0 * np.abs(p) ** 3 + 27.0 * q * q) < 8.0 * _EPS * _EPS * scale
        disc = np.where(use_pq, disc_pq, disc)
        sad = np.where(use_pq, np.sqrt(np.abs(disc_pq)), sad)
    three_real = disc >= 0
    with np.errstate(all="ignore"):
        # 1. isolated root of the depressed cubic
        radius = 2.0 * np.sqrt(np.maximum(-p, 0.0) / 3.0)
        theta = np.arctan2(sad, -3.0 * np.sqrt(3.0) * q)
        t_trig = radius * np.cos(np.where(theta <= np.pi / 2, theta / 3.0, theta / 3.0 + 2.0 * np.pi / 3.0))
        E = np.cbrt((3.0 * np.sqrt(3.0) * np.abs(q) + sad) / 2.0)
        t_hyp = np.where(E > 0, -_sgn(q) * (E - p / np.where(E > 0, E, 1.0)) / np.sqrt(3.0), 0.0)
        t = np.where(three_real, t_trig, t_hyp)
        r = t - a2 / 3.0
        # 2. Newton on the original cubic.  Its result is accurate to eps * S / |P'(r)| (S the sum
        # of the absolute terms of P(r)), the closed form to eps * (t_size + |a2|/3) with t_size the
        # size of the terms that make up t: polish only where the first is smaller (not near a
        # multiple root) and the step reduces |P|.
        t_size = np.where(three_real, radius, (E + np.abs(p) / np.where(E > 0, E, 1.0)) / np.sqrt(3.0))
        dPt = 3.0 * t * t + p
        last = np.zeros_like(r)
        for _ in range(2):
            P = ((r + a2) * r + a1) * r + a0
            dP = (3.0 * r + 2.0 * a2) * r + a1
            ar = np.abs(r)
            noise = ((ar + np.abs(a2)) * ar + np.abs(a1)) * ar + np.abs(a0)
            useful = noise < np.abs(dP) * (t_size + np.abs(a2) / 3.0)
            step = np.where(dP != 0, P / np.where(dP != 0, dP, 1.0), 0.0)
            r_new = r - step
            P_new = ((r_new + a2) * r_new + a1) * r_new + a0
            ok = useful & np.isfinite(r_new) & (np.abs(P_new) <= np.abs(P))
            r = np.where(ok, r_new, r)
            last = np.where(ok, np.abs(step), last)
        # 3. deflation: sum sigma and product pi of the other two roots
        nz = r != 0
        rr = np.where(nz, r, 1.0)
        rel_r = _EPS + last / np.abs(rr)
        sigma_a = -(a2 + r)
        err_sigma_a = _EPS * (np.abs(a2) + np.abs(r)) + last
        pi_b = -a0 / rr
        sigma_b = (a1 - pi_b) / rr
        err_sigma_b = (np.abs(a1) + np.abs(pi_b)) / np.abs(rr) * (_EPS + 2.0 * rel_r)
        use_b = nz & (err_sigma_b < err_sigma_a)
        sigma = np.where(use_b, sigma_b, sigma_a)
        pi_a = a1 - r * sigma
        err_pi_a = _EPS * (np.abs(a1) + 2.0 * np.abs(r * sigma)) + last * np.abs(sigma)
        err_pi_b = np.abs(pi_b) * rel_r
        pi = np.where(nz & (err_pi_b < err_pi_a), pi_b, pi_a)
        # 4. the pair, split by the discriminant
        d = np.where(dPt > 0, sad / (2.0 * np.where(dPt > 0, dPt, 1.0)), 0.0)
        # Fujiwara: every root of t^3 + p t + q has |t| <= 2 max(|p|^(1/2), |q/2|^(1/3))
        d = np.minimum(d, 2.0 * np.maximum(np.sqrt(np.abs(p)), np.cbrt(np.abs(q) / 2.0)))
        big = sigma / 2.0 + _sgn(sigma) * d
        small = np.where(big != 0, pi / np.where(big != 0, big, 1.0), 0.0)
        l2 = np.where(three_real, big, sigma / 2.0 + 1j * d)
        l3 = np.where(three_real, small, sigma / 2.0 - 1j * d)
    return _stack(r, l2, l3)
'''


def py_name(integrator: str) -> str:
    return "eigenvalues_" + integrator.replace("-", "_")


def dd_factor(f: sp.Expr) -> sp.Expr:
    """A polynomial factor of the discriminant, evaluated in double-double unless it is a monomial."""
    poly = sp.Poly(f, tau, zeta)
    if len(poly.terms()) == 1:
        return f
    if any(not c.is_Integer for c in poly.coeffs()):
        return dd_rational(f)
    terms = [sp.Tuple(sp.Integer(c), i, j) for (i, j), c in sorted(poly.terms())]
    return DD_POLY(sp.Tuple(*terms), tau, zeta)


def dd_rational(f: sp.Expr) -> sp.Expr:
    """A polynomial with rational coefficients as (integer polynomial in double-double) / denominator."""
    poly = sp.Poly(f, tau, zeta)
    den = sp.ilcm(*[sp.Rational(c).q for c in poly.coeffs()])
    return dd_factor(sp.expand(f * den)) / den


def discriminant_numeric(name: str) -> tuple[sp.Expr, sp.Expr]:
    """(Disc, sqrt(|Disc|)) for the kernels: factor by factor, near-zero factors in double-double."""
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
    """
    const, factors = R.discriminant_factors(name)
    out = abs(const)
    for f, m in factors:
        poly = sp.Poly(f, tau, zeta)
        out *= sum(abs(c) * tau**i * zeta**j for (i, j), c in poly.terms()) ** m
    return out


def kernel_expr(name: str) -> sp.Expr:
    """The sound-form eigenvalue kernel of one integrator, as a call of a preamble helper."""
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
    """Eqs. (42)-(43) literally (complex principal roots), with C_j dt = -2 zeta tau, K_j dt^2 = -tau^2."""
    N = -9 * R.Cj * R.dt + 27 * R.Kj * R.dt**2 - 2
    M = 3 * R.Cj * R.dt + 1
    D = CCBRT(CSQRT(N**2 - 4 * M**3) + N)
    # no expansion: the differences are evaluated as printed, cancellation included
    return STACK(*[r.subs(R.PAPER_TO_DIMENSIONLESS) for r in R.paper_eq42_roots(D)])


ARGS = (
    (tau, "omega*dt, dimensionless step (omega = sqrt(k*A))"),
    (zeta, "c*A/(2*omega), damping ratio"),
)


def kernels() -> list[Kernel]:
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
    text = python_module(
        "dtcrit.symbolic.roots_codegen",
        "Eigenvalues of the integrators' amplification matrices (numerically sound closed forms) and the\n"
        "paper's Cardano route (Peng et al. 2020, Eqs. (42)-(43)) for comparison.",
        kernels(),
        preamble=PREAMBLE,
        postamble=postamble(),
    )
    return {"eigenvalues.py": text}
