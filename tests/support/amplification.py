"""Test-side direct route: the amplification matrix of an integrator built *numerically*.

The integrator's update rule (dtcrit.integrators.schemes) is applied to each unit state vector with plain
numbers (floats or mpmath), in scaled units omega = 1 (K = 1, C = 2 zeta, step tau).  No SymPy,
no characteristic polynomial, no closed form: the spectral radius of this matrix is the direct
check of every bound.
"""
import mpmath as mp
import numpy as np

from dtcrit.integrators.schemes import INTEGRATORS, LinearForce


def matrix_float(name, tau, zeta):
    integ = INTEGRATORS[name]
    n = len(integ.state)
    f = LinearForce(1.0, 2.0 * zeta)
    cols = []
    for j in range(n):
        e = [0.0] * n
        e[j] = 1.0
        cols.append([float(v) for v in integ.step(tuple(e), tau, f)])
    return np.array(cols).T


def matrix_mp(name, tau, zeta):
    integ = INTEGRATORS[name]
    n = len(integ.state)
    f = LinearForce(mp.mpf(1), 2 * mp.mpf(zeta))
    G = mp.matrix(n, n)
    for j in range(n):
        e = [mp.mpf(0)] * n
        e[j] = mp.mpf(1)
        col = integ.step(tuple(e), mp.mpf(tau), f)
        for i in range(n):
            G[i, j] = col[i]
    return G


def spectral_radius_mp(name, tau, zeta, dps=50):
    with mp.workdps(dps):
        ev, _ = mp.eig(matrix_mp(name, tau, zeta))
        return max(abs(v) for v in ev)


def spectral_radius_np(name, tau, zeta):
    return float(np.max(np.abs(np.linalg.eigvals(matrix_float(name, tau, zeta)))))
