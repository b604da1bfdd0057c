"""Hertz damping conventions that name one code's collision law: their scene keys, their dashpots at the
linearisation overlap (``dtcrit step``) and the restitution of their impact (``dtcrit collide``).

``[contact] damping_convention`` of a Hertz contact may name one of these laws
(``physics.collision_laws.DAMPING_MODELS``; ``F_el = K delta^(3/2)``, ``K = (4/3) E* sqrt(R*)``, so
``F_el/delta = (2/3) k_n`` with the tangent stiffness ``k_n = 2 E* sqrt(R* delta)``):

* ``lammps-tsuji``: ``eta_n = sqrt(2) alpha(e) sqrt(m* F_el/delta)`` (LAMMPS src/GRANULAR/gran_sub_mod_damping.cpp,
  GranSubModDampingTsuji); ``lammps-tsuji-2021``: the same without ``sqrt(2)`` (the 29Sep2021 release);
* ``lammps-coeff-restitution``: ``eta_n = sqrt(3/2) 2 sqrt(5/6) zeta(e) sqrt(m* F_el/delta)``
  (GranSubModDampingCoeffRestitution), which is ``2 sqrt(5/6) zeta sqrt(m* k_n)``;
* ``lammps-viscoelastic``: ``eta_n = eta_n0 m* a``, ``a = sqrt(R* delta)`` (``eta_n0`` [1/(m s)] as LAMMPS takes it,
  pair_granular doc "damping viscoelastic");
* ``lammps-mass-velocity``: ``eta_n = eta_n0 m*`` (``eta_n0`` [1/s]);
* ``yade-mindlin``: ``c_n = 2 beta(e) sqrt(m* k_n)``, ``beta`` Thornton et al. (2013) B6-B7 (YADE
  pkg/dem/HertzMindlin.cpp); ``c_s = 2 beta(e) sqrt(m* k_s)`` (``es = en`` when only ``en`` is given);
* ``mercurydpm``: HertzianViscoelastic ``c_n = sqrt(5) zeta(e) sqrt(m* F_el/delta)`` = ``2 sqrt(5/6) zeta sqrt(m* k_n)``
  (HertzianViscoelasticInteraction.cc).

The restitution-taking laws take ``restitution``; ``lammps-viscoelastic`` and ``lammps-mass-velocity`` take
``damping_coefficient`` (``eta_n0``).  The tangential dashpot: LAMMPS ``eta_t = x_gammat eta_n``
(pair_granular, ``tangential mindlin NULL x_gammat mu``), ``x_gammat`` given as ``tangential_damping_factor``
(required: LAMMPS has no default); MercuryDPM ``slidingDissipation = tangential_damping_factor x dissipation``
(default 2/7, as the ``mercurydpm`` linear convention); YADE as above.  Against a wall ``m* = m``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from dtcrit.errors import InputError
from dtcrit.physics.damping_conventions import (TSUJI_FACTORS, Convention, lammps_coeff_restitution_damp, thornton_damping_ratio,
                                                tsuji_alpha)

__all__ = ["LawDamping", "LAW_CONVENTIONS", "law_convention", "is_law_convention", "check_law_input", "law_dashpots",
           "dashpot_exponent", "continuum_restitution"]


@dataclass(frozen=True)
class LawDamping:
    """One code's Hertz damping law as a scene names it.

    Parameters
    ----------
    name : str
        The ``damping_convention``.
    core : str
        Its key in ``physics.collision_laws.DAMPING_MODELS``.
    takes : str
        ``"restitution"`` or ``"coefficient"`` (``damping_coefficient``, the code's ``eta_n0``).
    tangential : str
        ``"factor"`` (``c_s = x c_n`` with ``tangential_damping_factor`` x) or ``"yade"``.
    default_factor : float or None
        ``x`` when the scene gives none (None: required).
    code : str
        The code and source it stands for.
    """

    name: str
    core: str
    takes: str
    tangential: str
    default_factor: float | None
    code: str


LAW_CONVENTIONS: dict[str, LawDamping] = {d.name: d for d in (
    LawDamping("lammps-tsuji", "lammps-tsuji", "restitution", "factor", None,
               "LAMMPS pair granular damping tsuji: sqrt(2) alpha(e) sqrt(m* F/delta)"),
    LawDamping("lammps-tsuji-2021", "lammps-tsuji-2021", "restitution", "factor", None,
               "LAMMPS 29Sep2021 pair granular damping tsuji: alpha(e) sqrt(m* F/delta)"),
    LawDamping("lammps-coeff-restitution", "lammps-coeff-restitution", "restitution", "factor", None,
               "LAMMPS pair granular damping coeff_restitution"),
    LawDamping("lammps-viscoelastic", "lammps-viscoelastic", "coefficient", "factor", None,
               "LAMMPS pair granular damping viscoelastic: eta_n0 m* a"),
    LawDamping("lammps-mass-velocity", "lammps-mass-velocity", "coefficient", "factor", None,
               "LAMMPS pair granular damping mass_velocity: eta_n0 m*"),
    LawDamping("yade-mindlin", "yade-mindlin", "restitution", "yade", None,
               "YADE Ip2_FrictMat_FrictMat_MindlinPhys(en): 2 beta(en) sqrt(m* k_j), Thornton 2013"),
    LawDamping("mercurydpm", "mercurydpm", "restitution", "factor", 2.0 / 7.0,
               "MercuryDPM HertzianViscoelastic: sqrt(5) zeta sqrt(m* F/delta), sliding 2/7"),
)}

_DASHPOT_EXPONENT = {"lammps-viscoelastic": 0.5, "lammps-mass-velocity": 0.0}


def is_law_convention(name: str | None, model: str) -> bool:
    """Whether ``name`` is one of ``LAW_CONVENTIONS`` on a Hertz contact.

    Parameters
    ----------
    name : str or None
        The ``damping_convention``.
    model : str
        The contact model.

    Returns
    -------
    bool
        True for a Hertz contact under a law convention.
    """
    return model == "hertz" and name in LAW_CONVENTIONS


def law_convention(name: str) -> Convention:
    """The ``Convention`` record of a law convention (its damping ratios are the plain ``c/(2 sqrt(k m*))``).

    Parameters
    ----------
    name : str
        A key of ``LAW_CONVENTIONS``.

    Returns
    -------
    Convention
        Unit factors (ratios are mode damping ratios), shear rule ``"law"``, wall mass ``m``, Hertz only.
    """
    return Convention(name, LAW_CONVENTIONS[name].code, 1.0, 1.0, 1.0, "law", 1.0, ("hertz",))


def dashpot_exponent(name: str) -> float:
    """``q`` of ``c_n = c0 delta^q`` for a law convention (1/4 unless the law takes a coefficient).

    Parameters
    ----------
    name : str
        A key of ``LAW_CONVENTIONS``.

    Returns
    -------
    float
        ``q``.
    """
    return _DASHPOT_EXPONENT.get(name, 0.25)


def check_law_input(prefix: str, convention: str | None, model: str, given: dict) -> tuple[float | None, float | None]:
    """Validate the damping keys of a table against its convention.

    Parameters
    ----------
    prefix : str
        Key prefix (``contact.``).
    convention : str or None
        The ``damping_convention`` named.
    model : str
        The contact model.
    given : dict
        ``restitution``, ``damping_ratio`` (given as such), ``damping_coefficient``, ``tangential_damping_factor``
        (None when absent).

    Returns
    -------
    tuple
        ``(damping_coefficient, tangential_damping_factor)``.
    """
    coef, factor = given.get("damping_coefficient"), given.get("tangential_damping_factor")
    if not is_law_convention(convention, model):
        for key, value in (("damping_coefficient", coef), ("tangential_damping_factor", factor)):
            if value is not None:
                raise InputError(prefix + key, "used only with a Hertz damping_convention that takes it "
                                 f"({', '.join(LAW_CONVENTIONS)}); not with {convention or 'the default'!r}")
        return None, None
    assert convention is not None  # is_law_convention
    law = LAW_CONVENTIONS[convention]
    if given.get("damping_ratio") is not None:
        raise InputError(prefix + "damping_ratio", f"{convention} takes "
                         f"{'restitution' if law.takes == 'restitution' else 'damping_coefficient'}, not a damping ratio")
    if law.takes == "coefficient":
        if given.get("restitution") is not None:
            raise InputError(prefix + "restitution", f"{convention} takes damping_coefficient (eta_n0 as LAMMPS takes it); "
                             "its restitution depends on the speed: give damping_coefficient, not restitution")
        if coef is None:
            raise InputError(prefix + "damping_coefficient", f"missing: {convention} takes its coefficient eta_n0 "
                             f"[{'1/(m s)' if law.core == 'lammps-viscoelastic' else '1/s'}]")
    elif coef is not None:
        raise InputError(prefix + "damping_coefficient", f"{convention} takes restitution, not damping_coefficient")
    if factor is not None and law.tangential == "yade":
        raise InputError(prefix + "tangential_damping_factor", "yade-mindlin's tangential dashpot is 2 beta(en) sqrt(m* k_s) "
                         "(es = en); no factor is taken")
    return coef, factor


def _tangential_factor(law: LawDamping, factor: float | None, key: str) -> float:
    if factor is not None:
        return factor
    if law.default_factor is None:
        raise InputError(key, f"missing: {law.name}'s tangential dashpot is x_gammat times the normal one "
                         "(LAMMPS pair granular tangential mindlin NULL x_gammat mu); give x_gammat")
    return law.default_factor


def law_dashpots(name: str, *, restitution: float | None, coefficient: float | None, tangential_factor: float | None,
                 kn: float, ks: float, m_eff: float, contact_radius: float | None,
                 key: str = "contact.tangential_damping_factor") -> tuple[float, float]:
    """``(c_n, c_s)`` [N s/m] of a law convention at the overlap whose tangent stiffnesses are ``kn``, ``ks``.

    Parameters
    ----------
    name : str
        A key of ``LAW_CONVENTIONS``.
    restitution : float or None
        ``e`` (the restitution-taking laws; None: no dashpot).
    coefficient : float or None
        ``eta_n0`` (``lammps-viscoelastic`` [1/(m s)], ``lammps-mass-velocity`` [1/s]).
    tangential_factor : float or None
        ``x`` of ``c_s = x c_n`` (None: the law's default, or refused).
    kn, ks : float
        Tangent stiffnesses ``2 E* a``, ``8 G* a`` [N/m].
    m_eff : float
        ``m*`` [kg] (``m`` against a wall).
    contact_radius : float or None
        ``a = sqrt(R* delta)`` [m] (``lammps-viscoelastic``).
    key : str
        The key named when the tangential factor is missing.

    Returns
    -------
    tuple of float
        ``(c_n, c_s)``; ``(0, 0)`` without damping input.
    """
    law = LAW_CONVENTIONS[name]
    if (restitution if law.takes == "restitution" else coefficient) is None:
        return 0.0, 0.0
    root = math.sqrt(m_eff * 2.0 / 3.0 * kn)  # sqrt(m* F_el/delta)
    if law.takes == "restitution":
        e = float(restitution)  # type: ignore[arg-type]
        if law.core == "yade-mindlin":
            beta = thornton_damping_ratio(e)
            return 2.0 * beta * math.sqrt(m_eff * kn), 2.0 * beta * math.sqrt(m_eff * ks)
        if law.core.startswith("lammps-tsuji"):
            cn = TSUJI_FACTORS["2021" if law.core.endswith("2021") else "current"] * tsuji_alpha(e) * root
        else:  # coeff_restitution; mercurydpm: sqrt(5) zeta = sqrt(3/2) 2 sqrt(5/6) zeta
            cn = lammps_coeff_restitution_damp(e, "hertz") * root
    elif law.core == "lammps-viscoelastic":
        if contact_radius is None:
            raise InputError("contact.damping_convention", "lammps-viscoelastic needs the contact radius sqrt(R* delta) "
                             "of a sphere pair")
        cn = float(coefficient) * m_eff * contact_radius  # type: ignore[arg-type]
    else:
        cn = float(coefficient) * m_eff  # type: ignore[arg-type]
    return cn, _tangential_factor(law, tangential_factor, key) * cn


def continuum_restitution(name: str, *, restitution: float | None, coefficient: float | None, m_eff: float,
                          E_eff: float, R_eff: float, v: float) -> float:
    """The restitution of the continuum impact at speed ``v`` under the law (``collisions.reference``).

    Parameters
    ----------
    name : str
        A key of ``LAW_CONVENTIONS``.
    restitution, coefficient : float or None
        As the law takes it.
    m_eff : float
        ``m*`` [kg].
    E_eff, R_eff : float
        ``E*`` [Pa], ``R*`` [m].
    v : float
        Normal impact speed [m/s].

    Returns
    -------
    float
        Exit over entry speed (0: the contact does not rebound).
    """
    from dtcrit.collisions.reference import solve_reference
    from dtcrit.collisions.scaled import scaled_from_physical
    from dtcrit.physics.collision_laws import collision_law

    law = LAW_CONVENTIONS[name]
    phys = collision_law("hertz", law.core, m_eff=m_eff, E_eff=E_eff, R_eff=R_eff, restitution=restitution,
                         coefficient=coefficient)
    return solve_reference(scaled_from_physical(phys, v)).restitution
