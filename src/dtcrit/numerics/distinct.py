"""Sorted distinct values of an array without ``numpy.unique``.

``numpy.unique`` imports ``numpy.ma`` on first use (about 8 ms of a fresh interpreter, a twentieth of
``dtcrit step``'s start); the scenes' and bodies' few small arrays only need the sorted distinct
values, which a sort and a comparison of neighbours give.
"""
from __future__ import annotations

import numpy as np


def distinct(a) -> np.ndarray:
    """The sorted distinct values of ``a`` (flattened), as ``numpy.unique(a)`` gives those of finite values.

    Parameters
    ----------
    a : array_like
        Values (any shape; compared with ``!=``, so ``-0.0`` and ``0.0`` are one value, and each NaN
        is kept, last, where ``numpy.unique`` keeps one).

    Returns
    -------
    numpy.ndarray
        1-D, ascending, each value once.

    Examples
    --------
    >>> distinct([3.0, 1.0, 3.0, 2.0]).tolist()
    [1.0, 2.0, 3.0]
    """
    s = np.sort(np.asarray(a).reshape(-1))
    return s[np.concatenate([[True], s[1:] != s[:-1]])] if s.size else s


def distinct_rows(a) -> np.ndarray:
    """The distinct rows of a 2-D array in lexicographic order (first column first), as
    ``numpy.unique(a, axis=0)`` gives them for booleans, integers and finite floats.

    Parameters
    ----------
    a : array_like
        Shape (m, k).

    Returns
    -------
    numpy.ndarray
        Shape (d, k), each row once.

    Examples
    --------
    >>> distinct_rows([[1, 0], [0, 1], [1, 0]]).tolist()
    [[0, 1], [1, 0]]
    """
    a = np.asarray(a)
    if a.shape[0] == 0:
        return a
    s = a[np.lexsort(a.T[::-1])]
    return s[np.concatenate([[True], (s[1:] != s[:-1]).any(axis=1)])]
