"""The smallest (or largest) positive real root of a monic cubic (NumPy only).

The one cubic solver of dtcrit: the generated critical-step kernels
(``dtcrit._generated.critical_steps``, boundaries such as Peng et al. 2020, Eq. (40)) and the runtime
(``dtcrit.integrators.precise``, ``dtcrit.integrators.precise_onstep``) call
:func:`cubic_positive_root`; the NumPy text ``dtcrit codegen`` emits
(``dtcrit/codegen/helper_sources/cubic_positive_root.py.txt``) is the same algorithm with two
compensated Newton steps, ``cubic_positive_root(..., compensated_steps=2)`` (a test checks them bit
for bit).  The 50-digit reference of the tests is :func:`dtcrit.numerics.reference.mp_cubic_positive_root`.
"""
from __future__ import annotations

import numpy as np

from dtcrit.numerics.eft import two_product, two_sum


def compensated_newton(t, a2, a1, a0):
    """One Newton step on ``t^3 + a2 t^2 + a1 t + a0`` with the residual from compensated Horner.

    The residual is summed with error-free products and sums (:func:`dtcrit.numerics.eft.two_product`,
    :func:`dtcrit.numerics.eft.two_sum`; Graillat, Langlois & Louvet 2005), so the step is accurate
    even where ``a1 t`` and ``a0`` nearly cancel (small damping).

    Parameters
    ----------
    t : numpy.ndarray
        Current approximation of the root.
    a2, a1, a0 : numpy.ndarray
        Coefficients of the monic cubic (broadcast against ``t``).

    Returns
    -------
    numpy.ndarray
        The improved root; ``t`` itself where it is not finite or the derivative vanishes.
    """
    s = np.ones_like(t)
    c = np.zeros_like(t)
    for a in (a2, a1, a0):
        pr, pe = two_product(s, t)
        s, se = two_sum(pr, a)
        c = c * t + (pe + se)
    dg = (3.0 * t + 2.0 * a2) * t + a1
    ok = np.isfinite(t) & (dg != 0)
    return np.where(ok, t - (s + c) / np.where(ok, dg, 1.0), t)


def cubic_positive_root(a2, a1, a0, largest, compensated_steps: int = 0):
    """Smallest (largest if ``largest``) positive real root of ``t^3 + a2 t^2 + a1 t + a0``; 0.0 if none.

    Viete's forms: trigonometric when the three roots are real, the hyperbolic forms of Cardano's
    formula (no cancellation) otherwise; the smallest (largest) positive candidate; then three Newton
    steps on the cubic polish the root to working precision, and ``compensated_steps`` further steps
    take the residual from compensated Horner (:func:`compensated_newton`).

    Parameters
    ----------
    a2, a1, a0 : float or array_like
        Coefficients of the monic cubic (broadcast against each other).
    largest : bool
        Return the largest positive root instead of the smallest.
    compensated_steps : int, optional
        Number of compensated Newton steps after the three plain ones (0 in the runtime, 2 in the
        NumPy code ``dtcrit codegen`` emits).

    Returns
    -------
    float or numpy.ndarray
        The root (a 0-d input gives a NumPy scalar), 0.0 where the cubic has no positive real root.
    """
    a2, a1, a0 = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (a2, a1, a0)))
    shift = a2 / 3.0
    p = a1 - a2 * shift
    q = (2.0 * shift * shift - a1) * shift + a0
    with np.errstate(all="ignore"):
        # three real roots (p < 0 and the discriminant is non-positive)
        r = 2.0 * np.sqrt(np.maximum(-p, 0.0) / 3.0)
        arg = np.clip(np.where(r > 0, 4.0 * q / np.where(r > 0, r, 1.0) ** 3, 0.0), -1.0, 1.0)
        phi = np.arccos(-arg) / 3.0
        trig = np.stack([r * np.cos(phi - 2.0 * np.pi * j / 3.0) - shift for j in range(3)])
        # one real root: hyperbolic forms of Cardano's formula
        sp3 = np.sqrt(np.abs(p) / 3.0)
        pos = np.where(sp3 > 0, sp3, 1.0)
        hyp_pos = -2.0 * sp3 * np.sinh(np.arcsinh(1.5 * q / (np.abs(p) * pos)) / 3.0)
        hyp_neg = -2.0 * np.sign(q) * sp3 * np.cosh(
            np.arccosh(np.maximum(1.5 * np.abs(q) / (np.abs(p) * pos), 1.0)) / 3.0)
        zero_p = -np.cbrt(q)
        one = np.where(p > 0, hyp_pos, np.where(p < 0, hyp_neg, zero_p)) - shift
        three_real = (p < 0) & (q * q / 4.0 + p * p * p / 27.0 <= 0)
        cand = np.where(three_real, trig, np.stack([one, np.full_like(one, np.nan), np.full_like(one, np.nan)]))
        if largest:
            t = np.max(np.where(cand > 0, cand, -np.inf), axis=0)
        else:
            t = np.min(np.where(cand > 0, cand, np.inf), axis=0)
        for _ in range(3):
            g = ((t + a2) * t + a1) * t + a0
            dg = (3.0 * t + 2.0 * a2) * t + a1
            step = np.where(np.isfinite(t) & (dg != 0), g / np.where(dg != 0, dg, 1.0), 0.0)
            t = t - step
        for _ in range(compensated_steps):
            t = compensated_newton(t, a2, a1, a0)
        t = np.where(np.isfinite(t), t, 0.0)
    return t[()] if t.ndim == 0 else t
