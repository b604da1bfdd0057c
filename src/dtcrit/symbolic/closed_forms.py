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

from dtcrit.symbolic.boundary import Piece, active_pieces, tau_crit_mp
from dtcrit.symbolic.integrators import tau, zeta

omega, gamma = sp.symbols("omega gamma", positive=True)


@dataclass(frozen=True)
class ClosedPiece:
    piece: Piece
    kind: str  # "root" (closed form in tau) or "cubic" (smallest positive root of a cubic)
    tau_expr: sp.Expr | None  # dimensionless tau(zeta), for degree <= 2
    dt_expr: sp.Expr | None  # dt(omega, gamma), for degree <= 2
    cubic: tuple[sp.Expr, ...] | None  # monic coefficients (a2, a1, a0) in zeta, for degree 3


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
            out.append(ClosedPiece(p, "cubic", None, None, monic))
        else:
            raise NotImplementedError(f"{name}: boundary factor of degree {deg}")
    return tuple(out)


def formula_text(name: str) -> str:
    """Human-readable closed form of tau_crit(zeta) = omega * dt, piece by piece."""
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
