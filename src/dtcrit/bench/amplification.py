"""Amplification matrices built numerically from the integrators' update rules (no SymPy).

Each scheme of ``dtcrit.schemes`` is applied to the unit state vectors in scaled units (omega = 1:
``K = 1``, ``C = 2 zeta``, step ``tau = omega dt``), so column ``j`` of the matrix is the update of
the ``j``-th unit vector (Peng et al. 2020, Eq. (40) for the printed scheme).  The spectral radius
depends on ``(tau, zeta)`` only, so the scaled matrix decides stability for any ``k A``.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np

from dtcrit.schemes import INTEGRATORS, LinearForce


def matrices(name: str, tau, zeta) -> np.ndarray:
    """Array of shape (n, d, d): the amplification matrix for each (tau, zeta) pair (float64)."""
    integ = INTEGRATORS[name]
    tau, zeta = np.broadcast_arrays(np.asarray(tau, dtype=float), np.asarray(zeta, dtype=float))
    tau, zeta = tau.ravel(), zeta.ravel()
    d = len(integ.state)
    force = LinearForce(1.0, 2.0 * zeta)
    G = np.empty((tau.size, d, d))
    zero, one = np.zeros(tau.size), np.ones(tau.size)
    for j in range(d):
        unit = tuple(one if i == j else zero for i in range(d))
        column = integ.step(unit, tau, force)
        for i in range(d):
            G[:, i, j] = column[i]
    return G


def spectral_radius_eigvals(name: str, tau, zeta) -> np.ndarray:
    """max |lambda| by batched ``numpy.linalg.eigvals`` (LAPACK geev) of the float64 matrices."""
    return np.max(np.abs(np.linalg.eigvals(matrices(name, tau, zeta))), axis=1)


def matrix_mp(name: str, tau, zeta) -> mp.matrix:
    """The amplification matrix in mpmath at the current working precision."""
    integ = INTEGRATORS[name]
    d = len(integ.state)
    force = LinearForce(mp.mpf(1), 2 * mp.mpf(zeta))
    G = mp.matrix(d, d)
    for j in range(d):
        unit = tuple(mp.mpf(1) if i == j else mp.mpf(0) for i in range(d))
        column = integ.step(unit, mp.mpf(tau), force)
        for i in range(d):
            G[i, j] = column[i]
    return G


def spectral_radius_mp(name: str, tau, zeta):
    """max |lambda| by ``mpmath.eig`` at the current working precision."""
    eigenvalues = mp.eig(matrix_mp(name, tau, zeta), left=False, right=False)
    return max(abs(v) for v in eigenvalues)
