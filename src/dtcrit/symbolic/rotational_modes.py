"""Emit ``dtcrit/_generated/rotational_modes.py``: the contact element with rotational springs, derived.

Two spheres (masses ``m_i``, moments ``I_i``, radii ``R_i``; particle 1 at the origin, the normal
``n = e_z`` towards particle 2, the contact arms ``r_1 = R_1 n`` and ``r_2 = -R_2 n`` as LAMMPS's gran
styles and YADE apply them) carry a contact element with six springs: on the relative displacement
of the contact points ``u = x_2 + theta_2 x r_2 - x_1 - theta_1 x r_1`` (normal ``k_n``, shear ``k_s``)
and on the relative rotation ``phi = theta_2 - theta_1`` (rolling ``k_r`` perpendicular to ``n``,
twisting ``k_tw`` about ``n``; YADE's CohFrictPhys moment law, LIGGGHTS's EPSD family and LAMMPS's
``granular`` rolling/twisting models all act on this relative rotation).  With ``e = B q`` the six
deformations of the twelve coordinates ``q``, the element obeys ``e'' = -A6 (K e + C e')`` with the
6x6 coefficient matrix ``A6 = B M^-1 B^T``.  :func:`coefficient_blocks` builds ``A6`` from ``B`` and
``M`` (nothing typed in) and reads off its blocks:

* ``u_z`` alone: the normal mode, ``A_n = 1/m_1 + 1/m_2``;
* ``(u_x, phi_y)`` and ``(u_y, phi_x)``: two identical 2x2 shear-rolling blocks
  ``[[a_ss, a_sr], [a_sr, a_rr]]`` (determinant ``(1/m_1 + 1/m_2)(1/I_1 + 1/I_2) + (R_1 + R_2)^2/(I_1 I_2)``,
  emitted in that form: ``a_ss a_rr - a_sr^2`` cancels) with ``a_ss = A_t`` (the tangential coefficient without rotational
  springs), ``a_rr = 1/I_1 + 1/I_2`` and ``a_sr = +-(R_1/I_1 - R_2/I_2)``;
* ``phi_z`` alone: the twisting mode, ``a_tw = 1/I_1 + 1/I_2``.

So twisting always separates; shear and rolling separate exactly when ``R_1/I_1 = R_2/I_2`` (two equal
spheres), and then the counter-rotation (rolling) mode has ``omega^2 = k_r (1/I_1 + 1/I_2) = 2 k_r/I``
and the twisting mode ``omega^2 = 2 k_tw/I``.  Against a fixed wall (the partner's mass and moment
taken to infinity) ``a_sr = R/I`` never vanishes: the rolling spring couples to the shear spring, and
``omega^2 = k_r/I`` is a mode only without shear spring.
"""
from __future__ import annotations

import sympy as sp

from dtcrit.symbolic.emit import Kernel, python_module

PRODUCER = "dtcrit.symbolic.rotational_modes"
TARGET = "rotational_modes.py"

m1, m2, I1, I2, R1, R2 = sp.symbols("m1 m2 I1 I2 R1 R2", positive=True)
m, moment, R = sp.symbols("m I R", positive=True)  # one sphere against a wall (emitted names m, I, R)


def _cross_matrix(v: sp.Matrix) -> sp.Matrix:
    """``[v]x`` with ``[v]x w = v x w``."""
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def deformation_matrix(r1: float | sp.Expr, r2: float | sp.Expr) -> sp.Matrix:
    """``B`` (6 x 12): ``(u, phi)`` of the coordinates ``(x_1, theta_1, x_2, theta_2)``, ``n = e_z``.

    ``theta x r = -[r]x theta``, so ``u = x_2 - [r_2]x theta_2 - x_1 + [r_1]x theta_1``.

    Parameters
    ----------
    r1 : float or sympy.Expr
        Radius of sphere 1 (arm ``r_1 = R_1 n``).
    r2 : float or sympy.Expr
        Radius of sphere 2 (arm ``r_2 = -R_2 n``).

    Returns
    -------
    sympy.Matrix
        ``B``.
    """
    n = sp.Matrix([0, 0, 1])
    a1, a2 = r1 * n, -r2 * n
    eye, zero = sp.eye(3), sp.zeros(3)
    top = sp.Matrix.hstack(-eye, _cross_matrix(a1), eye, -_cross_matrix(a2))
    bottom = sp.Matrix.hstack(zero, -eye, zero, eye)
    return sp.Matrix.vstack(top, bottom)


def coefficient_matrix_6(masses, moments, radii) -> sp.Matrix:
    """``A6 = B M^-1 B^T`` for two spheres; ``masses``/``moments`` entries may be ``sp.oo`` (a wall).

    Parameters
    ----------
    masses : tuple of 2
        Masses ``m_1``, ``m_2`` (``sympy.oo`` for a wall).
    moments : tuple of 2
        Moments of inertia ``I_1``, ``I_2`` (``sympy.oo`` for a wall).
    radii : tuple of 2
        Radii ``R_1``, ``R_2`` (the contact arms).

    Returns
    -------
    sympy.Matrix
        ``A6`` (6x6).
    """
    inv = []
    for mass, moment in zip(masses, moments):
        inv += [0 if mass == sp.oo else 1 / mass] * 3 + [0 if moment == sp.oo else 1 / moment] * 3
    B = deformation_matrix(*radii)
    return sp.simplify(B * sp.diag(*inv) * B.T)


def coefficient_blocks(masses=(m1, m2), moments=(I1, I2), radii=(R1, R2)) -> dict[str, sp.Expr]:
    """The blocks of ``A6`` (module docstring) and the entries that must vanish for them to separate.

    Parameters
    ----------
    masses : tuple of 2
        Masses ``m_1``, ``m_2`` (``sympy.oo`` for a wall).
    moments : tuple of 2
        Moments of inertia ``I_1``, ``I_2`` (``sympy.oo`` for a wall).
    radii : tuple of 2
        Radii ``R_1``, ``R_2`` (the contact arms).

    Returns
    -------
    dict of str to sympy.Expr
        The block entries (``a_n``, ``a_ss``, ``a_sr``, ``a_rr``, ``a_tw``, the second shear-rolling block) and
        ``other_couplings``, the entries outside the blocks.
    """
    A = coefficient_matrix_6(masses, moments, radii)
    ux, uy, uz, px, py, pz = range(6)
    shear_rolling = {(ux, py), (uy, px)}
    coupled_elsewhere = [A[i, j] for i in range(6) for j in range(6)
                         if i < j and (i, j) not in shear_rolling and A[i, j] != 0]
    return {
        "a_n": A[uz, uz], "a_ss": A[ux, ux], "a_rr": A[py, py], "a_sr": A[ux, py], "a_tw": A[pz, pz],
        "a_ss_other": A[uy, uy], "a_rr_other": A[px, px], "a_sr_other": A[uy, px],
        "other_couplings": coupled_elsewhere,
    }


def equal_sphere_frequencies() -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """``omega^2`` of the shear, rolling and twisting modes of two equal spheres (``I = 2/5 m R^2``),
    the eigenvalues of ``K^1/2 A K^1/2`` of each block.

    Returns
    -------
    tuple of sympy.Expr
        ``(omega_shear^2, omega_rolling^2, omega_twisting^2)``.
    """
    ks, kr, ktw = sp.symbols("k_s k_r k_tw", positive=True)
    inertia = sp.Rational(2, 5) * m * R**2
    b = coefficient_blocks((m, m), (inertia, inertia), (R, R))
    block = sp.Matrix([[b["a_ss"], b["a_sr"]], [b["a_sr"], b["a_rr"]]])
    root = sp.diag(sp.sqrt(ks), sp.sqrt(kr))
    values = sorted((sp.simplify(v) for v in (root * block * root).eigenvals()), key=sp.default_sort_key)
    return values[0], values[1], sp.simplify(ktw * b["a_tw"])


def _as_sum(expr: sp.Expr, terms: tuple) -> sp.Expr:
    """``expr`` rewritten as the unevaluated sum of ``terms`` (no products of moments: no overflow for
    huge moments), after checking that the two are equal.
    """
    form = sp.Add(*terms, evaluate=False)
    if sp.simplify(expr - form) != 0:
        raise AssertionError(f"{expr} is not {form}")
    return form


def kernels() -> list[Kernel]:
    """The emitted kernels of the contact element with rotational springs (the blocks of ``A6``).

    Returns
    -------
    list of Kernel
        One per emitted function of ``dtcrit/_generated/rotational_modes.py``.
    """
    pair = coefficient_blocks()
    wall = coefficient_blocks((m, sp.oo), (moment, sp.oo), (R, 0))
    for key in ("a_rr", "a_tw"):
        pair[key] = _as_sum(pair[key], (1 / I1, 1 / I2))
    # det = a_ss a_rr - a_sr^2 as a sum of positive terms: the difference cancels for unequal spheres
    pair["a_det"] = _as_sum(sp.simplify(pair["a_ss"] * pair["a_rr"] - pair["a_sr"] ** 2),
                            ((1 / m1 + 1 / m2) * (1 / I1 + 1 / I2), (R1 + R2) ** 2 / (I1 * I2)))
    wall["a_det"] = _as_sum(sp.simplify(wall["a_ss"] * wall["a_rr"] - wall["a_sr"] ** 2), (1 / (m * moment),))
    sphere_args = [(m1, "mass of sphere 1 [kg]"), (I1, "its moment of inertia [kg m^2]"), (R1, "its radius (arm) [m]"),
                   (m2, "mass of sphere 2 [kg]"), (I2, "its moment of inertia [kg m^2]"), (R2, "its radius (arm) [m]")]
    wall_args = [(m, "mass of the sphere [kg]"), (moment, "its moment of inertia [kg m^2]"), (R, "its radius (arm) [m]")]
    return [
        Kernel(
            name="shear_rolling_block",
            args=sphere_args,
            expr=(pair["a_ss"], pair["a_sr"], pair["a_rr"], pair["a_tw"], pair["a_det"]),
            doc="Two spheres: the shear-rolling block [[a_ss, a_sr], [a_sr, a_rr]] and the twisting coefficient "
                "a_tw of A6 = B M^-1 B^T (contact deformations u, phi = theta_2 - theta_1; arms R_i n).",
            returns="(a_ss [1/kg], a_sr [1/(kg m)], a_rr [1/(kg m^2)], a_tw [1/(kg m^2)], det [1/(kg^2 m^2)])",
            cse=False,
        ),
        Kernel(
            name="wall_shear_rolling_block",
            args=wall_args,
            expr=(wall["a_ss"], wall["a_sr"], wall["a_rr"], wall["a_tw"], wall["a_det"]),
            doc="A sphere against a fixed wall: the same block with the partner's mass and moment infinite.",
            returns="(a_ss [1/kg], a_sr [1/(kg m)], a_rr [1/(kg m^2)], a_tw [1/(kg m^2)], det [1/(kg^2 m^2)])",
            cse=False,
        ),
    ]


def generated_files() -> dict[str, str]:
    """The emitted rotational-modes module, by its path under ``dtcrit/_generated``.

    Returns
    -------
    dict of str to str
        File name -> Python source.
    """
    summary = (
        "Coefficient blocks of the contact element with rotational springs (rolling, twisting).\n"
        "Derived in dtcrit.symbolic.rotational_modes from A6 = B M^-1 B^T; used by dtcrit.scenes.pair_modes."
    )
    return {TARGET: python_module(PRODUCER, summary, kernels())}
