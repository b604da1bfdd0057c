"""Amplification matrices evaluated numerically from the update rules (runtime; no SymPy).

The update rule of ``dtcrit.integrators.schemes`` is applied to each unit state vector in scaled units
(omega = 1: ``K = 1``, ``C = 2 zeta``, step ``tau = omega dt``), so column ``j`` of ``G`` is the
image of the ``j``-th unit vector.  The spectral radius depends on ``(tau, zeta)`` only.
"""
from __future__ import annotations

import numpy as np

from dtcrit.integrators.schemes import LinearForce, lookup


def matrices(integrator: str, tau, zeta) -> np.ndarray:
    """Batched amplification matrices ``G(tau, zeta)`` of one scheme, built from its update rule.

    Column ``j`` of ``G`` is one step of the rule from the ``j``-th unit state, in scaled units
    (``K = 1``, ``C = 2 zeta``; Peng et al. 2020, Eq. (30)).

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or registered user scheme (``dtcrit.integrators.schemes.lookup``).
    tau : float or array_like
        Dimensionless step ``omega dt``.
    zeta : float or array_like
        Damping ratio ``c A / (2 omega)``.

    Returns
    -------
    numpy.ndarray
        Shape ``broadcast(tau, zeta).shape + (d, d)``, ``d`` the number of state variables.
    """
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
    """Spectral radius ``max |lambda(G)|`` (complex eigenvalues included), by batched ``numpy.linalg.eigvals``.

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or registered user scheme (``dtcrit.integrators.schemes.lookup``).
    tau : float or array_like
        Dimensionless step ``omega dt``.
    zeta : float or array_like
        Damping ratio ``c A / (2 omega)``.

    Returns
    -------
    float or numpy.ndarray
        The spectral radius, a scalar for scalar inputs; the scheme is stable where it is <= 1.

    Examples
    --------
    >>> from dtcrit import spectral_radius
    >>> rho = spectral_radius("velocity-verlet", [1.0, 2.5], 0.0)   # omega dt below and above 2
    >>> bool(abs(rho[0] - 1.0) < 1e-12), bool(rho[1] > 1.0)
    (True, True)
    """
    rho = np.max(np.abs(np.linalg.eigvals(matrices(integrator, tau, zeta))), axis=-1)
    return rho[()] if rho.ndim == 0 else rho


def matrix_mp(integrator: str, tau, zeta):
    """The amplification matrix as an ``mpmath.matrix`` at the current working precision.

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or registered user scheme (``dtcrit.integrators.schemes.lookup``).
    tau : float or array_like
        Dimensionless step ``omega dt``.
    zeta : float or array_like
        Damping ratio ``c A / (2 omega)``.

    Returns
    -------
    mpmath.matrix
        ``G`` (d x d), column ``j`` the rule applied to the ``j``-th unit state.
    """
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
    """Spectral radius ``max |lambda(G)|`` by ``mpmath.eig``.

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or registered user scheme (``dtcrit.integrators.schemes.lookup``).
    tau : float or array_like
        Dimensionless step ``omega dt``.
    zeta : float or array_like
        Damping ratio ``c A / (2 omega)``.
    dps : int, optional
        Decimal digits to work at; the current working precision when None.

    Returns
    -------
    mpmath.mpf
        The spectral radius.
    """
    import mpmath as mp

    with mp.workdps(dps or mp.mp.dps):
        eigenvalues = mp.eig(matrix_mp(integrator, tau, zeta), left=False, right=False)
        return max(abs(v) for v in eigenvalues)
