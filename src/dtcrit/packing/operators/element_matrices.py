"""The contact element's matrices: ``B``, ``T`` and the 6 x 6 blocks, from the functions of ``contact_element``.

The element ``sum B^T T B`` of one contact (``dtcrit.packing.operators.contact_element``, module
docstring) as matrices, each column the element's motion, frame law or action on a unit vector
(exact: a unit vector only selects entries):

* ``element_side_into``, ``element_blocks_into``, ``slip_jacobians_into`` -- one contact, compiled into
  the loops of ``particle_pass`` (the bounds' pass) and ``dtcrit.packing.bounds.estimate_kernels``;
* ``frame_tensor``, ``slip_jacobians``, ``rotation_jacobians``, ``element_blocks`` -- vectorised over
  contacts, ``B^T T B`` by ``numpy.matmul`` (the assembled matrices, the SLEPc back-end, the NumPy
  block pass).
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np

from dtcrit.packing.operators.contact_element import (
    ZERO3, _jitable, body_forces, centre_motion, contact_slip, frame_law, relative_rotation, to_global,
)

__all__ = ["element_side_into", "element_blocks_into", "slip_jacobians_into", "components", "frame_tensor", "slip_jacobians",
           "rotation_jacobians", "element_blocks"]


@_jitable
def _unit(k, first):
    """Component ``first .. first + 2`` of the ``k``-th unit vector of R^6, as a 3-tuple."""
    return (1.0 if k == first else 0.0, 1.0 if k == first + 1 else 0.0, 1.0 if k == first + 2 else 0.0)


@_jitable
def element_side_into(n, arm_i, arm_j, rot_i, rot_j, oriented, kn, ks, ktw, kr, g, springs, rolling, preload,
                      side, own, ij):
    """One body's half of the element's blocks: ``side`` 0 writes ``ii`` into ``own`` and ``ij``
    (the action on the unit vectors of body ``i``: column ``k`` of ``ii`` and row ``k`` of ``ij``),
    ``side`` 1 writes ``jj`` into ``own`` and ``ij`` (on the unit vectors of ``j``: column ``k`` of
    ``ij`` and of ``jj``).  Either side gives the whole coupling block ``ij = K_ij`` (rows of ``i``'s
    DOFs), the element being symmetric; the particle pass (``particle_pass``) computes a contact's
    blocks once from each side, the side of the particle it sums.

    Parameters
    ----------
    n, arm_i, arm_j, rot_i, rot_j, oriented : see ``body_forces``
        Frame, arms [m] and body rotations of one contact.
    kn, ks, ktw, kr, g : float
        Coefficients of the three terms (``element_forces``).
    springs, rolling, preload : bool
        Which terms the contact carries.
    side : int
        0 (body ``i``) or 1 (body ``j``).
    own, ij : numpy.ndarray
        Output blocks, each (6, 6), overwritten: the side's diagonal block and ``K_ij``.
    """
    for k in range(6):
        u = _unit(k, 0)
        t = _unit(k, 3)
        if side == 0:
            f, m_i, m_j = body_forces(n, arm_i, arm_j, rot_i, rot_j, oriented, u, t, ZERO3, ZERO3,
                                      kn, ks, ktw, kr, g, springs, rolling, preload)
            for a in range(3):
                own[a, k] = -f[a]
                own[3 + a, k] = m_i[a]
                ij[k, a] = f[a]
                ij[k, 3 + a] = m_j[a]
        else:
            f, m_i, m_j = body_forces(n, arm_i, arm_j, rot_i, rot_j, oriented, ZERO3, ZERO3, u, t,
                                      kn, ks, ktw, kr, g, springs, rolling, preload)
            for a in range(3):
                ij[a, k] = -f[a]
                ij[3 + a, k] = m_i[a]
                own[a, k] = f[a]
                own[3 + a, k] = m_j[a]


@_jitable
def element_blocks_into(n, arm_i, arm_j, rot_i, rot_j, oriented, kn, ks, ktw, kr, g, springs, rolling, preload,
                        ii, jj, ij):
    """The element's 6 x 6 blocks ``ii``, ``jj``, ``ij`` written into the given arrays: column ``k``
    is the action (``body_forces``) on the ``k``-th unit vector of body ``i`` (``ii``, ``ij^T``) or
    ``j`` (``ij``, ``jj``): ``element_side_into`` of both sides, ``ij`` as side 1 gives it.

    Parameters
    ----------
    n, arm_i, arm_j, rot_i, rot_j, oriented : see ``body_forces``
        Frame, arms [m] and body rotations of one contact.
    kn, ks, ktw, kr, g : float
        Coefficients of the three terms (``element_forces``).
    springs, rolling, preload : bool
        Which terms the contact carries.
    ii, jj, ij : numpy.ndarray
        Output blocks, each (6, 6), overwritten.
    """
    element_side_into(n, arm_i, arm_j, rot_i, rot_j, oriented, kn, ks, ktw, kr, g, springs, rolling, preload,
                      0, ii, ij)
    element_side_into(n, arm_i, arm_j, rot_i, rot_j, oriented, kn, ks, ktw, kr, g, springs, rolling, preload,
                      1, jj, ij)


@_jitable
def slip_jacobians_into(arm_i, arm_j, rot_i, rot_j, oriented, b_i, b_j):
    """``B_i``, ``B_j`` (each 3 x 6) of the contact springs written into the given arrays: column
    ``k`` is ``contact_slip`` of the ``k``-th unit vector of the body's DOFs, i.e.
    ``B_i = [-1 | [a_i]_x R_i]``, ``B_j = [1 | -[a_j]_x R_j]``.

    Parameters
    ----------
    arm_i, arm_j : tuple
        Branch vectors from the centres to the contact point [m].
    rot_i, rot_j : tuple
        Rows of the bodies' rotation matrices (``rotation_rows``); read only when ``oriented``.
    oriented : bool
        Whether the bodies' DOFs are about principal axes.
    b_i, b_j : numpy.ndarray
        Output arrays, each (3, 6), overwritten.
    """
    for k in range(6):
        u = _unit(k, 0)
        t_i = to_global(rot_i, _unit(k, 3)) if oriented else _unit(k, 3)
        t_j = to_global(rot_j, _unit(k, 3)) if oriented else _unit(k, 3)
        col_i = contact_slip(centre_motion(u, ZERO3), t_i, ZERO3, arm_i, arm_j)
        col_j = contact_slip(centre_motion(ZERO3, u), ZERO3, t_j, arm_i, arm_j)
        for a in range(3):
            b_i[a, k] = col_i[a]
            b_j[a, k] = col_j[a]


def components(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The component form of a stack of 3-vectors: the tuple of its three columns (views).

    Parameters
    ----------
    vectors : numpy.ndarray
        Shape (nc, 3).

    Returns
    -------
    tuple of numpy.ndarray
        ``(x, y, z)``, each (nc,).
    """
    return (vectors[:, 0], vectors[:, 1], vectors[:, 2])


def frame_tensor(normal: np.ndarray, along: np.ndarray, across: np.ndarray) -> np.ndarray:
    """The frame tensor ``T = along n n^T + across (1 - n n^T)`` of each contact, ``frame_law`` on
    the unit vectors.

    Parameters
    ----------
    normal : numpy.ndarray
        Unit normals, shape (nc, 3).
    along, across : numpy.ndarray
        Coefficients along and across the normal, shape (nc,) (e.g. ``k_n``, ``k_s`` [N/m]).

    Returns
    -------
    numpy.ndarray
        ``T``, shape (nc, 3, 3).
    """
    n = components(normal)
    out = np.empty((normal.shape[0], 3, 3))
    for k in range(3):
        col = frame_law(n, along, across, _unit(k, 0))
        for a in range(3):
            out[:, a, k] = col[a]
    return out


def _motion_matrices(motion: Callable[..., tuple], nc: int, rot_i: np.ndarray | None,
                     rot_j: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """``(B_i, B_j)``, each (nc, 3, 6), of a linear ``motion(u_i, theta_i, u_j, theta_j)``: its values
    on the unit vectors, the rotation columns then turned to body axes (``@ R``) when given.
    """
    out = []
    for side in range(2):
        b = np.empty((nc, 3, 6))
        for k in range(6):
            args: list[Any] = [ZERO3] * 4
            args[2 * side] = _unit(k, 0)
            args[2 * side + 1] = _unit(k, 3)
            col = motion(*args)
            for a in range(3):
                b[:, a, k] = col[a]
        rot = rot_i if side == 0 else rot_j
        if rot is not None:
            b[:, :, 3:] = np.ascontiguousarray(b[:, :, 3:]) @ rot
        out.append(b)
    return out[0], out[1]


def slip_jacobians(arm_i: np.ndarray, arm_j: np.ndarray, rot_i: np.ndarray | None = None,
                   rot_j: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(B_i, B_j)`` of the contact springs, ``B_i = [-1 | [a_i]_x R_i]``, ``B_j = [1 | -[a_j]_x R_j]``
    (``contact_slip`` on the unit vectors), vectorised over contacts.

    Parameters
    ----------
    arm_i, arm_j : numpy.ndarray
        Branch vectors ``x_c - x_i``, ``x_c - x_j``, shape (nc, 3) [m].
    rot_i, rot_j : numpy.ndarray or None
        Rotation matrices of the bodies of each contact, shape (nc, 3, 3); ``None``: global axes.

    Returns
    -------
    tuple of numpy.ndarray
        ``B_i`` and ``B_j``, each (nc, 3, 6).
    """
    ai, aj = components(arm_i), components(arm_j)

    def motion(u_i, t_i, u_j, t_j):
        return contact_slip(centre_motion(u_i, u_j), t_i, t_j, ai, aj)

    return _motion_matrices(motion, arm_i.shape[0], rot_i, rot_j)


def rotation_jacobians(nc: int, rot_i: np.ndarray | None = None,
                       rot_j: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(B_i, B_j) = ([0 | -R_i], [0 | R_j])`` of the rolling and twisting springs
    (``relative_rotation`` on the unit vectors).

    Parameters
    ----------
    nc : int
        Number of contacts.
    rot_i, rot_j : numpy.ndarray or None
        Rotation matrices, shape (nc, 3, 3); ``None``: global axes.

    Returns
    -------
    tuple of numpy.ndarray
        ``B_i`` and ``B_j``, each (nc, 3, 6).
    """
    return _motion_matrices(lambda u_i, t_i, u_j, t_j: relative_rotation(t_i, t_j), nc, rot_i, rot_j)


def _pair_blocks(b_i: np.ndarray, b_j: np.ndarray, tensor: np.ndarray) -> tuple[np.ndarray, ...]:
    """``(B_i^T T B_i, B_j^T T B_j, B_i^T T B_j)`` for stacks of (nc, 3, 6) ``B`` and (nc, 3, 3) ``T``."""
    tb_i, tb_j = tensor @ b_i, tensor @ b_j
    b_it, b_jt = np.swapaxes(b_i, 1, 2), np.swapaxes(b_j, 1, 2)
    return b_it @ tb_i, b_jt @ tb_j, b_it @ tb_j


def element_blocks(normal: np.ndarray, arm_i: np.ndarray, arm_j: np.ndarray, along: np.ndarray,
                   across: np.ndarray, *, rot_i: np.ndarray | None = None, rot_j: np.ndarray | None = None,
                   twist: np.ndarray | None = None, roll: np.ndarray | None = None,
                   preload: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The blocks ``(ii, jj, ij)`` of each contact's element ``sum B^T T B`` (module docstring),
    vectorised over contacts.

    Parameters
    ----------
    normal : numpy.ndarray
        Unit normals, shape (nc, 3).
    arm_i, arm_j : numpy.ndarray
        Branch vectors from the centres to the contact point, shape (nc, 3) [m].
    along, across : numpy.ndarray
        Normal and tangential springs ``k_n``, ``k_s`` [N/m] (dashpots ``c_n``, ``c_s`` [N s/m]), (nc,).
    rot_i, rot_j : numpy.ndarray or None
        Rotation matrices of the bodies, shape (nc, 3, 3); ``None``: DOFs about the global axes.
    twist, roll : numpy.ndarray or None
        Twisting and rolling springs ``k_tw``, ``k_r`` [N m/rad] (or dashpots); the term is absent
        when both are ``None`` (one ``None`` counts as zero).
    preload : numpy.ndarray or None
        ``F/r`` [N/m] of the pre-load term (compressive normal force over centre distance), or ``None``.

    Returns
    -------
    tuple of numpy.ndarray
        ``ii = B_i^T T B_i``, ``jj = B_j^T T B_j`` and ``ij = B_i^T T B_j`` summed over the terms,
        each (nc, 6, 6).
    """
    nc = normal.shape[0]
    b_i, b_j = slip_jacobians(arm_i, arm_j, rot_i, rot_j)
    blocks = _pair_blocks(b_i, b_j, frame_tensor(normal, along, across))
    if twist is not None or roll is not None:
        zero = np.zeros(nc)
        r_i, r_j = rotation_jacobians(nc, rot_i, rot_j)
        extra = _pair_blocks(r_i, r_j, frame_tensor(normal, zero if twist is None else twist,
                                                    zero if roll is None else roll))
        blocks = tuple(a + b for a, b in zip(blocks, extra))
    if preload is not None:
        c_i, c_j = _motion_matrices(lambda u_i, t_i, u_j, t_j: centre_motion(u_i, u_j), nc, None, None)
        extra = _pair_blocks(c_i, c_j, frame_tensor(normal, np.zeros(nc), -preload))
        blocks = tuple(a + b for a, b in zip(blocks, extra))
    return blocks[0], blocks[1], blocks[2]
