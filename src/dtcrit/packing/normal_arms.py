"""Contact arms that lie along the contact normal, stored as their lengths.

A sphere contact's arms are ``a_i = l_i n`` and ``a_j = -l_j n`` with ``l = R - delta/2`` (the
contact point in the middle of the overlap, Peng et al. 2020, Eqs (1)-(2)).  Stored as (C, 3)
vectors they cost 48 bytes a contact; :class:`NormalArms` keeps the length (8 bytes) and the
contacts' own normal array, and gives the vectors on demand: indexing, NumPy functions and
ufuncs see the (C, 3) array ``sign * l[:, None] * n``, computed with the same arithmetic the
vectors were stored with before (so the same bits); they are read-only (a write raises
``TypeError``, as a write that changed nothing would be silent).  The sphere product and the bounds
read the lengths directly (``lengths_along``, ``kernel_arms``).
"""
from __future__ import annotations

import numpy as np
from numpy.lib.mixins import NDArrayOperatorsMixin

__all__ = ["NormalArms", "kernel_arms", "lengths_along"]

WRITERS = (np.copyto, np.put, np.place, np.putmask, np.put_along_axis, np.fill_diagonal)
"""NumPy functions that write into their first argument: refused on ``NormalArms`` (read-only)."""


class NormalArms(NDArrayOperatorsMixin):
    """(C, 3) arms ``sign * length[:, None] * normal`` held as their factors.

    Parameters
    ----------
    length : numpy.ndarray
        (C,) arm lengths [m] along the normal.
    normal : numpy.ndarray
        (C, 3) unit normals (the contact list's own array, not copied).
    sign : float
        ``+1`` for the arm of ``i`` (towards ``j``), ``-1`` for the arm of ``j``.

    Examples
    --------
    >>> import numpy as np
    >>> arms = NormalArms(np.array([0.5]), np.array([[0.0, 0.0, 1.0]]), -1.0)
    >>> np.asarray(arms).tolist(), arms.shape
    ([[-0.0, -0.0, -0.5]], (1, 3))
    """

    __array_priority__ = 20.0

    def __init__(self, length: np.ndarray, normal: np.ndarray, sign: float):
        self.length = np.asarray(length, dtype=float)
        self.normal = normal
        self.sign = float(sign)
        if self.length.ndim != 1 or normal.shape != (self.length.shape[0], 3) or self.sign not in (1.0, -1.0):
            raise ValueError("NormalArms: lengths (C,), normals (C, 3) and a sign of +1 or -1")

    @property
    def shape(self) -> tuple[int, int]:
        """``(C, 3)``."""
        return (int(self.length.shape[0]), 3)

    @property
    def ndim(self) -> int:
        """2."""
        return 2

    @property
    def dtype(self) -> np.dtype:
        """float64."""
        return np.dtype(float)

    @property
    def size(self) -> int:
        """``3 C``."""
        return 3 * int(self.length.shape[0])

    @property
    def nbytes(self) -> int:
        """Bytes held of its own (the lengths; the normals belong to the contact list)."""
        return int(self.length.nbytes)

    def __len__(self) -> int:
        return int(self.length.shape[0])

    def _rows(self, rows) -> np.ndarray:
        length = self.length[rows]
        if self.sign < 0:
            return -(length[..., None] * self.normal[rows])
        return length[..., None] * self.normal[rows]

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        out = self._rows(slice(None))
        return out if dtype is None else out.astype(dtype, copy=False)

    def __getitem__(self, key) -> np.ndarray:
        if not isinstance(key, tuple):
            return self._rows(key)
        rest = key[1:]
        if not key or not all(isinstance(k, (int, np.integer, slice)) for k in rest):
            return np.asarray(self)[key]  # paired or advanced indices across both axes: on the vectors
        rows = self._rows(key[0])
        return rows[rest] if rows.ndim == 1 else rows[(slice(None),) + rest]

    def select(self, rows, normal: np.ndarray) -> "NormalArms":
        """The arms of the contacts ``rows``, still as lengths, on their (already selected) ``normal``.

        Parameters
        ----------
        rows : numpy.ndarray or slice
            Mask or indices of the contacts kept.
        normal : numpy.ndarray
            Their normals, ``normal[rows]`` of the original list.

        Returns
        -------
        NormalArms
            The selection.
        """
        return NormalArms(self.length[rows], normal, self.sign)

    def copy(self) -> np.ndarray:
        """The (C, 3) vectors as a new array.

        Returns
        -------
        numpy.ndarray
            ``sign * length[:, None] * normal``.
        """
        return np.asarray(self)

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        written = list(kwargs.get("out", None) or ()) + ([inputs[0]] if method == "at" else [])
        if any(isinstance(x, NormalArms) for x in written):
            raise TypeError("NormalArms are read-only: write to np.asarray(arms), a copy")
        inputs = tuple(np.asarray(x) if isinstance(x, NormalArms) else x for x in inputs)
        return getattr(ufunc, method)(*inputs, **kwargs)

    def __array_function__(self, func, types, args, kwargs):
        if func in WRITERS and args and isinstance(args[0], NormalArms):
            raise TypeError(f"NormalArms are read-only: np.{func.__name__} cannot write to them")
        def plain(x):
            if isinstance(x, NormalArms):
                return np.asarray(x)
            if isinstance(x, (list, tuple)):
                return type(x)(plain(y) for y in x)
            return x

        return func(*plain(args), **{k: plain(v) for k, v in kwargs.items()})

    def __repr__(self) -> str:
        return f"NormalArms({len(self)} contacts, sign {self.sign:+g})"


def lengths_along(arm_i, arm_j, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """``(l_i, l_j)`` of arms held as :class:`NormalArms` on ``normal`` (``a_i = l_i n``,
    ``a_j = -l_j n``), else ``None``.

    Parameters
    ----------
    arm_i, arm_j : NormalArms or numpy.ndarray
        The contact list's arms.
    normal : numpy.ndarray
        The contact list's normals.

    Returns
    -------
    tuple of numpy.ndarray or None
        The lengths (the stored arrays, not copies).
    """
    if (isinstance(arm_i, NormalArms) and isinstance(arm_j, NormalArms) and arm_i.sign > 0 > arm_j.sign
            and arm_i.normal is normal and arm_j.normal is normal):
        return arm_i.length, arm_j.length
    return None


def kernel_arms(contacts) -> tuple[np.ndarray, np.ndarray]:
    """The arms as the compiled loops read them (``contact_element.arm_rows``): (C, 1) views of the
    lengths when held as :class:`NormalArms` (no copy), else contiguous (C, 3) vectors.

    Parameters
    ----------
    contacts : Contacts
        The contact list.

    Returns
    -------
    tuple of numpy.ndarray
        ``(arm_i, arm_j)``, both (C, 1) or both (C, 3).
    """
    stored = lengths_along(contacts.arm_i, contacts.arm_j, contacts.normal)
    if stored is not None and stored[0].flags.c_contiguous and stored[1].flags.c_contiguous:
        return stored[0].reshape(-1, 1), stored[1].reshape(-1, 1)
    return (np.ascontiguousarray(contacts.arm_i, dtype=float), np.ascontiguousarray(contacts.arm_j, dtype=float))
