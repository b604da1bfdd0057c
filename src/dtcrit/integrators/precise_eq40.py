"""The Eq. (40) scheme's critical step, chunk by chunk in bounded variables (runtime; no SymPy).

Peng et al. 2020, Eq. (40): the boundary cubic ``tau^3 - 4 zeta tau^2 + (4 zeta^2 + 2) tau - 2 zeta``
is rewritten in w = c^2 A/(2k + c^2 A) in [0, 1] (``eq40_bounded_cubic``), whose wanted root r lies in
(1, 3/2), so that dt = (c/2) r/(k + c^2 A/2) is reached by two Halley steps and one Newton step for
every element at once, with no branch on zeta (``_eq40_chunk``, used by
``dtcrit.integrators.precise.fast_steps``).
"""
from __future__ import annotations

import numpy as np

_K_LO, _K_HI = 2.0**-1000, 2.0**1000
_A_LO = 2.0**-511


def eq40_bounded_cubic(w, m):
    """Coefficients (c3, c2, c1, c0) of the Eq. (40) scheme's boundary cubic in bounded variables.

    With s = zeta^2, w = 2s/(1 + 2s) (= c^2 A/(2k + c^2 A)), m = 1 - w and tau = zeta m r (tau the
    smallest positive root of tau^3 - 4 zeta tau^2 + (4 zeta^2 + 2) tau - 2 zeta), the cubic is a
    multiple of h(r) = b r^3 - a r^2 + r - 1 with a = w m, b = a m/4, whose wanted root is its only
    root in (1, 3/2) for every zeta >= 0: h < 0 on [0, 1], h(3/2) > 0 and h' >= 1/4 on [1, 3/2]
    (derived from ``dtcrit.symbolic.closed_forms`` in ``tests/integrators/test_precise.py``).  In delta = r - 1,
    h = c3 delta^3 + c2 delta^2 + c1 delta + c0.  Plain arithmetic (the test calls it on symbols).

    Parameters
    ----------
    w : float or array_like or sympy.Expr
        ``c^2 A / (2k + c^2 A)``, in [0, 1].
    m : float or array_like or sympy.Expr
        ``1 - w``.

    Returns
    -------
    tuple
        ``(c3, c2, c1, c0)``, the coefficients of ``h`` in ``delta = r - 1``.
    """
    a = w * m
    b = a * m * 0.25
    return b, 3 * b - a, 1 - 2 * a + 3 * b, b - a


def _eq40_step(d, c3, c2, c1, c0, t1, t2, t3, t4, halley: bool):
    """One Newton (or Halley) step on h(delta) = ((c3 d + c2) d + c1) d + c0, in place on ``d``."""
    np.multiply(c3, d, out=t1)  # c3 d
    np.add(t1, c2, out=t2)  # P1 = c3 d + c2
    if halley:
        np.add(t1, t2, out=t3)
        t3 += t1  # h''/2 = 3 c3 d + c2
    t1 += t2
    t1 *= d
    np.multiply(t2, d, out=t4)
    t4 += c1  # P2 = P1 d + c1
    t1 += t4  # h' = (c3 d + P1) d + P2
    t4 *= d
    t4 += c0  # h = P2 d + c0
    if not halley:
        t4 /= t1
        d -= t4
        return
    t3 *= t4  # h h''/2
    np.multiply(t1, t1, out=t2)
    t2 -= t3  # h'^2 - h h''/2
    t1 *= t4
    t1 /= t2
    d -= t1  # Halley: d - h h' / (h'^2 - h h''/2)


def _eq40_chunk(k, c, A, o, B) -> bool:
    """Step dt = L r, L = (c/2) / (k + c^2 A/2), on one chunk (tau = zeta m r, ``eq40_bounded_cubic``), r = 1 + delta
    by a Halley step from delta = 0, a Halley step and a Newton step (h' >= 1/4 on [1, 3/2]; the
    three steps reach the root to about an ulp for every zeta, ``tests/integrators/test_precise.py``).  False when the chunk is outside the unscaled
    range (k + c^2 A/2 outside [2^-1000, 2^1000], A < 2^-511, or a NaN): inside it nothing
    overflows, and a c A or c^2 A that underflows is negligible against k.
    """
    d, c3, c2, c1, c0, t1, t2, t3, t4 = B
    np.multiply(c, A, out=d)
    d *= c
    d *= 0.5  # p = c^2 A/2
    np.add(k, d, out=t1)
    if not (t1.min() >= _K_LO and t1.max() <= _K_HI and A.min() >= _A_LO):
        return False
    np.divide(k, t1, out=c3)  # m = k/(k + p)
    np.divide(c, t1, out=o)
    o *= 0.5  # the lead L = (c/2)/(k + p)
    np.subtract(1.0, c3, out=d)  # w = 1 - m (an absolute error of an ulp moves r by about as much)
    d *= c3  # a = w m
    c3 *= d
    c3 *= 0.25  # b = a m/4
    np.subtract(c3, d, out=c0)  # b - a
    np.multiply(c3, 3.0, out=c2)
    c2 -= d  # 3b - a
    np.subtract(c2, d, out=c1)
    c1 += 1.0  # 1 - 2a + 3b
    np.multiply(c0, c2, out=t1)  # Halley from delta = 0: delta = c0 c1 / (c0 c2 - c1^2)
    np.multiply(c1, c1, out=t2)
    t1 -= t2
    np.multiply(c0, c1, out=d)
    d /= t1
    _eq40_step(d, c3, c2, c1, c0, t1, t2, t3, t4, True)
    _eq40_step(d, c3, c2, c1, c0, t1, t2, t3, t4, False)
    np.multiply(o, d, out=t1)
    o += t1  # dt = L r = L + L delta (delta's last bits enter only the correction)
    return True
