"""An independent assembly of the contact element with rolling and twisting springs.

The 12-DOF system of two spheres (6-DOF for a sphere at a wall) is assembled from the contact-point
kinematics and the relative rotation, along an oblique normal; nothing here uses dtcrit's modes,
kernels or coupled-block solver.  Shared by the rolling-mode and bonded-scene tests.
"""
from __future__ import annotations

import math

import numpy as np

from support.multidof import skew

NORMAL = np.array([0.3, -0.5, 0.8]) / math.sqrt(0.98)


def element(n, kn, ks, kr, ktw):
    """6x6 stiffness on (u, phi): kn n n^T + ks (1 - n n^T) on u, kr (1 - n n^T) + ktw n n^T on phi."""
    P = np.outer(n, n)
    out = np.zeros((6, 6))
    out[:3, :3] = kn * P + ks * (np.eye(3) - P)
    out[3:, 3:] = ktw * P + kr * (np.eye(3) - P)
    return out


def pair_system(m1, I1, R1, m2, I2, R2, k, c, n=NORMAL):
    """M, K, C of two spheres: u = x2 + th2 x (-R2 n) - x1 - th1 x (R1 n), phi = th2 - th1."""
    e = np.eye(3)
    top = np.hstack([-e, skew(R1 * n), e, -skew(-R2 * n)])
    bottom = np.hstack([0 * e, -e, 0 * e, e])
    B = np.vstack([top, bottom])
    M = np.diag([m1] * 3 + [I1] * 3 + [m2] * 3 + [I2] * 3)
    return M, B.T @ element(n, *k) @ B, B.T @ element(n, *c) @ B


def wall_system(m, inertia, R, k, c, n=NORMAL):
    """M, K, C of a sphere at a wall: u = x + th x (-R n) at the contact point, phi = th."""
    e = np.eye(3)
    B = np.vstack([np.hstack([e, skew(R * n)]), np.hstack([0 * e, e])])
    M = np.diag([m] * 3 + [inertia] * 3)
    return M, B.T @ element(n, *k) @ B, B.T @ element(n, *c) @ B


def omega2_max(M, K):
    """Largest eigenvalue of M^-1 K (M diagonal), from the symmetric M^-1/2 K M^-1/2."""
    d = 1.0 / np.sqrt(np.diag(M))
    return float(np.linalg.eigvalsh(d[:, None] * K * d[None, :])[-1])


def sphere(r, rho):
    """Mass and moment of inertia (2/5 m r^2) of a solid sphere of radius r and density rho."""
    m = rho * 4.0 / 3.0 * math.pi * r**3
    return m, 0.4 * m * r * r
