"""Quaternions and rotations for the contact kinematics (Peng et al. 2020, Eq. (7)): skew matrices, the
body-to-world rotation matrix of a unit quaternion, products, conjugates, and the check of the
rotation convention.

Convention (the one dtcrit uses wherever it carries a quaternion): ``q = (qw, qx, qy, qz)`` is a
particle's orientation, body to world: ``v_world = R(q) v_body`` with ``R(q)`` the matrix printed as
Eq. (7).  The paper's Eq. (5) matrix, world to body (``M_L = R M_G``), is ``R(q)^T``, which is the
matrix of the conjugate quaternion (:func:`check_rotation_convention` proves it).
"""
from __future__ import annotations

from itertools import permutations, product

import sympy as sp

# ----------------------------------------------------------------------------------------------
# Small vector helpers
# ----------------------------------------------------------------------------------------------


def skew(v) -> sp.Matrix:
    """The cross-product matrix ``[v]x`` with ``[v]x w = v x w``.

    Parameters
    ----------
    v : sequence of 3
        The vector.

    Returns
    -------
    sympy.Matrix
        The 3x3 skew-symmetric matrix.
    """
    x, y, z = (sp.sympify(c) for c in v)
    return sp.Matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])


def cross(u, v) -> sp.Matrix:
    """The cross product ``u x v``.

    Parameters
    ----------
    u : sequence of 3
        First vector.
    v : sequence of 3
        Second vector.

    Returns
    -------
    sympy.Matrix
        ``u x v`` (3x1).
    """
    return sp.Matrix(u).cross(sp.Matrix(v))


# ----------------------------------------------------------------------------------------------
# Rotations from unit quaternions (Eqs 7-8) and their consistency
# ----------------------------------------------------------------------------------------------


def quaternion_rotation_matrix(q) -> sp.Matrix:
    """Peng et al. 2020, Eqs (7)-(8): the rotation matrix of the unit quaternion ``q = (qw, qx, qy, qz)``.

    Read body to world: for a particle of orientation ``q``, ``v_world = R(q) v_body`` (the columns are
    the body axes in world components).  The paper's Eq (5) matrix, world to body, is ``R(q)^T =
    R(conjugate q)``: where a derivation uses this function's value as the Eq (5) matrix, its
    argument is the conjugate of the particle's orientation quaternion.

    Parameters
    ----------
    q : sequence of 4
        Unit quaternion ``(w, x, y, z)``.

    Returns
    -------
    sympy.Matrix
        ``R(q)`` (3x3).
    """
    w, x, y, z = (sp.sympify(c) for c in q)
    return sp.Matrix(
        [
            [w**2 + x**2 - y**2 - z**2, 2 * x * y - 2 * w * z, 2 * x * z + 2 * w * y],
            [2 * x * y + 2 * w * z, w**2 - x**2 + y**2 - z**2, 2 * y * z - 2 * w * x],
            [2 * x * z - 2 * w * y, 2 * y * z + 2 * w * x, w**2 - x**2 - y**2 + z**2],
        ]
    )


def quaternion_product(p, q) -> tuple:
    """Hamilton product ``p q`` of quaternions given as ``(w, x, y, z)``.

    Parameters
    ----------
    p : sequence of 4
        Left factor.
    q : sequence of 4
        Right factor.

    Returns
    -------
    tuple
        ``p q`` as ``(w, x, y, z)``.
    """
    pw, px, py, pz = (sp.sympify(c) for c in p)
    qw, qx, qy, qz = (sp.sympify(c) for c in q)
    return (
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    )


def quaternion_conjugate(q) -> tuple:
    """The conjugate ``(w, -x, -y, -z)`` of a quaternion (the inverse of a unit one).

    Parameters
    ----------
    q : sequence of 4
        Quaternion ``(w, x, y, z)``.

    Returns
    -------
    tuple
        Its conjugate.
    """
    w, x, y, z = (sp.sympify(c) for c in q)
    return (w, -x, -y, -z)


def quaternion_from_matrix(R: sp.Matrix) -> tuple:
    """An exact unit quaternion ``q`` with ``quaternion_rotation_matrix(q) == R`` (R proper orthogonal).

    For a body-to-world matrix ``R`` this is the particle's orientation quaternion; for the paper's
    Eq (5) matrix (world to body) it is the conjugate of it.

    Shepperd's choice of the largest diagonal combination keeps the square root away from zero.

    Parameters
    ----------
    R : sympy.Matrix
        A proper orthogonal 3x3 matrix.

    Returns
    -------
    tuple
        ``(w, x, y, z)``.
    """
    R = sp.Matrix(R)
    t = R.trace()
    cands = [t, R[0, 0], R[1, 1], R[2, 2]]
    k = max(range(4), key=lambda i: float(cands[i]))
    if k == 0:
        w = sp.sqrt(1 + t) / 2
        q = (w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w))
    elif k == 1:
        x = sp.sqrt(1 + R[0, 0] - R[1, 1] - R[2, 2]) / 2
        q = ((R[2, 1] - R[1, 2]) / (4 * x), x, (R[0, 1] + R[1, 0]) / (4 * x), (R[0, 2] + R[2, 0]) / (4 * x))
    elif k == 2:
        y = sp.sqrt(1 - R[0, 0] + R[1, 1] - R[2, 2]) / 2
        q = ((R[0, 2] - R[2, 0]) / (4 * y), (R[0, 1] + R[1, 0]) / (4 * y), y, (R[1, 2] + R[2, 1]) / (4 * y))
    else:
        z = sp.sqrt(1 - R[0, 0] - R[1, 1] + R[2, 2]) / 2
        q = ((R[1, 0] - R[0, 1]) / (4 * z), (R[0, 2] + R[2, 0]) / (4 * z), (R[1, 2] + R[2, 1]) / (4 * z), z)
    q = tuple(sp.radsimp(sp.nsimplify(c)) for c in q)
    if (quaternion_rotation_matrix(q) - R).applyfunc(sp.simplify) != sp.zeros(3, 3):
        raise ValueError("not a proper rotation matrix")
    return q


def check_rotation_convention() -> dict[str, bool]:
    """Symbolic checks that Eq (7) with Eq (5) is a self-consistent convention (see module docstring):
    ``R(q)`` is a rotation, its inverse (the paper's Eq (5) matrix when ``R(q)`` is body to world) is the
    matrix of the conjugate quaternion, and products of quaternions compose the rotations.

    Returns
    -------
    dict of str to bool
        Each check by name (all True when the convention holds).
    """
    qw, qx, qy, qz, pw, px, py, pz = sp.symbols("q_w q_x q_y q_z p_w p_x p_y p_z", real=True)
    q, p = (qw, qx, qy, qz), (pw, px, py, pz)
    unit_q = {qw: sp.sqrt(1 - qx**2 - qy**2 - qz**2)}
    R = quaternion_rotation_matrix(q)
    RtR = (R.T * R).subs(unit_q).applyfunc(sp.expand)
    det = sp.expand(R.det().subs(unit_q))
    inverse_is_conjugate = (R.T - quaternion_rotation_matrix(quaternion_conjugate(q))).applyfunc(sp.expand)
    composition = (
        quaternion_rotation_matrix(quaternion_product(q, p)) - R * quaternion_rotation_matrix(p)
    ).applyfunc(sp.expand)
    # Eq (5) then Eq (13): local components of a global vector, mapped back, give the vector again
    v = sp.Matrix(sp.symbols("v_x v_y v_z", real=True))
    round_trip = (R.T * (R * v) - v).subs(unit_q).applyfunc(sp.expand)
    # rows of R are the body axes in the global frame: R applied to row i gives e_i
    rows_are_body_axes = all(
        ((R * R[i, :].T).subs(unit_q).applyfunc(sp.expand) - sp.eye(3)[:, i]) == sp.zeros(3, 1) for i in range(3)
    )
    return {
        "R^T R = 1 for |q| = 1": RtR == sp.eye(3),
        "det R = 1 for |q| = 1": det == 1,
        "R^-1 = R(conjugate q)": inverse_is_conjugate == sp.zeros(3, 3),
        "R(q p) = R(q) R(p)": composition == sp.zeros(3, 3),
        "R^-1 (R v) = v (Eqs 5 and 13-16 invert each other)": round_trip == sp.zeros(3, 1),
        "rows of R are the body axes in global components": rows_are_body_axes,
    }


def axis_rotations() -> list[sp.Matrix]:
    """The 24 proper rotations that map coordinate axes onto coordinate axes (signed permutations).

    Returns
    -------
    list of sympy.Matrix
        The 24 rotation matrices.
    """
    out = []
    for perm in permutations(range(3)):
        for signs in product((1, -1), repeat=3):
            R = sp.zeros(3, 3)
            for i, j in enumerate(perm):
                R[i, j] = signs[i]
            if R.det() == 1:
                out.append(R)
    return out
