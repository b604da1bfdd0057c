"""The range of numbers a read packing may carry into the eigen-solve.

Every value a reader accepts is finite, but products of them need not be: a contact spring of
``1e5`` N/m on a body whose moment of inertia is ``1e-320`` kg m^2 gives ``omega^2 ~ k a^2 / I ~
1e319`` s^-2, which overflows inside the mass-scaled matrix ``M^-1/2 K M^-1/2`` and stops the
solver with a library message.  :func:`check_rates` bounds, contact by contact, the largest entry
that contact adds to the mass-scaled stiffness (and to the squared mass-scaled damping),

    rate_c = max(k_n, k_s, F_n/d) (1/m_i + |a_i|^2 / I_i + 1/m_j + |a_j|^2 / I_j)
             + max(k_r, k_tw) (1/I_i + 1/I_j) + [max(c_n, c_s) (1/m_i + |a_i|^2 / I_i + ...)]^2

(``I`` the smallest principal moment, ``a`` the contact arm, ``F_n/d`` the pre-load's geometric
stiffness over the centre distance), and refuses a contact whose rate is
not below ``MAX_RATE`` [1/s^2], naming its line or key: the step would be below ``2/sqrt(MAX_RATE)``
= 2e-100 s, where the solver's sums of squares (``~rate^2``) no longer fit in double precision.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from dtcrit.errors import InputError, Location

def _error(where: str | Location, reason: str) -> InputError:
    """An error at ``where``: a key (``FILE: bodies[3]``) or a :class:`Location`."""
    return InputError.at(where, reason) if isinstance(where, Location) else InputError(where, reason)


MAX_RATE = 1e200
"""Largest accepted ``rate_c`` [1/s^2] (module docstring)."""


def contact_rates(masses, inertia, i, j, arm_i, arm_j, k, k_rot=None, c=None) -> np.ndarray:
    """``rate_c`` of the module docstring for contacts ``(i, j)``.

    Parameters
    ----------
    masses : array_like
        The bodies' masses [kg].
    inertia : array_like
        The bodies' principal moments [kg m^2] (one per body, or rows of three: the smallest is used).
    i, j : numpy.ndarray
        The contacts' body indices.
    arm_i, arm_j : numpy.ndarray
        The contact arms [m], ``(contacts, 3)``.
    k : array_like
        The largest translational spring of each contact [N/m].
    k_rot : array_like or None
        The largest rotational spring of each contact [N m/rad].
    c : array_like or None
        The largest dashpot of each contact [N s/m].

    Returns
    -------
    numpy.ndarray
        ``rate_c`` [1/s^2] of each contact (``inf`` where it overflows).
    """
    masses, inertia = np.asarray(masses, float), np.asarray(inertia, float).reshape(len(masses), -1).min(axis=1)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        arm_i2 = np.einsum("ij,ij->i", arm_i, arm_i)
        arm_j2 = np.einsum("ij,ij->i", arm_j, arm_j)
        reach = 1.0 / masses[i] + arm_i2 / inertia[i] + 1.0 / masses[j] + arm_j2 / inertia[j]
        turn = 1.0 / inertia[i] + 1.0 / inertia[j]
        rate = _times(k, reach)
        if k_rot is not None:
            rate = rate + _times(k_rot, turn)
        if c is not None:
            rate = rate + _times(c, reach) ** 2
    return rate


def _times(coefficient, factor) -> np.ndarray:
    """``coefficient * factor`` with an absent term (coefficient 0) zero even where ``factor`` overflows."""
    coefficient = np.asarray(coefficient, float)
    return np.where(coefficient == 0, 0.0, coefficient * factor)


def check_rates(rate: np.ndarray, key_of: Callable[[int], str | Location]) -> None:
    """Refuse the first contact whose ``rate`` is not below ``MAX_RATE``.

    Parameters
    ----------
    rate : numpy.ndarray
        ``rate_c`` of each contact (:func:`contact_rates`).
    key_of : callable
        ``key_of(c)`` locates contact ``c``: a key or a ``dtcrit.errors.Location``.
    """
    bad = ~(rate < MAX_RATE)
    if bad.any():
        c = int(np.argmax(bad))
        size = f"~ {rate[c]:.3g} 1/s^2" if np.isfinite(rate[c]) else "beyond double precision"
        raise _error(key_of(c), f"its springs and dashpots on these masses and moments of inertia give "
                                    f"omega^2 {size}, above the {MAX_RATE:g} 1/s^2 the eigen-solve carries in double "
                                    "precision (a step below 2e-100 s)")


MAX_LENGTH = 1e100
"""Largest accepted coordinate, size or box bound [m]: the contact search and the arms square and
multiply lengths (``|x|^2``, ``k |a|^2``), which must stay far inside double precision."""


def check_lengths(values, key_of: Callable[[int], str | Location], what: str) -> None:
    """Refuse the first row of ``values`` holding a length beyond ``MAX_LENGTH``.

    Parameters
    ----------
    values : array_like
        Lengths [m]: one row per particle, or a flat array.
    key_of : callable
        ``key_of(k)`` locates row ``k``: a key or a ``dtcrit.errors.Location``.
    what : str
        What the lengths are (``"a coordinate"``), for the message.
    """
    v = np.abs(np.asarray(values, float))
    bad = ~(v.reshape(len(v), -1) <= MAX_LENGTH).all(axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        raise _error(key_of(k), f"{what} {v[k].max():g} m is beyond the {MAX_LENGTH:g} m a packing's lengths may "
                                    "reach (they are squared and multiplied in double precision)")


MIN_INERTIA = 1e-100
"""Smallest accepted mass [kg] or principal moment of inertia [kg m^2]: the mass-scaled matrices
divide every spring by them, so a spring of up to 1e100 N/m stays below ``MAX_RATE`` (a sphere of
1 nm weighs ~1e-24 kg and turns with ~1e-42 kg m^2)."""


def check_inertia(values, key_of: Callable[[int], str | Location], what: str) -> None:
    """Refuse the first row of ``values`` holding a value below ``MIN_INERTIA``.

    Parameters
    ----------
    values : array_like
        Masses [kg], or rows of principal moments [kg m^2].
    key_of : callable
        ``key_of(k)`` locates row ``k``: a key or a ``dtcrit.errors.Location``.
    what : str
        What the values are (``"the mass [kg]"``), for the message.
    """
    v = np.asarray(values, float)
    bad = ~(v.reshape(len(v), -1) >= MIN_INERTIA).all(axis=1)
    if bad.any():
        k = int(np.argmax(bad))
        raise _error(key_of(k), f"{what} {v[k].min():g} is below the {MIN_INERTIA:g} a packing's masses and moments "
                                    "may reach (every spring is divided by them in double precision)")
