"""Test-side direct route for systems of many degrees of freedom: ``M xddot = -K x - C xdot``.

The integrator's own update rule (dtcrit.integrators.schemes) is applied to every unit state
vector with a *matrix* force, so the columns of the result are the amplification matrix of the
whole system; its spectral radius (all eigenvalues, numpy) is compared with the steps dtcrit
prints.  Nothing here uses dtcrit's closed forms, modes or bounds.
"""
import numpy as np

from dtcrit.integrators.schemes import INTEGRATORS


class _Operator:
    """A matrix standing in for a scalar in the update rules (``1 - h dv/2``, ``v / (...)``)."""

    __array_ufunc__ = None  # numpy defers ``vector / operator`` to __rtruediv__

    def __init__(self, a):
        self.a = np.asarray(a, dtype=float)

    def __mul__(self, s):
        return _Operator(self.a * s)

    __rmul__ = __mul__

    def __truediv__(self, s):
        return _Operator(self.a / s)

    def __rsub__(self, s):  # s - A with s a scalar
        return _Operator(s * np.eye(self.a.shape[0]) - self.a)

    def __rtruediv__(self, v):  # v / A: solve A x = v
        return np.linalg.solve(self.a, v)


class MatrixForce:
    """``f(x, v) = -M^-1 (K x + C v)`` for state vectors."""

    def __init__(self, M, K, C):
        minv = np.linalg.inv(np.asarray(M, dtype=float))
        self.K = minv @ np.asarray(K, dtype=float)
        self.C = minv @ np.asarray(C, dtype=float)
        self.dv = _Operator(-self.C)

    def __call__(self, x, v):
        return -(self.K @ x) - (self.C @ v)


def amplification(name, dt, M, K, C):
    integ = INTEGRATORS[name]
    n = np.asarray(M).shape[0]
    d = len(integ.state)
    f = MatrixForce(M, K, C)
    G = np.zeros((d * n, d * n))
    for j in range(d * n):
        e = np.zeros(d * n)
        e[j] = 1.0
        out = integ.step(tuple(e[k * n:(k + 1) * n] for k in range(d)), dt, f)
        G[:, j] = np.concatenate([np.asarray(o, dtype=float) for o in out])
    return G


def spectral_radius(name, dt, M, K, C):
    return float(np.max(np.abs(np.linalg.eigvals(amplification(name, dt, M, K, C)))))


def skew(r):
    x, y, z = r
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def contact_matrices(n, k_n, k_s):
    """3x3 ``k_n n n^T + k_s (1 - n n^T)``."""
    n = np.asarray(n, dtype=float) / np.linalg.norm(n)
    return k_n * np.outer(n, n) + k_s * (np.eye(3) - np.outer(n, n))


def two_spheres(m1, I1, R1, m2, I2, R2, kn, ks, cn, cs, normal=(0.3, -0.5, 0.8)):
    """12-DOF M, K, C of two spheres in contact along ``normal`` (from 1 to 2), torque arm = radius.

    Relative displacement of the contact point: (u2 + th2 x r2) - (u1 + th1 x r1), r1 = R1 n, r2 = -R2 n,
    th x r = -[r]x th.
    """
    n = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    B = np.hstack([-np.eye(3), skew(R1 * n), np.eye(3), -skew(-R2 * n)])
    K = B.T @ contact_matrices(n, kn, ks) @ B
    C = B.T @ contact_matrices(n, cn, cs) @ B
    M = np.diag([m1] * 3 + [I1] * 3 + [m2] * 3 + [I2] * 3)
    return M, K, C


def sphere_on_wall(m, I, R, kn, ks, cn, cs, normal=(0.0, 0.6, 0.8)):
    """6-DOF M, K, C of a sphere against a fixed wall with outward normal ``normal`` (arm = radius)."""
    n = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    B = np.hstack([np.eye(3), -skew(-R * n)])
    return np.diag([m] * 3 + [I] * 3), B.T @ contact_matrices(n, kn, ks) @ B, B.T @ contact_matrices(n, cn, cs) @ B
