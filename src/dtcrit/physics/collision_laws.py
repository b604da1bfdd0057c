"""Normal collision laws of two spheres as the DEM codes write them: elastic force plus dashpot, clipped or not.

Every law is ``F(delta, delta') = F_el(delta) + c(delta) delta'`` while the overlap ``delta > 0``
(``delta'`` > 0 approaching), with ``F_el = k delta`` (``hooke``) or ``F_el = K delta^(3/2)``,
``K = (4/3) E* sqrt(R*)`` (``hertz``), and a dashpot ``c(delta) = c0 delta^q``; a code that clips sets
``F = max(F, 0)`` (no attraction).  ``DAMPING_MODELS`` says, per key, what the code takes and how it
maps it (each read in the code's source):

* ``lammps-viscoelastic``: ``eta_n = damp m_eff a``, ``a = sqrt(R* delta)`` for hooke and hertz alike
  (src/GRANULAR/gran_sub_mod_damping_kernel.h, gran_damping_viscoelastic_prefactor; the contact radius of
  GranSubModNormal is ``sqrt(dR)``); takes ``damp`` [1/(m s)];
* ``lammps-mass-velocity``: ``eta_n = damp m_eff``; takes ``damp`` [1/s];
* ``lammps-tsuji``: ``eta_n = damp sqrt(m_eff F_ne/delta)``, ``damp = f alpha(e)`` with LAMMPS's polynomial
  ``alpha`` and ``f = sqrt(2)`` in the current source (GranSubModDampingTsuji::init, ``damp *= MY_SQRT2``)
  and ``f = 1`` in the 29Sep2021 release Debian ships (key ``lammps-tsuji-2021``, or ``tsuji_version="2021"``:
  a two-sphere collision in Debian's ``lmp`` gives e = 0.9284 for input 0.9, as this law, not 0.9002); takes ``e``;
* ``lammps-coeff-restitution``: as tsuji with ``damp`` from ``e`` (GranSubModDampingCoeffRestitution::init;
  absent from the 2021 release); takes ``e``;
* ``liggghts``: hooke ``gamma_n = 2 zeta sqrt(k m*)``, hertz ``gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*)``,
  ``S_n = 2 E* sqrt(R* delta)`` (normal_model_hooke.h, normal_model_hertz.h; EDEM Hertz-Mindlin is the
  same law); takes ``e``;
* ``yade-mindlin``: ``Ip2_FrictMat_FrictMat_MindlinPhys(en)``: ``betan`` from ``en`` by Thornton et al. (2013)
  eqs. B6-B7 (fit coefficients h1-h10), ``Law2_ScGeom_MindlinPhys_Mindlin``: ``c_n = 2 betan sqrt(m* k_n)``,
  ``k_n = 2 E* sqrt(R* delta)``, total normal force clipped at zero (pkg/dem/HertzMindlin.cpp of yade/trunk;
  YADE 2023.02a restitutes ``en``: 0.10002 for 0.1; older sources used ``2 sqrt(5/6) beta``), Hertz only;
* ``mercurydpm``: LinearViscoelastic ``F = k delta + gamma delta'`` (``gamma`` [kg/s] or from ``e``);
  HertzianViscoelastic ``c = d sqrt(m* (4/3) E* sqrt(R* delta))`` (``d`` or from ``e``,
  HertzianViscoelasticInteraction.cc);
* ``none``: no dashpot.

``mindlin_tangential`` is one step of LAMMPS's tangential Mindlin force with its Coulomb limit (the oblique
impact is not yet stepped).  Cohesion (JKR, DMT) changes the impact and is not modelled: refused with one line.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from dtcrit.errors import InputError
from dtcrit.physics.damping_conventions import (
    TSUJI_FACTORS,
    damping_ratio_from_restitution,
    hertz_mindlin_dissipation,
    lammps_coeff_restitution_damp,
    tsuji_alpha,
    yade_mindlin_dissipation,
)

__all__ = ["NORMALS", "DAMPING_MODELS", "CLIPPING", "DampingModel", "CollisionLaw", "collision_law",
           "check_normal", "check_damping", "check_restitution", "mindlin_tangential"]

NORMALS: tuple[str, ...] = ("hooke", "hertz")


@dataclass(frozen=True)
class DampingModel:
    """How one code defines its normal dashpot.

    Parameters
    ----------
    key : str
        The damping key (``"lammps-tsuji"``).
    takes : str
        ``"restitution"`` (the code takes ``e``) or ``"coefficient"`` (the code takes its own coefficient).
    clips : bool
        Whether the code clips the total normal force at zero by default.
    exponents : dict
        normal -> ``q`` of ``c(delta) = c0 delta^q``.
    source : str
        Where the law was read.
    """

    key: str
    takes: str
    clips: bool
    exponents: dict
    source: str


DAMPING_MODELS: dict[str, DampingModel] = {m.key: m for m in (
    DampingModel("lammps-viscoelastic", "coefficient", False, {"hooke": 0.5, "hertz": 0.5},
                 "LAMMPS src/GRANULAR/gran_sub_mod_damping_kernel.h (damp*meff*contact_radius)"),
    DampingModel("lammps-tsuji", "restitution", False, {"hooke": 0.0, "hertz": 0.25},
                 "LAMMPS src/GRANULAR/gran_sub_mod_damping.cpp (GranSubModDampingTsuji)"),
    DampingModel("lammps-tsuji-2021", "restitution", False, {"hooke": 0.0, "hertz": 0.25},
                 "LAMMPS 29Sep2021 pair_granular.cpp (tsuji without the sqrt(2); Debian's lmp, measured)"),
    DampingModel("lammps-coeff-restitution", "restitution", False, {"hooke": 0.0, "hertz": 0.25},
                 "LAMMPS src/GRANULAR/gran_sub_mod_damping.cpp (GranSubModDampingCoeffRestitution)"),
    DampingModel("lammps-mass-velocity", "coefficient", False, {"hooke": 0.0, "hertz": 0.0},
                 "LAMMPS src/GRANULAR/gran_sub_mod_damping_kernel.h (damp*meff)"),
    DampingModel("liggghts", "restitution", False, {"hooke": 0.0, "hertz": 0.25},
                 "LIGGGHTS normal_model_hooke.h, normal_model_hertz.h (limitForce off by default)"),
    DampingModel("yade-mindlin", "restitution", True, {"hertz": 0.25},
                 "YADE pkg/dem/HertzMindlin.cpp (Ip2_FrictMat_FrictMat_MindlinPhys en: Thornton 2013 B6-B7; Law2 clips)"),
    DampingModel("mercurydpm", "restitution", False, {"hooke": 0.0, "hertz": 0.25},
                 "MercuryDPM LinearViscoelasticInteraction.cc, HertzianViscoelasticInteraction.cc"),
    DampingModel("none", "restitution", False, {"hooke": 0.0, "hertz": 0.0}, "no dashpot"),
)}

CLIPPING: dict[str, tuple[str, str]] = {
    "LAMMPS pair granular": ("not by default; keyword limit_damping clips",
                             "src/GRANULAR/granular_model.cpp: if (limit_damping && Fntot < 0.0) Fntot = 0.0"),
    "LIGGGHTS": ("not by default; limitForce on clips",
                 "normal_model_hertz.h / normal_model_hooke.h: if(limitForce && (Fn<0.0)) Fn = 0.0"),
    "YADE Law2_ScGeom_MindlinPhys_Mindlin": ("always (without adhesion)",
                                             "pkg/dem/HertzMindlin.cpp: if (normTemp.dot(normal) < 0) normalForce = 0"),
    "MercuryDPM": ("never", "LinearViscoelasticInteraction.cc, HertzianViscoelasticInteraction.cc: "
                            "normalForce = k delta - dissipation v_n while overlap > 0"),
}
"""Which code clips the normal force at zero, with the line of source that decides it."""


def check_normal(normal) -> str:
    """The normal law's key, checked (``"hooke"`` or ``"hertz"``).

    Parameters
    ----------
    normal : str
        The key.

    Returns
    -------
    str
        The key.
    """
    if normal not in NORMALS:
        raise InputError("normal", f"must be one of {', '.join(NORMALS)} (got {normal!r})")
    return normal


def check_damping(damping, normal: str) -> DampingModel:
    """The damping model of a key, checked against the normal law.

    Parameters
    ----------
    damping : str
        A key of ``DAMPING_MODELS``.
    normal : str
        ``"hooke"`` or ``"hertz"``.

    Returns
    -------
    DampingModel
        The model.
    """
    if damping not in DAMPING_MODELS:
        raise InputError("damping", f"must be one of {', '.join(DAMPING_MODELS)} (got {damping!r})")
    model = DAMPING_MODELS[damping]
    if normal not in model.exponents:
        raise InputError("damping", f"{damping} is defined for {', '.join(model.exponents)} contacts only, not {normal}")
    return model


def check_restitution(e, key: str = "restitution") -> float:
    """A restitution coefficient, checked: a finite number in (0, 1].

    Parameters
    ----------
    e : float
        The coefficient.
    key : str
        The input key named in the error.

    Returns
    -------
    float
        ``e``.
    """
    try:
        x = float(e)
    except (TypeError, ValueError):
        raise InputError(key, f"must be a number (got {e!r})") from None
    if not (math.isfinite(x) and 0.0 < x <= 1.0):
        raise InputError(key, f"must lie in (0, 1] (got {e!r})")
    return x


@dataclass(frozen=True)
class CollisionLaw:
    """``F = stiffness delta^p + c0 delta^q delta'`` for ``delta > 0``, clipped at 0 when ``clip``; 0 otherwise.

    Parameters
    ----------
    normal, damping : str
        The keys it was built from.
    m_eff : float
        Effective mass [kg].
    stiffness : float
        ``k`` [N/m] (hooke) or ``K = (4/3) E* sqrt(R*)`` [N/m^(3/2)] (hertz).
    exponent : float
        ``p``: 1 or 3/2.
    c0 : float
        Dashpot prefactor, ``c(delta) = c0 delta^q`` [N s/m / m^q].
    q : float
        Overlap exponent of the dashpot.
    clip : bool
        Whether the total force is clipped at zero.
    """

    normal: str
    damping: str
    m_eff: float
    stiffness: float
    exponent: float
    c0: float
    q: float
    clip: bool

    def force(self, overlap: Any, overlap_rate: Any) -> Any:
        """Normal force [N] (positive repulsive), vectorised over overlaps and their rates.

        Parameters
        ----------
        overlap : float or numpy.ndarray
            ``delta`` [m]; no force where ``delta <= 0``.
        overlap_rate : float or numpy.ndarray
            ``d delta/dt`` [m/s], positive while approaching.

        Returns
        -------
        float or numpy.ndarray
            ``F``.
        """
        d = np.asarray(overlap, dtype=float)
        dp = np.maximum(d, 0.0)
        f = self.stiffness * dp**self.exponent + self.c0 * dp**self.q * np.asarray(overlap_rate, dtype=float)
        if self.clip:
            f = np.maximum(f, 0.0)
        out = np.where(d > 0.0, f, 0.0)
        return float(out) if out.ndim == 0 else out


def _stiffness(normal, k, E_eff, R_eff) -> float:
    if normal == "hooke":
        if k is None or not k > 0:
            raise InputError("k", f"the hooke law needs a positive stiffness k [N/m] (got {k!r})")
        return float(k)
    if E_eff is None or R_eff is None or not (E_eff > 0 and R_eff > 0):
        raise InputError("E_eff", "the hertz law needs positive E_eff [Pa] and R_eff [m]")
    return 4.0 / 3.0 * float(E_eff) * math.sqrt(float(R_eff))


def _dashpot(model: DampingModel, normal, m, kk, R_eff, e, coefficient, tsuji_version) -> float:
    """``c0`` of ``c = c0 delta^q`` for the model (see the module docstring for each source)."""
    key = model.key
    if key == "none":
        return 0.0
    if model.takes == "coefficient" or (key == "mercurydpm" and coefficient is not None):
        if coefficient is None or not coefficient >= 0:
            raise InputError("coefficient", f"{key} takes its damping coefficient (>= 0), got {coefficient!r}")
        if key == "lammps-viscoelastic":
            if R_eff is None or not R_eff > 0:
                raise InputError("R_eff", "lammps-viscoelastic needs R_eff (its dashpot is damp*m_eff*sqrt(R* delta))")
            return coefficient * m * math.sqrt(R_eff)
        if key == "lammps-mass-velocity":
            return coefficient * m
        return coefficient if normal == "hooke" else coefficient * math.sqrt(m * kk)  # mercurydpm gamma or d
    e = check_restitution(e)
    zeta = damping_ratio_from_restitution(e)
    if key.startswith("lammps-tsuji"):
        tsuji_version = "2021" if key == "lammps-tsuji-2021" else tsuji_version
        if tsuji_version not in TSUJI_FACTORS:
            raise InputError("tsuji_version", f"must be one of {', '.join(TSUJI_FACTORS)} (got {tsuji_version!r})")
        return TSUJI_FACTORS[tsuji_version] * tsuji_alpha(e) * math.sqrt(m * kk)
    if key == "lammps-coeff-restitution":
        return lammps_coeff_restitution_damp(e, normal) * math.sqrt(m * kk)
    if normal == "hooke":  # liggghts, mercurydpm: 2 zeta sqrt(k m)
        return 2.0 * zeta * math.sqrt(m * kk)
    if key == "yade-mindlin":
        return yade_mindlin_dissipation(e) * math.sqrt(m * kk)
    return hertz_mindlin_dissipation(e) * math.sqrt(m * kk)  # liggghts, mercurydpm (hertz)


def collision_law(normal: str, damping: str, *, m_eff: float, k: float | None = None, E_eff: float | None = None,
                  R_eff: float | None = None, restitution: float | None = None, coefficient: float | None = None,
                  clip: bool | None = None, tsuji_version: str = "current", cohesion: str | None = None) -> CollisionLaw:
    """The normal collision law of one code with its parameters as that code takes them.

    Parameters
    ----------
    normal : str
        ``"hooke"`` (``F_el = k delta``) or ``"hertz"`` (``F_el = (4/3) E* sqrt(R*) delta^(3/2)``).
    damping : str
        A key of ``DAMPING_MODELS``.
    m_eff : float
        Effective mass [kg].
    k : float, optional
        Hooke stiffness [N/m].
    E_eff, R_eff : float, optional
        ``E*`` [Pa] and ``R*`` [m] (hertz; ``R_eff`` also for ``lammps-viscoelastic``).
    restitution : float, optional
        ``e`` in (0, 1] for the models that take it.
    coefficient : float, optional
        The code's own damping coefficient for ``lammps-viscoelastic``, ``lammps-mass-velocity`` and (instead
        of ``e``) ``mercurydpm``.
    clip : bool, optional
        Clip the normal force at zero; default: what the code does (``CLIPPING``).
    tsuji_version : str
        ``"current"`` (factor sqrt(2)) or ``"2021"`` (Debian's LAMMPS) for ``lammps-tsuji``.
    cohesion : str, optional
        Refused: JKR and DMT cohesion are not modelled.

    Returns
    -------
    CollisionLaw
        The law; ``force(overlap, overlap_rate)`` evaluates it.
    """
    if cohesion is not None:
        raise InputError("cohesion", f"{cohesion!r} cohesion changes the impact and is not modelled (JKR and DMT)")
    normal = check_normal(normal)
    model = check_damping(damping, normal)
    if not (m_eff is not None and m_eff > 0 and math.isfinite(m_eff)):
        raise InputError("m_eff", f"must be a positive finite mass (got {m_eff!r})")
    kk = _stiffness(normal, k, E_eff, R_eff)
    c0 = _dashpot(model, normal, float(m_eff), kk, R_eff, restitution, coefficient, tsuji_version)
    return CollisionLaw(normal, damping, float(m_eff), kk, 1.0 if normal == "hooke" else 1.5, float(c0),
                        model.exponents[normal], model.clips if clip is None else bool(clip))


def mindlin_tangential(xi: Any, v_t: Any, dt: float, contact_radius: Any, k: float, damp: Any, mu: float,
                       f_n_crit: Any) -> tuple[Any, Any]:
    """One step of LAMMPS's ``tangential mindlin`` along one tangential direction (vectorised over contacts).

    ``xi += v_t dt``; ``F_t = -k a xi - damp v_t``; if ``|F_t| > mu F_ncrit`` the force is scaled to the
    Coulomb limit and the displacement reset to ``xi = -(F_t + damp v_t)/(k a)``
    (src/GRANULAR/gran_sub_mod_tangential_kernel.h, gran_tangential_mindlin; ``k = 8 G*`` when NULL,
    ``damp = x_gammat`` times the normal damping prefactor, ``F_ncrit = |F_n,tot|``).  The history rotation
    of a turning contact plane and the ``rescale`` variants are not modelled.

    Parameters
    ----------
    xi : float or numpy.ndarray
        Tangential displacement history [m] before the step.
    v_t : float or numpy.ndarray
        Tangential relative velocity at the contact [m/s].
    dt : float
        Step [s].
    contact_radius : float or numpy.ndarray
        ``a = sqrt(R* delta)`` [m].
    k : float
        ``k`` [Pa] (``8 G*`` for Mindlin).
    damp : float or numpy.ndarray
        Tangential damping coefficient [N s/m].
    mu : float
        Friction coefficient.
    f_n_crit : float or numpy.ndarray
        ``|F_n|`` [N].

    Returns
    -------
    tuple
        ``(F_t, xi_new)``.
    """
    x = np.asarray(xi, dtype=float) + np.asarray(v_t, dtype=float) * dt
    ka = k * np.asarray(contact_radius, dtype=float)
    f = -ka * x - damp * np.asarray(v_t, dtype=float)
    limit = mu * np.asarray(f_n_crit, dtype=float)
    slip = np.abs(f) > limit
    f_slip = np.where(slip, np.sign(f) * limit, f)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_slip = np.where(slip, -(f_slip + damp * np.asarray(v_t, dtype=float)) / ka, x)
    return f_slip, x_slip
