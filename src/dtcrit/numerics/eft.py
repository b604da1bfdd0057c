"""Error-free transformations of float64 arithmetic (NumPy only).

* ``split(a)``: Veltkamp's splitting ``a = hi + lo`` with ``hi`` holding 26 bits (constant ``2^27 + 1``);
* ``two_product(a, b)``: Dekker's product, ``p + e = a b`` exactly with ``p = fl(a b)``
  (Dekker 1971, Eq. (5.12); valid while ``|a|, |b| < 2^995`` and ``e`` does not underflow);
* ``two_sum(a, b)``: Knuth's two-sum, ``s + e = a + b`` exactly with ``s = fl(a + b)`` (TAOCP vol. 2,
  Sec. 4.2.2, Theorem B; no ordering of ``|a|`` and ``|b|`` needed);
* ``dd_polynomial(terms, x, y)``: a polynomial with integer coefficients in double-double arithmetic.

No fused multiply-add is used, so every result is the same on every IEEE 754 platform.  The emitted
C and Fortran helpers (``dtcrit/codegen/helper_sources``) perform the same operations in the same order.
"""
from __future__ import annotations

import numpy as np

SPLITTER = 134217729.0
"""``2^27 + 1``, Veltkamp's splitting constant for float64 (53-bit significands)."""


def split(a):
    """Veltkamp's splitting of ``a`` into a high and a low half.

    Parameters
    ----------
    a : float or numpy.ndarray
        Value to split (``|a| < 2^995``, so that ``SPLITTER a`` does not overflow).

    Returns
    -------
    tuple of float or numpy.ndarray
        ``(hi, lo)`` with ``hi + lo = a`` exactly and each half fitting in 26 bits.
    """
    t = SPLITTER * a
    hi = t - (t - a)
    return hi, a - hi


def two_product(a, b):
    """Dekker's error-free product ``a b = p + e``.

    Parameters
    ----------
    a, b : float or numpy.ndarray
        Factors (``|a|, |b| < 2^995``; the error term is exact unless it underflows).

    Returns
    -------
    tuple of float or numpy.ndarray
        ``(p, e)`` with ``p = fl(a b)`` and ``e = a b - p`` exactly (Dekker 1971, Eq. (5.12)).
    """
    p = a * b
    t = SPLITTER * a
    ah = t - (t - a)
    al = a - ah
    t = SPLITTER * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def two_sum(a, b):
    """Knuth's error-free sum ``a + b = s + e``.

    Parameters
    ----------
    a, b : float or numpy.ndarray
        Addends (finite; any order of magnitude).

    Returns
    -------
    tuple of float or numpy.ndarray
        ``(s, e)`` with ``s = fl(a + b)`` and ``e = a + b - s`` exactly (Knuth, TAOCP 4.2.2, Theorem B).
    """
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def dd_polynomial(terms, x, y):
    """``sum(c x^i y^j for (c, i, j) in terms)`` in double-double arithmetic, rounded once.

    The integer coefficients are exact; every product and sum keeps its rounding error
    (``two_product``, ``two_sum``), so the result has a relative error of about 1e-16 even where the
    terms cancel to many digits (the factors of a discriminant near a double root).

    Parameters
    ----------
    terms : iterable of (int, int, int)
        ``(c, i, j)``: integer coefficient and the exponents of ``x`` and ``y``.
    x, y : float or numpy.ndarray
        The variables (broadcast against each other).

    Returns
    -------
    numpy.ndarray
        The value of the polynomial, the double-double sum rounded to float64.
    """
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    hi = np.zeros(x.shape)
    lo = np.zeros(x.shape)
    for c, i, j in terms:
        th = np.full(x.shape, float(c))
        tl = np.zeros(x.shape)
        for v in (x,) * i + (y,) * j:
            p, e = two_product(th, v)
            th, tl = two_sum(p, e + tl * v)
        s, e = two_sum(hi, th)
        hi, lo = two_sum(s, e + lo + tl)
    return hi + lo
