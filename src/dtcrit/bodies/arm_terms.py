"""The per-particle arm term ``[p]x^T I^-1 [p]x`` of Peng et al. (2020), Section 3, its largest
eigenvalue, and the result type of every arm-supremum route (:class:`ArmSupremum`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit._generated import contact as _k

SUP_RTOL = 1e-7
"""Smooth bodies: refine until the upper bound is within this relative distance of the best surface value."""
SUP_MAX_HALFSPACES = 12000
SUP_MAX_ITERATIONS = 80
SUPPORT_SLACK = 1e-12
"""Relative inflation of support offsets h(n): rounding in a support point never cuts the body."""


# ============================================================================================
# The per-particle term and its largest eigenvalue (vectorised over a leading axis)
# ============================================================================================
def arm_terms_local(points: np.ndarray, inertia) -> np.ndarray:
    """``[p]x^T I^-1 [p]x`` (generated kernel ``arm_term``) for each row of ``points`` (local frame).

    Parameters
    ----------
    points : numpy.ndarray
        Contact points in the principal frame, shape (N, 3) [m].
    inertia : array_like
        Principal moments ``(I_xx, I_yy, I_zz)`` [kg m^2].

    Returns
    -------
    numpy.ndarray
        The symmetric terms, shape (N, 3, 3) [1/kg].
    """
    p = np.atleast_2d(np.asarray(points, dtype=float))
    ixx, iyy, izz = (float(i) for i in inertia)
    terms = _k.arm_term(p[:, 0], p[:, 1], p[:, 2], ixx, iyy, izz)  # xx, yy, zz, xy, xz, yz
    sym = np.empty((p.shape[0], 3, 3))
    for value, (i, j) in zip(terms, ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))):
        sym[:, i, j] = sym[:, j, i] = value  # a term the kernel returns as a constant is broadcast
    return sym


def largest_eigenvalue(sym: np.ndarray) -> np.ndarray:
    """Largest eigenvalue of each symmetric 3x3 matrix in ``sym`` (..., 3, 3).

    Parameters
    ----------
    sym : numpy.ndarray
        Symmetric matrices, shape (..., 3, 3).

    Returns
    -------
    numpy.ndarray
        The largest eigenvalues, shape (...).
    """
    return np.linalg.eigvalsh(sym)[..., -1]


def arm_lambda(points: np.ndarray, inertia) -> np.ndarray:
    """``lambda_max([p]x^T I^-1 [p]x)`` for each row of ``points``.

    Parameters
    ----------
    points : numpy.ndarray
        Contact points in the principal frame, shape (N, 3) [m].
    inertia : array_like
        Principal moments [kg m^2].

    Returns
    -------
    numpy.ndarray
        The largest eigenvalues, shape (N,) [1/kg].
    """
    return largest_eigenvalue(arm_terms_local(points, inertia))


def fibonacci_sphere(n: int) -> np.ndarray:
    """``n`` nearly uniform unit vectors (deterministic Fibonacci lattice).

    Parameters
    ----------
    n : int
        Number of vectors.

    Returns
    -------
    numpy.ndarray
        Unit vectors, shape (n, 3).
    """
    i = np.arange(n) + 0.5
    polar = np.arccos(1.0 - 2.0 * i / n)
    azim = math.pi * (1.0 + math.sqrt(5.0)) * i
    return np.column_stack([np.cos(azim) * np.sin(polar), np.sin(azim) * np.sin(polar), np.cos(polar)])


# ============================================================================================
# Result and dispatch
# ============================================================================================
@dataclass(frozen=True)
class ArmSupremum:
    """Bounds on ``S`` for one shape: ``lower <= S <= upper`` [1/kg].

    ``point`` is a surface point (local frame) where ``lower`` is attained, ``normal`` an outward
    unit normal there (in the normal cone at a vertex: ``support(normal) == point``), and
    ``method`` says how the bounds were obtained (see the module docstring); ``work`` counts the
    half-spaces (cutting planes) or cells (octant cones) used, 0 for the exact routes.

    Parameters
    ----------
    upper : float
        Upper bound on ``S`` [1/kg].
    lower : float
        Lower bound, attained at ``point`` [1/kg].
    point : tuple of float
        Surface point (local frame) where ``lower`` is attained [m].
    normal : tuple of float
        Outward unit normal at ``point``.
    method : str
        How the bounds were obtained.
    work : int
        Half-spaces or cells used (0 for the exact routes).
    """

    upper: float
    lower: float
    point: tuple[float, float, float]
    normal: tuple[float, float, float]
    method: str
    work: int = 0

    @property
    def relative_gap(self) -> float:
        """``upper/lower - 1``: how far apart the bounds are."""
        return self.upper / self.lower - 1.0
