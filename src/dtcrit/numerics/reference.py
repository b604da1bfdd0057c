"""High-precision references of the numerical primitives (mpmath; for tests and the 50-digit checks).

Imports mpmath at import time: the runtime never imports this module (``dtcrit.numerics`` does
not load it); ``dtcrit.codegen.kernel_mp`` and the tests do.
"""
from __future__ import annotations

import mpmath as mp


def mp_cubic_positive_root(a2, a1, a0, largest) -> mp.mpf:
    """Smallest (largest if ``largest``) positive real root of ``t^3 + a2 t^2 + a1 t + a0`` at the working precision.

    mpmath ``polyroots`` with extra precision on the cubic with its exact roots at 0 deflated, then
    Newton steps at twice the precision; the reference of
    :func:`dtcrit.numerics.cubic.cubic_positive_root` and of the emitted helpers.

    Parameters
    ----------
    a2, a1, a0 : mpmath.mpf or float
        Coefficients of the monic cubic, taken as exact.
    largest : bool
        Return the largest positive root instead of the smallest.

    Returns
    -------
    mpmath.mpf
        The root at ``mp.mp.dps`` digits; 0 when there is no positive real root.
    """
    dps = mp.mp.dps
    coeffs = [mp.mpf(1), mp.mpf(a2), mp.mpf(a1), mp.mpf(a0)]
    poly = list(coeffs)
    while len(poly) > 1 and poly[-1] == 0:
        # an exact root at 0 is not positive: deflate it (adams-bashforth-2 undamped is t^3, whose
        # clustered polyroots values would otherwise pass as a positive root of size 1e-143)
        poly.pop()
    if len(poly) == 1:
        return mp.mpf(0)
    nonzero = [abs(c) for c in coeffs if c != 0]
    spread_bits = int(mp.log(max(nonzero) / min(nonzero), 2)) if len(nonzero) > 1 else 0
    extra = min(spread_bits, 256)  # widely spread coefficients: more bits for the root iteration
    with mp.workdps(2 * dps + 20):
        roots = mp.polyroots(poly, maxsteps=2000, extraprec=8 * dps + 4 * extra)
        scale = 1 + max(abs(r) for r in roots)
        good = [mp.re(r) for r in roots if abs(mp.im(r)) <= mp.mpf(10) ** (-dps) * scale and mp.re(r) > 0]
        if not good:
            return mp.mpf(0)
        t = max(good) if bool(largest) else min(good)
        for _ in range(8):  # Newton polish at the raised precision (quadratic from polyroots' value)
            f = ((t + coeffs[1]) * t + coeffs[2]) * t + coeffs[3]
            df = (3 * t + 2 * coeffs[1]) * t + coeffs[2]
            if df == 0:
                break
            t -= f / df
    return +mp.re(t)
