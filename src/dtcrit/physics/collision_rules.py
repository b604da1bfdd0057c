"""The DEM codes' rules for the step of a collision (none derived), as each code or paper states them.

* ``liggghts-hertz-0.1``, ``liggghts-hertz-0.2``: LIGGGHTS ``fix check/timestep/gran N f_R f_H`` warns when
  dt exceeds ``f_H`` times the Hertz time ``2.87 (m*^2/(R* E*^2 v_max))^(1/5)``
  (fix_check_timestep_gran.cpp; ``f_H`` = 0.1 or 0.2 in its examples,
  ``rules_of_thumb.HERTZ_FRACTIONS``);
* ``edem-rayleigh-0.2``, ``edem-rayleigh-0.4``: EDEM's advice of 20-40 % of the Rayleigh time
  ``T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766)`` of the smallest particle (Li et al. 2005;
  ``rules_of_thumb.rayleigh_time``);
* ``tc-over-50``: the collision time over 50 (MercuryDPM drivers, MFiX ``DTSOLID_FACTOR`` 50,
  MFIX-Exa ``tcoll_ratio`` 50, src/des/MFIX_PC_InitCollisionParams.cpp);
* ``burns-2019``: Burns, Piiroinen & Hanley (2019), IJNME, doi 10.1002/nme.6056, eq. (68)
  (as solved by the public MATLAB script PACCCK.mlx that cites it):
  ``1 - 3.5 dt c/m* - 3.5 sqrt(v) k1 dt^(5/2)/m* = 0`` with ``k1 = 8 G* sqrt(R*)`` (Mindlin) and
  ``c = -2 sqrt(5/6) beta sqrt(s_t m*)``, ``beta = ln e/sqrt(ln^2 e + pi^2)``.  dtcrit takes
  ``s_t = k1 sqrt(delta_max)``, the Mindlin tangential stiffness ``8 G* sqrt(R* delta_max)`` at the
  elastic peak overlap of the impact at ``v`` (the stiffest the tangential spring gets in that impact).
  The left side decreases strictly in dt from 1, so the root is unique (found by bisection, ``brentq``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq

from dtcrit.errors import InputError
from dtcrit.physics.rules_of_thumb import HERTZ_FRACTIONS, hertz_contact_time, rayleigh_time

__all__ = ["CodeRule", "EDEM_FRACTIONS", "STEPS_PER_COLLISION", "liggghts_hertz_steps", "edem_rayleigh_steps",
           "collision_time_fraction", "burns_step", "code_rules"]

EDEM_FRACTIONS = (0.2, 0.4)
"""EDEM's advised fractions of the Rayleigh time (Altair EDEM documentation, time step)."""
STEPS_PER_COLLISION = 50.0
"""MercuryDPM drivers, MFiX ``DTSOLID_FACTOR``, MFIX-Exa ``tcoll_ratio``: t_c/50."""


@dataclass(frozen=True)
class CodeRule:
    """One code's step for a collision.

    Parameters
    ----------
    key : str
        Short key (``"liggghts-hertz-0.1"``).
    label : str
        What the rule is, in words.
    dt : float or None
        The step it gives [s] (None where it does not apply, e.g. the Hertz rules for a linear law).
    source : str
        Where the rule is stated.
    """

    key: str
    label: str
    dt: float | None
    source: str


def _positive(key: str, value) -> float:
    if value is None or not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise InputError(key, f"must be a positive finite number (got {value!r})")
    return float(value)


def liggghts_hertz_steps(m_star: float, r_star: float, e_star: float, v_max: float) -> dict[float, float]:
    """LIGGGHTS ``check/timestep/gran``: fractions ``f_H`` of the Hertz time at ``v_max``.

    Parameters
    ----------
    m_star, r_star, e_star : float
        Effective mass [kg], radius [m] and Young's modulus [Pa].
    v_max : float
        Largest relative impact speed [m/s].

    Returns
    -------
    dict
        ``f_H -> f_H * 2.87 (m*^2/(R* E*^2 v_max))^(1/5)`` [s] for ``f_H`` in ``HERTZ_FRACTIONS``.
    """
    t_h = hertz_contact_time(_positive("m_star", m_star), _positive("r_star", r_star), _positive("e_star", e_star),
                             _positive("v_max", v_max))
    return {f: f * t_h for f in HERTZ_FRACTIONS}


def edem_rayleigh_steps(radius: float, density: float, youngs_modulus: float, poisson_ratio: float) -> dict[float, float]:
    """EDEM's 20 % and 40 % of the Rayleigh time ``T_R`` of a particle (Li et al. 2005).

    Parameters
    ----------
    radius, density, youngs_modulus, poisson_ratio : float
        The particle's radius [m], density [kg/m^3], Young's modulus [Pa] and Poisson's ratio.

    Returns
    -------
    dict
        ``fraction -> fraction * T_R`` [s] for the fractions in ``EDEM_FRACTIONS``.
    """
    t_r = rayleigh_time(_positive("radius", radius), _positive("density", density),
                        _positive("youngs_modulus", youngs_modulus), poisson_ratio)
    return {f: f * t_r for f in EDEM_FRACTIONS}


def collision_time_fraction(t_c: float, steps: float = STEPS_PER_COLLISION) -> float:
    """The collision time over a fixed number of steps (MercuryDPM, MFiX, MFIX-Exa: 50).

    Parameters
    ----------
    t_c : float
        Collision time [s].
    steps : float
        Steps per collision.

    Returns
    -------
    float
        ``t_c/steps`` [s].
    """
    return _positive("t_c", t_c) / _positive("steps", steps)


def burns_step(m_star: float, k1: float, v: float, restitution: float, s_t: float) -> float:
    """Burns, Piiroinen & Hanley (2019) eq. (68): the root dt of ``1 - 3.5 dt c/m* - 3.5 sqrt(v) k1 dt^(5/2)/m*``.

    Parameters
    ----------
    m_star : float
        Effective mass [kg].
    k1 : float
        ``8 G* sqrt(R*)`` [N/m^(3/2)].
    v : float
        Assumed relative speed [m/s].
    restitution : float
        ``e`` in (0, 1] (``c = -2 sqrt(5/6) beta sqrt(s_t m*)``, ``beta = ln e/sqrt(ln^2 e + pi^2)``).
    s_t : float
        The tangential stiffness in ``c`` [N/m] (module docstring: dtcrit's choice).

    Returns
    -------
    float
        dt [s].
    """
    m, k, vv, st = (_positive(n, x) for n, x in (("m_star", m_star), ("k1", k1), ("v", v), ("s_t", s_t)))
    e = _positive("restitution", restitution)
    if e > 1.0:
        raise InputError("restitution", f"must lie in (0, 1] (got {restitution!r})")
    beta = math.log(e) / math.sqrt(math.log(e) ** 2 + math.pi ** 2)
    c = -2.0 * math.sqrt(5.0 / 6.0) * beta * math.sqrt(st * m)
    a, b = 3.5 * c / m, 3.5 * math.sqrt(vv) * k / m

    def f(x: float) -> float:
        return 1.0 - a * x - b * x ** 2.5

    hi = 1.01 * min(1.0 / a if a > 0 else math.inf, b ** -0.4)  # f(hi) < 0 beyond either bound
    return float(brentq(f, 0.0, hi, xtol=1e-300, rtol=1e-14))


def code_rules(*, t_c: float, m_star: float, v_max: float, hertz: dict | None = None,
               particle: dict | None = None, restitution: float = 1.0) -> list[CodeRule]:
    """The codes' steps for one contact (module docstring).

    Parameters
    ----------
    t_c : float
        The contact's collision time [s].
    m_star : float
        Effective mass [kg].
    v_max : float
        Largest impact speed [m/s].
    hertz : dict, optional
        Hertz contact: ``E_sqrtR`` (``E* sqrt(R*)`` [N/m^(3/2)]), ``k1`` (``8 G* sqrt(R*)``) and
        ``delta_max`` [m]; None for a linear law (the Hertz rules then do not apply).
    particle : dict, optional
        ``radius``, ``density``, ``youngs_modulus``, ``poisson_ratio`` of the smallest particle
        (EDEM's Rayleigh rule; None: not applicable).
    restitution : float
        ``e`` (Burns et al.'s dashpot).

    Returns
    -------
    list of CodeRule
        One entry per rule (``dt`` None where it does not apply).
    """
    out: list[CodeRule] = []
    src_l = "LIGGGHTS fix_check_timestep_gran.cpp (fraction_h)"
    for f in HERTZ_FRACTIONS:
        dt = None
        if hertz is not None:  # E* and R* enter as E* sqrt(R*) only
            dt = liggghts_hertz_steps(m_star, 1.0, hertz["E_sqrtR"], v_max)[f]
        out.append(CodeRule(f"liggghts-hertz-{f:g}", f"LIGGGHTS check/timestep/gran: {f:g} x Hertz time", dt, src_l))
    for f in EDEM_FRACTIONS:
        dt = edem_rayleigh_steps(**particle)[f] if particle is not None else None
        out.append(CodeRule(f"edem-rayleigh-{f:g}", f"EDEM: {f:.0%} of the Rayleigh time", dt,
                            "Altair EDEM documentation; Li et al. (2005)"))
    out.append(CodeRule("tc-over-50", "collision time / 50", collision_time_fraction(t_c),
                        "MercuryDPM drivers; MFiX DTSOLID_FACTOR; MFIX-Exa tcoll_ratio"))
    dt_b = None
    if hertz is not None:
        dt_b = burns_step(m_star, hertz["k1"], v_max, restitution, hertz["k1"] * math.sqrt(hertz["delta_max"]))
    out.append(CodeRule("burns-2019", "Burns, Piiroinen & Hanley (2019) eq. 68", dt_b, "doi 10.1002/nme.6056"))
    return out
