"""The dimensionless impact, derived: each collision law in units of ``t_c`` and the elastic peak overlap.

A normal law ``m delta'' = -(k delta^p + c0 delta^q delta')`` with ``delta = D u`` and ``t = T s`` becomes
``u'' = -(k D^(p-1) T^2/m) u^p - (c0 D^q T/m) u^q u'``.  Choosing ``D`` the elastic peak overlap
(``m v^2/2 = k D^(p+1)/(p+1)``) and ``T = t_c = W D/v`` the elastic contact time, with
``W = 2 int_0^1 du/sqrt(1 - u^(p+1)) = (2/(p+1)) B(1/(p+1), 1/2)``, the elastic coefficient becomes
``kappa = (p+1) W^2/2`` and the entry speed ``W``: numbers of the normal law alone.  What survives is
the damping group ``g = c0 D^q T/m`` (a function of the restitution) and whether the force is clipped.
``scaled_form`` returns the group of each damping model and its exponent of the impact speed ``v``
(0: the restitution does not depend on the speed).
"""
from __future__ import annotations

import sympy as sp

m, k, v, c0, R, d, damp = sp.symbols("m k v c_0 R d damp", positive=True)
p, q = sp.symbols("p q", positive=True)

# q and c0 of each damping model (dtcrit.physics.collision_laws), per normal law; d: the dimensionless
# prefactor of sqrt(m k delta^(p-1)) (tsuji, coeff_restitution, LIGGGHTS, YADE, MercuryDPM Hertz, the
# linear dashpot of hooke), damp: LAMMPS's viscoelastic / mass_velocity coefficient
DASHPOTS: dict[str, tuple[sp.Expr, sp.Expr]] = {
    "sqrt(m S_n)": (None, None),  # filled per normal law below: q = (p-1)/2, c0 = d sqrt(m k)
    "lammps-viscoelastic": (sp.Rational(1, 2), damp * m * sp.sqrt(R)),
    "lammps-mass-velocity": (sp.Integer(0), damp * m),
}
MODEL_CLASS = {
    "lammps-tsuji": "sqrt(m S_n)", "lammps-tsuji-2021": "sqrt(m S_n)", "lammps-coeff-restitution": "sqrt(m S_n)", "liggghts": "sqrt(m S_n)",
    "yade-mindlin": "sqrt(m S_n)", "mercurydpm": "sqrt(m S_n)", "none": "sqrt(m S_n)",
    "lammps-viscoelastic": "lammps-viscoelastic", "lammps-mass-velocity": "lammps-mass-velocity",
}


def contact_integral(pp) -> sp.Expr:
    """``W = 2 int_0^1 du/sqrt(1 - u^(p+1))`` in closed form, ``(2/(p+1)) B(1/(p+1), 1/2)``.

    Parameters
    ----------
    pp : sympy.Rational
        The exponent ``p`` of the elastic force.

    Returns
    -------
    sympy.Expr
        ``W`` (``pi`` for ``p = 1``).
    """
    a = 1 / (pp + 1)
    return sp.simplify(2 * a * sp.gamma(a) * sp.gamma(sp.Rational(1, 2)) / sp.gamma(a + sp.Rational(1, 2)))


def scales(pp) -> tuple[sp.Expr, sp.Expr]:
    """``(D, T)``: the elastic peak overlap and contact time of ``m delta'' = -k delta^p`` at entry speed ``v``.

    Parameters
    ----------
    pp : sympy.Rational
        The exponent ``p``.

    Returns
    -------
    tuple of sympy.Expr
        ``D = ((p+1) m v^2/(2 k))^(1/(p+1))``, ``T = W D/v``.
    """
    D = ((pp + 1) * m * v**2 / (2 * k)) ** (1 / (pp + 1))
    return D, contact_integral(pp) * D / v


def scaled_form(normal: str, damping: str) -> dict:
    """The scaled law of one model: ``kappa``, ``w0``, ``q``, the group ``g`` and its exponent of ``v``.

    Parameters
    ----------
    normal : str
        ``"hooke"`` (``p = 1``) or ``"hertz"`` (``p = 3/2``).
    damping : str
        A key of ``MODEL_CLASS``.

    Returns
    -------
    dict
        ``p``, ``q``, ``kappa``, ``w0``, ``g`` (SymPy), ``speed_exponent`` (of ``v`` in ``g``).
    """
    pp = sp.Integer(1) if normal == "hooke" else sp.Rational(3, 2)
    D, T = scales(pp)
    kappa = sp.simplify(k * D ** (pp - 1) * T**2 / m)
    cls = MODEL_CLASS[damping]
    if cls == "sqrt(m S_n)":
        qq, cc = (pp - 1) / 2, d * sp.sqrt(m * k)
    else:
        qq, cc = DASHPOTS[cls]
    g = sp.simplify(sp.powsimp(cc * D**qq * T / m, force=True))
    expo = sp.simplify(sp.diff(sp.log(g), v) * v)
    return {"p": pp, "q": qq, "kappa": kappa, "w0": sp.simplify(v * T / D), "g": g, "speed_exponent": expo}


def hertz_time_constant() -> sp.Expr:
    """The constant ``C`` of ``t_c = C (m*^2/(R* E*^2 v))^(1/5)`` for ``F = (4/3) E* sqrt(R*) delta^(3/2)``.

    Returns
    -------
    sympy.Expr
        ``(4/5) B(2/5, 1/2) (15/16)^(2/5)``.
    """
    E, Rs = sp.symbols("E R_s", positive=True)
    _, T = scales(sp.Rational(3, 2))
    t_c = T.subs(k, sp.Rational(4, 3) * E * sp.sqrt(Rs))
    return sp.simplify(t_c / (m**2 / (Rs * E**2 * v)) ** sp.Rational(1, 5))


__all__ = ["contact_integral", "scales", "scaled_form", "hertz_time_constant", "MODEL_CLASS"]
