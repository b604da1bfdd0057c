"""Contact kinematics of two rigid particles, rebuilt from first principles with SymPy.

Peng, Burns & Hanley (2020), Section 2 (Eqs 1-20), Section 3 (Eqs 22-26) and Section 5 (Eqs 50-57).

Nothing here is typed in per configuration: the general functions below (quaternion -> rotation,
inertia tensor, Euler's equations, frame changes, contact-point accelerations) are composed into
:func:`relative_accelerations`, and the coefficient matrix of the contact force, the rotation
("Omega") terms and the relative angular acceleration are read off from that one expression.

Rotation convention (the paper's, Eqs 5-8 and 13-16)
----------------------------------------------------
``R(q)`` is the matrix printed as Eq (7) for the unit quaternion ``q = (qw, qx, qy, qz)``.  The
paper uses it as ``M_L = R M_G`` (Eq 5): ``R`` maps *global* components to *local* (body)
components, so the rows of ``R`` are the body axes written in the global frame, and Eqs (13)-(16)
go back with ``R^{-1} = R^T``.  :func:`check_rotation_convention` verifies symbolically that, for
a unit quaternion, ``R`` is orthogonal with determinant 1, that ``R^{-1}`` is the matrix of the
conjugate quaternion, that composition follows the quaternion product, and that the chain
global -> local -> global used by Eqs (5), (11), (13) is the identity, so the convention is
self-consistent.  (Eq. (7) is the usual *active* rotation matrix of ``q``, so with Eq. (5) a
particle's ``q`` is the conjugate of the usual body-to-world orientation quaternion; only the
matrix enters the kinematics.)

Sign conventions of Figure 1: the force ``F`` and moment ``M`` act on particle 2, ``-F`` and
``-M`` on particle 1; ``r_i = x_c - x_i`` (Eqs 1-2); ``xdd_c = xdd_c2 - xdd_c1`` (Eq 19) and
``wdot_c = wdot_G2 - wdot_G1`` (Eq 20).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from dtcrit.symbolic.quaternions import cross

# ----------------------------------------------------------------------------------------------
# Inertia, moments, Euler's equations, frame changes (Eqs 3-6, 9-16)
# ----------------------------------------------------------------------------------------------


def inertia_tensor(Ixx, Iyy, Izz, Ixy=0, Ixz=0, Iyz=0) -> sp.Matrix:
    """Peng et al. 2020, Eqs (9)-(10): the (symmetric) inertia tensor in the local frame.

    Under the paper's assumption 2 (principal local axes) the products of inertia vanish.

    Parameters
    ----------
    Ixx, Iyy, Izz : sympy.Expr or number
        Moments of inertia about the local axes [kg m^2].
    Ixy, Ixz, Iyz : sympy.Expr or number
        Products of inertia [kg m^2] (0 on principal axes).

    Returns
    -------
    sympy.Matrix
        The 3x3 tensor.
    """
    return sp.Matrix([[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]])


def global_moments(r1, r2, F, M) -> tuple[sp.Matrix, sp.Matrix]:
    """Peng et al. 2020, Eqs (3)-(4): ``M_G1 = r1 x (-F) + (-M)``, ``M_G2 = r2 x F + M``.

    Parameters
    ----------
    r1 : sequence or sympy.Matrix
        Contact arm of particle 1, global components.
    r2 : sequence or sympy.Matrix
        Contact arm of particle 2, global components.
    F : sequence or sympy.Matrix
        Contact force on particle 2 (global).
    M : sequence or sympy.Matrix
        Contact moment on particle 2 (global).

    Returns
    -------
    tuple of sympy.Matrix
        ``(M_G1, M_G2)``.
    """
    F, M = sp.Matrix(F), sp.Matrix(M)
    return cross(r1, -F) - M, cross(r2, F) + M


def to_local(R: sp.Matrix, v_global) -> sp.Matrix:
    """Peng et al. 2020, Eqs (5)-(6): ``v_L = R v_G``.

    Parameters
    ----------
    R : sympy.Matrix
        Rotation global -> local.
    v_global : sequence or sympy.Matrix
        Global components.

    Returns
    -------
    sympy.Matrix
        Local components.
    """
    return R * sp.Matrix(v_global)


def to_global(R: sp.Matrix, v_local) -> sp.Matrix:
    """Peng et al. 2020, Eqs (13)-(16): ``v_G = R^{-1} v_L`` with ``R^{-1} = R^T`` (unit quaternion).

    Parameters
    ----------
    R : sympy.Matrix
        Rotation global -> local.
    v_local : sequence or sympy.Matrix
        Local components.

    Returns
    -------
    sympy.Matrix
        Global components.
    """
    return R.T * sp.Matrix(v_local)


def euler_angular_acceleration(inertia: sp.Matrix, M_local, w_local) -> sp.Matrix:
    """Peng et al. 2020, Eqs (11)-(12): ``wdot_L = I^{-1} (M_L - w_L x I w_L)`` (Euler's equations).

    Parameters
    ----------
    inertia : sympy.Matrix
        Local inertia tensor.
    M_local : sequence or sympy.Matrix
        Moment, local components.
    w_local : sequence or sympy.Matrix
        Angular velocity, local components.

    Returns
    -------
    sympy.Matrix
        ``wdot_L``.
    """
    w = sp.Matrix(w_local)
    return inertia.inv() * (sp.Matrix(M_local) - cross(w, inertia * w))


def contact_point_acceleration(wdot_G, w_G, r, F, m, sign) -> sp.Matrix:
    """Peng et al. 2020, Eqs (17)-(18): ``wdot x r + w x (w x r) + sign F / m`` (sign -1 on particle 1).

    Parameters
    ----------
    wdot_G : sympy.Matrix
        Angular acceleration, global components.
    w_G : sympy.Matrix
        Angular velocity, global components.
    r : sympy.Matrix
        Contact arm, global components.
    F : sympy.Matrix
        Contact force on particle 2.
    m : sympy.Expr
        Mass.
    sign : int
        -1 for particle 1, +1 for particle 2.

    Returns
    -------
    sympy.Matrix
        Acceleration of the contact point of that particle.
    """
    w = sp.Matrix(w_G)
    return cross(wdot_G, r) + cross(w, cross(w, r)) + sign * sp.Matrix(F) / m


# ----------------------------------------------------------------------------------------------
# Two particles in contact (Eqs 1-20)
# ----------------------------------------------------------------------------------------------


@dataclass
class RigidParticle:
    """One particle: mass ``m``, local inertia tensor ``inertia`` (``I``), rotation ``R`` (global -> local, Eq 5),
    contact arm ``r = x_c - x`` in global components (Eqs 1-2) and angular velocity.

    Parameters
    ----------
    m : sympy.Expr
        Mass.
    inertia : sympy.Matrix
        Local inertia tensor (:func:`inertia_tensor`).
    R : sympy.Matrix
        Rotation global -> local (Eq 5).
    r : sympy.Matrix
        Contact arm ``x_c - x``, global components.
    w : sympy.Matrix
        Angular velocity (zero by default).
    w_is_local : bool
        Whether ``w`` holds local (body) components ``w_L`` or global ones ``w_G`` (Eqs 15-16 relate them).
    """

    m: sp.Expr
    inertia: sp.Matrix
    R: sp.Matrix
    r: sp.Matrix
    w: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))
    w_is_local: bool = False

    @property
    def w_G(self) -> sp.Matrix:
        """The angular velocity in global components."""
        return to_global(self.R, self.w) if self.w_is_local else sp.Matrix(self.w)

    @property
    def w_L(self) -> sp.Matrix:
        """The angular velocity in local (body) components."""
        return sp.Matrix(self.w) if self.w_is_local else to_local(self.R, self.w)


def relative_accelerations(p1: RigidParticle, p2: RigidParticle, F, M=(0, 0, 0)) -> tuple[sp.Matrix, sp.Matrix]:
    """Peng et al. 2020, Eqs (1)-(20): ``(xdd_c, wdot_c)`` for force ``F`` and moment ``M`` on particle 2.

    Parameters
    ----------
    p1 : RigidParticle
        Particle 1 (the force acts on it as ``-F``).
    p2 : RigidParticle
        Particle 2 (the force acts on it as ``F``).
    F : sequence or sympy.Matrix
        Contact force on particle 2 (global).
    M : sequence or sympy.Matrix
        Contact moment on particle 2 (global).

    Returns
    -------
    tuple of sympy.Matrix
        Relative acceleration of the contact points and relative angular acceleration.
    """
    M_G1, M_G2 = global_moments(p1.r, p2.r, F, M)  # Eqs 3-4
    wdot_L1 = euler_angular_acceleration(p1.inertia, to_local(p1.R, M_G1), p1.w_L)  # Eqs 5, 11
    wdot_L2 = euler_angular_acceleration(p2.inertia, to_local(p2.R, M_G2), p2.w_L)  # Eqs 6, 12
    wdot_G1, wdot_G2 = to_global(p1.R, wdot_L1), to_global(p2.R, wdot_L2)  # Eqs 13-14
    xdd_c1 = contact_point_acceleration(wdot_G1, p1.w_G, p1.r, F, p1.m, -1)  # Eq 17
    xdd_c2 = contact_point_acceleration(wdot_G2, p2.w_G, p2.r, F, p2.m, +1)  # Eq 18
    return xdd_c2 - xdd_c1, wdot_G2 - wdot_G1  # Eqs 19-20


F_SYMBOLS = sp.symbols("F_x F_y F_z", real=True)


def coefficient_matrix(p1: RigidParticle, p2: RigidParticle, simplify: bool = True) -> sp.Matrix:
    """The 3x3 coefficient of ``F`` in ``xdd_c`` (the general form of the matrix in Eqs 22-25).

    ``xdd_c`` is affine in ``F`` (Euler's equations are linear in the moment; checked by
    :func:`check_affine_in_force`), so column ``k`` is ``xdd_c(F = e_k) - xdd_c(F = 0)``; it does
    not depend on the angular velocities.

    Parameters
    ----------
    p1 : RigidParticle
        Particle 1 (the force acts on it as ``-F``).
    p2 : RigidParticle
        Particle 2 (the force acts on it as ``F``).
    simplify : bool
        Simplify each entry.

    Returns
    -------
    sympy.Matrix
        The coefficient matrix ``A`` [1/kg].
    """
    x0, _ = relative_accelerations(p1, p2, (0, 0, 0))
    cols = [relative_accelerations(p1, p2, tuple(sp.eye(3)[:, k]))[0] - x0 for k in range(3)]
    A = sp.Matrix.hstack(*cols)
    return A.applyfunc(sp.cancel) if simplify else A


def rotation_terms(p1: RigidParticle, p2: RigidParticle) -> sp.Matrix:
    """``Omega`` of Eq (25): ``xdd_c`` at ``F = 0``, ``M = 0`` (velocity-dependent terms only).

    Parameters
    ----------
    p1 : RigidParticle
        Particle 1 (the force acts on it as ``-F``).
    p2 : RigidParticle
        Particle 2 (the force acts on it as ``F``).

    Returns
    -------
    sympy.Matrix
        ``Omega``.
    """
    xdd, _ = relative_accelerations(p1, p2, (0, 0, 0))
    return xdd.applyfunc(lambda e: sp.factor(sp.cancel(e)))


def relative_angular_acceleration(p1: RigidParticle, p2: RigidParticle) -> sp.Matrix:
    """``wdot_c`` at ``F = 0``, ``M = 0`` (Eqs 50-52: the gyroscopic terms of Euler's equations).

    Parameters
    ----------
    p1 : RigidParticle
        Particle 1 (the force acts on it as ``-F``).
    p2 : RigidParticle
        Particle 2 (the force acts on it as ``F``).

    Returns
    -------
    sympy.Matrix
        ``wdot_c``.
    """
    _, wdot = relative_accelerations(p1, p2, (0, 0, 0))
    return wdot.applyfunc(lambda e: sp.factor(sp.cancel(e)))


def check_affine_in_force(p1: RigidParticle, p2: RigidParticle) -> bool:
    """``xdd_c(F) == A F + Omega`` identically (the decomposition of Eq 25 is exact).

    Parameters
    ----------
    p1 : RigidParticle
        Particle 1 (the force acts on it as ``-F``).
    p2 : RigidParticle
        Particle 2 (the force acts on it as ``F``).

    Returns
    -------
    bool
        True when the identity holds.
    """
    xdd, _ = relative_accelerations(p1, p2, F_SYMBOLS)
    A = xdd.jacobian(sp.Matrix(F_SYMBOLS))
    Om = xdd.subs({f: 0 for f in F_SYMBOLS})
    constant_jacobian = all(sp.diff(A[i, j], f) == 0 for i in range(3) for j in range(3) for f in F_SYMBOLS)
    return constant_jacobian and (xdd - A * sp.Matrix(F_SYMBOLS) - Om).applyfunc(sp.simplify) == sp.zeros(3, 1)
