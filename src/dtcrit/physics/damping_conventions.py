"""How DEM codes turn a restitution coefficient or damping ratio into dashpots, per direction.

Also LAMMPS's own dashpot defaults and its Tsuji coefficient (``pair_style gran/*``, ``granular``).

A scene gives damping once (``restitution``, ``damping_ratio`` or the coefficients ``cn``/``cs``)
and names the code whose convention maps it (``[contact] damping_convention``).  Each convention
fixes, per direction j (normal n, tangential t), a factor ``f_j`` and a mass ``M_j`` with

    c_j = f_j * 2 zeta_j sqrt(k_j M_j),

where ``zeta_j`` is the damping ratio *as that code defines it* (the one dtcrit prints), and how
``zeta_t`` follows from the user's ``zeta``.  ``zeta(e) = -ln e / sqrt(pi^2 + ln^2 e)`` throughout.
The mode damping ratio that decides the step, ``c A / (2 sqrt(k A))``, is reported beside it.

Sources (each read in the code's source or documentation; see ``docs/howto/step.md``,
section "Damping conventions"):

* ``lammps`` -- LAMMPS ``pair_style gran/hooke(/history)``: F_n = kn delta - meff gamman v_n,
  tangential dashpot meff gammat v_t with gammat = gamman/2 when NULL (pair_gran_hooke_history.cpp,
  ``settings``): c_n = 2 zeta sqrt(kn m*), c_t = c_n / 2.  Walls (fix wall/gran): meff = m.
* ``liggghts`` -- LIGGGHTS hooke: gamman = 2 zeta sqrt(kn m*), gammat = gamman (tangential_damping
  on); hertz: c_j = 2 sqrt(5/6) zeta sqrt(S_j m*) with the tangent stiffnesses S_n, S_t
  (normal_model_hooke.h, normal_model_hertz.h, tangential_model_history.h).  Walls: m.
* ``edem`` -- EDEM Hertz-Mindlin (no slip): c_j = 2 sqrt(5/6) zeta sqrt(S_j m*) (Altair EDEM
  documentation, Hertz-Mindlin (no slip)).  Hertz contacts only.
* ``mercurydpm`` -- MercuryDPM LinearViscoelastic: c_n = 2 zeta sqrt(kn m*) (from collision time
  and restitution); tangential by the 2/7 convention, c_t = (2/7) c_n
  (LinearViscoelasticNormalSpecies.cc, SlidingFrictionSpecies.cc).  Walls: m.
* ``yade`` -- YADE ViscElMat (Ip2_ViscElMat_ViscElMat_ViscElPhys): c_n = 2 zeta sqrt(kn m*),
  c_t = 2 zeta sqrt(ks (2/7) m*) (ViscoelasticPM.cpp); a fixed body's zero mass is replaced by the
  particle's, so at walls m* = m/2.
* ``pfc`` -- PFC linear model: c_j = 2 beta_j sqrt(k_j m_c), the same critical damping ratio in
  each direction with the reduced mass.
* Hertz contacts may also name one code's collision law (``lammps-tsuji``, ``lammps-tsuji-2021``,
  ``lammps-coeff-restitution``, ``lammps-viscoelastic``, ``lammps-mass-velocity``, ``yade-mindlin``,
  ``mercurydpm``): their dashpots are that law's at the linearisation overlap (``dtcrit.scenes.law_damping``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = [
    "Convention",
    "CONVENTIONS",
    "DEFAULT_CONVENTION",
    "HERTZ_FACTOR",
    "liggghts_hertz",
    "damping_ratio_from_restitution",
    "tsuji_alpha",
    "lammps_gran_defaults",
    "liggghts_beta",
    "liggghts_hertz_dashpot",
    "liggghts_hooke_dashpot",
    "TSUJI_FACTORS",
    "lammps_coeff_restitution_damp",
    "hertz_mindlin_dissipation",
    "THORNTON_H",
    "thornton_damping_ratio",
    "yade_mindlin_dissipation",
]

HERTZ_FACTOR = 2.0 * math.sqrt(5.0 / 6.0) / 2.0  # c = 2 sqrt(5/6) zeta sqrt(S m*) = f * 2 zeta sqrt(S m*)


@dataclass(frozen=True)
class Convention:
    """One code's map ``zeta -> (c_n, c_t)``, ``c_j = f_j 2 zeta_j sqrt(k_j M_j)`` (module docstring).

    Parameters
    ----------
    name : str
        The convention's name (``[contact] damping_convention``).
    code : str
        The code and contact model it stands for.
    factor_n, factor_t : float
        ``f_n``, ``f_t``.
    mass_t : float
        ``M_t / m*``.
    shear_rule : str
        How ``c_t`` follows: ``"zeta"`` (the same zeta defines it), ``"same"`` (``c_t = c_n``),
        ``"half"`` (``c_t = c_n/2``) or ``"two_sevenths"`` (``c_t = 2/7 c_n``).
    wall_mass : float
        The effective mass of a particle of mass ``m`` against a fixed wall, divided by ``m``.
    models : tuple of str
        The contact models it is defined for.
    """

    name: str
    code: str
    factor_n: float
    factor_t: float
    mass_t: float
    shear_rule: str
    wall_mass: float
    models: tuple[str, ...] = ("linear", "hertz", "yade")

    def dashpots(self, zeta: float, kn: float, ks: float, m_eff: float) -> tuple[float, float]:
        """``(c_n, c_t)`` [N s/m] for the user's damping ratio ``zeta``.

        Parameters
        ----------
        zeta : float
            The damping ratio as given.
        kn, ks : float
            Normal and tangential springs [N/m].
        m_eff : float
            Effective mass [kg] (``m*``, or the convention's wall mass).

        Returns
        -------
        tuple of float
            ``(c_n, c_t)`` [N s/m].
        """
        cn = self.factor_n * 2.0 * zeta * math.sqrt(kn) * math.sqrt(m_eff)
        if self.shear_rule == "half":
            return cn, 0.5 * cn
        if self.shear_rule == "two_sevenths":
            return cn, 2.0 / 7.0 * cn
        if self.shear_rule == "same":
            return cn, cn
        return cn, self.factor_t * 2.0 * zeta * math.sqrt(ks) * math.sqrt(self.mass_t * m_eff)

    def ratios(self, cn: float, cs: float, kn: float, ks: float, m_eff: float) -> tuple[float, float | None]:
        """``(zeta_n, zeta_t)`` as this convention defines them.

        Parameters
        ----------
        cn, cs : float
            Normal and tangential dashpots [N s/m].
        kn, ks : float
            Normal and tangential springs [N/m].
        m_eff : float
            Effective mass [kg].

        Returns
        -------
        tuple
            ``(zeta_n, zeta_t)``; ``zeta_t`` is None without a tangential spring.
        """
        zn = cn / (self.factor_n * 2.0 * math.sqrt(kn) * math.sqrt(m_eff))
        if ks <= 0.0:
            return zn, None
        mass_t = self.mass_t if self.shear_rule == "zeta" else 1.0
        factor_t = self.factor_t if self.shear_rule == "zeta" else 1.0
        return zn, cs / (factor_t * 2.0 * math.sqrt(ks) * math.sqrt(mass_t * m_eff))


CONVENTIONS: dict[str, Convention] = {
    "lammps": Convention("lammps", "LAMMPS pair gran/hooke(/history), fix wall/gran: gammat = gamman/2",
                         1.0, 1.0, 1.0, "half", 1.0, ("linear", "yade")),
    "liggghts": Convention("liggghts", "LIGGGHTS hooke (gammat = gamman) / hertz (2 sqrt(5/6) zeta sqrt(S m*))",
                           1.0, 1.0, 1.0, "same", 1.0),
    "edem": Convention("edem", "EDEM Hertz-Mindlin (no slip): 2 sqrt(5/6) zeta sqrt(S_j m*)",
                       HERTZ_FACTOR, HERTZ_FACTOR, 1.0, "zeta", 1.0, ("hertz",)),
    "mercurydpm": Convention("mercurydpm", "MercuryDPM LinearViscoelastic, tangential dissipation 2/7 of normal",
                             1.0, 1.0, 1.0, "two_sevenths", 1.0, ("linear", "yade", "hertz")),
    "yade": Convention("yade", "YADE ViscElMat: c_t = 2 zeta sqrt(ks (2/7) m*); m* = m/2 at walls",
                       1.0, 1.0, 2.0 / 7.0, "zeta", 0.5, ("linear", "yade")),
    "pfc": Convention("pfc", "PFC linear: c_j = 2 beta sqrt(k_j m_c) in each direction", 1.0, 1.0, 1.0, "zeta", 1.0),
}
# Hertz conventions that name one code's collision law (dashpots: dtcrit.scenes.law_damping)
CONVENTIONS.update({name: Convention(name, f"{name} collision law (dtcrit.scenes.law_damping)", 1.0, 1.0, 1.0, "law", 1.0,
                                     ("hertz",))
                    for name in ("lammps-tsuji", "lammps-tsuji-2021", "lammps-coeff-restitution", "lammps-viscoelastic",
                                 "lammps-mass-velocity", "yade-mindlin")})
DEFAULT_CONVENTION = {"linear": "lammps", "yade": "yade", "hertz": "liggghts"}


def liggghts_hertz() -> Convention:
    """LIGGGHTS's Hertz convention: EDEM's law ``2 sqrt(5/6) zeta sqrt(S_j m*)`` under its own name.

    Returns
    -------
    Convention
        The ``liggghts`` convention for Hertz contacts.
    """
    e = CONVENTIONS["edem"]
    return Convention("liggghts", CONVENTIONS["liggghts"].code, e.factor_n, e.factor_t, 1.0, "zeta", 1.0)


def damping_ratio_from_restitution(e: float) -> float:
    """Damping ratio of a linear spring-dashpot whose normal restitution coefficient is ``e``.

    zeta = -ln e / sqrt(pi^2 + ln^2 e)  (exit/entry speed ratio exp(-zeta pi / sqrt(1 - zeta^2)) = e);
    e = 1 gives 0, e -> 0 gives 1.

    Parameters
    ----------
    e : float
        Normal restitution coefficient.

    Returns
    -------
    float
        The damping ratio ``zeta``.
    """
    if e >= 1.0:
        return 0.0
    if e <= 0.0:
        return 1.0
    L = -math.log(e)
    return L / math.hypot(math.pi, L)


def liggghts_beta(e: float) -> float:
    """LIGGGHTS's ``betaeff = ln e / sqrt(ln^2 e + pi^2)`` of a restitution coefficient (negative for ``e < 1``).

    ``createBetaEff`` in LIGGGHTS-PUBLIC ``src/global_properties.cpp``; it is ``-zeta(e)`` of
    :func:`damping_ratio_from_restitution`.  LIGGGHTS itself refuses ``e`` outside ``(0.05, 1]``.

    Parameters
    ----------
    e : float
        Restitution coefficient, ``0 < e <= 1``.

    Returns
    -------
    float
        ``beta`` (0 for ``e = 1``).
    """
    return -damping_ratio_from_restitution(e)


def liggghts_hertz_dashpot(beta: Any, stiffness: Any, m_eff: Any) -> Any:
    """LIGGGHTS ``model hertz`` dashpot ``gamma = -2 sqrt(5/6) beta sqrt(S m*)``.

    ``S`` is ``S_n = 2 Y* sqrt(R* delta)`` for the normal dashpot and ``S_t = 8 G* sqrt(R* delta)``
    for the tangential one (LIGGGHTS-PUBLIC ``src/normal_model_hertz.h``): the ``liggghts``/``edem``
    convention ``c = 2 sqrt(5/6) zeta sqrt(S m*)`` with ``zeta = -beta``.

    Parameters
    ----------
    beta : float or numpy.ndarray
        :func:`liggghts_beta` of the pair's restitution coefficient.
    stiffness : float or numpy.ndarray
        ``S_n`` or ``S_t`` [N/m].
    m_eff : float or numpy.ndarray
        Effective mass ``m*`` [kg].

    Returns
    -------
    float or numpy.ndarray
        The dashpot [N s/m].
    """
    return -2.0 * math.sqrt(5.0 / 6.0) * beta * (stiffness * m_eff) ** 0.5


def liggghts_hooke_dashpot(beta: Any, kn: Any, m_eff: Any) -> Any:
    """LIGGGHTS ``model hooke`` normal dashpot ``gamma_n = sqrt(4 m* k_n ln^2 e/(ln^2 e + pi^2)) = 2 |beta| sqrt(k_n m*)``.

    LIGGGHTS-PUBLIC ``src/normal_model_hooke.h`` (``viscous off``); with ``tangential_damping on`` the
    tangential dashpot is the same ``gamma_t = gamma_n``: the ``liggghts`` convention for linear springs.

    Parameters
    ----------
    beta : float or numpy.ndarray
        :func:`liggghts_beta` of the pair's restitution coefficient.
    kn : float or numpy.ndarray
        The normal spring [N/m] (``dtcrit.physics.contact_laws.liggghts_hooke_stiffness``).
    m_eff : float or numpy.ndarray
        Effective mass ``m*`` [kg].

    Returns
    -------
    float or numpy.ndarray
        ``gamma_n`` [N s/m].
    """
    return (4.0 * m_eff * kn * beta * beta) ** 0.5


def tsuji_alpha(e: Any) -> Any:
    """LAMMPS ``damping tsuji``: the polynomial ``alpha(e)`` with ``eta_n = alpha(e) sqrt(m_eff k)``.

    ``alpha(e) = 1.2728 - 4.2783 e + 11.087 e^2 - 22.348 e^3 + 27.467 e^4 - 18.022 e^5 + 4.8218 e^6``
    (LAMMPS ``pair_granular`` docs; Tsuji et al. 1992).

    Parameters
    ----------
    e : float or numpy.ndarray
        Restitution coefficient.

    Returns
    -------
    float or numpy.ndarray
        ``alpha(e)``.
    """
    coeffs = (1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218)
    return sum(c * e**k for k, c in enumerate(coeffs))


def lammps_gran_defaults(kn: float, kt: float | None, gamma_n: float, gamma_t: float | None) -> tuple[float, float]:
    """``(K_t, gamma_t)`` of LAMMPS ``pair_style gran/*`` with its ``NULL`` defaults filled in.

    ``K_t`` NULL -> ``2/7 K_n``; ``gamma_t`` NULL -> ``gamma_n/2`` (``pair_gran_hooke_history.cpp``,
    ``settings``), the same half as the ``lammps`` convention's ``c_t = c_n/2``.

    Parameters
    ----------
    kn : float
        Normal spring ``K_n``.
    kt : float or None
        Tangential spring ``K_t``, ``None`` for NULL.
    gamma_n : float
        Normal damping ``gamma_n`` [1/s].
    gamma_t : float or None
        Tangential damping ``gamma_t`` [1/s], ``None`` for NULL.

    Returns
    -------
    tuple
        ``(K_t, gamma_t)``.
    """
    return 2.0 / 7.0 * kn if kt is None else kt, 0.5 * gamma_n if gamma_t is None else gamma_t


# ---------------------------------------------------------------------------------------------
# restitution -> damping coefficient as the collision laws of dtcrit.physics.collision_laws take it
# ---------------------------------------------------------------------------------------------

TSUJI_FACTORS: dict[str, float] = {"current": math.sqrt(2.0), "2021": 1.0}
"""LAMMPS ``damping tsuji``: the factor on ``alpha(e)``.  ``current``: ``damp *= MY_SQRT2`` "for effective
mass convention (as in Tsuji 1992)" (src/GRANULAR/gran_sub_mod_damping.cpp, GranSubModDampingTsuji::init);
``2021``: no factor (pair_granular.cpp of the 29Sep2021 release that Debian ships)."""


def lammps_coeff_restitution_damp(e: float, normal: str) -> float:
    """LAMMPS ``damping coeff_restitution``: the prefactor ``damp`` of ``eta_n = damp sqrt(m_eff F_ne/delta)``.

    ``hooke``: ``-2 ln e/sqrt(pi^2 + ln^2 e)``; otherwise (Hertz) ``-sqrt(3/2) 2 sqrt(5/6) ln e/sqrt(pi^2 + ln^2 e)``
    (src/GRANULAR/gran_sub_mod_damping.cpp, GranSubModDampingCoeffRestitution::init).

    Parameters
    ----------
    e : float
        Restitution coefficient in (0, 1].
    normal : str
        ``"hooke"`` or ``"hertz"``.

    Returns
    -------
    float
        ``damp`` (dimensionless).
    """
    zeta = damping_ratio_from_restitution(e)
    return 2.0 * zeta if normal == "hooke" else math.sqrt(1.5) * 2.0 * math.sqrt(5.0 / 6.0) * zeta


def hertz_mindlin_dissipation(e: float) -> float:
    """``d`` of the Hertz-Mindlin dashpot ``c = d sqrt(m* K sqrt(delta))`` (``F_el = K delta^(3/2)``).

    The Tsuji/Antypov calibration ``c = 2 sqrt(5/6) beta sqrt(S_n m*)`` with ``S_n = (3/2) K sqrt(delta)``
    (LIGGGHTS normal_model_hertz.h, EDEM Hertz-Mindlin; YADE's ``Ip2_FrictMat_FrictMat_MindlinPhys`` coded it
    before it moved to Thornton's map, see ``yade_mindlin_dissipation``) is ``d = sqrt(5) beta``, ``beta = -ln e/sqrt(pi^2 + ln^2 e)``; MercuryDPM's HertzianViscoelastic
    ``dissipation`` is this ``d`` (HertzianViscoelasticInteraction.cc).

    Parameters
    ----------
    e : float
        Restitution coefficient in (0, 1].

    Returns
    -------
    float
        ``d`` (dimensionless).
    """
    return math.sqrt(5.0) * damping_ratio_from_restitution(e)


#: Thornton et al. (2013, Powder Technol. 233) Table 2 fit coefficients h1..h10, as YADE codes them
#: (pkg/dem/HertzMindlin.cpp, Ip2_FrictMat_FrictMat_MindlinPhys::go)
THORNTON_H: tuple[float, ...] = (-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29,
                                 -11342.18, 6276.757, -1489.915)


def thornton_damping_ratio(e: float) -> float:
    """Damping ratio of a clipped Hertz dashpot ``2 beta sqrt(m* S_n)`` that restitutes ``e`` (Thornton et al. 2013).

    Eqs. (B6)-(B7): ``alpha = e (h1 + e (h2 + ... + e h10))``, ``beta = sqrt(1/(1 - (1+e)^2 exp(alpha)) - 1)``,
    nested as YADE's ``Ip2_FrictMat_FrictMat_MindlinPhys::go`` nests it (pkg/dem/HertzMindlin.cpp; ``en = 1``
    gives 0).  The fit holds for the law whose total normal force is clipped at zero.

    Parameters
    ----------
    e : float
        Normal restitution coefficient in (0, 1].

    Returns
    -------
    float
        ``beta`` (YADE's ``betan``).
    """
    if e >= 1.0:
        return 0.0
    acc = THORNTON_H[-1]
    for h in THORNTON_H[-2::-1]:
        acc = h + e * acc
    return math.sqrt(1.0 / (1.0 - (1.0 + e) ** 2 * math.exp(e * acc)) - 1.0)


def yade_mindlin_dissipation(e: float) -> float:
    """``d`` of YADE's Hertz-Mindlin dashpot ``c = d sqrt(m* K sqrt(delta))`` from ``en`` (``F_el = K delta^(3/2)``).

    YADE (pkg/dem/HertzMindlin.cpp): ``Ip2_FrictMat_FrictMat_MindlinPhys`` with ``en`` sets ``betan`` by
    Thornton's map (``thornton_damping_ratio``); ``Law2_ScGeom_MindlinPhys_Mindlin`` damps with
    ``cn = 2 betan sqrt(mbar kn)``, ``kn = (3/2) kno sqrt(uN)``, ``kno = K``, and clips the total normal force at
    zero; so ``d = 2 sqrt(3/2) beta = sqrt(6) beta``.

    Parameters
    ----------
    e : float
        Normal restitution coefficient ``en`` in (0, 1].

    Returns
    -------
    float
        ``d`` (dimensionless).
    """
    return math.sqrt(6.0) * thornton_damping_ratio(e)
