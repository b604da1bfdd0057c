"""The tip-to-tip contact configurations of Peng et al. (2020), Figure 2 and Appendix A: symbolic
particles, the candidate configurations, Eq. (26)'s dominance certificates and the Figure 2
symbolic accelerations.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from dtcrit.symbolic.coefficient_forms import a_max_printed
from dtcrit.symbolic.kinematics import (
    RigidParticle,
    coefficient_matrix,
    euler_angular_acceleration,
    inertia_tensor,
    relative_angular_acceleration,
    rotation_terms,
    to_global,
)
from dtcrit.symbolic.quaternions import axis_rotations, quaternion_from_matrix

# ----------------------------------------------------------------------------------------------
# Symbols for two particles and the Figure 2 configurations
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ParticleSymbols:
    """Mass, principal moments, half-lengths and angular-velocity components of particle ``j``.

    Parameters
    ----------
    j : int
        The particle's number (1 or 2), the suffix of its symbols.
    """

    j: int

    def _s(self, name, **kw):
        return sp.Symbol(f"{name}{self.j}", **kw)

    @property
    def m(self):
        """The mass ``m_j`` (positive symbol)."""
        return self._s("m", positive=True)

    @property
    def Ixx(self):
        """The principal moment ``I_xx_j`` (positive symbol)."""
        return self._s("I_xx", positive=True)

    @property
    def Iyy(self):
        """The principal moment ``I_yy_j`` (positive symbol)."""
        return self._s("I_yy", positive=True)

    @property
    def Izz(self):
        """The principal moment ``I_zz_j`` (positive symbol)."""
        return self._s("I_zz", positive=True)

    @property
    def half_lengths(self):
        """The half-lengths ``(a_j, b_j, c_j)`` along the local x, y, z axes (positive symbols)."""
        return tuple(self._s(n, positive=True) for n in ("a", "b", "c"))

    @property
    def w(self):
        """The angular velocity ``(omega_x_j, omega_y_j, omega_z_j)`` (real symbols, 3x1)."""
        return sp.Matrix([self._s(f"omega_{c}", real=True) for c in "xyz"])

    @property
    def inertia(self):
        """The local inertia tensor ``diag(I_xx_j, I_yy_j, I_zz_j)`` (principal axes)."""
        return inertia_tensor(self.Ixx, self.Iyy, self.Izz)


P1, P2 = ParticleSymbols(1), ParticleSymbols(2)


@dataclass(frozen=True)
class TipConfiguration:
    """A tip-to-tip configuration: each particle's rotation (global -> local, Eq 5) and the body axis
    (0 = x, 1 = y, 2 = z) and sign of its contact arm, ``r_local = sign * half_length * e_axis``.

    Parameters
    ----------
    label : str
        The configuration's name (a Figure 2 panel or a candidate's index).
    R1 : sympy.ImmutableMatrix
        Rotation of particle 1, global -> local.
    arm1 : tuple of (int, int)
        (axis, sign) of particle 1's arm.
    R2 : sympy.ImmutableMatrix
        Rotation of particle 2, global -> local.
    arm2 : tuple of (int, int)
        (axis, sign) of particle 2's arm.
    """

    label: str
    R1: sp.ImmutableMatrix
    arm1: tuple[int, int]
    R2: sp.ImmutableMatrix
    arm2: tuple[int, int]

    def arm_local(self, j: int) -> sp.Matrix:
        """The contact arm of particle ``j`` in its local components.

        Parameters
        ----------
        j : int
            1 or 2.

        Returns
        -------
        sympy.Matrix
            ``sign * half_length * e_axis`` (3x1).
        """
        ps = P1 if j == 1 else P2
        axis, sign = self.arm1 if j == 1 else self.arm2
        return sign * ps.half_lengths[axis] * sp.eye(3)[:, axis]

    def arm_global(self, j: int) -> sp.Matrix:
        """The contact arm of particle ``j`` in global components.

        Parameters
        ----------
        j : int
            1 or 2.

        Returns
        -------
        sympy.Matrix
            ``R_j^T r_local`` (3x1).
        """
        R = self.R1 if j == 1 else self.R2
        return to_global(sp.Matrix(R), self.arm_local(j))

    def quaternions(self) -> tuple[tuple, tuple]:
        """The particles' orientation quaternions, body to world (dtcrit's one convention): ``R_j^T = R(q_j)``
        with ``R_j`` the paper's Eq. (5) matrix (world to body).

        Returns
        -------
        tuple of tuple
            ``(q_1, q_2)``, each ``(w, x, y, z)``.
        """
        return quaternion_from_matrix(sp.Matrix(self.R1).T), quaternion_from_matrix(sp.Matrix(self.R2).T)

    def particles(self, w_is_local: bool = False, rotate=None) -> tuple[RigidParticle, RigidParticle]:
        """Both particles, optionally with the whole pair turned by the global rotation ``rotate``
        (a matrix ``Q``: global vectors ``v -> Q v``, so ``R_j -> R_j Q^T`` and ``r_j -> Q r_j``).

        Parameters
        ----------
        w_is_local : bool
            Read the angular-velocity symbols as local (body) components.
        rotate : sympy.Matrix, optional
            The global rotation ``Q``.

        Returns
        -------
        tuple of RigidParticle
            Particles 1 and 2.
        """
        Q = sp.eye(3) if rotate is None else sp.Matrix(rotate)
        out = []
        for j, ps in ((1, P1), (2, P2)):
            R = sp.Matrix(self.R1 if j == 1 else self.R2) * Q.T
            out.append(RigidParticle(ps.m, ps.inertia, R, Q * self.arm_global(j), ps.w, w_is_local))
        return out[0], out[1]

    def normals_opposite(self) -> bool:
        """At a tip of a centrally symmetric body aligned with its principal axes the outward normal is
        along the arm; a contact of two smooth bodies needs opposite normals, i.e. antiparallel arms.

        Returns
        -------
        bool
            True when the two arms are antiparallel in global components.
        """
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
    24 rotations x 6 arms of particle 2 (864 in all), in a fixed order.

    Returns
    -------
    list of TipConfiguration
        The candidates.
    """
    out: list[TipConfiguration] = []
    tips = [(axis, sign) for axis in range(3) for sign in (1, -1)]
    for arm1 in tips:
        for k, R2 in enumerate(axis_rotations()):
            for arm2 in tips:
                out.append(TipConfiguration(f"cand{len(out)}", IDENTITY, arm1, sp.ImmutableMatrix(R2), arm2))
    return out


def ordering_substitution() -> tuple[dict, list[sp.Symbol]]:
    """Assumption 3 as a substitution with non-negative slacks, for both particles:
    ``I_yy = I_xx + u``, ``I_zz = I_xx + u + v``, ``b = c + p``, ``a = c + p + q``.

    Returns
    -------
    tuple of (dict, list of sympy.Symbol)
        The substitution and its slack symbols.
    """
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
    ``expr >= 0`` under assumption 3 for every admissible value.

    Parameters
    ----------
    expr : sympy.Expr
        The expression to certify.

    Returns
    -------
    bool
        Whether the certificate holds (False does not prove ``expr < 0``).
    """
    subs, _ = ordering_substitution()
    num, den = sp.fraction(sp.together(sp.expand(expr.subs(subs))))
    num, den = sp.expand(num), sp.expand(den)
    if num == 0:
        return True
    def coefficients(x):
        return sp.Poly(x, *sorted(x.free_symbols, key=str)).coeffs() if x.free_symbols else [x]

    return all(c >= 0 for c in coefficients(num)) and all(c >= 0 for c in coefficients(den))


def eq26_dominates(label: str) -> dict[str, bool]:
    """For one Figure 2 configuration: ``A_max - A_kk >= 0`` under assumption 3 (certificate per entry).

    Parameters
    ----------
    label : str
        The Figure 2 panel.

    Returns
    -------
    dict of str to bool
        ``{"A_x": ..., "A_y": ..., "A_z": ...}``.
    """
    A = fig2_symbolic(label, True)["A"]
    amax = a_max_printed(P1.m, P1.Ixx, P1.half_lengths[0], P2.m, P2.Ixx, P2.half_lengths[0])
    return {f"A_{'xyz'[k]}": nonnegativity_certificate(amax - A[k, k]) for k in range(3)}


# ----------------------------------------------------------------------------------------------
# Rotation-dominant terms (Section 5)
# ----------------------------------------------------------------------------------------------


def gyroscopic_coefficients(Ixx, Iyy, Izz) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """``(c_x, c_y, c_z)`` with torque-free Euler equations ``wdot_x = c_x w_y w_z`` etc.

    Read off from :func:`euler_angular_acceleration` (Eqs 11-12 with ``M_L = 0``), not typed in.

    Parameters
    ----------
    Ixx, Iyy, Izz : sympy.Expr
        Principal moments of inertia.

    Returns
    -------
    tuple of sympy.Expr
        ``(c_x, c_y, c_z)``, e.g. ``c_x = (I_yy - I_zz)/I_xx``.
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
