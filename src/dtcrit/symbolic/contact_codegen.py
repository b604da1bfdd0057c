"""Emit ``dtcrit/_generated/contact.py``: numeric kernels of the contact kinematics.

Every expression is taken from :mod:`dtcrit.symbolic.kinematics` (Peng et al. 2020, Sections 2, 3
and 5), never typed in here:

* ``a_max``: Eq (26) as printed;
* ``b_max``: Eq (54);
* ``rotation_matrix``: Eq (7), body to world (``v_world = R(q) v_body``; the convention of
  ``dtcrit.numerics.rotations``; the paper's Eq (5) matrix, world to body, is its transpose);
* ``arm_term``: the rotational part one particle adds to the coefficient matrix of the contact
  force, in its local frame, from the general kinematics (Eqs 3-19 with the partner removed);
* ``gyroscopic_coefficients``: torque-free Euler equations (Eqs 11-12 with ``M_L = 0``);
* ``ellipsoid_arm_supremum``: the supremum over an ellipsoid of the largest eigenvalue of
  ``arm_term``, ``max_{i != j} d_i^2 / I_j`` (:func:`ellipsoid_tip_values`; proof in
  ``derivations/records/sec2_3_kinematics.md``).
"""
from __future__ import annotations

import sympy as sp

from dtcrit.symbolic import coefficient_forms as cforms
from dtcrit.symbolic import kinematics as kin
from dtcrit.symbolic import quaternions as quat
from dtcrit.symbolic import tip_configurations as tips
from dtcrit.symbolic.emit import Kernel, python_module

PRODUCER = "dtcrit.symbolic.contact_codegen"
TARGET = "contact.py"

m1, m2, Ixx1, Ixx2, a1, a2 = sp.symbols("m1 m2 Ixx1 Ixx2 a1 a2", positive=True)
Ixx, Iyy, Izz = sp.symbols("Ixx Iyy Izz", positive=True)
rx, ry, rz = sp.symbols("rx ry rz", real=True)
qw, qx, qy, qz = sp.symbols("qw qx qy qz", real=True)
da, db, dc = sp.symbols("da db dc", positive=True)


def ellipsoid_tip_values(d=(da, db, dc), inertia=(Ixx, Iyy, Izz)) -> list[sp.Expr]:
    """Eigenvalues of ``arm_term`` at the six tips ``+-d_i e_i`` of an ellipsoid with semi-axes
    ``d`` along the principal axes: ``d_i^2 / I_j`` for ``j != i`` (taken from the generated
    kinematics, not typed in).  Their maximum is the supremum over the whole ellipsoid (the
    proof is an inequality, written out in ``derivations/records/sec2_3_kinematics.md``).

    Parameters
    ----------
    d : tuple of sympy.Expr
        Semi-axes along the principal axes [m].
    inertia : tuple of sympy.Expr
        Principal moments ``(Ixx, Iyy, Izz)`` [kg m^2].

    Returns
    -------
    list of sympy.Expr
        The non-zero eigenvalues ``d_i^2 / I_j`` [1/kg].
    """
    inertia_matrix = kin.inertia_tensor(*inertia)
    values = []
    for i, di in enumerate(d):
        tip = [0, 0, 0]
        tip[i] = di
        T = cforms.arm_term(tip, inertia_matrix)
        for lam, mult in T.eigenvals().items():
            if lam != 0:
                values.extend([sp.factor(lam)] * mult)
    return values


def kernels() -> list[Kernel]:
    """The contact kinematics kernels listed in the module docstring.

    Returns
    -------
    list of Kernel
        ``a_max``, ``b_max``, ``rotation_matrix``, ``arm_term``, ``gyroscopic_coefficients`` and
        ``ellipsoid_arm_supremum``.
    """
    inertia = [(Ixx, "principal moment about local x [kg m^2]"), (Iyy, "about local y [kg m^2]"),
               (Izz, "about local z [kg m^2]")]
    T = cforms.arm_term((rx, ry, rz), kin.inertia_tensor(Ixx, Iyy, Izz))
    R = quat.quaternion_rotation_matrix((qw, qx, qy, qz))
    return [
        Kernel(
            name="a_max",
            args=[(m1, "mass of particle 1 [kg]"), (Ixx1, "smallest principal moment of particle 1 [kg m^2]"),
                  (a1, "largest half-length of particle 1 [m]"), (m2, "mass of particle 2 [kg]"),
                  (Ixx2, "smallest principal moment of particle 2 [kg m^2]"),
                  (a2, "largest half-length of particle 2 [m]")],
            expr=cforms.a_max_printed(m1, Ixx1, a1, m2, Ixx2, a2),
            doc="Peng et al. 2020, Eq. (26) as printed: A_max = a1^2/Ixx1 + a2^2/Ixx2 + 1/m1 + 1/m2.",
            returns="A_max [1/kg]",
            cse=False,
        ),
        Kernel(
            name="b_max",
            args=inertia,
            expr=cforms.b_max_printed(Ixx, Iyy, Izz),
            doc="Peng et al. 2020, Eq. (54): max(|Ixx-Iyy|/Izz, |Ixx-Izz|/Iyy, |Iyy-Izz|/Ixx).",
            returns="B_max [-]",
            cse=False,
        ),
        Kernel(
            name="rotation_matrix",
            args=[(qw, "quaternion scalar part"), (qx, "x part"), (qy, "y part"), (qz, "z part")],
            expr=tuple(R),
            doc="Peng et al. 2020, Eq. (7): rotation matrix of a unit quaternion, body to world (v_world = R v_body).",
            returns="(R00, R01, R02, R10, R11, R12, R20, R21, R22), row by row",
        ),
        Kernel(
            name="arm_term",
            args=[(rx, "contact arm, local x [m]"), (ry, "local y [m]"), (rz, "local z [m]"), *inertia],
            # expanded: sums of positive terms r_i^2/I_j on the diagonal (no products of moments)
            expr=tuple(sp.expand(T[i, j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))),
            doc="One particle's rotational part of the force coefficient matrix, local frame ([r]x^T I^-1 [r]x, Eqs 3-19).",
            returns="(Txx, Tyy, Tzz, Txy, Txz, Tyz) [1/kg]",
        ),
        Kernel(
            name="gyroscopic_coefficients",
            args=inertia,
            expr=tips.gyroscopic_coefficients(Ixx, Iyy, Izz),
            doc="Torque-free Euler equations (Eqs 11-12, M_L = 0): wdot_x = c_x w_y w_z, wdot_y = c_y w_z w_x, wdot_z = c_z w_x w_y.",
            returns="(c_x, c_y, c_z) [-]",
            cse=False,
        ),
        Kernel(
            name="ellipsoid_arm_supremum",
            args=[(da, "semi-axis along local x [m]"), (db, "along local y [m]"), (dc, "along local z [m]"), *inertia],
            expr=sp.Max(*ellipsoid_tip_values()),
            doc="Supremum over an ellipsoid (semi-axes along the principal axes) of lambda_max([r]x^T I^-1 [r]x): max_{i != j} d_i^2/I_j.",
            returns="S [1/kg]",
            cse=False,
        ),
    ]


def generated_files() -> dict[str, str]:
    """The files this producer writes under ``dtcrit/_generated`` (``dtcrit.symbolic.regenerate``).

    Returns
    -------
    dict of str to str
        ``{"contact.py": text}``.
    """
    summary = (
        "Contact kinematics kernels (Peng et al. 2020, Eqs 7, 11-12, 17-19, 26, 54).\n"
        "Derived in dtcrit.symbolic.kinematics; used by dtcrit.bodies.contact."
    )
    return {TARGET: python_module(PRODUCER, summary, kernels(), preamble="import functools")}
