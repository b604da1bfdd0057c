"""Closed forms of the coefficient matrix, read off the general kinematics of ``dtcrit.symbolic.kinematics``.

Peng, Burns & Hanley (2020), Eq. (26) (``A_max`` as printed) and Eq. (54) (``B_max`` as printed);
one particle's rotational part ``[r]x^T I^{-1} [r]x`` (:func:`arm_term`) and the sphere pair's
closed form ``2/m 1 + 5/m (1 - n n^T)`` (:func:`sphere_pair_check`), both obtained from
:func:`dtcrit.symbolic.kinematics.relative_accelerations`, not typed in.
"""
from __future__ import annotations

import sympy as sp

from dtcrit.symbolic.kinematics import RigidParticle, coefficient_matrix, inertia_tensor
from dtcrit.symbolic.quaternions import quaternion_rotation_matrix, skew


def arm_term(r_local, inertia: sp.Matrix) -> sp.Matrix:
    """The rotational part one particle adds to the coefficient matrix, in its own local frame.

    Obtained from the general kinematics (particle 2 of :func:`relative_accelerations` with
    ``R = 1``, infinite-mass partner and rigid partner), not typed in; it equals
    ``[r]x^T I^{-1} [r]x`` (checked by :func:`check_arm_term_closed_form`).

    Parameters
    ----------
    r_local : sequence or sympy.Matrix
        Contact arm, local components.
    inertia : sympy.Matrix
        Local inertia tensor.

    Returns
    -------
    sympy.Matrix
        The 3x3 arm term.
    """
    inf_partner = RigidParticle(m=sp.oo, inertia=sp.eye(3), R=sp.eye(3), r=sp.zeros(3, 1))
    body = RigidParticle(m=sp.Symbol("m_dummy", positive=True), inertia=inertia, R=sp.eye(3), r=sp.Matrix(r_local))
    A = coefficient_matrix(inf_partner, body)
    return (A - sp.eye(3) / body.m).applyfunc(sp.cancel)


def check_arm_term_closed_form(r_local, inertia: sp.Matrix) -> bool:
    """:func:`arm_term` equals ``[r]x^T I^{-1} [r]x`` identically.

    Parameters
    ----------
    r_local : sequence or sympy.Matrix
        Contact arm, local components.
    inertia : sympy.Matrix
        Local inertia tensor.

    Returns
    -------
    bool
        True when the identity holds.
    """
    X = skew(r_local)
    return (arm_term(r_local, inertia) - X.T * inertia.inv() * X).applyfunc(sp.simplify) == sp.zeros(3, 3)


def a_max_printed(m1, Ixx1, a1, m2, Ixx2, a2) -> sp.Expr:
    """Peng et al. 2020, Eq (26) as printed: ``a1^2/Ixx1 + a2^2/Ixx2 + 1/m1 + 1/m2``.

    Parameters
    ----------
    m1, m2 : sympy.Expr or number
        Masses.
    Ixx1, Ixx2 : sympy.Expr or number
        The moments of inertia the printed form divides by.
    a1, a2 : sympy.Expr or number
        Arm lengths (semi-axes).

    Returns
    -------
    sympy.Expr
        ``A_max`` [1/kg].
    """
    return a1**2 / Ixx1 + a2**2 / Ixx2 + 1 / m1 + 1 / m2


def b_max_printed(Ixx, Iyy, Izz) -> sp.Expr:
    """Peng et al. 2020, Eq (54): ``max(|Ixx-Iyy|/Izz, |Ixx-Izz|/Iyy, |Iyy-Izz|/Ixx)``.

    Parameters
    ----------
    Ixx, Iyy, Izz : sympy.Expr or number
        Principal moments of inertia.

    Returns
    -------
    sympy.Expr
        ``B_max``.
    """
    return sp.Max(sp.Abs(Ixx - Iyy) / Izz, sp.Abs(Ixx - Izz) / Iyy, sp.Abs(Iyy - Izz) / Ixx)


def sphere_pair_check() -> dict[str, object]:
    """Two identical spheres (mass ``m``, radius ``rho``, ``I = 2/5 m rho^2``) in contact along an
    arbitrary unit normal ``n``, with arbitrary unit quaternions for both, through the general
    kinematics.

    Returns
    -------
    dict
        The residual ``A - (2/m 1 + 5/m (1 - n n^T))`` reduced modulo the three unit-norm constraints
        (``residual``, zero when the closed form holds), the eigenvalue checks along and across ``n``,
        ``lambda_max = 7/m`` and ``A_max`` of Eq (26) for the same spheres (``a_max_eq26``), with the
        symbols ``m``, ``rho``, ``n``.
    """
    m, rho = sp.symbols("m rho", positive=True)
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    q1 = sp.symbols("q_w1 q_x1 q_y1 q_z1", real=True)
    q2 = sp.symbols("q_w2 q_x2 q_y2 q_z2", real=True)
    inertia = inertia_tensor(*(sp.Rational(2, 5) * m * rho**2,) * 3)
    p1 = RigidParticle(m, inertia, quaternion_rotation_matrix(q1), rho * n)
    p2 = RigidParticle(m, inertia, quaternion_rotation_matrix(q2), -rho * n)
    A = coefficient_matrix(p1, p2, simplify=False)
    closed = 2 / m * sp.eye(3) + 5 / m * (sp.eye(3) - n * n.T)
    constraints = [sum(c**2 for c in q1) - 1, sum(c**2 for c in q2) - 1, sum(c**2 for c in n) - 1]
    gens = list(q1) + list(q2) + list(n)

    def reduce(e):
        return sp.reduced(sp.expand(e * m), constraints, *gens)[1]

    residual = (A - closed).applyfunc(reduce)
    # eigen-structure of the closed form: n is an eigenvector (2/m), any u normal to n gives 7/m
    u = sp.Matrix([-n[1], n[0], 0])
    along = (closed * n - 2 / m * n).applyfunc(reduce)
    across = (closed * u - 7 / m * u).applyfunc(sp.expand)  # n . u = 0 identically
    trace = reduce(closed.trace())  # 2/m + 7/m + 7/m: the third eigenvalue is 7/m as well
    return {
        "m": m, "rho": rho, "n": n, "closed_form": closed, "residual": residual,
        "eigen_along_n": along, "eigen_across_n": across, "trace_times_m": trace,
        "lambda_max": sp.Rational(7) / m,
        "a_max_eq26": sp.simplify(a_max_printed(m, inertia[0, 0], rho, m, inertia[0, 0], rho)),
    }
