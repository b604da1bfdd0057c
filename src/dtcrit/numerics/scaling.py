"""Exact power-of-two scaling of rates built from k, c and A (NumPy only).

The critical step is homogeneous of degree -1 in the rates omega = sqrt(k A) and gamma = c A / 2
(Peng et al. 2020, Eqs. (29)-(30)), so ``dt = 2^-s dt(omega 2^-s, gamma 2^-s)`` exactly.  Here the
rates are formed from the ``frexp`` mantissas and exponents of k, c and A, so that no product
``k A`` or ``c A`` is ever rounded into overflow or underflow:

* ``frexp_parts(*xs)``: ``x = m 2^e`` with ``1/2 <= |m| < 1`` for each argument;
* ``scaled_root(mk, ek, mA, eA)``: ``sqrt(k A) = w 2^s`` with ``w`` in ``[1/2, 1.42)``, the odd
  exponent folded into the mantissa (one rounding, the square root);
* ``scaled_rates(k, c, A)``: ``omega = w 2^s`` and ``gamma = g 2^s`` on the common scale of omega.
"""
from __future__ import annotations

import numpy as np


def frexp_parts(*xs):
    """Mantissas and exponents of every argument, flattened in argument order.

    Parameters
    ----------
    *xs : float or array_like
        Values to split (converted to float64 arrays).

    Returns
    -------
    tuple of numpy.ndarray
        ``(m1, e1, m2, e2, ...)`` with ``x_i = m_i 2^e_i`` and ``1/2 <= |m_i| < 1`` (``numpy.frexp``;
        ``m = x`` and ``e = 0`` for 0, inf and NaN).
    """
    out: tuple = ()
    for x in xs:
        out += tuple(np.frexp(np.asarray(x, dtype=float)))
    return out


def scaled_root(mk, ek, mA, eA):
    """``sqrt(k A) = w 2^s`` from the mantissas and exponents of k and A.

    Parameters
    ----------
    mk, mA : numpy.ndarray
        Mantissas of k and A, in ``[1/2, 1)`` for positive finite values.
    ek, eA : numpy.ndarray
        Their integer exponents.

    Returns
    -------
    tuple of numpy.ndarray
        ``(w, s)``: ``w = sqrt(mk mA 2^odd)`` in ``[1/2, 1.42)`` and the integer ``s = (ek + eA - odd)/2``,
        ``odd = (ek + eA) mod 2``; exact apart from the rounding of the product and the square root.
    """
    e = ek + eA
    odd = e & 1
    w = np.sqrt(mk * mA * np.where(odd, 2.0, 1.0))
    return w, (e - odd) // 2


def scaled_rates(k, c, A):
    """The rates omega = sqrt(k A) and gamma = c A / 2 on the common scale ``2^s`` of omega.

    Parameters
    ----------
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].

    Returns
    -------
    tuple of numpy.ndarray
        ``(w, g, s)`` with ``omega = w 2^s``, ``gamma = g 2^s`` (1/s), ``w`` in ``[1/2, 1.42)``;
        ``g`` may overflow or underflow where zeta = gamma/omega lies beyond float64.
    """
    mk, ek, mA, eA, mc, ec = frexp_parts(k, A, c)
    w, s = scaled_root(mk, ek, mA, eA)
    g = np.ldexp(mc * mA * 0.5, ec + eA - s)
    return w, g, s
