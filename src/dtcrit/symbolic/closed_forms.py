"""Closed forms of the critical step, piece by piece, in numerically sound shapes.

For every piece of ``dtcrit.symbolic.boundary.active_pieces`` the governing boundary factor is
solved for ``tau``:

* degree 1: the single root;
* degree 2: the root that equals the exact boundary, written in the cancellation-free form
  (``q = -(b + sign(b) sqrt(D))/2``, roots ``q/a`` and ``c/q``) with the discriminant factored
  symbolically (no ``zeta^2 - 1`` evaluated as a difference);
* degree 3: the smallest positive root of the cubic (Viete's trigonometric / hyperbolic forms
  followed by Newton polishing, in ``dtcrit._generated``'s preamble).

The dimensionless root ``tau(zeta)`` is then rewritten in the rates ``omega = sqrt(k A)`` and
``gamma = c A / 2`` (so ``zeta = gamma/omega`` and ``dt = tau/omega``) as a homogeneous
expression of degree -1; sums of two squares under a root are printed as ``hypot``.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import mpmath as mp
import sympy as sp

from dtcrit.mp_roots import balance_roots
from dtcrit.symbolic.boundary import Piece, active_pieces, tau_crit_mp
from dtcrit.symbolic.integrators import tau, zeta

omega, gamma = sp.symbols("omega gamma", positive=True)


@dataclass(frozen=True)
class ClosedPiece:
    """The closed form of the critical step on one piece of the damping axis.

    Parameters
    ----------
    piece : Piece
        The damping interval and its boundary factor.
    kind : str
        ``"root"`` (closed form in tau) or ``"cubic"`` (smallest positive root of a cubic).
    tau_expr : sympy.Expr or None
        Dimensionless ``tau(zeta)``, for degree <= 2.
    dt_expr : sympy.Expr or None
        ``dt(omega, gamma)``, for degree <= 2.
    cubic : tuple of sympy.Expr or None
        Monic coefficients ``(a2, a1, a0)`` in ``zeta``, for degree 3.
    cubic_large : tuple of sympy.Expr or None
        For ``zeta >= 1``: monic ``(b2, b1, b0)`` in ``eps = 1/zeta^2`` (:func:`reciprocal_cubic`).
    """

    piece: Piece
    kind: str  # "root" (closed form in tau) or "cubic" (smallest positive root of a cubic)
    tau_expr: sp.Expr | None  # dimensionless tau(zeta), for degree <= 2
    dt_expr: sp.Expr | None  # dt(omega, gamma), for degree <= 2
    cubic: tuple[sp.Expr, ...] | None  # monic coefficients (a2, a1, a0) in zeta, for degree 3
    cubic_large: tuple[sp.Expr, ...] | None = None  # zeta >= 1: monic (b2, b1, b0) in eps = 1/zeta^2


eps = sp.Symbol("epsilon", positive=True)
y = sp.Symbol("y", positive=True)


def reciprocal_cubic(monic: tuple[sp.Expr, ...]) -> tuple[sp.Expr, ...]:
    """Coefficients of the cubic in y, tau = 1/(zeta y), as polynomials in eps = 1/zeta^2.

    For large zeta the smallest root tau ~ 1/zeta, and the monic cubic in tau has coefficients
    growing like zeta^2 (overflowing float64 beyond zeta ~ 1e150).  In y the coefficients stay
    bounded for zeta >= 1 and the wanted root is the *largest* positive y.

    Parameters
    ----------
    monic : tuple of sympy.Expr
        Monic coefficients ``(a2, a1, a0)`` of the cubic in ``tau``.

    Returns
    -------
    tuple of sympy.Expr
        Monic coefficients ``(b2, b1, b0)`` of the cubic in ``y``.
    """
    a2, a1, a0 = monic
    g = tau**3 + a2 * tau**2 + a1 * tau + a0
    expr = sp.expand(g.subs(tau, 1 / (zeta * y)) * zeta**3 * y**3)
    poly = sp.Poly(expr, y)
    lead = poly.LC()
    coeffs = [sp.expand(sp.cancel(c / lead)) for c in poly.all_coeffs()[1:]]
    out = tuple(sp.expand(c.subs(zeta, 1 / sp.sqrt(eps))) for c in coeffs)
    for c in out:
        if c.has(zeta) or not c.is_polynomial(eps):
            raise RuntimeError(f"reciprocal cubic coefficient {c} is not a polynomial in eps")
    return out


def _homogeneous_sqrt(f: sp.Expr) -> sp.Expr:
    """sqrt(f(zeta)) with zeta = gamma/omega, as sqrt(F(gamma, omega)) / omega^(deg/2)."""
    d = sp.Poly(f, zeta).degree()
    F = sp.expand(f.subs(zeta, gamma / omega) * omega**d)
    return sp.sqrt(sp.factor(F)) / omega ** sp.Rational(d, 2)


def _sqrt_discriminant(D: sp.Expr) -> sp.Expr:
    """sqrt(D(zeta)) as a product of square roots of D's irreducible factors, in (omega, gamma)."""
    const, factors = sp.factor_list(sp.expand(D), zeta)
    out = sp.sqrt(const)
    for f, m in factors:
        if m % 2 == 0:
            out *= sp.Abs(f.subs(zeta, gamma / omega)) ** (m // 2)
        else:
            out *= _homogeneous_sqrt(f) * (f.subs(zeta, gamma / omega) ** ((m - 1) // 2) if m > 1 else 1)
    return out


def _quadratic_root(name: str, p: Piece) -> tuple[sp.Expr, sp.Expr]:
    a, b, c = p.factor.poly.all_coeffs()
    D = sp.expand(b**2 - 4 * a * c)
    z0 = p.sample_zeta
    t_exact, _ = tau_crit_mp(name, z0, dps=30)
    sb = sp.sign(b.subs(zeta, z0))
    sb = 1 if sb >= 0 else -1
    sqrtD_dimless = sp.sqrt(D)
    q_dimless = -(b + sb * sqrtD_dimless) / 2
    candidates_dimless = [q_dimless / a, c / q_dimless]
    with mp.workdps(30):
        values = [mp.mpf(sp.N(e.subs(zeta, z0), 30)) for e in candidates_dimless]
        pick = min(range(2), key=lambda i: abs(values[i] - t_exact))
        if abs(values[pick] - t_exact) > mp.mpf(10) ** -20 * max(1, abs(t_exact)):
            raise RuntimeError(f"no quadratic root matches the exact boundary for {p}")
    # dimensional, homogeneous form: dt = tau(gamma/omega)/omega
    sub = {zeta: gamma / omega}
    q = -(b.subs(sub) + sb * _sqrt_discriminant(D)) / 2
    dt = (q / a.subs(sub) if pick == 0 else c.subs(sub) / q) / omega
    return sp.simplify(candidates_dimless[pick]), sp.simplify(dt)


@lru_cache(maxsize=None)
def closed_pieces(name: str) -> tuple[ClosedPiece, ...]:
    """The closed form of the critical step of ``name``, piece by piece over zeta > 0.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of ClosedPiece
        One closed form per piece of :func:`dtcrit.symbolic.boundary.active_pieces`.
    """
    out = []
    for p in active_pieces(name):
        deg = p.factor.poly.degree()
        if deg == 1:
            t = sp.solve(p.factor.poly.as_expr(), tau)[0]
            out.append(ClosedPiece(p, "root", t, sp.simplify(t.subs(zeta, gamma / omega) / omega), None))
        elif deg == 2:
            t, dt = _quadratic_root(name, p)
            out.append(ClosedPiece(p, "root", t, dt, None))
        elif deg == 3:
            coeffs = p.factor.poly.all_coeffs()
            monic = tuple(sp.expand(c / coeffs[0]) for c in coeffs[1:])
            out.append(ClosedPiece(p, "cubic", None, None, monic, reciprocal_cubic(monic)))
        else:
            raise NotImplementedError(f"{name}: boundary factor of degree {deg}")
    return tuple(out)


def formula_text(name: str) -> str:
    """Human-readable closed form of tau_crit(zeta) = omega * dt, piece by piece.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    str
        The formula text.
    """
    parts = []
    for cp in closed_pieces(name):
        lo, hi = cp.piece.zeta_lo, cp.piece.zeta_hi
        rng = f"{lo} <= zeta" + (f" <= {hi}" if hi != sp.oo else "")
        if cp.kind == "root":
            body = f"omega*dt = {sp.sstr(cp.tau_expr)}"
        else:
            poly = sp.sstr(sp.expand(cp.piece.factor.poly.as_expr()))
            body = f"omega*dt = smallest positive root tau of {poly} = 0"
        parts.append(f"{body}  ({rng})")
    return "; ".join(parts) + "; with omega = sqrt(k*A), zeta = c*A/(2*omega)"


def tau_crit_closed_mp(name: str, z, dps: int = 50):
    """tau_crit(zeta) from the closed form, evaluated in mpmath at ``dps`` digits (reference values).

    ``z`` may be an mpmath number or anything mpmath converts exactly (a float is taken exactly).

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).
    z : mpmath number, float or str
        Damping ratio ``zeta``.
    dps : int
        Decimal digits.

    Returns
    -------
    mpmath.mpf
        The critical ``tau = omega dt`` (0 when no step is stable).
    """
    with mp.workdps(dps + 10):
        z = mp.mpf(z)
        for cp in closed_pieces(name):
            hi = cp.piece.zeta_hi
            if hi != sp.oo and z > mp.mpf(sp.N(hi, dps + 20)):
                continue
            if cp.kind == "root":
                f = sp.lambdify(zeta, cp.tau_expr, modules="mpmath")
                return +f(z)
            return _cubic_tau_mp(cp, z, dps)
    raise AssertionError("unreachable")


def _cubic_tau_mp(cp: ClosedPiece, z, dps: int):
    """Smallest positive root of the governing cubic at high precision.

    mpmath's polyroots on the cubic in tau (zeta < 1) or in y = 1/(zeta tau) (zeta >= 1, where the
    tau-coefficients span too many decades), then Newton on the *original* cubic in tau at
    2*dps digits, so the reference does not rest on the reciprocal transformation.
    """
    cubic, cubic_large = cp.cubic, cp.cubic_large
    if cubic is None or cubic_large is None:
        raise ValueError("_cubic_tau_mp: the piece is not a cubic")

    def positive_real(coeffs, pick):
        roots = mp.polyroots(coeffs, maxsteps=800, extraprec=6 * dps)
        good = [mp.re(r) for r in roots if abs(mp.im(r)) <= mp.mpf(10) ** (-dps) * (1 + abs(r)) and mp.re(r) > 0]
        return pick(good) if good else None

    if z == 0:
        coeffs = [mp.mpf(1)] + [mp.mpf(sp.N(c.subs(zeta, 0), dps)) for c in cubic]
        while len(coeffs) > 1 and coeffs[-1] == 0:
            coeffs.pop()  # an exact root at 0 is not positive (adams-bashforth-2's undamped cubic is tau^3)
        if len(coeffs) == 1:
            return mp.mpf(0)
        t = positive_real(coeffs, min)
        return t if t is not None else mp.mpf(0)
    if z < mp.mpf(10) ** -6:
        # tiny damping: the wanted root scales like a power of zeta (zeta itself for most schemes,
        # 2 zeta^(1/3) for adams-bashforth-2, whose undamped cubic is tau^3)
        return _tiny_zeta_root(cp, z, dps)
    elif z < 1:
        t = positive_real([mp.mpf(1)] + [sp.lambdify(zeta, c, modules="mpmath")(z) for c in cubic], min)
    else:
        e = 1 / (z * z)
        yy = positive_real([mp.mpf(1)] + [sp.lambdify(eps, c, modules="mpmath")(e) for c in cubic_large], max)
        t = None if yy is None else 1 / (z * yy)
    if t is None:
        return mp.mpf(0)
    with mp.workdps(2 * dps):
        fs = [sp.lambdify(zeta, c, modules="mpmath") for c in cubic]
        a2, a1, a0 = (f(z) for f in fs)
        t = mp.findroot(lambda u: ((u + a2) * u + a1) * u + a0, t)
    return +t


def _tiny_zeta_root(cp: ClosedPiece, z, dps: int):
    """Smallest positive root of the cubic in tau for zeta < 1e-6 (0 when it has none), from the cubic's
    two-term balances (``dtcrit.mp_roots.balance_roots``) at ``2 dps`` digits.
    """
    if cp.cubic is None:
        raise ValueError("_tiny_zeta_root: the piece is not a cubic")
    cubic = cp.cubic
    with mp.workdps(2 * dps):
        found = balance_roots([sp.lambdify(zeta, c, modules="mpmath")(z) for c in cubic], dps)
    return +min(found) if found else mp.mpf(0)


def dt_crit_mp(name: str, k, c, A, dps: int = 50):
    """Reference critical step for the exact float inputs (k, c, A), at ``dps`` digits.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).
    k : float
        Contact stiffness [N/m].
    c : float
        Viscous damping [N s/m].
    A : float
        Inverse inertia coefficient [1/kg].
    dps : int
        Decimal digits.

    Returns
    -------
    mpmath.mpf
        The critical step [s].
    """
    with mp.workdps(dps + 10):
        k, c, A = mp.mpf(k), mp.mpf(c), mp.mpf(A)
        w = mp.sqrt(k * A)
        return tau_crit_closed_mp(name, c * A / (2 * w), dps) / w
