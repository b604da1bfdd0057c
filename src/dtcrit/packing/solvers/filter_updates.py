"""Fused vector updates of the Chebyshev filter (``largest_mode.chebyshev_filter``).

The three-term step ``y2 = (4/theta) A y1 - 2 y1 - y0`` and the renormalisation of ``y2`` and ``y1``
were NumPy expressions, seven passes over vectors of 6N per product (16 reads and writes of a vector).
Here they are two loops on Numba's threads (9): the same IEEE operations in the same order on each
entry (``t = c y2``, ``t -= y1`` twice, ``t -= y0``; ``y /= norm``), so the same bits; the norm stays
``numpy.linalg.norm``.  Without Numba the NumPy expressions run.
"""
from __future__ import annotations

import numpy as np

from dtcrit.packing.operators.matrix_free_kernels import _jit, available, prange

__all__ = ["available", "three_term", "divide_both"]


def _three_term_loop(y2, y1, y0, c):
    for k in prange(y2.shape[0]):
        t = y2[k] * c
        t -= y1[k]
        t -= y1[k]
        t -= y0[k]
        y2[k] = t


def _divide_both_loop(y2, y1, d):
    for k in prange(y2.shape[0]):
        y2[k] /= d
        y1[k] /= d


_three_term = _jit(_three_term_loop, parallel=True)
_divide_both = _jit(_divide_both_loop, parallel=True)


def three_term(y2: np.ndarray, y1: np.ndarray, y0: np.ndarray, c: float) -> None:
    """``y2 = c y2 - y1 - y1 - y0`` in place (``c = 4/theta``, ``y2`` holding ``A y1``).

    Parameters
    ----------
    y2, y1, y0 : numpy.ndarray
        Contiguous float vectors of one length; ``y2`` is overwritten.
    c : float
        The factor of ``A y1``.
    """
    if available():
        _three_term(y2, y1, y0, float(c))
        return
    y2 *= c
    y2 -= y1
    y2 -= y1
    y2 -= y0


def divide_both(y2: np.ndarray, y1: np.ndarray, d: float) -> None:
    """``y2 /= d``, ``y1 /= d`` in place.

    Parameters
    ----------
    y2, y1 : numpy.ndarray
        Contiguous float vectors of one length.
    d : float
        The divisor (the norm of ``y2``).
    """
    if available():
        _divide_both(y2, y1, float(d))
        return
    y2 /= d
    y1 /= d
