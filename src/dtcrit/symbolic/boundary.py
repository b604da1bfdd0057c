"""The exact stability boundary tau_crit(zeta) of each integrator, from its Jury conditions.

For a fixed damping ratio ``zeta`` every Jury condition is a rational function of ``tau``; the
stability region in ``tau`` changes only at the positive roots of the condition numerators
("boundary factors").  ``tau_crit_mp`` evaluates the exact boundary at any precision by testing
the conditions between consecutive roots; ``active_pieces`` finds which boundary factor governs
over which range of ``zeta`` (with the switch points solved exactly from resultants), which is
what the closed forms and the generated kernels are built from.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import mpmath as mp
import sympy as sp

from dtcrit.symbolic.integrators import characteristic_polynomial, tau, zeta
from dtcrit.symbolic.jury import jury_conditions


@dataclass(frozen=True)
class BoundaryFactor:
    """One factor of a Jury condition's numerator: where it vanishes, an eigenvalue reaches the unit circle.

    Parameters
    ----------
    condition : str
        Label of the Jury condition it comes from.
    poly : sympy.Poly
        Polynomial in ``tau`` with coefficients in ``zeta``.
    """

    condition: str  # label of the Jury condition it comes from
    poly: sp.Poly  # polynomial in tau with coefficients in zeta


@lru_cache(maxsize=None)
def conditions(name: str) -> tuple[tuple[str, sp.Expr], ...]:
    """The Jury conditions (Jury 1964; degrees 1-3) of the scheme's characteristic polynomial.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of (str, sympy.Expr)
        (label, expression that must be > 0) pairs, in ``tau`` and ``zeta``.
    """
    return tuple(jury_conditions(characteristic_polynomial(name)))


@lru_cache(maxsize=None)
def boundary_factors(name: str) -> tuple[BoundaryFactor, ...]:
    """Distinct factors (in tau, positive degree, not tau itself) of the condition numerators.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of BoundaryFactor
        The candidate stability boundaries ``tau(zeta)``.
    """
    seen: dict[sp.Expr, BoundaryFactor] = {}
    for label, expr in conditions(name):
        num, _ = sp.fraction(sp.together(expr))
        _, factors = sp.factor_list(num, tau)
        for f, _mult in factors:
            p = sp.Poly(f, tau)
            if p.degree() < 1 or p.as_expr() == tau:
                continue
            if p.LC().could_extract_minus_sign():
                p = -p
            key = sp.expand(p.as_expr())
            seen.setdefault(key, BoundaryFactor(label, p))
    return tuple(seen.values())


def _conditions_hold(name: str, z, t) -> bool:
    for _label, expr in conditions(name):
        value = expr.subs(zeta, z)
        if value == 0:  # identically zero in tau at this zeta: roots on the circle (marginal)
            continue
        v = mp.mpf(sp.N(value.subs(tau, t), mp.mp.dps + 10)) if not isinstance(t, sp.Basic) else None
        if v is None:
            v = mp.mpf(sp.N(value.subs(tau, t), mp.mp.dps + 10))
        if not v > 0:
            return False
    return True


def _positive_roots(name: str, z) -> list[tuple[mp.mpf, int]]:
    out = []
    for i, bf in enumerate(boundary_factors(name)):
        coeffs = [mp.mpf(sp.N(c.subs(zeta, z), mp.mp.dps + 10)) for c in bf.poly.all_coeffs()]
        while coeffs and coeffs[0] == 0:
            coeffs.pop(0)
        while len(coeffs) > 1 and coeffs[-1] == 0:  # roots at tau = 0 (a multiple one stalls polyroots)
            coeffs.pop()
        if len(coeffs) < 2:
            continue
        roots = mp.polyroots(coeffs, maxsteps=200, extraprec=4 * mp.mp.dps)
        for r in roots:
            r = mp.mpc(r)
            if abs(r.imag) <= mp.mpf(10) ** (-mp.mp.dps // 2) * max(1, abs(r)) and r.real > 0:
                out.append((mp.mpf(r.real), i))
    return sorted(out)


def tau_crit_mp(name: str, z, dps: int = 50) -> tuple[mp.mpf, int | None]:
    """(tau_crit, index of the governing boundary factor) at damping ratio ``z`` (exact boundary).

    ``tau_crit = 0`` (factor ``None``) when the scheme is unstable for every tau > 0.

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).
    z : mpmath number, str or float
        Damping ratio ``zeta`` (converted exactly by mpmath).
    dps : int
        Decimal digits of the mpmath evaluation.

    Returns
    -------
    tuple of (mpmath.mpf, int or None)
        The critical ``tau = omega dt`` and the index into :func:`boundary_factors`.
    """
    with mp.workdps(dps):
        z = sp.Rational(z) if not isinstance(z, sp.Basic) else z
        roots = _positive_roots(name, z)
        points = [mp.mpf(0)] + [r for r, _ in roots]
        first = points[1] / 2 if len(points) > 1 else mp.mpf(1) / 1000
        if not _conditions_hold(name, z, first):
            return mp.mpf(0), None
        for j, (r, idx) in enumerate(roots):
            nxt = roots[j + 1][0] if j + 1 < len(roots) else r * 2 + 1
            mid = (r + nxt) / 2
            if nxt - r < mp.mpf(10) ** (-dps // 2) * r:  # coincident roots: look just past both
                continue
            if not _conditions_hold(name, z, mid):
                return r, idx
        return mp.inf, None


@dataclass(frozen=True)
class Piece:
    """On ``zeta_lo <= zeta <= zeta_hi`` the critical tau is a root of ``factor``.

    Parameters
    ----------
    zeta_lo : sympy.Expr
        Lower end of the damping interval.
    zeta_hi : sympy.Expr
        Upper end (``sympy.oo`` for the last piece).
    factor : BoundaryFactor
        The governing boundary factor.
    sample_zeta : sympy.Rational
        An interior point, used to pick the right root.
    """

    zeta_lo: sp.Expr
    zeta_hi: sp.Expr  # sp.oo for the last piece
    factor: BoundaryFactor
    sample_zeta: sp.Rational  # an interior point, used to pick the right root


# Damping ratios scanned for the governing factor (exact rationals); switch points between two
# factors are then solved exactly from the resultant of the two factors in tau.
_SCAN = [sp.Integer(0)] + [sp.Rational(m, 4) * sp.Integer(10) ** e for e in range(-6, 7) for m in (1, 2, 3, 4, 6, 8)]


def _switch_point(f1: BoundaryFactor, f2: BoundaryFactor, lo, hi) -> sp.Expr:
    res = sp.resultant(f1.poly.as_expr(), f2.poly.as_expr(), tau)
    candidates = [r for r in sp.Poly(res, zeta).real_roots() if lo <= r <= hi] if res.has(zeta) else []
    candidates = sorted(set(candidates), key=lambda r: float(r))
    if len(candidates) != 1:
        raise RuntimeError(f"could not isolate the switch point between {f1} and {f2} in [{lo}, {hi}]")
    return candidates[0]


@lru_cache(maxsize=None)
def active_pieces(name: str) -> tuple[Piece, ...]:
    """The governing boundary factor over zeta > 0, from an exact scan and exact switch points.

    ``zeta = 0`` is handled by ``tau_crit_mp`` (it may be 0: unstable when undamped).

    Parameters
    ----------
    name : str
        A scheme key (``dtcrit.integrators.schemes``).

    Returns
    -------
    tuple of Piece
        The pieces, in increasing ``zeta``.
    """
    factors = boundary_factors(name)
    scan: list[tuple[sp.Expr, int]] = []
    for z, idx in [(z, tau_crit_mp(name, z, dps=40)[1]) for z in _SCAN[1:]]:
        if idx is None:
            raise RuntimeError(f"{name}: unstable for every step at some zeta > 0; not supported yet")
        scan.append((z, idx))
    runs: list[list[tuple[sp.Expr, int]]] = [[scan[0]]]
    for z, idx in scan[1:]:
        if idx == runs[-1][-1][1]:
            runs[-1].append((z, idx))
        else:
            runs.append([(z, idx)])
    pieces: list[Piece] = []
    lo: sp.Expr = sp.Integer(0)
    for i, run in enumerate(runs):
        idx = run[0][1]
        if i + 1 < len(runs):
            hi = _switch_point(factors[idx], factors[runs[i + 1][0][1]], run[-1][0], runs[i + 1][0][0])
        else:
            hi = sp.oo
        pieces.append(Piece(lo, hi, factors[idx], run[len(run) // 2][0]))
        lo = hi
    return tuple(pieces)
