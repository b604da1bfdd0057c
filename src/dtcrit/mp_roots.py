"""Small positive roots of a cubic at high precision, from its two-term balances (mpmath only).

Shared by the 50-digit references of ``dtcrit.symbolic.closed_forms`` and ``dtcrit.bench.reference``
for tiny damping, where the wanted root of the boundary cubic scales like a power of zeta (zeta itself
for most schemes, ``2 zeta^(1/3)`` for adams-bashforth-2, whose undamped cubic is ``tau^3``).  A leaf:
it imports nothing from dtcrit.
"""
from __future__ import annotations

import mpmath as mp


def balance_roots(coeffs, dps: int) -> list:
    """Positive real roots of ``u^3 + a2 u^2 + a1 u + a0`` reached from its two-term balances.

    Each balance ``|a_i| s^i = |a_j| s^j`` gives a root's leading-order size ``s`` (its Newton
    polygon).  Newton runs on the cubic in ``w = u/s`` from ``w = 1``, where the roots are O(1):
    findroot's tolerance is absolute, so in ``u`` it would accept a root near 1e-100
    (adams-bashforth-2 at zeta = 1e-300) after one step.  A root is kept when its residual is small
    against the cubic's largest term there.  Call it at the working precision wanted (e.g. ``2 dps``
    digits).

    Parameters
    ----------
    coeffs : sequence
        ``[a2, a1, a0]``, numbers or numeric strings (converted with ``mpmath.mpf``).
    dps : int
        Decimal digits the residual must meet (``10^(-dps)`` relative to the largest term).

    Returns
    -------
    list of mpmath.mpf
        The positive roots found, one per balance that converged (a root may repeat).
    """
    a = [mp.mpf(1)] + [mp.mpf(c) for c in coeffs]  # a[i] multiplies u^(3-i)
    found = []
    for i in range(4):
        for j in range(i + 1, 4):
            if a[i] == 0 or a[j] == 0:
                continue
            s = abs(a[j] / a[i]) ** (mp.mpf(1) / (j - i))
            b = [a[m] / s**m for m in range(4)]  # the cubic in w = u/s, monic
            cubic = lambda w: ((w + b[1]) * w + b[2]) * w + b[3]  # noqa: E731
            try:
                w = mp.findroot(cubic, mp.mpf(1))
            except (ValueError, ZeroDivisionError):
                continue
            size = abs(w) ** 3 + abs(b[1] * w * w) + abs(b[2] * w) + abs(b[3])
            if mp.im(w) == 0 and w > 0 and abs(cubic(w)) <= mp.mpf(10) ** (-dps) * size:
                found.append(s * mp.re(w))
    return found
