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

Everything derives from the four motion and frame functions (``contact_slip``,
``relative_rotation``, ``centre_motion``, ``frame_law``), written in component arithmetic on
3-tuples whose entries are floats or NumPy arrays of contacts.  They run as plain Python on arrays
(vectorised over contacts) and, registered with ``numba.extending.register_jitable``, inside the
compiled loops of ``matrix_free_kernels`` and ``dtcrit.packing.bounds.estimate_kernels``.
``element_forces`` (``body_forces`` in body DOFs) is the element's action ``B^T T B q``: the
matrix-free products of both paths.  The matrices (``B``, ``T``, the blocks ``ii``, ``jj``, ``ij``)
are these functions on unit vectors: ``dtcrit.packing.operators.element_matrices``.

Numba caches a compiled loop keyed on its own file only: after editing this module, touch the
kernel modules (or clear their ``__pycache__``) so that their cached machine code is rebuilt.
"""
from __future__ import annotations

from typing import Any, Callable, TypeVar

_F = TypeVar("_F", bound=Callable[..., Any])


def _register(fn: _F, **options: str) -> _F:
    """``fn`` registered for calls from compiled code (``numba.extending.register_jitable``), still a
    plain Python function when called from Python (and without Numba).
    """
    try:
        from numba.extending import register_jitable
    except ImportError:  # pragma: no cover - without Numba the NumPy paths call the same functions
        return fn
    return register_jitable(**options)(fn) if options else register_jitable(fn)


_jitable = _register


def _inlined(fn: _F) -> _F:
    """Inlined in Numba IR where called: the product loops stay one fused loop."""
    return _register(fn, inline="always")


__all__ = ["cross", "dot", "to_global", "to_body", "contact_slip", "relative_rotation", "centre_motion",
           "frame_law", "element_forces", "body_forces", "rotation_rows", "arm_rows", "contact_frame", "coefficient_at",
           "IDENTITY", "ZERO3"]

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
def arm_rows(arm_i, arm_j, nrm, c):
    """Contact ``c``'s two arms as 3-tuples, from the compiled loops' arm arguments.

    Arms held as vectors are (C, 3); sphere arms held as their lengths along the normal are (C, 1)
    (``dtcrit.packing.normal_arms.kernel_arms``): ``a_i = l_i n``, ``a_j = -(l_j n)``, the arithmetic
    of ``NormalArms``, so both forms give the same bits.

    Parameters
    ----------
    arm_i, arm_j : numpy.ndarray
        (C, 3) arm vectors or (C, 1) lengths.
    nrm : numpy.ndarray
        (C, 3) unit normals.
    c : int
        The contact.

    Returns
    -------
    tuple
        ``(a_i, a_j)``, each a 3-tuple of floats.
    """
    if arm_i.shape[1] == 1:
        li = arm_i[c, 0]
        lj = arm_j[c, 0]
        return ((li * nrm[c, 0], li * nrm[c, 1], li * nrm[c, 2]),
                (-(lj * nrm[c, 0]), -(lj * nrm[c, 1]), -(lj * nrm[c, 2])))
    return ((arm_i[c, 0], arm_i[c, 1], arm_i[c, 2]), (arm_j[c, 0], arm_j[c, 1], arm_j[c, 2]))


@_inlined
def coefficient_at(values, c):
    """Contact ``c``'s coefficient: ``values[0]`` when ``values`` holds one for every contact (length 1,
    ``dtcrit.packing.uniform_values.kernel_values``), else ``values[c]`` (one index, ``min(c, len - 1)``,
    no branch for Numba's inliner to merge).

    Parameters
    ----------
    values : numpy.ndarray
        (1,) or (C,) coefficients.
    c : int
        The contact.

    Returns
    -------
    float
        Its coefficient.
    """
    return values[min(c, values.shape[0] - 1)]


@_inlined
def contact_frame(c, ci, cj, nrm, arm_i, arm_j, rot, springs, oriented):
    """Contact ``c``'s bodies, their rotation rows, normal and arms as the compiled loops read them.

    Parameters
    ----------
    c : int
        The contact.
    ci, cj : numpy.ndarray
        (C,) body indices.
    nrm : numpy.ndarray
        (C, 3) unit normals.
    arm_i, arm_j : numpy.ndarray
        (C, 3) arm vectors or (C, 1) lengths (``arm_rows``).
    rot : numpy.ndarray
        (N, 3, 3) body rotations, read when ``oriented``.
    springs, oriented : bool
        Whether the contact springs (and so the arms) act; whether bodies carry rotations.

    Returns
    -------
    tuple
        ``(i, j, rot_i, rot_j, n, a_i, a_j)`` (zero arms without springs, ``IDENTITY`` rows unoriented).
    """
    i = ci[c]
    j = cj[c]
    ri = rotation_rows(rot, i) if oriented else IDENTITY
    rj = rotation_rows(rot, j) if oriented else IDENTITY
    n = (nrm[c, 0], nrm[c, 1], nrm[c, 2])
    ai, aj = arm_rows(arm_i, arm_j, nrm, c) if springs else (ZERO3, ZERO3)
    return i, j, ri, rj, n, ai, aj


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
    return to_global(r, t) if oriented else t


@_jitable
def _body(r, m, oriented):
    """``R^T m`` when ``oriented``, else ``m``."""
    return to_body(r, m) if oriented else m


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
