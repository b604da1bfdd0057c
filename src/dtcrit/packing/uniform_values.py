"""Per-contact values that are the same on every contact, held once.

A contact law with constant springs (``model.LinearLaw``), a dashpot or normal force given as one
number, the effective radius ``R* = R R / (R + R)`` of a packing of equal spheres: each gives every
contact one number.  ``Contacts`` holds such a value as a read-only view of stride 0
(``numpy.broadcast_to``, ``uniform``): it indexes, slices and broadcasts as the (C,) array it stands
for, in 8 bytes instead of ``8 C``; a write into it raises ``ValueError`` (read-only).  Arrays of
one value per contact are kept as given (never scanned for equal entries).

The compiled loops receive a uniform value as a length-1 contiguous array (``kernel_values``) and
read every contact's coefficient through ``dtcrit.packing.operators.contact_element.coefficient_at``
(``values[0]`` for length 1, ``values[c]`` otherwise), so both forms give the same bits.
"""
from __future__ import annotations

import numpy as np

__all__ = ["uniform", "entries", "is_uniform", "one_value", "held", "held_bytes", "kernel_values", "taken"]


def uniform(value, count: int) -> np.ndarray:
    """``count`` entries of ``value`` as a read-only float64 view of stride 0.

    Parameters
    ----------
    value : float
        The value of every entry.
    count : int
        Entries.

    Returns
    -------
    numpy.ndarray
        (count,) view of one float64 (``numpy.broadcast_to``).

    Examples
    --------
    >>> v = uniform(2.5, 4)
    >>> v.tolist(), v.strides, v.flags.writeable
    ([2.5, 2.5, 2.5, 2.5], (0,), False)
    """
    return np.broadcast_to(np.float64(value), (int(count),))


def entries(value, count: int) -> np.ndarray:
    """``value`` as ``count`` entries: a number as a uniform view (``uniform``), an array as it is.

    Parameters
    ----------
    value : float or numpy.ndarray
        One number for every entry, or (count,) values.
    count : int
        Entries.

    Returns
    -------
    numpy.ndarray
        (count,) values.
    """
    return uniform(value, count) if np.ndim(value) == 0 else value


def is_uniform(a) -> bool:
    """Whether ``a`` holds one value for all its entries: a 0-d array or a 1-d array of stride 0.

    Parameters
    ----------
    a : object
        An array (anything else is not uniform).

    Returns
    -------
    bool
        ``True`` for a 0-d array or a non-empty 1-d array of stride 0.
    """
    return isinstance(a, np.ndarray) and (a.ndim == 0 or (a.ndim == 1 and a.shape[0] > 0 and a.strides[0] == 0))


def one_value(value, count: int) -> np.ndarray | None:
    """The one value of ``value`` as a length-1 float64 array when ``value`` gives every one of ``count``
    entries the same number (a scalar, a 0-d array, a length-1 array, a 1-d array of stride 0), else
    ``None`` (one value per entry: to be copied and checked entry by entry).

    Parameters
    ----------
    value : float or array_like
        One value, or one per entry.
    count : int
        Entries.

    Returns
    -------
    numpy.ndarray or None
        ``[v]`` (float64), or ``None``.
    """
    a = value if isinstance(value, np.ndarray) else np.asarray(value)
    if count > 0 and (a.ndim == 0 or (a.ndim == 1 and (a.shape[0] == 1 or (a.shape[0] == count and a.strides[0] == 0)))):
        return np.asarray(a.reshape(-1)[:1], dtype=float)
    return None


def held(a: np.ndarray) -> np.ndarray:
    """The values ``a`` holds: its one value (length 1) when uniform, else ``a`` itself (for checks such
    as ``numpy.all(held(a) >= 0)`` that need not visit a uniform view's every entry).

    Parameters
    ----------
    a : numpy.ndarray
        Per-entry values.

    Returns
    -------
    numpy.ndarray
        ``a[:1]`` when ``is_uniform(a)`` (1-d), ``a`` otherwise.
    """
    return a.reshape(-1)[:1] if is_uniform(a) else a


def held_bytes(a: np.ndarray) -> int:
    """Bytes of memory behind ``a``: one item for a uniform view, ``a.nbytes`` otherwise.

    Parameters
    ----------
    a : numpy.ndarray
        Per-entry values.

    Returns
    -------
    int
        The bytes.
    """
    return int(held(a).nbytes) if is_uniform(a) else int(a.nbytes)


def taken(a: np.ndarray, count: int, mask) -> np.ndarray:
    """``a[mask]`` (``count`` entries), a uniform view staying a uniform view.

    Parameters
    ----------
    a : numpy.ndarray
        (C,) per-entry values.
    count : int
        Entries selected by ``mask``.
    mask : numpy.ndarray
        Boolean mask or index array.

    Returns
    -------
    numpy.ndarray
        The selected entries.
    """
    return uniform(a.reshape(-1)[0], count) if is_uniform(a) and a.ndim == 1 else a[mask]


def kernel_values(a) -> np.ndarray:
    """A per-contact coefficient as the compiled loops take it: a length-1 copy of a uniform view's one
    value, else ``numpy.ascontiguousarray(a, float)`` (no copy of a contiguous float64 array; never a
    full copy of a uniform view).

    Parameters
    ----------
    a : numpy.ndarray
        (C,) coefficients, or a uniform view of them.

    Returns
    -------
    numpy.ndarray
        Contiguous float64, length 1 or C (read by ``contact_element.coefficient_at``).
    """
    if is_uniform(a):
        return np.array([a.reshape(-1)[0]], dtype=float)
    return np.ascontiguousarray(a, dtype=float)
