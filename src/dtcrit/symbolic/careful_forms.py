"""The careful evaluation of the critical step dt(k, c, A), as a chain of assignments for every language.

``dtcrit.integrators.precise`` evaluates the derived closed forms well for every float64 input;
this module writes the *same* forms as a SymPy assignment chain that ``dtcrit.codegen`` prints
into C, Fortran and NumPy (``careful_chain(integrator)``).  The chain is built from the closed
forms of ``dtcrit.symbolic.closed_forms`` (via ``stability_codegen.kernel_expr``) and a few
floating-point primitives, opaque to SymPy so that nothing is simplified away:

* ``mantissa(x)``, ``exponent(x)``: ``x = mantissa 2^exponent`` with the mantissa in [1/2, 1)
  (C ``frexp``, Fortran ``fraction``/``exponent``); the exponent of a non-finite x is 0;
* ``ldexp(x, e)``: ``x 2^e``, exact unless the result leaves the normal range;
* ``two_product_error(a, b)`` = ``a b - fl(a b)`` and ``two_sum_error(a, b)`` = ``a + b - fl(a + b)``,
  both exact (Dekker's product with Veltkamp's splitting; Knuth's two-sum);
* ``is_nan(x)``.

The forms (each checked against the derived pieces in ``tests/symbolic/test_kernels_careful_forms.py``):

* every integrator but forward Euler: the kernel dt(omega, gamma) is homogeneous of degree -1,
  so ``dt = 2^-s dt(omega 2^-s, gamma 2^-s)`` with the power of two taken from the *larger* rate,
  from the mantissas and exponents of k, c, A (no k A, c A or zeta is ever formed in float64);
* forward Euler: ``dt = c/k`` when ``R = c^2 A - 4k <= 0`` (zeta <= 1), else ``4/(c A + sqrt(A R))``,
  the residual R summed exactly from error-free products of the mantissas (near zeta = 1 it is
  ill-conditioned in the rounded rates);
* a cubic piece (the Eq. (40) scheme): its cubic is ``tau Q(tau) + P(0)`` with Q a quadratic,
  so for zeta <= 1 ``dt = (-P(0)/omega) / Q(tau*)``, ``-P(0)/omega`` straight from c/k and the
  computed root entering only through Q (its completed square, ``(tau - h)^2 + q0``);
* a domain guard: NaN in k, c or A, or a negative one, gives NaN (never a plausible step).

The result is 0 where no positive float64 step is stable (also when the exact step lies below
the float64 range) and inf when it lies beyond it.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp
from sympy.logic.boolalg import BooleanFunction

from dtcrit.symbolic.closed_forms import closed_pieces, gamma, omega
from dtcrit.symbolic.integrators import tau, zeta
from dtcrit.symbolic.stability_codegen import CUBIC_ROOT, kernel_expr


class mantissa(sp.Function):
    """m with x = m 2^e, 1/2 <= |m| < 1 (0 for x = 0): C ``frexp``, Fortran ``fraction``.

    Parameters
    ----------
    *args : sympy.Expr
        ``x``, the number split.
    """

    nargs = 1


class exponent(sp.Function):
    """e with x = m 2^e, as a float (0 for x = 0 or a non-finite x).

    Parameters
    ----------
    *args : sympy.Expr
        ``x``, the number split.
    """

    nargs = 1


class ldexp(sp.Function):
    """x 2^e (e a whole number held in a float).

    Parameters
    ----------
    *args : sympy.Expr
        ``x`` and the whole number ``e``.
    """

    nargs = 2


class two_product_error(sp.Function):
    """a b - fl(a b), exactly (Dekker).

    Parameters
    ----------
    *args : sympy.Expr
        The factors ``a`` and ``b``.
    """

    nargs = 2


class two_sum_error(sp.Function):
    """a + b - fl(a + b), exactly (Knuth).

    Parameters
    ----------
    *args : sympy.Expr
        The addends ``a`` and ``b``.
    """

    nargs = 2


class is_nan(BooleanFunction):
    """True where x is NaN (C ``isnan``, Fortran ``ieee_is_nan``, ``np.isnan``).

    Parameters
    ----------
    *args : sympy.Expr
        ``x``, the value tested.
    """

    nargs = 1


class is_negative(BooleanFunction):
    """x < 0, never decided by SymPy from a symbol's assumptions (an argument declared positive may
    still arrive negative in the emitted code).

    Parameters
    ----------
    *args : sympy.Expr
        ``x``, the value compared with 0.
    """

    nargs = 1


def nan_min(*xs: sp.Expr) -> sp.Expr:
    """Minimum that is NaN when any argument is NaN (C ``fmin`` and Fortran ``min`` drop a NaN).

    Parameters
    ----------
    *xs : sympy.Expr
        The arguments.

    Returns
    -------
    sympy.Piecewise
        NaN where an argument is NaN, else their minimum.
    """
    return sp.Piecewise((sp.nan, sp.Or(*(is_nan(x) for x in xs))), (sp.Min(*xs), True))


def nan_max(*xs: sp.Expr) -> sp.Expr:
    """Maximum that is NaN when any argument is NaN.

    Parameters
    ----------
    *xs : sympy.Expr
        The arguments.

    Returns
    -------
    sympy.Piecewise
        NaN where an argument is NaN, else their maximum.
    """
    return sp.Piecewise((sp.nan, sp.Or(*(is_nan(x) for x in xs))), (sp.Max(*xs), True))


K, C, A = sp.symbols("k c A", real=True)
ARGUMENTS = (
    (K, "stiffness of the mode", "N/m"),
    (C, "viscous damping coefficient of the mode", "N s/m"),
    (A, "inverse inertia coefficient of the mode", "1/kg"),
)


@dataclass(frozen=True)
class Chain:
    """``result`` computed from ``args`` by ``steps`` (each ``(symbol, expression)`` uses earlier names only).

    Parameters
    ----------
    integrator : str
        Name of the integrator.
    args : tuple of sympy.Symbol
        The arguments, ``(k, c, A)`` or ``(k, A)``.
    steps : tuple of (sympy.Symbol, sympy.Expr)
        The assignments in order.
    result : sympy.Symbol
        The name of the step dt [s].
    equations : tuple of str
        The forms used, for the header of the emitted file.
    """

    integrator: str
    args: tuple[sp.Symbol, ...]
    steps: tuple[tuple[sp.Symbol, sp.Expr], ...]
    result: sp.Symbol
    equations: tuple[str, ...]


def _r(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)


def _split(steps: list, x: sp.Symbol, tag: str):
    m, e = _r(f"m{tag}"), _r(f"e{tag}")
    steps += [(m, mantissa(x)), (e, exponent(x))]
    return m, e


def _omega_scaled(steps, mk, ek, mA, eA):
    """Rate omega = w 2^sw with w in [1/2, 1.42): sqrt of the mantissa product, the odd exponent folded in."""
    e, odd, sw, w = _r("e_kA"), _r("odd"), _r("s_omega"), _r("w")
    steps += [(e, ek + eA), (odd, e - 2 * sp.floor(e / 2)), (sw, (e - odd) / 2), (w, sp.sqrt(mk * mA * (1 + odd)))]
    return w, sw


def cubic_identity(cp) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(P0, h, q0) with P(tau) = tau ((tau - h)^2 + q0) + P0 for the monic cubic P of a cubic piece,
    coefficients in zeta: the root satisfies tau* = -P0 / ((tau* - h)^2 + q0).

    Parameters
    ----------
    cp : dtcrit.symbolic.closed_forms.ClosedPiece
        A piece of kind ``"cubic"``.

    Returns
    -------
    tuple of sympy.Expr
        ``(P0, h, q0)`` as polynomials in zeta.
    """
    P = sp.expand(tau**3 + sum(c * tau ** (2 - i) for i, c in enumerate(cp.cubic)))
    P0 = P.subs(tau, 0)
    Q = sp.Poly(sp.cancel((P - P0) / tau), tau)
    a, b, c0 = Q.all_coeffs()
    if a != 1:  # pragma: no cover - monic by construction
        raise ValueError("cubic is not monic")
    h, q0 = sp.expand(-b / 2), sp.expand(c0 - b**2 / 4)
    if sp.expand(tau * ((tau - h) ** 2 + q0) + P0 - P) != 0:  # pragma: no cover - algebra
        raise AssertionError("cubic identity failed")
    return P0, h, q0


def cubic_small_zeta(cp) -> tuple[sp.Expr, int] | None:
    """(p1, E) for a cubic piece whose undamped cubic is tau^3 (Adams-Bashforth 2), else None.

    There P = tau^3 + O(zeta) with P(0) = -p1 zeta + O(zeta^2), so tau* = (p1 zeta)^(1/3) (1 + delta) with
    delta = O(zeta^(j/3)) from the linearised correction delta ~ -(P(T0 u) - T0^3 u^3 + p1 u^3)/(3 T0^3 u^3),
    u = zeta^(1/3), T0 = p1^(1/3); E is the largest whole number with |delta| <= 2^-64 for zeta <= 2^E
    (a margin of 2^-11 ulp on the leading term).  Then dt = tau*/omega = (p1 c / (2 k^2 A))^(1/3).

    Parameters
    ----------
    cp : dtcrit.symbolic.closed_forms.ClosedPiece
        A piece of kind ``"cubic"``.

    Returns
    -------
    tuple of (sympy.Expr, int) or None
        ``(p1, E)``, or None when the undamped cubic is not ``tau^3``.
    """
    if cp.piece.zeta_lo != 0 or any(co.subs(zeta, 0) != 0 for co in cp.cubic):
        return None
    p1 = sp.nsimplify(-sp.diff(cp.cubic[2], zeta).subs(zeta, 0))
    if not p1.is_positive:
        return None
    u = sp.Symbol("u", positive=True)
    t0 = sp.cbrt(p1)
    P = t0**3 * u**3 + sum(co.subs(zeta, u**3) * (t0 * u) ** (2 - i) for i, co in enumerate(cp.cubic))
    delta = sp.expand(sp.cancel((P + p1 * u**3 - t0**3 * u**3) / (3 * t0**3 * u**3)))
    lead = sp.series(delta, u, 0, 12).removeO().as_leading_term(u)
    coef, j = lead.as_coeff_exponent(u)
    u_max = (sp.Integer(2) ** -64 / sp.Abs(coef)) ** (1 / j)
    return p1, int(sp.floor(3 * sp.log(u_max, 2).evalf(30)))


def _scaled_closed_form(name, steps, mk, ek, mc, ec, mA, eA):
    """Step dt = 2^-s kernel(omega 2^-s, gamma 2^-s), s from the larger rate (``precise.scaled_closed_form``)."""
    w, sw = _omega_scaled(steps, mk, ek, mA, eA)
    gm, sg, s = _r("g"), _r("s_gamma"), _r("s")
    steps += [(gm, mc * mA / 2), (sg, ec + eA)]
    if name == "leapfrog-centred":
        steps.append((s, sw))
    else:
        steps.append((s, sp.Piecewise((sp.Max(sw, sg), sp.Gt(gm, 0)), (sw, True))))
    w1, g1 = sp.Symbol("omega_s", nonnegative=True), sp.Symbol("gamma_s", nonnegative=True)
    steps += [(w1, ldexp(w, sw - s)), (g1, ldexp(gm, sg - s))]
    kern = kernel_expr(name).xreplace({omega: w1, gamma: g1})
    return ldexp(kern, -s), w, sw, gm, sg


def _small_zeta_step(steps, body, small, sw, sg, mk, ek, mc, ec, mA, eA) -> sp.Expr:
    """``cubic_small_zeta``'s leading order dt = (p1 c / (2 k^2 A))^(1/3) where zeta <= 2^E, written as
    2^q (x 2^r)^(1/3), x = (p1/2) mc / (mk^2 mA) and ec - 2 ek - eA = 3q + r (no k^2, c A or zeta is formed:
    at k = 1e300, c = 5e-324 zeta is 2.5e-474 while dt = 2.7e-308).  zeta < 2^(s_gamma - s_omega) since
    gamma's and omega's mantissa ratio is below 1; finite c, k and A only (their mantissas are below 1).
    """
    p1, e_max = small
    e3, q3, x3 = _r("e_small"), _r("q_small"), _r("x_small")
    steps += [(e3, ec - 2 * ek - eA), (q3, sp.floor(e3 / 3)), (x3, ldexp((p1 / 2) * mc / (mk * mk * mA), e3 - 3 * q3))]
    cond = sp.And(sp.Le(sg - sw, e_max), sp.Gt(mc, 0), sp.Lt(mc, 1), sp.Lt(mk, 1), sp.Lt(mA, 1))
    return sp.Piecewise((ldexp(sp.cbrt(x3), q3), cond), (body, True))


def _forward_euler(steps, mk, ek, mc, ec, mA, eA) -> sp.Expr:
    """``precise.forward_euler_exact``: R / 2^ek from error-free products, |shift| <= 64."""
    E, En = _r("E"), _r("E_near")
    steps += [(E, 2 * ec + eA - ek), (En, sp.Min(sp.Max(E, -64), 64))]
    names = iter(("p", "pe", "q", "qe", "r", "re"))
    p, pe, q, qe, r, re = (_r(n) for n in names)
    steps += [(p, mc * mc), (pe, two_product_error(mc, mc)), (q, p * mA), (qe, two_product_error(p, mA)),
              (r, pe * mA), (re, two_product_error(pe, mA))]
    terms = []
    for t in (q, qe, r, re):
        ts = _r(f"{t}_s")
        steps.append((ts, ldexp(t, En)))
        terms.append(ts)
    minus4k = _r("m4k")
    steps.append((minus4k, -4 * mk))
    s, err = _r("sum0"), _r("err0")
    steps += [(s, terms[0] + minus4k), (err, two_sum_error(terms[0], minus4k))]
    for n, t in enumerate(terms[1:], start=1):
        s2, err2 = _r(f"sum{n}"), _r(f"err{n}")
        steps += [(s2, s + t), (err2, err + two_sum_error(s, t))]
        s, err = s2, err2
    Rn, near, ar, u = _r("R_n"), _r("near"), _r("AR"), _r("u")
    steps.append((Rn, s + err))  # (c^2 A - 4k) / 2^ek
    far = mc * mc * mA - ldexp(4 * mk, -sp.Min(sp.Max(E, -1100), 1100))  # |E| > 64: one term dominates
    steps.append((ar, sp.Piecewise((ldexp(mA * Rn, -En), sp.Le(sp.Abs(E), 64)), (mA * far, True))))
    steps.append((u, mc * mA))
    over_cond = sp.And(sp.Gt(mc, 0), sp.Or(sp.And(sp.Le(sp.Abs(E), 64), sp.Gt(Rn, 0)), sp.And(sp.Gt(sp.Abs(E), 64), sp.Gt(E, 0))))
    over = ldexp(4 / (u + sp.sqrt(sp.Max(ar, 0))), -(ec + eA))
    under = ldexp(mc / mk, ec - ek)
    del near
    return sp.Piecewise((over, over_cond), (under, True))


def _undamped_chain(name: str) -> Chain:
    """An undamped mode (c = 0): dt = 2^-sw tau_crit(0)/w with omega = w 2^sw (no stable step: 0)."""
    steps: list[tuple[sp.Symbol, sp.Expr]] = []
    mk, ek = _split(steps, K, "k")
    mA, eA = _split(steps, A, "A")
    w, sw = _omega_scaled(steps, mk, ek, mA, eA)
    tau0 = sp.simplify((kernel_expr(name) * omega).subs(gamma, 0))
    if tau0.has(CUBIC_ROOT) or not tau0.is_number:  # pragma: no cover - cubic pieces have no undamped step
        raise ValueError(f"'{name}': no closed undamped step")
    raw, dt = _r("dt_raw"), _r("dt")
    steps.append((raw, ldexp(tau0 / w, -sw)))
    bad = sp.Or(is_nan(K), is_nan(A), sp.Lt(K, 0), sp.Lt(A, 0))
    steps.append((dt, sp.Piecewise((sp.nan, bad), (raw, True))))
    eqs = ("k = mk 2^ek, A = mA 2^eA (frexp); omega = sqrt(k A) = w 2^s", f"dt = 2^-s {sp.sstr(tau0)}/w  (c = 0)",
           "NaN in k or A, or a negative one: NaN")
    return Chain(name, (K, A), tuple(steps), dt, eqs)


@lru_cache(maxsize=None)
def careful_chain(name: str, damped: bool = True) -> Chain:
    """The careful dt(k, c, A) of integrator ``name`` (see the module docstring); ``damped=False``:
    dt(k, A) of an undamped mode (integrators with a stable undamped step only).
    """
    if not damped:
        return _undamped_chain(name)
    steps: list[tuple[sp.Symbol, sp.Expr]] = []
    mk, ek = _split(steps, K, "k")
    mc, ec = _split(steps, C, "c")
    mA, eA = _split(steps, A, "A")
    eqs = ["k = mk 2^ek, c = mc 2^ec, A = mA 2^eA (frexp); omega = sqrt(k A), gamma = c A/2, zeta = gamma/omega"]
    pieces = closed_pieces(name)
    if name == "forward-euler":
        body = _forward_euler(steps, mk, ek, mc, ec, mA, eA)
        eqs.append("dt = c/k if R = c^2 A - 4k <= 0, else 4/(c A + sqrt(A R)); R from error-free products "
                   "of the mantissas (exact near zeta = 1)")
    else:
        body, w, sw, gm, sg = _scaled_closed_form(name, steps, mk, ek, mc, ec, mA, eA)
        eqs.append("dt = 2^-s dt(omega 2^-s, gamma 2^-s), 2^s from the larger of omega and gamma (exact scaling)")
        cubic = [cp for cp in pieces if cp.kind == "cubic"]
        if cubic:
            (cp,) = cubic
            P0, h, q0 = cubic_identity(cp)
            z, t, d = _r("zeta_w"), _r("tau_root"), _r("d")
            steps += [(z, ldexp(gm, sg - sw) / w)]
            if cp.cubic is None:  # pragma: no cover - a cubic piece carries its cubic
                raise ValueError(f"'{name}': a cubic piece without its cubic")
            root = CUBIC_ROOT(*(co.subs(zeta, z) for co in cp.cubic), sp.false)
            steps += [(t, root), (d, t - h.subs(zeta, z))]
            # -P0/omega = (2 zeta)/omega = c/k for this cubic: checked in the tests
            lead = _r("c_over_k")
            steps.append((lead, ldexp(mc / mk, ec - ek) * sp.simplify(-P0 / (2 * zeta))))
            ident = lead / (d * d + q0.subs(zeta, z))
            z_hi = sp.Min(1, cp.piece.zeta_hi)  # the identity holds where the cubic piece governs
            # z > 0: where zeta itself underflows (c A subnormal against omega) the identity is 0/0 for a
            # cubic whose q0 vanishes with zeta (Adams-Bashforth 2); the scaled closed form gives its limit
            body = sp.Piecewise((ident, sp.And(sp.Le(z, z_hi), sp.Gt(z, 0), sp.Gt(mc, 0))), (body, True))
            eqs.append(f"zeta <= 1: dt = (c/k) / ((tau - {sp.sstr(h)})^2 + {sp.sstr(q0)}), tau the root of the cubic "
                       "(the cubic is tau ((tau - h)^2 + q0) - 2 zeta)")
            small = cubic_small_zeta(cp)
            if small is not None:
                body = _small_zeta_step(steps, body, small, sw, sg, mk, ek, mc, ec, mA, eA)
                eqs.append(f"zeta <= 2^{small[1]}: dt = ({sp.sstr(small[0] / 2)} c / (k^2 A))^(1/3) from the mantissas "
                           "and exponents (the leading order; zeta itself may underflow)")
    raw, dt = _r("dt_raw"), _r("dt")
    steps.append((raw, body))
    bad = sp.Or(is_nan(K), is_nan(C), is_nan(A), sp.Lt(K, 0), sp.Lt(C, 0), sp.Lt(A, 0))
    steps.append((dt, sp.Piecewise((sp.nan, bad), (raw, True))))
    eqs.append("NaN in k, c or A, or a negative one: NaN")
    return Chain(name, (K, C, A), tuple(steps), dt, tuple(eqs))
