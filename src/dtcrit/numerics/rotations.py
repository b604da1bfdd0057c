"""Rotation matrices of unit quaternions, in dtcrit's one convention (NumPy only).

Convention ``BODY_TO_WORLD``: a quaternion ``q = (qw, qx, qy, qz)`` is a particle's orientation and
stands for the matrix ``R(q)`` printed as Peng et al. 2020, Eq. (7), read body to world:
``v_world = R(q) v_body`` (the columns of ``R(q)`` are the body axes in world components).  The
paper's Eq. (5) matrix (world to body, ``M_L = R M_G``) is ``R(q)^T``, the matrix of the conjugate
quaternion.  This is the convention of ``dtcrit.symbolic.quaternions`` (which proves the relations
symbolically) and of the generated ``dtcrit._generated.contact.rotation_matrix``.
"""
from __future__ import annotations

import numpy as np

BODY_TO_WORLD = "body-to-world"
"""The name of the one convention: ``v_world = R(q) v_body`` with ``R(q)`` the matrix of Eq. (7)."""


def _matrix(w, x, y, z, diagonal) -> np.ndarray:
    """Eq. (7) from its off-diagonal terms and the given ``diagonal`` (the two forms differ only there)."""
    rows = (
        (diagonal[0], 2 * (x * y - w * z), 2 * (x * z + w * y)),
        (2 * (x * y + w * z), diagonal[1], 2 * (y * z - w * x)),
        (2 * (x * z - w * y), 2 * (y * z + w * x), diagonal[2]),
    )
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2)


def body_to_world_matrix(q) -> np.ndarray:
    """Peng et al. 2020, Eq. (7): the body-to-world matrix of unit quaternions ``(qw, qx, qy, qz)``.

    Written in the homogeneous form ``R00 = qw^2 + qx^2 - qy^2 - qz^2``, ``R01 = 2 (qx qy - qw qz)``, ...
    (the form of ``dtcrit.symbolic.quaternions.quaternion_rotation_matrix``); the quaternion is used
    as given (normalise it first: a non-unit ``q`` scales the matrix by ``|q|^2``).

    Parameters
    ----------
    q : array_like
        Quaternions, shape ``(..., 4)``, scalar part first.

    Returns
    -------
    numpy.ndarray
        Shape ``(..., 3, 3)``: ``R(q)`` with ``v_world = R(q) v_body``.
    """
    qa = np.asarray(q, dtype=float)
    if qa.shape[-1:] != (4,):
        raise ValueError(f"a quaternion has 4 components (got shape {qa.shape})")
    w, x, y, z = np.moveaxis(qa, -1, 0)
    return _matrix(w, x, y, z, (w * w + x * x - y * y - z * z, w * w - x * x + y * y - z * z,
                                w * w - x * x - y * y + z * z))


def unit_body_to_world_matrix(q) -> np.ndarray:
    """The body-to-world matrix of :func:`body_to_world_matrix` in the form valid for unit quaternions.

    ``R00 = 1 - 2 (qy^2 + qz^2)``, ``R01 = 2 (qx qy - qw qz)``, ... (Eq. (7) with ``qw^2 + qx^2 + qy^2 +
    qz^2 = 1``): the form the readers of engine files use on quaternions they have normalised, exactly
    orthogonal up to rounding even when ``q`` is only near unit length.

    Parameters
    ----------
    q : array_like
        Unit quaternions, shape ``(..., 4)``, scalar part first.

    Returns
    -------
    numpy.ndarray
        Shape ``(..., 3, 3)``: ``R(q)`` with ``v_world = R(q) v_body``.
    """
    qa = np.asarray(q, dtype=float)
    if qa.shape[-1:] != (4,):
        raise ValueError(f"a quaternion has 4 components (got shape {qa.shape})")
    w, x, y, z = np.moveaxis(qa, -1, 0)
    return _matrix(w, x, y, z, (1 - 2 * (y * y + z * z), 1 - 2 * (x * x + z * z), 1 - 2 * (x * x + y * y)))


def world_to_body_matrix(q) -> np.ndarray:
    """Peng et al. 2020, Eq. (5): the world-to-body matrix ``R(q)^T`` (``M_L = R M_G``).

    Parameters
    ----------
    q : array_like
        Quaternions, shape ``(..., 4)``, scalar part first.

    Returns
    -------
    numpy.ndarray
        Shape ``(..., 3, 3)``: the transpose of :func:`body_to_world_matrix`.
    """
    return np.swapaxes(body_to_world_matrix(q), -1, -2)
