"""Boundary search on the spectral radius: the largest step whose amplification matrix is stable.

The direct routes of the bench (float64 eigenvalues, the paper's Cardano eigenvalues, mpmath
eigenvalues) do not know any closed form: they bisect on the dimensionless step ``tau = omega dt``
between ``tau = 0`` (the identity: stable) and ``TAU_HI = 4`` (unstable for every scheme and
damping ratio the toolkit has: its largest exact bound is 2, the central difference).

The bisection runs on the bit patterns of non-negative float64 numbers, which are ordered like
the numbers themselves, so 62 halvings take the bracket ``[0, 4]`` down to two adjacent floats at
any magnitude of ``tau`` (a damping ratio of 1e12 gives tau* ~ 1e-12; no fixed absolute
tolerance is involved).  "Stable" means ``rho <= 1 + tol``: with the tolerance ``tol`` a few
rounding units of the working precision, a scheme whose eigenvalues lie *on* the unit circle
(undamped central difference) is not declared unstable by rounding.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

TAU_HI = 4.0
_HI_BITS = np.float64(TAU_HI).view(np.int64)


def bisect_tau(stable: Callable[[np.ndarray], np.ndarray], n: int) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) adjacent floats with ``stable(lo)`` true and ``stable(hi)`` false, elementwise.

    ``stable(tau)`` maps an array of ``n`` steps to booleans.  Where even the smallest positive
    step is unstable, ``lo`` is 0.0 (no stable step); where ``TAU_HI`` tests stable, ``lo`` and
    ``hi`` are NaN (no bracket: the search failed).

    Parameters
    ----------
    stable : callable
        Maps an array of ``n`` steps tau to booleans.
    n : int
        Number of scenes.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi)``.
    """
    lo = np.zeros(n, dtype=np.int64)
    hi = np.full(n, _HI_BITS, dtype=np.int64)
    at_top = np.asarray(stable(np.full(n, TAU_HI)), dtype=bool)
    for _ in range(64):
        gap = hi - lo
        if not np.any(gap > 1):
            break
        mid = lo + gap // 2
        ok = np.asarray(stable(mid.view(np.float64)), dtype=bool)
        lo = np.where(ok, mid, lo)
        hi = np.where(ok, hi, mid)
    lo_f, hi_f = lo.view(np.float64).copy(), hi.view(np.float64).copy()
    lo_f[at_top] = np.nan
    hi_f[at_top] = np.nan
    return lo_f, hi_f


def bisect_tau_mp(stable: Callable, bits: int = 64, min_exponent: int = -100_000):
    """(lo, hi) mpmath numbers with ``stable(lo)`` true, ``stable(hi)`` false, hi/lo - 1 < 2^-bits.

    For the mpmath routes, whose tau* may lie below float64's range (zeta ~ 5e444 gives
    tau* ~ 1e-445): an exponential search on the binary exponent (tau = 2^-1, 2^-2, 2^-4, ...)
    brackets tau* between two powers of two, a bisection on the exponent narrows it to
    [2^e, 2^(e+1)], and a bisection on the mantissa finishes.  ``(0, 2^min_exponent)`` when every
    step tried is unstable; ``(nan, nan)`` when ``TAU_HI`` tests stable (no bracket).

    Parameters
    ----------
    stable : callable
        Maps an mpmath step tau to a boolean.
    bits : int
        Relative width of the final bracket, ``2^-bits``.
    min_exponent : int
        Smallest binary exponent tried.

    Returns
    -------
    tuple
        ``(lo, hi)`` as mpmath numbers.
    """
    import mpmath as mp

    if stable(mp.mpf(TAU_HI)):
        return mp.nan, mp.nan
    hi_e, j = 2, 1  # stable(2^hi_e) is false
    while True:
        e = -j
        if e < min_exponent:
            return mp.mpf(0), mp.ldexp(1, min_exponent)
        if stable(mp.ldexp(1, e)):
            lo_e = e
            break
        hi_e, j = e, 2 * j
    while hi_e - lo_e > 1:  # stable(2^lo_e), not stable(2^hi_e)
        mid = (lo_e + hi_e) // 2
        if stable(mp.ldexp(1, mid)):
            lo_e = mid
        else:
            hi_e = mid
    lo, hi = mp.ldexp(1, lo_e), mp.ldexp(1, hi_e)
    for _ in range(bits):
        mid = (lo + hi) / 2
        if stable(mid):
            lo = mid
        else:
            hi = mid
    return lo, hi


def bisect_tau_scalar(stable: Callable[[float], bool]) -> tuple[float, float]:
    """Scalar form of ``bisect_tau`` (for the mpmath routes, one scene at a time).

    Parameters
    ----------
    stable : callable
        Maps a float step tau to a boolean.

    Returns
    -------
    tuple of float
        ``(lo, hi)`` adjacent floats.
    """
    if stable(TAU_HI):
        return math.nan, math.nan
    lo, hi = 0, int(_HI_BITS)
    while hi - lo > 1:
        mid = lo + (hi - lo) // 2
        if stable(float(np.int64(mid).view(np.float64))):
            lo = mid
        else:
            hi = mid
    return float(np.int64(lo).view(np.float64)), float(np.int64(hi).view(np.float64))
