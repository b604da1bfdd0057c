"""Helpers of ``sec4_stability.py``: sample damping ratios, deterministic number text, 50-digit
spectral radii and critical steps of the integrators' amplification matrices (mpmath), and the
printed bounds (Eq. (46), Belytschko's Eq. (34), the CFL note) as functions of the damping ratio.
"""
from __future__ import annotations

from functools import lru_cache

import mpmath as mp
import sympy as sp

from dtcrit.integrators.amplification import matrix_mp
from dtcrit.symbolic import paper_section4 as p4
from dtcrit.symbolic.boundary import tau_crit_mp
from dtcrit.symbolic.integrators import characteristic_polynomial, lam, tau, zeta

DPS = 50
ZETAS = ("0", "0.1", "0.5", "1", "2", "10")  # sample damping ratios (exact decimals)
ZETAS_UNDER = ("0", "0.1", "0.5", "0.9")  # for the underdamped-only formulas
BETAS = ("0", "0.1", "0.3", "0.5", "0.7", "1", "2")
CENTRAL = ("symplectic-euler", "leapfrog", "velocity-verlet")

k, c, A, m, beta = p4.k, p4.c, p4.A, p4.m, p4.beta


# ----------------------------------------------------------------------------- helpers


def _n(x, digits: int = 6) -> str:
    """Deterministic number text."""
    if x is None:
        return "-"
    if isinstance(x, str):
        return x
    with mp.workdps(DPS):
        x = mp.mpf(x) if not isinstance(x, mp.mpc) else x
        if mp.isinf(x):
            return "inf"
        return mp.nstr(x, digits, min_fixed=-4, max_fixed=6)


def _zero(expr) -> bool:
    return sp.simplify(sp.expand(expr)) == 0


def _verdict(ok: bool, yes: str = "reproduced", no: str = "differs") -> str:
    return f"**{yes if ok else no}**"


def eigenvalues(name: str, t, z) -> list:
    with mp.workdps(DPS):
        ev, _ = mp.eig(matrix_mp(name, t, z))
        return [mp.mpc(v) for v in ev]


def rho(name: str, t, z):
    with mp.workdps(DPS):
        return max(abs(v) for v in eigenvalues(name, t, z))


@lru_cache(maxsize=None)
def tau_star(name: str, z: str):
    """Exact critical tau (Jury boundary, dtcrit.symbolic.boundary) at zeta = z (a decimal string)."""
    with mp.workdps(DPS):
        return tau_crit_mp(name, sp.Rational(z), dps=40)[0]


def mpz(z: str):
    with mp.workdps(DPS):
        return mp.mpf(z)


def tau_eq46(z):
    with mp.workdps(DPS):
        z = mp.mpf(z)
        return 2 * z + 2 * mp.sqrt(z * z + 1)


def tau_eq34(z):
    with mp.workdps(DPS):
        z = mp.mpf(z)
        return 2 / mp.sqrt(1 - z * z)


def tau_cfl(z):
    with mp.workdps(DPS):
        z = mp.mpf(z)
        return 2 * (mp.sqrt(z * z + 1) - z)


def lambda_minus_one_bound(name: str) -> sp.Expr | None:
    """Smallest positive root tau of (-1)^n p(-1) = 0 (a real eigenvalue at -1), as a function of zeta.

    Returned as a Piecewise-free expression valid where it is real; None when there is none.
    """
    p = characteristic_polynomial(name)
    n = p.degree()
    f = sp.factor(sp.expand((-1) ** n * p.as_expr().subs(lam, -1)))
    roots = sp.solve(f, tau)
    # the root that is positive at zeta = 2 (where every candidate is real)
    positive = [r for r in roots if sp.N(r.subs(zeta, 2)).is_real and sp.N(r.subs(zeta, 2)) > 0]
    if not positive:
        return None
    return sp.simplify(min(positive, key=lambda r: sp.N(r.subs(zeta, 2))))
