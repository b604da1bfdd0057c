"""How DEM codes turn a restitution coefficient or damping ratio into dashpots, per direction.

A scene gives damping once (``restitution``, ``damping_ratio`` or the coefficients ``cn``/``cs``)
and names the code whose convention maps it (``[contact] damping_convention``).  Each convention
fixes, per direction j (normal n, tangential t), a factor ``f_j`` and a mass ``M_j`` with

    c_j = f_j * 2 zeta_j sqrt(k_j M_j),

where ``zeta_j`` is the damping ratio *as that code defines it* (the one dtcrit prints), and how
``zeta_t`` follows from the user's ``zeta``.  ``zeta(e) = -ln e / sqrt(pi^2 + ln^2 e)`` throughout.
The mode damping ratio that decides the step, ``c A / (2 sqrt(k A))``, is reported beside it.

Sources (each read in the code's source or documentation; see README, "Damping conventions"):

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
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from dtcrit.errors import InputError

DAMPING_KEYS = ("cn", "cs", "restitution", "damping_ratio")

HERTZ_FACTOR = 2.0 * math.sqrt(5.0 / 6.0) / 2.0  # c = 2 sqrt(5/6) zeta sqrt(S m*) = f * 2 zeta sqrt(S m*)


@dataclass(frozen=True)
class Convention:
    """One code's map zeta -> (c_n, c_t); see the module docstring."""

    name: str
    code: str  # the code and contact model it stands for
    factor_n: float
    factor_t: float
    mass_t: float  # M_t / m*
    shear_rule: str  # "zeta" (the same zeta defines c_t), "same" (c_t = c_n), "half" (c_t = c_n/2), "two_sevenths"
    wall_mass: float  # the effective mass of a particle of mass m against a fixed wall, / m
    models: tuple[str, ...] = ("linear", "hertz", "yade")

    def dashpots(self, zeta: float, kn: float, ks: float, m_eff: float) -> tuple[float, float]:
        """(c_n, c_t) [N s/m] for the user's damping ratio ``zeta`` and effective mass ``m_eff``."""
        cn = self.factor_n * 2.0 * zeta * math.sqrt(kn) * math.sqrt(m_eff)
        if self.shear_rule == "half":
            return cn, 0.5 * cn
        if self.shear_rule == "two_sevenths":
            return cn, 2.0 / 7.0 * cn
        if self.shear_rule == "same":
            return cn, cn
        return cn, self.factor_t * 2.0 * zeta * math.sqrt(ks) * math.sqrt(self.mass_t * m_eff)

    def ratios(self, cn: float, cs: float, kn: float, ks: float, m_eff: float) -> tuple[float, float | None]:
        """(zeta_n, zeta_t) as this convention defines them; zeta_t is None without a tangential spring."""
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
                             1.0, 1.0, 1.0, "two_sevenths", 1.0, ("linear", "yade")),
    "yade": Convention("yade", "YADE ViscElMat: c_t = 2 zeta sqrt(ks (2/7) m*); m* = m/2 at walls",
                       1.0, 1.0, 2.0 / 7.0, "zeta", 0.5, ("linear", "yade")),
    "pfc": Convention("pfc", "PFC linear: c_j = 2 beta sqrt(k_j m_c) in each direction", 1.0, 1.0, 1.0, "zeta", 1.0),
}
DEFAULT_CONVENTION = {"linear": "lammps", "yade": "yade", "hertz": "liggghts"}


def liggghts_hertz() -> Convention:
    """LIGGGHTS's Hertz convention is EDEM's law (2 sqrt(5/6) zeta sqrt(S_j m*)) under its own name."""
    e = CONVENTIONS["edem"]
    return Convention("liggghts", CONVENTIONS["liggghts"].code, e.factor_n, e.factor_t, 1.0, "zeta", 1.0)


def convention_for(name: str | None, model: str, key: str = "contact.damping_convention") -> Convention:
    """The convention a scene uses: the one named, or the default of the contact model."""
    chosen = DEFAULT_CONVENTION[model] if name is None else name
    if chosen not in CONVENTIONS:
        raise InputError(key, f"unknown damping convention {chosen!r}; choose one of {', '.join(CONVENTIONS)}")
    conv = CONVENTIONS[chosen]
    if model not in conv.models:
        raise InputError(key, f"the {chosen!r} convention is defined for {', '.join(conv.models)} contacts, not {model}")
    if chosen == "liggghts" and model == "hertz":
        return liggghts_hertz()
    return conv


def damping_ratio_from_restitution(e: float) -> float:
    """Damping ratio of a linear spring-dashpot whose normal restitution coefficient is ``e``.

    zeta = -ln e / sqrt(pi^2 + ln^2 e)  (exit/entry speed ratio exp(-zeta pi / sqrt(1 - zeta^2)) = e);
    e = 1 gives 0, e -> 0 gives 1.
    """
    if e >= 1.0:
        return 0.0
    if e <= 0.0:
        return 1.0
    L = -math.log(e)
    return L / math.hypot(math.pi, L)


def damping_kind(restitution, damping_ratio, cn, cs) -> str:
    """How damping was given: none | coefficients | restitution | damping_ratio."""
    if restitution is not None:
        return "restitution"
    if damping_ratio is not None:
        return "damping_ratio"
    return "coefficients" if (cn or 0.0) > 0 or (cs or 0.0) > 0 else "none"


def parse_damping(prefix: str, table: dict) -> tuple[float | None, float | None, float | None, float | None]:
    """``(cn, cs, restitution, damping_ratio)`` of a table that gives damping one way only
    (coefficients ``cn``/``cs``, ``restitution`` or ``damping_ratio``); a restitution coefficient
    sets the damping ratio ``zeta(e)``.
    """
    from dtcrit.scenes.fields import _number

    given = [k for k in DAMPING_KEYS if k in table]
    ways = {("cn" if k in ("cn", "cs") else k) for k in given}
    if len(ways) > 1:
        names = " and ".join(sorted({"cn/cs" if k in ("cn", "cs") else k for k in given}))
        raise InputError(prefix + given[-1], f"conflicting damping specifications: {names}; give exactly one way")
    cn = _number(prefix + "cn", table["cn"], allow_zero=True) if "cn" in table else None
    cs = _number(prefix + "cs", table["cs"], allow_zero=True) if "cs" in table else None
    restitution = _number(prefix + "restitution", table["restitution"], hi=1.0) if "restitution" in table else None
    zeta = _number(prefix + "damping_ratio", table["damping_ratio"], allow_zero=True) if "damping_ratio" in table else None
    if restitution is not None:
        zeta = damping_ratio_from_restitution(restitution)
    return cn, cs, restitution, zeta
