"""An independent leapfrog threshold for two rigid bodies in one YADE contact.

Built from YADE's own kinematics (YADE 2023.02a, pkg/dem/), not from dtcrit: the contact point
``x_1 + a_1 n`` with ``a_i = R_i - delta/2`` (Ig2_Sphere_Sphere_ScGeom.cpp), the shear force applied there
(torque arms ``a_i``, ElasticContactLaw.cpp), the slip rate of ``ScGeom::getIncidentVel``
(``alpha (v_2 - v_1) + R_2 n x w_2 + R_1 n x w_1`` with ``avoidGranularRatcheting``, else the velocity of the
contact point, ``alpha = 1`` and arms ``a_i``), a normal force turning with the centre line, rolling and
twisting springs on the relative rotation, dashpots on the same rates.  The generalized stiffness is
not symmetric; the threshold is found on the leapfrog's amplification matrix (velocities at half
steps, the dashpots on the lagged velocity), by bisection: the step is unstable when an eigenvalue
leaves the unit circle on the left (through -1, the numerical instability).  Growth through +1 is the
physical instability of a negative stiffness (a pre-loaded sphere rolling off a fixed one), present at
every step and not the step's limit.
"""
from __future__ import annotations

import numpy as np


def _cross(n: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])


def pair_matrices(x1, x2, r1, r2, *, kn, ks, kr=0.0, ktw=0.0, cn=0.0, cs=0.0, fn=0.0, ratcheting=True):
    """The 12 x 12 stiffness and damping of the contact on ``(u_1, theta_1, u_2, theta_2)`` (module docstring).

    Returns
    -------
    tuple of numpy.ndarray
        ``(K, C)`` with generalized forces ``-K q - C q'``.
    """
    sep = np.asarray(x2, float) - np.asarray(x1, float)
    r = float(np.linalg.norm(sep))
    n = sep / r
    delta = r1 + r2 - r
    a1, a2 = r1 - delta / 2, r2 - delta / 2
    alpha, b1, b2 = ((r1 + r2) / r, r1, r2) if ratcheting else (1.0, a1, a2)
    eye, nx, proj = np.eye(3), _cross(n), np.eye(3) - np.outer(n, n)
    slip = proj @ np.hstack([-alpha * eye, b1 * nx, alpha * eye, b2 * nx])        # 3 x 12
    spread = np.vstack([-eye, -a1 * nx, eye, -a2 * nx])                            # 12 x 3: force on 2 -> forces
    normal = np.concatenate([-n, np.zeros(3), n, np.zeros(3)])
    turn = np.hstack([-eye, np.zeros((3, 3)), eye, np.zeros((3, 3))])
    spin = np.hstack([np.zeros((3, 3)), -eye, np.zeros((3, 3)), eye])
    k = kn * np.outer(normal, normal) + ks * spread @ slip - (fn / r) * turn.T @ proj @ turn
    k = k + spin.T @ (kr * proj + ktw * np.outer(n, n)) @ spin
    c = cn * np.outer(normal, normal) + cs * spread @ slip
    return k, c


def leapfrog_threshold(k: np.ndarray, c: np.ndarray, masses, inertias, free=(True, True), tol: float = 1e-9) -> float:
    """The largest stable leapfrog step of ``M q'' = -K q - C q'`` over the free bodies' coordinates.

    Parameters
    ----------
    k, c : numpy.ndarray
        The 12 x 12 stiffness and damping (:func:`pair_matrices`).
    masses : sequence of float
        The two masses [kg].
    inertias : sequence of numpy.ndarray
        The two 3 x 3 inertia tensors in the global frame [kg m^2].
    free : tuple of bool
        Which bodies move (a fixed body's coordinates are dropped).
    tol : float
        An eigenvalue with negative real part and modulus above ``1 + tol`` counts as unstable.

    Returns
    -------
    float
        The threshold [s], to ~1e-10 relative.
    """
    keep = np.concatenate([np.arange(6 * b, 6 * b + 6) for b in range(2) if free[b]])
    blocks = [np.diag([m] * 3) if q == 0 else inertias[b] for b, m in enumerate(masses) for q in (0, 1)]
    m_full = np.zeros((12, 12))
    for q, block in enumerate(blocks):
        m_full[3 * q:3 * q + 3, 3 * q:3 * q + 3] = block
    minv = np.linalg.inv(m_full[np.ix_(keep, keep)])
    a, b = minv @ k[np.ix_(keep, keep)], minv @ c[np.ix_(keep, keep)]
    eye = np.eye(len(keep))

    def unstable(h: float) -> bool:
        damp = eye - h * b
        amp = np.block([[eye - h * h * a, h * damp], [-h * a, damp]])
        z = np.linalg.eigvals(amp)
        return bool(np.any((abs(z) > 1.0 + tol) & (z.real < 0)))

    lo, hi = 0.0, 1.0
    while not unstable(hi):
        hi *= 2.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if unstable(mid) else (mid, hi)
        if hi - lo < 1e-13 * hi:
            break
    return hi
