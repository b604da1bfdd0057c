"""Batched rotations and directions (leading axis of length N): cross-product matrices, the rotation
taking one unit vector to another, Rodrigues' axis-angle matrices, uniformly random rotations (from
Peng et al. 2020, Eq. (7) quaternion matrices) and uniformly random unit vectors.

Orientations are body to global (``v_global = Q v_body``), as in :mod:`dtcrit.bodies.contact_search`.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit._generated import contact as _k

def skew(v: np.ndarray) -> np.ndarray:
    """``[v]x`` for each row of ``v`` (shape (..., 3) -> (..., 3, 3)).

    Parameters
    ----------
    v : numpy.ndarray
        Vectors, shape (..., 3).

    Returns
    -------
    numpy.ndarray
        Cross-product matrices, ``[v]x w = v x w``.
    """
    v = np.asarray(v, dtype=float)
    z = np.zeros(v.shape[:-1])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([np.stack([z, -w, y], -1), np.stack([w, z, -x], -1), np.stack([-y, x, z], -1)], -2)


def rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Proper rotations (body -> global style, ``Q a = b``) taking unit rows ``a`` to unit rows ``b``.

    Parameters
    ----------
    a, b : numpy.ndarray
        Unit vectors, shape (N, 3) or (3,).

    Returns
    -------
    numpy.ndarray
        Rotation matrices, shape (N, 3, 3).
    """
    a, b = np.atleast_2d(a).astype(float), np.atleast_2d(b).astype(float)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    b = b / np.linalg.norm(b, axis=1, keepdims=True)
    axis = np.cross(a, b)
    s = np.linalg.norm(axis, axis=1)
    c = np.einsum("ij,ij->i", a, b)
    # antiparallel: half-turn about any axis normal to a
    helper = np.eye(3)[np.argmin(np.abs(a), axis=1)]
    perp = np.cross(a, helper)
    perp /= np.linalg.norm(perp, axis=1, keepdims=True)
    use_perp = s < 1e-12
    k = np.where(use_perp[:, None], perp, axis / np.where(s > 0, s, 1.0)[:, None])
    angle = np.where(use_perp, np.where(c > 0, 0.0, math.pi), np.arctan2(s, c))
    return axis_angle(k, angle)


def axis_angle(axis: np.ndarray, angle) -> np.ndarray:
    """Rodrigues: rotation matrices (active, ``v -> Q v``) about unit ``axis`` rows by ``angle``.

    Parameters
    ----------
    axis : numpy.ndarray
        Unit axes, shape (N, 3).
    angle : array_like
        Angles [rad], shape (N,).

    Returns
    -------
    numpy.ndarray
        Rotation matrices, shape (N, 3, 3).
    """
    k = np.atleast_2d(axis).astype(float)
    k = k / np.linalg.norm(k, axis=1, keepdims=True)
    th = np.broadcast_to(np.asarray(angle, float), k.shape[:1])
    K = skew(k)
    s, c = np.sin(th)[:, None, None], np.cos(th)[:, None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def random_rotations(rng: np.random.Generator, n: int) -> np.ndarray:
    """Uniformly distributed body-to-world rotations: normalised Gaussian quaternions, the transposes of their
    Eq 7 matrices, i.e. the body-to-world matrices of the conjugate quaternions (uniform on SO(3) either way).

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of randomness.
    n : int
        Number of rotations.

    Returns
    -------
    numpy.ndarray
        Rotation matrices, shape (n, 3, 3).
    """
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    R = np.stack([np.asarray(e, float) for e in _k.rotation_matrix(q[:, 0], q[:, 1], q[:, 2], q[:, 3])], -1)
    return R.reshape(n, 3, 3).transpose(0, 2, 1)


def unit_vectors(rng: np.random.Generator, n: int) -> np.ndarray:
    """Uniformly distributed unit vectors (normalised Gaussian samples).

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of randomness.
    n : int
        Number of vectors.

    Returns
    -------
    numpy.ndarray
        Unit vectors, shape (n, 3).
    """
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)
