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
from functools import lru_cache
from itertools import permutations, product

import sympy as sp

# ----------------------------------------------------------------------------------------------
# Small vector helpers
# ----------------------------------------------------------------------------------------------


def skew(v) -> sp.Matrix:
    """The cross-product matrix ``[v]x`` with ``[v]x w = v x w``."""
    x, y, z = (sp.sympify(c) for c in v)
    return sp.Matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])


def cross(u, v) -> sp.Matrix:
    return sp.Matrix(u).cross(sp.Matrix(v))


# ----------------------------------------------------------------------------------------------
# Rotations from unit quaternions (Eqs 7-8) and their consistency
# ----------------------------------------------------------------------------------------------


def quaternion_rotation_matrix(q) -> sp.Matrix:
    """Peng et al. 2020, Eqs (7)-(8): the rotation matrix of the unit quaternion ``q = (qw, qx, qy, qz)``.

    Used as ``M_L = R M_G`` (Eq 5), i.e. it maps global components to local components.
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
    """Hamilton product ``p q`` of quaternions given as ``(w, x, y, z)``."""
    pw, px, py, pz = (sp.sympify(c) for c in p)
    qw, qx, qy, qz = (sp.sympify(c) for c in q)
    return (
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    )


def quaternion_conjugate(q) -> tuple:
    w, x, y, z = (sp.sympify(c) for c in q)
    return (w, -x, -y, -z)


def quaternion_from_matrix(R: sp.Matrix) -> tuple:
    """An exact unit quaternion ``q`` with ``quaternion_rotation_matrix(q) == R`` (R proper orthogonal).

    Shepperd's choice of the largest diagonal combination keeps the square root away from zero.
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
    """Symbolic checks that Eq (7) with Eq (5) is a self-consistent convention (see module docstring)."""
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
    """The 24 proper rotations that map coordinate axes onto coordinate axes (signed permutations)."""
    out = []
    for perm in permutations(range(3)):
        for signs in product((1, -1), repeat=3):
            R = sp.zeros(3, 3)
            for i, j in enumerate(perm):
                R[i, j] = signs[i]
            if R.det() == 1:
                out.append(R)
    return out


# ----------------------------------------------------------------------------------------------
# Inertia, moments, Euler's equations, frame changes (Eqs 3-6, 9-16)
# ----------------------------------------------------------------------------------------------


def inertia_tensor(Ixx, Iyy, Izz, Ixy=0, Ixz=0, Iyz=0) -> sp.Matrix:
    """Peng et al. 2020, Eqs (9)-(10): the (symmetric) inertia tensor in the local frame.

    Under the paper's assumption 2 (principal local axes) the products of inertia vanish.
    """
    return sp.Matrix([[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]])


def global_moments(r1, r2, F, M) -> tuple[sp.Matrix, sp.Matrix]:
    """Peng et al. 2020, Eqs (3)-(4): ``M_G1 = r1 x (-F) + (-M)``, ``M_G2 = r2 x F + M``."""
    F, M = sp.Matrix(F), sp.Matrix(M)
    return cross(r1, -F) - M, cross(r2, F) + M


def to_local(R: sp.Matrix, v_global) -> sp.Matrix:
    """Peng et al. 2020, Eqs (5)-(6): ``v_L = R v_G``."""
    return R * sp.Matrix(v_global)


def to_global(R: sp.Matrix, v_local) -> sp.Matrix:
    """Peng et al. 2020, Eqs (13)-(16): ``v_G = R^{-1} v_L`` with ``R^{-1} = R^T`` (unit quaternion)."""
    return R.T * sp.Matrix(v_local)


def euler_angular_acceleration(I: sp.Matrix, M_local, w_local) -> sp.Matrix:
    """Peng et al. 2020, Eqs (11)-(12): ``wdot_L = I^{-1} (M_L - w_L x I w_L)`` (Euler's equations)."""
    w = sp.Matrix(w_local)
    return I.inv() * (sp.Matrix(M_local) - cross(w, I * w))


def contact_point_acceleration(wdot_G, w_G, r, F, m, sign) -> sp.Matrix:
    """Peng et al. 2020, Eqs (17)-(18): ``wdot x r + w x (w x r) + sign F / m`` (sign -1 on particle 1)."""
    w = sp.Matrix(w_G)
    return cross(wdot_G, r) + cross(w, cross(w, r)) + sign * sp.Matrix(F) / m


# ----------------------------------------------------------------------------------------------
# Two particles in contact (Eqs 1-20)
# ----------------------------------------------------------------------------------------------


@dataclass
class RigidParticle:
    """One particle: mass ``m``, local inertia tensor ``I``, rotation ``R`` (global -> local, Eq 5),
    contact arm ``r = x_c - x`` in global components (Eqs 1-2) and angular velocity.

    ``w`` holds the angular velocity; ``w_is_local`` says whether its components are local
    (body) components ``w_L`` or global ones ``w_G`` (Eqs 15-16 relate them).
    """

    m: sp.Expr
    I: sp.Matrix
    R: sp.Matrix
    r: sp.Matrix
    w: sp.Matrix = field(default_factory=lambda: sp.zeros(3, 1))
    w_is_local: bool = False

    @property
    def w_G(self) -> sp.Matrix:
        return to_global(self.R, self.w) if self.w_is_local else sp.Matrix(self.w)

    @property
    def w_L(self) -> sp.Matrix:
        return sp.Matrix(self.w) if self.w_is_local else to_local(self.R, self.w)


def relative_accelerations(p1: RigidParticle, p2: RigidParticle, F, M=(0, 0, 0)) -> tuple[sp.Matrix, sp.Matrix]:
    """Peng et al. 2020, Eqs (1)-(20): ``(xdd_c, wdot_c)`` for force ``F`` and moment ``M`` on particle 2."""
    M_G1, M_G2 = global_moments(p1.r, p2.r, F, M)  # Eqs 3-4
    wdot_L1 = euler_angular_acceleration(p1.I, to_local(p1.R, M_G1), p1.w_L)  # Eqs 5, 11
    wdot_L2 = euler_angular_acceleration(p2.I, to_local(p2.R, M_G2), p2.w_L)  # Eqs 6, 12
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
    """
    x0, _ = relative_accelerations(p1, p2, (0, 0, 0))
    cols = [relative_accelerations(p1, p2, tuple(sp.eye(3)[:, k]))[0] - x0 for k in range(3)]
    A = sp.Matrix.hstack(*cols)
    return A.applyfunc(sp.cancel) if simplify else A


def rotation_terms(p1: RigidParticle, p2: RigidParticle) -> sp.Matrix:
    """``Omega`` of Eq (25): ``xdd_c`` at ``F = 0``, ``M = 0`` (velocity-dependent terms only)."""
    xdd, _ = relative_accelerations(p1, p2, (0, 0, 0))
    return xdd.applyfunc(lambda e: sp.factor(sp.cancel(e)))


def relative_angular_acceleration(p1: RigidParticle, p2: RigidParticle) -> sp.Matrix:
    """``wdot_c`` at ``F = 0``, ``M = 0`` (Eqs 50-52: the gyroscopic terms of Euler's equations)."""
    _, wdot = relative_accelerations(p1, p2, (0, 0, 0))
    return wdot.applyfunc(lambda e: sp.factor(sp.cancel(e)))


def check_affine_in_force(p1: RigidParticle, p2: RigidParticle) -> bool:
    """``xdd_c(F) == A F + Omega`` identically (the decomposition of Eq 25 is exact)."""
    xdd, _ = relative_accelerations(p1, p2, F_SYMBOLS)
    A = xdd.jacobian(sp.Matrix(F_SYMBOLS))
    Om = xdd.subs({f: 0 for f in F_SYMBOLS})
    constant_jacobian = all(sp.diff(A[i, j], f) == 0 for i in range(3) for j in range(3) for f in F_SYMBOLS)
    return constant_jacobian and (xdd - A * sp.Matrix(F_SYMBOLS) - Om).applyfunc(sp.simplify) == sp.zeros(3, 1)


# ----------------------------------------------------------------------------------------------
# Closed forms of the coefficient matrix
# ----------------------------------------------------------------------------------------------


def arm_term(r_local, I: sp.Matrix) -> sp.Matrix:
    """The rotational part one particle adds to the coefficient matrix, in its own local frame.

    Obtained from the general kinematics (particle 2 of :func:`relative_accelerations` with
    ``R = 1``, infinite-mass partner and rigid partner), not typed in; it equals
    ``[r]x^T I^{-1} [r]x`` (checked by :func:`check_arm_term_closed_form`).
    """
    inf_partner = RigidParticle(m=sp.oo, I=sp.eye(3), R=sp.eye(3), r=sp.zeros(3, 1))
    body = RigidParticle(m=sp.Symbol("m_dummy", positive=True), I=I, R=sp.eye(3), r=sp.Matrix(r_local))
    A = coefficient_matrix(inf_partner, body)
    return (A - sp.eye(3) / body.m).applyfunc(sp.cancel)


def check_arm_term_closed_form(r_local, I: sp.Matrix) -> bool:
    X = skew(r_local)
    return (arm_term(r_local, I) - X.T * I.inv() * X).applyfunc(sp.simplify) == sp.zeros(3, 3)


def a_max_printed(m1, Ixx1, a1, m2, Ixx2, a2) -> sp.Expr:
    """Peng et al. 2020, Eq (26) as printed: ``a1^2/Ixx1 + a2^2/Ixx2 + 1/m1 + 1/m2``."""
    return a1**2 / Ixx1 + a2**2 / Ixx2 + 1 / m1 + 1 / m2


def b_max_printed(Ixx, Iyy, Izz) -> sp.Expr:
    """Peng et al. 2020, Eq (54): ``max(|Ixx-Iyy|/Izz, |Ixx-Izz|/Iyy, |Iyy-Izz|/Ixx)``."""
    return sp.Max(sp.Abs(Ixx - Iyy) / Izz, sp.Abs(Ixx - Izz) / Iyy, sp.Abs(Iyy - Izz) / Ixx)


def sphere_pair_check() -> dict[str, object]:
    """Two identical spheres (mass ``m``, radius ``rho``, ``I = 2/5 m rho^2``) in contact along an
    arbitrary unit normal ``n``, with arbitrary unit quaternions for both, through the general
    kinematics.  Returns the residual ``A - (2/m 1 + 5/m (1 - n n^T))`` reduced modulo the three
    unit-norm constraints (zero matrix when the closed form holds), the eigenvalues of the closed
    form and ``A_max`` of Eq (26) for the same spheres.
    """
    m, rho = sp.symbols("m rho", positive=True)
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    q1 = sp.symbols("q_w1 q_x1 q_y1 q_z1", real=True)
    q2 = sp.symbols("q_w2 q_x2 q_y2 q_z2", real=True)
    I = inertia_tensor(*(sp.Rational(2, 5) * m * rho**2,) * 3)
    p1 = RigidParticle(m, I, quaternion_rotation_matrix(q1), rho * n)
    p2 = RigidParticle(m, I, quaternion_rotation_matrix(q2), -rho * n)
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
        "a_max_eq26": sp.simplify(a_max_printed(m, I[0, 0], rho, m, I[0, 0], rho)),
    }


# ----------------------------------------------------------------------------------------------
# Symbols for two particles and the Figure 2 configurations
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ParticleSymbols:
    """Mass, principal moments, half-lengths and angular-velocity components of particle ``j``."""

    j: int

    def _s(self, name, **kw):
        return sp.Symbol(f"{name}{self.j}", **kw)

    @property
    def m(self):
        return self._s("m", positive=True)

    @property
    def Ixx(self):
        return self._s("I_xx", positive=True)

    @property
    def Iyy(self):
        return self._s("I_yy", positive=True)

    @property
    def Izz(self):
        return self._s("I_zz", positive=True)

    @property
    def half_lengths(self):
        return tuple(self._s(n, positive=True) for n in ("a", "b", "c"))

    @property
    def w(self):
        return sp.Matrix([self._s(f"omega_{c}", real=True) for c in "xyz"])

    @property
    def I(self):
        return inertia_tensor(self.Ixx, self.Iyy, self.Izz)


P1, P2 = ParticleSymbols(1), ParticleSymbols(2)


@dataclass(frozen=True)
class TipConfiguration:
    """A tip-to-tip configuration: each particle's rotation (global -> local, Eq 5) and the body axis
    (0 = x, 1 = y, 2 = z) and sign of its contact arm, ``r_local = sign * half_length * e_axis``."""

    label: str
    R1: sp.ImmutableMatrix
    arm1: tuple[int, int]
    R2: sp.ImmutableMatrix
    arm2: tuple[int, int]

    def arm_local(self, j: int) -> sp.Matrix:
        ps = P1 if j == 1 else P2
        axis, sign = self.arm1 if j == 1 else self.arm2
        return sign * ps.half_lengths[axis] * sp.eye(3)[:, axis]

    def arm_global(self, j: int) -> sp.Matrix:
        R = self.R1 if j == 1 else self.R2
        return to_global(sp.Matrix(R), self.arm_local(j))

    def quaternions(self) -> tuple[tuple, tuple]:
        return quaternion_from_matrix(self.R1), quaternion_from_matrix(self.R2)

    def particles(self, w_is_local: bool = False, rotate=None) -> tuple[RigidParticle, RigidParticle]:
        """Both particles, optionally with the whole pair turned by the global rotation ``rotate``
        (a matrix ``Q``: global vectors ``v -> Q v``, so ``R_j -> R_j Q^T`` and ``r_j -> Q r_j``)."""
        Q = sp.eye(3) if rotate is None else sp.Matrix(rotate)
        out = []
        for j, ps in ((1, P1), (2, P2)):
            R = sp.Matrix(self.R1 if j == 1 else self.R2) * Q.T
            out.append(RigidParticle(ps.m, ps.I, R, Q * self.arm_global(j), ps.w, w_is_local))
        return tuple(out)

    def normals_opposite(self) -> bool:
        """At a tip of a centrally symmetric body aligned with its principal axes the outward normal is
        along the arm; a contact of two smooth bodies needs opposite normals, i.e. antiparallel arms."""
        u1, u2 = self.arm_global(1), self.arm_global(2)
        return sp.simplify(u1.dot(u2) + u1.norm() * u2.norm()) == 0


def _rows(*axes) -> sp.ImmutableMatrix:
    """Rotation whose rows (the body axes in global components) are the given signed unit axes."""
    e = sp.eye(3)
    M = sp.Matrix.vstack(*[sign * e[:, k].T for k, sign in axes])
    if M.det() != 1:
        raise ValueError("not a proper rotation")
    return sp.ImmutableMatrix(M)


# The three configurations of Figure 2, as reconstructed in derivations/sec2_3_kinematics.py by
# enumerating every axis-aligned tip-to-tip candidate against the printed Eqs (22)-(24) and (50)-(52).
# Particle 1 is axis aligned in all three (as in Appendix A).  ``_rows`` lists the body axes of
# particle 2 in global components.
IDENTITY = _rows((0, 1), (1, 1), (2, 1))
FIG2 = {
    # (A): particle 1's a1-tip (+a1 e_x) against particle 2's a2-tip; particle 2's body axes are
    #      (-e_z, -e_y, -e_x), so its arm is -a2 e_z (orthogonal to r1: not an admissible contact).
    "A": TipConfiguration("A", IDENTITY, (0, 1), _rows((2, -1), (1, -1), (0, -1)), (0, 1)),
    # (B): particle 1's c1-tip (+c1 e_z) against particle 2's a2-tip (-a2 e_z), particle 2 as in (A).
    "B": TipConfiguration("B", IDENTITY, (2, 1), _rows((2, -1), (1, -1), (0, -1)), (0, 1)),
    # (C): particle 1 as in (B); particle 2's body axes are (e_y, e_z, e_x), so the tip on the
    #      contact line is its b2-tip (-b2 e_z); the paper prints the arm length as a2.
    "C": TipConfiguration("C", IDENTITY, (2, 1), _rows((1, 1), (2, 1), (0, 1)), (1, -1)),
}


def candidate_configurations() -> list[TipConfiguration]:
    """Every axis-aligned tip-to-tip candidate with particle 1 axis aligned: 6 arms of particle 1 x
    24 rotations x 6 arms of particle 2 (864 in all), in a fixed order."""
    out = []
    tips = [(axis, sign) for axis in range(3) for sign in (1, -1)]
    for arm1 in tips:
        for k, R2 in enumerate(axis_rotations()):
            for arm2 in tips:
                out.append(TipConfiguration(f"cand{len(out)}", IDENTITY, arm1, sp.ImmutableMatrix(R2), arm2))
    return out


def ordering_substitution() -> tuple[dict, list[sp.Symbol]]:
    """Assumption 3 as a substitution with non-negative slacks, for both particles:
    ``I_yy = I_xx + u``, ``I_zz = I_xx + u + v``, ``b = c + p``, ``a = c + p + q``."""
    subs, slack = {}, []
    for ps in (P1, P2):
        j = ps.j
        u, v, p, q = sp.symbols(f"u{j} v{j} p{j} q{j}", nonnegative=True)
        a, b, c = ps.half_lengths
        subs.update({ps.Iyy: ps.Ixx + u, ps.Izz: ps.Ixx + u + v, b: c + p, a: c + p + q})
        slack += [u, v, p, q]
    return subs, slack


def nonnegativity_certificate(expr: sp.Expr) -> bool:
    """True when ``expr`` (after :func:`ordering_substitution`) is a ratio of polynomials in
    positive symbols and non-negative slacks whose coefficients are all non-negative, so that
    ``expr >= 0`` under assumption 3 for every admissible value."""
    subs, _ = ordering_substitution()
    num, den = sp.fraction(sp.together(sp.expand(expr.subs(subs))))
    num, den = sp.expand(num), sp.expand(den)
    if num == 0:
        return True
    def coefficients(x):
        return sp.Poly(x, *sorted(x.free_symbols, key=str)).coeffs() if x.free_symbols else [x]

    return all(c >= 0 for c in coefficients(num)) and all(c >= 0 for c in coefficients(den))


def eq26_dominates(label: str) -> dict[str, bool]:
    """For one Figure 2 configuration: ``A_max - A_kk >= 0`` under assumption 3 (certificate per entry)."""
    A = fig2_symbolic(label, True)["A"]
    amax = a_max_printed(P1.m, P1.Ixx, P1.half_lengths[0], P2.m, P2.Ixx, P2.half_lengths[0])
    return {f"A_{'xyz'[k]}": nonnegativity_certificate(amax - A[k, k]) for k in range(3)}


# ----------------------------------------------------------------------------------------------
# Rotation-dominant terms (Section 5)
# ----------------------------------------------------------------------------------------------


def gyroscopic_coefficients(Ixx, Iyy, Izz) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """``(c_x, c_y, c_z)`` with torque-free Euler equations ``wdot_x = c_x w_y w_z`` etc.

    Read off from :func:`euler_angular_acceleration` (Eqs 11-12 with ``M_L = 0``), not typed in.
    """
    w = sp.Matrix(sp.symbols("u_x u_y u_z", real=True))
    wdot = euler_angular_acceleration(inertia_tensor(Ixx, Iyy, Izz), sp.zeros(3, 1), w)
    pairs = ((1, 2), (2, 0), (0, 1))
    return tuple(sp.cancel(sp.diff(wdot[i], w[j], w[k])) for i, (j, k) in enumerate(pairs))


@lru_cache(maxsize=None)
def fig2_symbolic(label: str, w_is_local: bool) -> dict[str, sp.Matrix]:
    """Coefficient matrix, Omega terms and wdot_c for one Figure 2 configuration."""
    p1, p2 = FIG2[label].particles(w_is_local=w_is_local)
    return {
        "A": coefficient_matrix(p1, p2),
        "Omega": rotation_terms(p1, p2),
        "wdot_c": relative_angular_acceleration(p1, p2),
    }


# ----------------------------------------------------------------------------------------------
# The printed Eqs (22)-(24) and (50)-(52), transcribed from the text-extracted seed
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PrintedEntry:
    """One entry of a printed equation: the extracted text, the readings it admits (SymPy syntax in
    the names of :func:`printed_symbols`; several when the extraction is ambiguous, none when it is
    illegible) and the fixes applied."""

    equation: str
    entry: str
    raw: str
    readings: tuple[str, ...]
    fixes: str = ""

    @property
    def legible(self) -> bool:
        return bool(self.readings)


def printed_symbols() -> dict[str, sp.Symbol]:
    """Names used in the transcriptions: m1, Ixx1, Iyy1, Izz1, a1, b1, c1, wx1, wy1, wz1 (and ...2)."""
    out = {}
    for j, ps in ((1, P1), (2, P2)):
        out.update({f"m{j}": ps.m, f"Ixx{j}": ps.Ixx, f"Iyy{j}": ps.Iyy, f"Izz{j}": ps.Izz})
        out.update({f"{n}{j}": s for n, s in zip("abc", ps.half_lengths)})
        out.update({f"w{c}{j}": s for c, s in zip("xyz", ps.w)})
    return out


def parse_reading(text: str) -> sp.Expr:
    return sp.sympify(text, locals=printed_symbols())


_MU = "1/m1 + 1/m2"
_Z_OR_X1 = ("Izz1", "Ixx1")


def _alts(template: str, **choices) -> tuple[str, ...]:
    """All readings of ``template`` with each ``{name}`` replaced by each of its alternatives."""
    out = [template]
    for name, options in choices.items():
        out = [t.replace("{" + name + "}", o) for t in out for o in options]
    return tuple(out)


PRINTED: tuple[PrintedEntry, ...] = (
    # ---- Eq (22), Figure 2(A) ----
    PrintedEntry("22", "A_x", r"\frac{a_{2}^{2}}{I_{yy2}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"a2**2/Iyy2 + {_MU}",), "row printed without its two zero entries (layout)"),
    PrintedEntry("22", "A_y", r"0 & \frac{a_{1}^{2}}{I_{zz1}} + \frac{a_{2}^{2}}{I_{zz2}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"a1**2/Izz1 + a2**2/Izz2 + {_MU}",), "trailing zero missing (layout)"),
    PrintedEntry("22", "A_z", r"0 & 0 & \frac{a_{1}^{2}}{I_{yy1}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"a1**2/Iyy1 + {_MU}",)),
    PrintedEntry("22", "Omega_x",
                 r"a_{1}(\omega_{y1}^{2} + \omega_{z1}^{2}) + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{zz2} - I_{xx2} - I_{yy2})}{I_{yy2}}",
                 ("a1*(wy1**2 + wz1**2) + a2*wx2*wz2*(Izz2 - Ixx2 - Iyy2)/Iyy2",)),
    PrintedEntry("22", "Omega_y",
                 r"\frac{a_{1}\omega_{x1}\omega_{y1}(I_{yy1} - I_{zz1} - I_{xx1})}{I_{zz1}} + \frac{a_{2}\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2} - I_{xx2})}{I_{zy2}}",
                 _alts("a1*wx1*wy1*(Iyy1 - Izz1 - Ixx1)/Izz1 + a2*wy2*wz2*(Iyy2 - Izz2 - Ixx2)/{d}", d=("Izz2", "Iyy2")),
                 "I_{zy2} (a product of inertia, zero by assumption 2) read as I_zz2 or I_yy2"),
    PrintedEntry("22", "Omega_z",
                 r"\frac{a_{2}\omega_{x2}\omega_{x2}(I_{y2} - I_{xx2} - I_{xx2})}{I_{zz1}} + \frac{a_{2}\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2} - I_{xx2})}{I_{zy1}}",
                 (), "illegible: particle-2 velocities over particle-1 moments, repeated subscripts, second term copies Omega_y"),
    # ---- Eq (23), Figure 2(B) ----
    PrintedEntry("23", "A_x", r"\frac{c_{1}^{2}}{I_{yy1}} + \frac{a_{2}^{2}}{I_{yy2}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"c1**2/Iyy1 + a2**2/Iyy2 + {_MU}",)),
    PrintedEntry("23", "A_y", r"\frac{c_{1}^{2}}{I_{zx1}} + \frac{a_{2}^{2}}{I_{zz2}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 _alts(f"c1**2/{{z}} + a2**2/Izz2 + {_MU}", z=("Ixx1", "Izz1")),
                 "I_{zx1} (a product of inertia) read as I_xx1 or I_zz1"),
    PrintedEntry("23", "A_z", r"\frac{1}{m_{1}} + \frac{1}{m_{2}}", (_MU,)),
    PrintedEntry("23", "Omega_x",
                 r"\frac{c_{1}\omega_{x1}\omega_{z1}(I_{xx1} - I_{yy1} - I_{zx1})}{I_{yy1}} + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{zz2} - I_{xx2} - I_{yy2})}{I_{zy2}}",
                 _alts("c1*wx1*wz1*(Ixx1 - Iyy1 - {z})/Iyy1 + a2*wx2*wz2*(Izz2 - Ixx2 - Iyy2)/{d}", z=_Z_OR_X1, d=("Izz2", "Iyy2")),
                 "I_{zx1} read as I_zz1 or I_xx1; I_{zy2} read as I_zz2 or I_yy2"),
    PrintedEntry("23", "Omega_y",
                 r"\frac{c_{1}\omega_{y1}\omega_{z1}(I_{yy1} - I_{zx1})}{I_{xx1}} + \frac{a_{2}\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2} - I_{xx2})}{I_{zz2}}",
                 _alts("c1*wy1*wz1*(Iyy1 - {z})/Ixx1 + a2*wy2*wz2*(Iyy2 - Izz2 - Ixx2)/Izz2", z=_Z_OR_X1),
                 "I_{zx1} read as I_zz1 or I_xx1"),
    PrintedEntry("23", "Omega_z", "(row missing from the extraction)", (), "illegible: the extracted vector has two rows"),
    # ---- Eq (24), Figure 2(C) ----
    PrintedEntry("24", "A_x", r"\frac{a_{2}^{2}}{I_{xx2}} + \frac{c_{1}^{2}}{I_{yy1}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"a2**2/Ixx2 + c1**2/Iyy1 + {_MU}",)),
    PrintedEntry("24", "A_y", r"\frac{c_{1}^{2}}{I_{xx1}} + \frac{a_{2}^{2}}{I_{z22}} + \frac{1}{m_{1}} + \frac{1}{m_{2}}",
                 (f"c1**2/Ixx1 + a2**2/Izz2 + {_MU}",), "I_{z22} read as I_zz2 (digit 2 for the letter z)"),
    PrintedEntry("24", "A_z",
                 r"0 & 0 & \frac{c_{1}^{2}}{I_{xx1}} + \frac{a_{2}^{2}}{I_{x22}} + \frac{1}{m_{1}} + \frac{1}{m_{2}} & 0 \\ 0 & 0 & \frac{1}{m_{1}} + \frac{1}{m_{2}} & 0 \\ \dots",
                 (_MU, f"c1**2/Ixx1 + a2**2/Ixx2 + {_MU}"),
                 "the matrix is extracted with five rows; its last diagonal entry is read as 1/m1 + 1/m2 "
                 "(or, from the third row, c1^2/I_xx1 + a2^2/I_xx2 + 1/m1 + 1/m2 with I_{x22} as I_xx2)"),
    PrintedEntry("24", "Omega_x",
                 r"\frac{c_{1}\omega_{x1}\omega_{z1}(I_{xx1} - I_{yy1} - I_{zx1})}{I_{xx1}} + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{zz2} - I_{xx2} - I_{yy2})}{I_{xx2}}",
                 _alts("c1*wx1*wz1*(Ixx1 - Iyy1 - {z})/Ixx1 + a2*wx2*wz2*(Izz2 - Ixx2 - Iyy2)/Ixx2", z=_Z_OR_X1),
                 "I_{zx1} read as I_zz1 or I_xx1"),
    PrintedEntry("24", "Omega_y",
                 r"\frac{c_{1}\omega_{y1}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{xx1}} + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{zx2} - I_{yy2} - I_{zz2})}{I_{zz2}}",
                 _alts("c1*wy1*wz1*(Iyy1 - Izz1)/Ixx1 + a2*wx2*wz2*({z} - Iyy2 - Izz2)/Izz2", z=("Izz2", "Ixx2")),
                 "I_{zx2} read as I_zz2 or I_xx2"),
    PrintedEntry("24", "Omega_z",
                 r"\frac{c_{1}\omega_{y1}\omega_{z1}(I_{yy1} - I_{zz1} - I_{xx1})}{I_{xx1}} + \frac{a_{2}\omega_{x2}\omega_{z2}(I_{xz2} - I_{xx2} - I_{yy2})}{I_{zz2}}",
                 _alts("c1*wy1*wz1*(Iyy1 - Izz1 - Ixx1)/Ixx1 + a2*wx2*wz2*({z} - Ixx2 - Iyy2)/Izz2", z=("Ixx2", "Izz2")),
                 "I_{xz2} read as I_xx2 or I_zz2"),
    # ---- Eq (50), Figure 2(A) ----
    PrintedEntry("50", "wdot_x",
                 r"-\frac{\omega_{yl}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{xx1}} - \frac{\omega_{x2}\omega_{y2}(I_{xx2} - I_{yy2})}{I_{zz2}}",
                 ("-wy1*wz1*(Iyy1 - Izz1)/Ixx1 - wx2*wy2*(Ixx2 - Iyy2)/Izz2",), r"\omega_{yl} read as omega_y1 (letter l for digit 1)"),
    PrintedEntry("50", "wdot_y",
                 r"\frac{\omega_{x1}\omega_{z1}(I_{xx1} - I_{zz1})}{I_{yy1}} + \frac{\omega_{x2}\omega_{z2}(I_{xx2} - I_{zz2})}{I_{yy2}}",
                 ("wx1*wz1*(Ixx1 - Izz1)/Iyy1 + wx2*wz2*(Ixx2 - Izz2)/Iyy2",)),
    PrintedEntry("50", "wdot_z",
                 r"-\frac{\omega_{x1}\omega_{y1}(I_{xx1} - I_{yy1})}{I_{zz1}} - \frac{\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2})}{I_{xx2}}",
                 ("-wx1*wy1*(Ixx1 - Iyy1)/Izz1 - wy2*wz2*(Iyy2 - Izz2)/Ixx2",)),
    # ---- Eq (51), Figure 2(B): extracted twice; both renderings are readings ----
    PrintedEntry("51", "wdot_x",
                 r"(1) -\frac{\omega_{yl}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{zz1}} - \frac{\omega_{x2}\omega_{y2}(I_{xx2} - I_{yy2})}{I_{zz2}};  "
                 r"(2) -\frac{\omega_{yl}\omega_{z1}(l_{yy1} - l_{zz1})}{I_{zx1}} - \frac{\omega_{x2}\omega_{y2}(l_{xx2} - l_{yy2})}{I_{zz2}}",
                 ("-wy1*wz1*(Iyy1 - Izz1)/Izz1 - wx2*wy2*(Ixx2 - Iyy2)/Izz2",
                  *_alts("-wy1*wz1*(Iyy1 - Izz1)/{z} - wx2*wy2*(Ixx2 - Iyy2)/Izz2", z=_Z_OR_X1)),
                 r"two renderings; \omega_{yl} as omega_y1, l as I, I_{zx1} read as I_zz1 or I_xx1"),
    PrintedEntry("51", "wdot_y",
                 r"(1) -\frac{\omega_{x1}\omega_{z1}(I_{xx1} - I_{zz1})}{I_{yy1}} + \frac{\omega_{x2}\omega_{x2}(I_{xx2} - I_{zz2})}{I_{xx2}};  "
                 r"(2) \frac{\omega_{x1}\omega_{z1}(l_{xx1} - l_{zz1})}{I_{yy1}} + \frac{\omega_{x2}\omega_{z2}(l_{xx2} - l_{zz2})}{I_{yy2}}",
                 ("-wx1*wz1*(Ixx1 - Izz1)/Iyy1 + wx2*wx2*(Ixx2 - Izz2)/Ixx2",
                  "wx1*wz1*(Ixx1 - Izz1)/Iyy1 + wx2*wz2*(Ixx2 - Izz2)/Iyy2"),
                 "two renderings; l as I"),
    PrintedEntry("51", "wdot_z",
                 r"(1) -\frac{\omega_{x1}\omega_{y1}(I_{xx1} - I_{yy1})}{I_{zz1}} - \frac{\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2})}{I_{xx2}};  "
                 r"(2) -\frac{\omega_{xl}\omega_{y1}(l_{xx1} - l_{yy1})}{I_{zx1}} - \frac{\omega_{y2}\omega_{z2}(l_{yy2} - l_{zz2})}{I_{zz2}}",
                 ("-wx1*wy1*(Ixx1 - Iyy1)/Izz1 - wy2*wz2*(Iyy2 - Izz2)/Ixx2",
                  *_alts("-wx1*wy1*(Ixx1 - Iyy1)/{z} - wy2*wz2*(Iyy2 - Izz2)/Izz2", z=_Z_OR_X1)),
                 r"two renderings; \omega_{xl} as omega_x1, l as I, I_{zx1} read as I_zz1 or I_xx1"),
    # ---- Eq (52), Figure 2(C): extracted twice ----
    PrintedEntry("52", "wdot_x",
                 r"(1) -\frac{\omega_{yl}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{zz1}} + \frac{\omega_{x2}\omega_{y2}(I_{xx2} - I_{yy2})}{I_{xx2}};  "
                 r"(2) -\frac{\omega_{yl}\omega_{z1}(I_{yy1} - I_{zz1})}{I_{xx1}} + \frac{\omega_{x2}\omega_{y2}(I_{xx2} - I_{yy2})}{I_{zz2}}",
                 ("-wy1*wz1*(Iyy1 - Izz1)/Izz1 + wx2*wy2*(Ixx2 - Iyy2)/Ixx2",
                  "-wy1*wz1*(Iyy1 - Izz1)/Ixx1 + wx2*wy2*(Ixx2 - Iyy2)/Izz2"),
                 r"two renderings; \omega_{yl} as omega_y1"),
    PrintedEntry("52", "wdot_y",
                 r"(1) -\frac{\omega_{x1}\omega_{y1}(I_{yy1} - I_{zz1})}{I_{yy1}} + \frac{\omega_{x2}\omega_{y2}(I_{yy2} - I_{zz2})}{I_{xx2}};  "
                 r"(2) \frac{\omega_{x1}\omega_{z1}(I_{xx1} - I_{zz1})}{I_{yy1}} + \frac{\omega_{y2}\omega_{z2}(I_{yy2} - I_{zz2})}{I_{xx2}}",
                 ("-wx1*wy1*(Iyy1 - Izz1)/Iyy1 + wx2*wy2*(Iyy2 - Izz2)/Ixx2",
                  "wx1*wz1*(Ixx1 - Izz1)/Iyy1 + wy2*wz2*(Iyy2 - Izz2)/Ixx2"),
                 "two renderings"),
    PrintedEntry("52", "wdot_z",
                 r"(1) -\frac{\omega_{x1}\omega_{y1}(I_{xx1} - I_{yy1})}{I_{xy1}} - \frac{\omega_{x2}\omega_{z2}(I_{yy2} - I_{zz2})}{I_{xy2}};  "
                 r"(2) -\frac{\omega_{x1}\omega_{y1}(I_{xx1} - I_{yy1})}{I_{zz1}} - \frac{\omega_{x2}\omega_{z2}(I_{xx2} - I_{zz2})}{I_{yy2}}",
                 (*_alts("-wx1*wy1*(Ixx1 - Iyy1)/{d1} - wx2*wz2*(Iyy2 - Izz2)/{d2}", d1=("Ixx1", "Iyy1"), d2=("Ixx2", "Iyy2")),
                  "-wx1*wy1*(Ixx1 - Iyy1)/Izz1 - wx2*wz2*(Ixx2 - Izz2)/Iyy2"),
                 "two renderings; in (1) the products of inertia I_{xy1}, I_{xy2} read as I_xx or I_yy"),
)

PANELS = {"A": ("22", "50"), "B": ("23", "51"), "C": ("24", "52")}
ENTRY_INDEX = {"A_x": ("A", 0), "A_y": ("A", 1), "A_z": ("A", 2), "Omega_x": ("Omega", 0), "Omega_y": ("Omega", 1),
               "Omega_z": ("Omega", 2), "wdot_x": ("wdot_c", 0), "wdot_y": ("wdot_c", 1), "wdot_z": ("wdot_c", 2)}


def printed_entries(equation: str) -> list[PrintedEntry]:
    return [e for e in PRINTED if e.equation == equation]


def derived_entry(derived: dict[str, sp.Matrix], entry: str) -> sp.Expr:
    part, i = ENTRY_INDEX[entry]
    M = derived[part]
    return M[i, i] if part == "A" else M[i]


def compare_entry(derived: sp.Expr, e: PrintedEntry, substitutions: dict | None = None) -> int | None:
    """Index of the first reading identical to ``derived`` (SymPy, exact), -1 if none, None if illegible."""
    if not e.legible:
        return None
    for k, text in enumerate(e.readings):
        printed = parse_reading(text).subs(substitutions or {})
        if sp.simplify(sp.cancel(derived - printed)) == 0:
            return k
    return -1


# ----------------------------------------------------------------------------------------------
# Reconstruction of the Figure 2 configurations: every candidate against the printed entries
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CandidateScore:
    """How many legible printed entries one candidate reproduces, per part, and the matches.

    ``matches`` maps an entry name to the index of the reading it reproduces (-1: differs,
    None: illegible).  ``w_is_local``: omega symbols read as local (body) components;
    ``arm_length``: printed a2 read as the length of particle 2's arm (its half-length along the
    arm) rather than literally as its largest half-length.
    """

    panel: str
    index: int
    w_is_local: bool
    arm_length: bool
    matches: dict

    @property
    def total(self) -> int:
        return sum(1 for v in self.matches.values() if v is not None and v >= 0)

    def part(self, prefix: str) -> int:
        return sum(1 for k, v in self.matches.items() if k.startswith(prefix) and v is not None and v >= 0)


@lru_cache(maxsize=None)
def _general_pair_function(w_is_local: bool):
    """NumPy function of (particle symbols..., R1 (9), R2 (9), local arm 1 (3), local arm 2 (3))
    returning the 9 entries of A, the 3 of Omega and the 3 of wdot_c, from the general kinematics."""
    import numpy as np  # noqa: F401  (lambdify target)

    Rs = [sp.Matrix(3, 3, sp.symbols(f"R{j}_0:9")) for j in (1, 2)]
    arms = [sp.Matrix(sp.symbols(f"s{j}_0:3")) for j in (1, 2)]
    ps = [RigidParticle(s.m, s.I, R, to_global(R, arm), s.w, w_is_local) for s, R, arm in zip((P1, P2), Rs, arms)]
    # xdd_c is affine in F: column k of A is xdd_c(F = e_k) - xdd_c(F = 0)
    xdd0, wdot0 = relative_accelerations(ps[0], ps[1], (0, 0, 0))
    cols = [relative_accelerations(ps[0], ps[1], tuple(sp.eye(3)[:, k]))[0] - xdd0 for k in range(3)]
    exprs = list(sp.Matrix.hstack(*cols)) + list(xdd0) + list(wdot0)
    names = sorted(printed_symbols().items())
    args = [s for _, s in names] + list(Rs[0]) + list(Rs[1]) + list(arms[0]) + list(arms[1])
    return [n for n, _ in names], sp.lambdify(args, exprs, modules="numpy")


@lru_cache(maxsize=None)
def score_candidates(points: int = 2, seed: int = 20200) -> tuple[CandidateScore, ...]:
    """Score every candidate of :func:`candidate_configurations` against every panel's printed
    entries, for both readings of the omega symbols and both readings of printed ``a2``.

    The general kinematics is evaluated in floating point at ``points`` random parameter sets
    (all values in [0.5, 3]); an entry matches a reading when they agree to 1e-10 relative at
    all points.  Candidates chosen this way are re-checked exactly with SymPy in the records.
    """
    import numpy as np

    cands = candidate_configurations()
    N = len(cands)
    rng = np.random.default_rng(seed)
    R1 = np.array([[float(x) for x in c.R1] for c in cands]).T
    R2 = np.array([[float(x) for x in c.R2] for c in cands]).T
    length_name = {0: "a2", 1: "b2", 2: "c2"}
    out = []
    values = {}
    for lw in (False, True):
        names, fn = _general_pair_function(lw)
        for k in range(points):
            pt = {n: float(v) for n, v in zip(names, rng.uniform(0.5, 3.0, len(names)))}
            s1, s2 = np.zeros((3, N)), np.zeros((3, N))
            for n, c in enumerate(cands):
                s1[c.arm1[0], n] = c.arm1[1] * pt["abc"[c.arm1[0]] + "1"]
                s2[c.arm2[0], n] = c.arm2[1] * pt["abc"[c.arm2[0]] + "2"]
            res = fn(*([np.full(N, pt[n]) for n in names] + list(R1) + list(R2) + list(s1) + list(s2)))
            values[(lw, k)] = (pt, [np.broadcast_to(np.asarray(r, float), (N,)) for r in res])
    position = {"A": lambda i: 4 * i, "Omega": lambda i: 9 + i, "wdot_c": lambda i: 12 + i}
    symbols = printed_symbols()
    order = sorted(symbols, key=lambda n: str(symbols[n]))
    arm2_length = np.array([length_name[c.arm2[0]] for c in cands])
    printed_values: dict[tuple, np.ndarray] = {}
    printed_functions: dict[str, object] = {}

    def printed(text: str, lw: bool, k: int, arm_len: bool) -> np.ndarray:
        key = (text, lw, k, arm_len)
        if key not in printed_values:
            if text not in printed_functions:
                printed_functions[text] = sp.lambdify([symbols[n] for n in order], parse_reading(text), modules="numpy")
            fn = printed_functions[text]
            pt = values[(lw, k)][0]
            args = {n: np.full(N, pt[n]) for n in order}
            if arm_len:
                args["a2"] = np.array([pt[name] for name in arm2_length])
            printed_values[key] = np.broadcast_to(np.asarray(fn(*[args[n] for n in order]), float), (N,))
        return printed_values[key]

    for panel, eqs in PANELS.items():
        entries = [e for eq in eqs for e in printed_entries(eq)]
        for lw in (False, True):
            for arm_len in (False, True):
                table = {}
                for e in entries:
                    if not e.legible:
                        table[e.entry] = np.full(N, -2)
                        continue
                    part, i = ENTRY_INDEX[e.entry]
                    got = np.full(N, -1)
                    for r in reversed(range(len(e.readings))):
                        ok = np.ones(N, dtype=bool)
                        for k in range(points):
                            res = values[(lw, k)][1]
                            ok &= np.isclose(res[position[part](i)], printed(e.readings[r], lw, k, arm_len),
                                             rtol=1e-10, atol=1e-12)
                        got[ok] = r
                    table[e.entry] = got
                for n in range(N):
                    matches = {k: (None if v[n] == -2 else int(v[n])) for k, v in table.items()}
                    out.append(CandidateScore(panel, n, lw, arm_len, matches))
    return tuple(out)


def best_candidates(panel: str) -> list[CandidateScore]:
    """The highest-scoring candidates of a panel (ties kept, in a fixed order): most reproduced
    legible entries; ties broken by preferring the literal reading of a2, then admissible
    contacts (opposite normals at the two tips)."""
    cands = candidate_configurations()
    scores = [s for s in score_candidates() if s.panel == panel]
    top = max(s.total for s in scores)
    best = [s for s in scores if s.total == top]
    best = [s for s in best if not s.arm_length] or best
    return [s for s in best if cands[s.index].normals_opposite()] or best
