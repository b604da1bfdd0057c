"""Amplification matrices evaluated numerically from the update rules (runtime; no SymPy).

The update rule of ``dtcrit.integrators.schemes`` is applied to each unit state vector in scaled units
(omega = 1: ``K = 1``, ``C = 2 zeta``, step ``tau = omega dt``), so column ``j`` of ``G`` is the
image of the ``j``-th unit vector.  The spectral radius depends on ``(tau, zeta)`` only.
"""
from __future__ import annotations

import numpy as np

from dtcrit.integrators.schemes import LinearForce, lookup


def matrices(integrator: str, tau, zeta) -> np.ndarray:
    """Batched amplification matrices, shape ``broadcast(tau, zeta).shape + (d, d)``."""
    integ = lookup(integrator)
    tau, zeta = np.broadcast_arrays(np.asarray(tau, dtype=float), np.asarray(zeta, dtype=float))
    d = len(integ.state)
    force = LinearForce(1.0, 2.0 * zeta)
    G = np.empty(tau.shape + (d, d))
    zero, one = np.zeros(tau.shape), np.ones(tau.shape)
    for j in range(d):
        column = integ.step(tuple(one if i == j else zero for i in range(d)), tau, force)
        for i in range(d):
            G[..., i, j] = column[i]
    return G


def spectral_radius(integrator: str, tau, zeta) -> np.ndarray:
    """max |lambda(G)| over all eigenvalues (complex included), by batched ``numpy.linalg.eigvals``."""
    rho = np.max(np.abs(np.linalg.eigvals(matrices(integrator, tau, zeta))), axis=-1)
    return rho[()] if rho.ndim == 0 else rho


def matrix_mp(integrator: str, tau, zeta):
    """The amplification matrix as an ``mpmath.matrix`` at the current working precision."""
    import mpmath as mp

    integ = lookup(integrator)
    d = len(integ.state)
    force = LinearForce(mp.mpf(1), 2 * mp.mpf(zeta))
    G = mp.matrix(d, d)
    for j in range(d):
        column = integ.step(tuple(mp.mpf(1) if i == j else mp.mpf(0) for i in range(d)), mp.mpf(tau), force)
        for i in range(d):
            G[i, j] = column[i]
    return G


def spectral_radius_mp(integrator: str, tau, zeta, dps: int | None = None):
    """max |lambda(G)| by ``mpmath.eig`` (at ``dps`` digits, or the current working precision)."""
    import mpmath as mp

    with mp.workdps(dps or mp.mp.dps):
        eigenvalues = mp.eig(matrix_mp(integrator, tau, zeta), left=False, right=False)
        return max(abs(v) for v in eigenvalues)
