"""Rotations and direction samples for the Appendix A searches (NumPy only).

Orientation convention (dtcrit's one convention for quaternions, as in
``dtcrit.bodies.contact.coefficient_matrix``): body to world.  ``Q`` is the body-to-world matrix
(columns are the body axes in world components), so a body-frame vector ``v`` is ``Q v`` in the
world, and a quaternion ``q = (qw, qx, qy, qz)`` stands for ``Q = R(q)``, the matrix of Eq. (7).
Peng et al. 2020 write the inverse, ``R = Q^T`` (world to body, Eq. (5)).  Appendix A's quaternion
(``q_y = -sin(pi/8)``, ``q_w = cos(pi/8)``, "45 degrees around the minus y axis") is read this way, as
the usual active rotation of the body, as in the converter the paper cites (its ref. 23).
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.numerics.rotations import body_to_world_matrix

__all__ = [
    "rotation_about",
    "rotvec_matrix",
    "rotvec_matrices",
    "matrix_quaternion",
    "quaternion_matrix",
    "align_x_to",
    "fibonacci_sphere",
    "super_fibonacci_rotations",
    "unit_from_angles",
    "angles_from_unit",
]


def rotation_about(axis, angle: float) -> np.ndarray:
    """Active rotation by ``angle`` [rad] about the unit vector ``axis`` (Rodrigues' formula).

    Parameters
    ----------
    axis : array_like
        Rotation axis (normalised here).
    angle : float
        Angle [rad].

    Returns
    -------
    numpy.ndarray
        The 3x3 rotation matrix.
    """
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)


def rotvec_matrix(v) -> np.ndarray:
    """Rotation matrix of the rotation vector ``v`` (axis times angle).

    Parameters
    ----------
    v : array_like
        Rotation vector, axis times angle [rad].

    Returns
    -------
    numpy.ndarray
        The 3x3 rotation matrix (identity for a zero vector).
    """
    v = np.asarray(v, dtype=float)
    angle = float(np.linalg.norm(v))
    if angle < 1e-300:
        return np.eye(3)
    return rotation_about(v / angle, angle)


def quaternion_matrix(q) -> np.ndarray:
    """Peng et al. 2020, Eq. (7): the body-to-world matrix ``Q`` of the unit orientation quaternion
    ``(qw, qx, qy, qz)`` (``v_world = Q v_body``; ``dtcrit.numerics.rotations.body_to_world_matrix``).

    Parameters
    ----------
    q : array_like
        Unit quaternion ``(qw, qx, qy, qz)``.

    Returns
    -------
    numpy.ndarray
        The 3x3 matrix ``Q``.
    """
    return body_to_world_matrix(q)


def matrix_quaternion(Q) -> tuple[float, float, float, float]:
    """Unit orientation quaternion ``(qw, qx, qy, qz)`` (qw >= 0) of the body-to-world matrix ``Q``
    (Eq. (7) inverted: ``quaternion_matrix(matrix_quaternion(Q)) == Q``).

    Parameters
    ----------
    Q : array_like
        A 3x3 rotation matrix.

    Returns
    -------
    tuple of float
        ``(qw, qx, qy, qz)`` with ``qw >= 0``.
    """
    Q = np.asarray(Q, dtype=float)
    t = np.trace(Q)
    if t > 0:
        s = math.sqrt(1.0 + t) * 2
        q = (0.25 * s, (Q[2, 1] - Q[1, 2]) / s, (Q[0, 2] - Q[2, 0]) / s, (Q[1, 0] - Q[0, 1]) / s)
    else:
        i = int(np.argmax(np.diag(Q)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = math.sqrt(max(1.0 + Q[i, i] - Q[j, j] - Q[k, k], 0.0)) * 2
        vec = [0.0, 0.0, 0.0]
        vec[i] = 0.25 * s
        vec[j] = (Q[j, i] + Q[i, j]) / s
        vec[k] = (Q[k, i] + Q[i, k]) / s
        w = (Q[k, j] - Q[j, k]) / s
        q = (w, *vec)
    q = np.array(q) / np.linalg.norm(q)
    if q[0] < 0:
        q = -q
    w, x, y, z = (float(v) for v in q)
    return w, x, y, z


def align_x_to(u) -> np.ndarray:
    """The smallest rotation taking the x axis onto the unit vector ``u`` (``u != -x``).

    Parameters
    ----------
    u : array_like
        Target unit vector.

    Returns
    -------
    numpy.ndarray
        The 3x3 rotation matrix.
    """
    u = np.asarray(u, dtype=float)
    u = u / np.linalg.norm(u)
    x = np.array([1.0, 0.0, 0.0])
    axis = np.cross(x, u)
    s = float(np.linalg.norm(axis))
    if s < 1e-15:
        if u[0] > 0:
            return np.eye(3)
        raise ValueError("align_x_to: u = -x has no unique smallest rotation")
    return rotation_about(axis / s, math.atan2(s, float(u[0])))


def unit_from_angles(theta, phi) -> np.ndarray:
    """Unit vectors from polar angle ``theta`` (from +z) and azimuth ``phi`` (from +x); shape (..., 3).

    Parameters
    ----------
    theta : array_like
        Polar angle from +z [rad].
    phi : array_like
        Azimuth from +x [rad].

    Returns
    -------
    numpy.ndarray
        Unit vectors, shape (..., 3).
    """
    theta, phi = np.broadcast_arrays(np.asarray(theta, float), np.asarray(phi, float))
    st = np.sin(theta)
    return np.stack([st * np.cos(phi), st * np.sin(phi), np.cos(theta)], axis=-1)


def angles_from_unit(n) -> tuple[float, float]:
    """Polar angle (from +z) and azimuth (from +x) of a unit vector: the inverse of ``unit_from_angles``.

    Parameters
    ----------
    n : array_like
        Unit vector (3,).

    Returns
    -------
    tuple of float
        ``(theta, phi)`` [rad].
    """
    n = np.asarray(n, dtype=float)
    return math.acos(max(-1.0, min(1.0, float(n[2])))), math.atan2(float(n[1]), float(n[0]))


def fibonacci_sphere(n: int) -> np.ndarray:
    """``n`` nearly uniform unit vectors (golden-angle spiral), deterministic; shape (n, 3).

    Parameters
    ----------
    n : int
        Number of vectors.

    Returns
    -------
    numpy.ndarray
        Unit vectors, shape (n, 3).
    """
    i = np.arange(int(n), dtype=float)
    z = 1.0 - (2.0 * i + 1.0) / n
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = i * math.pi * (3.0 - math.sqrt(5.0))
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def super_fibonacci_rotations(n: int) -> np.ndarray:
    """``n`` nearly uniform rotations of SO(3), deterministic; shape (n, 3, 3).

    Unit quaternions on a double spiral of S^3 whose two angular rates are sqrt(2) and the real
    root psi of psi^4 = psi + 4 (Alexa 2022, "Super-Fibonacci spirals"): the radii sqrt(t) and
    sqrt(1 - t) make the points equal-area in the Hopf coordinates.

    Parameters
    ----------
    n : int
        Number of rotations.

    Returns
    -------
    numpy.ndarray
        Rotation matrices, shape (n, 3, 3).
    """
    psi = max(r.real for r in np.roots([1.0, 0.0, 0.0, -1.0, -4.0]) if abs(r.imag) < 1e-12)
    s = np.arange(int(n), dtype=float) + 0.5
    t = s / n
    d, e = np.sqrt(t), np.sqrt(1.0 - t)
    alpha = 2.0 * math.pi * s / math.sqrt(2.0)
    beta = 2.0 * math.pi * s / psi
    qx, qy, qz, qw = d * np.sin(alpha), d * np.cos(alpha), e * np.sin(beta), e * np.cos(beta)
    Q = np.empty((s.size, 3, 3))
    Q[:, 0, 0] = qw * qw + qx * qx - qy * qy - qz * qz
    Q[:, 0, 1] = 2 * (qx * qy - qw * qz)
    Q[:, 0, 2] = 2 * (qx * qz + qw * qy)
    Q[:, 1, 0] = 2 * (qx * qy + qw * qz)
    Q[:, 1, 1] = qw * qw - qx * qx + qy * qy - qz * qz
    Q[:, 1, 2] = 2 * (qy * qz - qw * qx)
    Q[:, 2, 0] = 2 * (qx * qz - qw * qy)
    Q[:, 2, 1] = 2 * (qy * qz + qw * qx)
    Q[:, 2, 2] = qw * qw - qx * qx - qy * qy + qz * qz
    return Q


def rotvec_matrices(v) -> np.ndarray:
    """Rotation matrices of the rows of ``v`` (N, 3) (rotation vectors); shape (N, 3, 3).

    Parameters
    ----------
    v : array_like
        Rotation vectors, shape (N, 3) [rad].

    Returns
    -------
    numpy.ndarray
        Rotation matrices, shape (N, 3, 3).
    """
    v = np.atleast_2d(np.asarray(v, dtype=float))
    angle = np.linalg.norm(v, axis=1)
    safe = np.where(angle > 1e-300, angle, 1.0)
    k = v / safe[:, None]
    K = np.zeros((v.shape[0], 3, 3))
    K[:, 0, 1], K[:, 0, 2] = -k[:, 2], k[:, 1]
    K[:, 1, 0], K[:, 1, 2] = k[:, 2], -k[:, 0]
    K[:, 2, 0], K[:, 2, 1] = -k[:, 1], k[:, 0]
    s = np.sin(angle)[:, None, None]
    c = (1.0 - np.cos(angle))[:, None, None]
    return np.eye(3) + s * K + c * (K @ K)
