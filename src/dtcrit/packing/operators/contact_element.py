"""The 6-DOF contact element: one contact between two rigid bodies, written once.

Degrees of freedom, six per body ``p``: ``q_p = (u_p, t_p)``, the translation of the centre in the
global frame and a small rotation about the body's principal axes, ``theta_p = R_p t_p`` in the
global frame (Otsubo et al. 2017, Section 3).  A contact between ``i`` and ``j`` with unit normal
``n`` and branch vectors (arms) ``a_i = x_c - x_i``, ``a_j = x_c - x_j`` from the centres to the
contact point carries three springs, each a tensor of the contact frame acting on one relative
motion (Peng et al. 2020, Eqs (1)-(2), (17)-(19), linearised):

==================  ====================================================  ==========================
term                relative motion                                       frame tensor
==================  ====================================================  ==========================
contact springs     ``delta = u_j - u_i + a_i x theta_i - a_j x theta_j``  ``T(n, k_n, k_s)``
rolling, twisting   ``w = theta_j - theta_i``                              ``T(n, k_tw, k_r)``
pre-load            ``d = u_j - u_i``                                      ``T(n, 0, -F/r)``
==================  ====================================================  ==========================

with ``T(n, along, across) v = along (n . v) n + across (v - (n . v) n)``.  The rolling and twisting
springs are YADE's CohFrictPhys moment law and LAMMPS ``granular`` ``rolling sds`` / ``twisting
marshall`` linearised; the pre-load term is the initial-stress stiffness of a contact carrying the
compressive normal force ``F`` at centre distance ``r`` (``dtcrit.packing.operators.assembly``).
Writing each motion as ``B_i q_i + B_j q_j``, the element is ``sum B^T T B`` (12 x 12, blocks
``ii``, ``jj``, ``ij``); the dashpot element has the same kinematics with ``c`` in place of ``k``.

Everything below derives from the four motion and frame functions (``contact_slip``,
``relative_rotation``, ``centre_motion``, ``frame_law``), written in component arithmetic on
3-tuples whose entries are floats or NumPy arrays of contacts.  They run as plain Python on arrays
(vectorised over contacts) and, registered with ``numba.extending.register_jitable``, inside the
compiled loops of ``matrix_free_kernels`` and ``dtcrit.packing.bounds.estimate_kernels``:

* ``element_forces`` -- the element's action ``B^T T B q`` (the matrix-free products, both paths);
* ``element_blocks_into`` -- the three 6 x 6 blocks, the action on the twelve unit vectors;
* ``slip_jacobians_into`` -- ``B_i``, ``B_j`` of the contact springs, the motion of the unit vectors;
* ``element_blocks`` -- the blocks vectorised over contacts, ``B^T T B`` by ``numpy.matmul`` from the
  matrices ``B`` and ``T`` the same functions give on unit vectors (exact: a unit vector only
  selects entries), so that the assembled matrices keep their bits.

Numba caches a compiled loop keyed on its own file only: after editing this module, touch the
kernel modules (or clear their ``__pycache__``) so that their cached machine code is rebuilt.
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np

try:  # compiled inline into the kernels that call them; plain Python everywhere else
    from numba.extending import register_jitable

    _jitable = register_jitable

    def _inlined(fn):  # inlined in Numba IR: the product loops stay one fused loop
        return register_jitable(inline="always")(fn)  # (a fresh decorator each: it consumes its options)
except ImportError:  # pragma: no cover - without Numba the NumPy paths call the same functions
    def _jitable(fn):
        return fn

    _inlined = _jitable

__all__ = ["cross", "dot", "to_global", "to_body", "contact_slip", "relative_rotation", "centre_motion",
           "frame_law", "element_forces", "body_forces", "element_blocks_into", "slip_jacobians_into",
           "rotation_rows", "IDENTITY", "components", "frame_tensor", "slip_jacobians", "rotation_jacobians", "element_blocks"]

ZERO3 = (0.0, 0.0, 0.0)
IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
"""Rows of the unit rotation (``rotation_rows`` of bodies whose DOFs are about the global axes)."""


@_jitable
def rotation_rows(rot, p):
    """The rows of body ``p``'s rotation matrix as nested 3-tuples (the form the element reads).

    Parameters
    ----------
    rot : numpy.ndarray
        Rotation matrices, shape (N, 3, 3) (principal axes in the global frame).
    p : int or numpy.ndarray
        Body index, or an array of indices (one per contact) for the vectorised form.

    Returns
    -------
    tuple
        ``((R_00, R_01, R_02), (R_10, ...), (R_20, ...))``, floats or arrays over contacts.
    """
    return ((rot[p, 0, 0], rot[p, 0, 1], rot[p, 0, 2]), (rot[p, 1, 0], rot[p, 1, 1], rot[p, 1, 2]),
            (rot[p, 2, 0], rot[p, 2, 1], rot[p, 2, 2]))


@_jitable
def cross(a, b):
    """Cross product ``a x b`` of two 3-vectors given as component tuples.

    Parameters
    ----------
    a, b : tuple
        Components ``(x, y, z)``, each a float or an array over contacts.

    Returns
    -------
    tuple
        The components of ``a x b``.
    """
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@_jitable
def dot(a, b):
    """Scalar product ``a . b`` of two component tuples, summed x, y, z in that order.

    Parameters
    ----------
    a, b : tuple
        Components ``(x, y, z)``, each a float or an array over contacts.

    Returns
    -------
    float or numpy.ndarray
        ``a_x b_x + a_y b_y + a_z b_z``.
    """
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@_jitable
def to_global(r, t):
    """``theta = R t``: a small body rotation (principal axes) in the global frame.

    Parameters
    ----------
    r : tuple
        Rows of the body's rotation matrix ``R`` (principal axes in the global frame), nested
        3-tuples indexed ``r[row][col]`` (``rotation_rows``).
    t : tuple
        Components of the rotation about the body's principal axes [rad].

    Returns
    -------
    tuple
        Components of ``R t`` [rad].
    """
    return (r[0][0] * t[0] + r[0][1] * t[1] + r[0][2] * t[2],
            r[1][0] * t[0] + r[1][1] * t[1] + r[1][2] * t[2],
            r[2][0] * t[0] + r[2][1] * t[1] + r[2][2] * t[2])


@_jitable
def to_body(r, m):
    """``R^T m``: a global moment on the body's principal axes (the adjoint of ``to_global``).

    Parameters
    ----------
    r : tuple
        Rows of the body's rotation matrix, nested 3-tuples indexed ``r[row][col]`` (``rotation_rows``).
    m : tuple
        Components of the moment in the global frame [N m].

    Returns
    -------
    tuple
        Components of ``R^T m`` [N m].
    """
    return (r[0][0] * m[0] + r[1][0] * m[1] + r[2][0] * m[2],
            r[0][1] * m[0] + r[1][1] * m[1] + r[2][1] * m[2],
            r[0][2] * m[0] + r[1][2] * m[1] + r[2][2] * m[2])


@_jitable
def centre_motion(u_i, u_j):
    """``d = u_j - u_i``: relative displacement of the two centres (the pre-load term's motion).

    Parameters
    ----------
    u_i, u_j : tuple
        Displacements of the centres of bodies ``i`` and ``j`` [m].

    Returns
    -------
    tuple
        Components of ``d`` [m].
    """
    return (u_j[0] - u_i[0], u_j[1] - u_i[1], u_j[2] - u_i[2])


@_jitable
def contact_slip(d, theta_i, theta_j, arm_i, arm_j):
    """``delta = d + a_i x theta_i - a_j x theta_j``: relative displacement of the two material
    points at the contact point (Peng et al. 2020, Eqs (17)-(19) linearised).

    Parameters
    ----------
    d : tuple
        Relative displacement of the centres, ``u_j - u_i`` [m].
    theta_i, theta_j : tuple
        Small rotations of the bodies in the global frame [rad].
    arm_i, arm_j : tuple
        Branch vectors ``x_c - x_i`` and ``x_c - x_j`` [m].

    Returns
    -------
    tuple
        Components of ``delta`` [m].
    """
    ci = cross(arm_i, theta_i)
    cj = cross(arm_j, theta_j)
    return (d[0] + ci[0] - cj[0], d[1] + ci[1] - cj[1], d[2] + ci[2] - cj[2])


@_jitable
def relative_rotation(theta_i, theta_j):
    """``w = theta_j - theta_i``: the relative rotation the rolling and twisting springs resist.

    Parameters
    ----------
    theta_i, theta_j : tuple
        Small rotations of the bodies in the global frame [rad].

    Returns
    -------
    tuple
        Components of ``w`` [rad].
    """
    return (theta_j[0] - theta_i[0], theta_j[1] - theta_i[1], theta_j[2] - theta_i[2])


@_jitable
def frame_law(n, along, across, v):
    """``T v = along (n . v) n + across (v - (n . v) n)``: a spring (or dashpot) of the contact frame.

    Parameters
    ----------
    n : tuple
        Unit contact normal.
    along, across : float or numpy.ndarray
        Coefficient along ``n`` and across it (``k_n``, ``k_s`` [N/m]; ``k_tw``, ``k_r`` [N m/rad];
        ``0``, ``-F/r`` for the pre-load; ``c`` for dashpots).
    v : tuple
        The relative motion the spring acts on.

    Returns
    -------
    tuple
        Components of ``T v`` (a force or a moment).
    """
    vn = dot(n, v)
    px = vn * n[0]
    py = vn * n[1]
    pz = vn * n[2]
    return (along * px + across * (v[0] - px), along * py + across * (v[1] - py), along * pz + across * (v[2] - pz))


@_inlined
def element_forces(n, arm_i, arm_j, theta_i, theta_j, d, kn, ks, ktw, kr, g, springs, rolling, preload):
    """The element's action in the global frame: force and moments of ``sum B^T T B q`` (module docstring).

    Parameters
    ----------
    n : tuple
        Unit contact normal.
    arm_i, arm_j : tuple
        Branch vectors from the centres to the contact point [m].
    theta_i, theta_j : tuple
        Small rotations of the bodies in the global frame [rad].
    d : tuple
        Relative displacement of the centres ``u_j - u_i`` [m].
    kn, ks : float or numpy.ndarray
        Normal and tangential springs [N/m] (or dashpots [N s/m]).
    ktw, kr : float or numpy.ndarray
        Twisting and rolling springs [N m/rad] (or dashpots).
    g : float or numpy.ndarray
        Pre-load coefficient ``F/r`` [N/m] (compressive normal force over centre distance).
    springs, rolling, preload : bool
        Which of the three terms the contact carries (an absent term adds nothing).

    Returns
    -------
    f : tuple
        Force on body ``j`` [N] (``-f`` on body ``i``).
    m_i, m_j : tuple
        Moments on bodies ``i`` and ``j`` in the global frame [N m].
    """
    f = ZERO3
    m_i = ZERO3
    m_j = ZERO3
    if springs:
        f = frame_law(n, kn, ks, contact_slip(d, theta_i, theta_j, arm_i, arm_j))
        ci = cross(arm_i, f)
        m_i = (-ci[0], -ci[1], -ci[2])
        m_j = cross(arm_j, f)
    if preload:
        p = frame_law(n, 0.0, -g, d)
        f = (f[0] + p[0], f[1] + p[1], f[2] + p[2])
    if rolling:
        m = frame_law(n, ktw, kr, relative_rotation(theta_i, theta_j))
        m_i = (m_i[0] - m[0], m_i[1] - m[1], m_i[2] - m[2])
        m_j = (m_j[0] + m[0], m_j[1] + m[1], m_j[2] + m[2])
    return f, m_i, m_j


@_jitable
def _global(r, t, oriented):
    """``R t`` when ``oriented``, else ``t`` (no branch left in the inlined ``body_forces``)."""
    if oriented:
        return to_global(r, t)
    return t


@_jitable
def _body(r, m, oriented):
    """``R^T m`` when ``oriented``, else ``m``."""
    if oriented:
        return to_body(r, m)
    return m


@_inlined
def body_forces(n, arm_i, arm_j, rot_i, rot_j, oriented, u_i, t_i, u_j, t_j, kn, ks, ktw, kr, g,
                springs, rolling, preload):
    """``element_forces`` in body DOFs: ``B_i^T T B q = (-f, R_i^T m_i)``, ``B_j^T T B q = (f, R_j^T m_j)``.

    Parameters
    ----------
    n, arm_i, arm_j : tuple
        Unit normal and branch vectors [m] (``element_forces``).
    rot_i, rot_j : tuple
        Rows of the bodies' rotation matrices (``rotation_rows``); read only when ``oriented``.
    oriented : bool
        Whether the bodies' DOFs are about principal axes ``R_p`` (else the global axes).
    u_i, t_i, u_j, t_j : tuple
        Translations [m] and body rotations [rad] of the two bodies.
    kn, ks, ktw, kr, g : float or numpy.ndarray
        Coefficients of the three terms (``element_forces``).
    springs, rolling, preload : bool
        Which terms the contact carries.

    Returns
    -------
    f : tuple
        Force on body ``j`` [N] (``-f`` on ``i``).
    m_i, m_j : tuple
        Moments on the bodies about their principal axes [N m].
    """
    f, m_i, m_j = element_forces(n, arm_i, arm_j, _global(rot_i, t_i, oriented), _global(rot_j, t_j, oriented),
                                 centre_motion(u_i, u_j), kn, ks, ktw, kr, g, springs, rolling, preload)
    return f, _body(rot_i, m_i, oriented), _body(rot_j, m_j, oriented)


@_jitable
def _unit(k, first):
    """Component ``first .. first + 2`` of the ``k``-th unit vector of R^6, as a 3-tuple."""
    return (1.0 if k == first else 0.0, 1.0 if k == first + 1 else 0.0, 1.0 if k == first + 2 else 0.0)


@_jitable
def element_blocks_into(n, arm_i, arm_j, rot_i, rot_j, oriented, kn, ks, ktw, kr, g, springs, rolling, preload,
                        ii, jj, ij):
    """The element's 6 x 6 blocks ``ii``, ``jj``, ``ij`` written into the given arrays: column ``k``
    is the action (``body_forces``) on the ``k``-th unit vector of body ``i`` (``ii``, ``ij^T``) or
    ``j`` (``ij``, ``jj``).

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
    for k in range(6):
        u = _unit(k, 0)
        t = _unit(k, 3)
        f, m_i, m_j = body_forces(n, arm_i, arm_j, rot_i, rot_j, oriented, u, t, ZERO3, ZERO3,
                                  kn, ks, ktw, kr, g, springs, rolling, preload)
        for a in range(3):
            ii[a, k] = -f[a]
            ii[3 + a, k] = m_i[a]
            ij[k, a] = f[a]
            ij[k, 3 + a] = m_j[a]
        f, m_i, m_j = body_forces(n, arm_i, arm_j, rot_i, rot_j, oriented, ZERO3, ZERO3, u, t,
                                  kn, ks, ktw, kr, g, springs, rolling, preload)
        for a in range(3):
            ij[a, k] = -f[a]
            ij[3 + a, k] = m_i[a]
            jj[a, k] = f[a]
            jj[3 + a, k] = m_j[a]


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


# -- vectorised over contacts: the matrices of the same functions -----------------------------------

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
    on the unit vectors, the rotation columns then turned to body axes (``@ R``) when given."""
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
