"""Rotational springs and dashpots of a contact, as a scene gives them.

Rolling ``k_r`` (the moment against the relative rotation
perpendicular to the normal) and twisting ``k_tw`` (about the normal), in N m/rad, with dashpots
``c_r``, ``c_tw`` in N m s/rad, given directly (``[contact]`` keys ``kr``, ``ktw``, ``cr``, ``ctw``) or by a
code's own model and parameters.  ``R* = R_1 R_2/(R_1 + R_2)``, ``k_n``, ``k_s`` the contact's springs:

``rolling_model``:

* ``"epsd"`` (LIGGGHTS ``rolling_model epsd``, ``rolling_model_epsd.h``): ``k_r = 2.25 k_n mu_r^2 R*^2``,
  ``c_r = eta_r 2 sqrt(I_r k_r)`` with ``I_r = 1.4 m_1 R_1^2 m_2 R_2^2/(m_1 R_1^2 + m_2 R_2^2)``;
  ``mu_r`` = ``rolling_friction`` (``coeffRollFrict``), ``eta_r`` = ``rolling_viscous_damping``
  (``coeffRollVisc``, default 0);
* ``"epsd2"`` (LIGGGHTS/Aspherix ``rolling_model epsd2``, ``rolling_model_epsd2.h``): ``k_r = k_t R*^2``
  with ``k_t`` the tangential spring, no dashpot (``mu_r`` only caps the moment);
* ``"epsd3"`` (``rolling_model_epsd3.h``): ``k_r = f k_n mu_r^2 R*^2`` with ``f`` =
  ``rolling_stiffness_factor`` (``coeffRollStiffness``), ``c_r`` as EPSD;
* ``"sds"`` (LAMMPS ``pair_style granular``, ``rolling sds k_roll gamma_roll mu``): a pseudo-force
  ``k_roll xi`` on ``R* (omega_i - omega_j) x n`` with torque ``R* n x F``: ``k_r = k_roll R*^2``,
  ``c_r = gamma_roll R*^2`` (keys ``k_roll``, ``gamma_roll``);
* ``"yade"`` (YADE ``Ip2_CohFrictMat_CohFrictMat_CohFrictPhys``, ``CohesiveFrictionalContactLaw.cpp``):
  ``k_r = alpha_kr k_s R_1 R_2`` and ``k_tw = alpha_ktw k_s R_1 R_2`` (keys ``alpha_kr``, ``alpha_ktw``;
  YADE takes the harmonic mean of the two materials' alphas); the moment ``k_r x bending`` acts
  as ``-M`` on body 1 and ``+M`` on body 2.

``twisting_model``:

* ``"marshall"`` (LAMMPS ``twisting marshall``): ``k_tw = k_t a^2/2``, ``c_tw = eta_t a^2/2`` from the
  tangential spring and dashpot, ``a = sqrt(R* delta)`` the contact radius (Hertz: at the largest
  overlap; other laws: key ``contact_radius``);
* ``"sds"`` (LAMMPS ``twisting sds k_twist gamma_twist mu``): ``k_tw = k_twist``, ``c_tw = gamma_twist``.

The formulas are :mod:`dtcrit.physics.rotational_springs`.  These models are defined for spheres; other shapes take ``kr``/``ktw`` directly.  Walls take their
own ``kr``, ``ktw``, ``cr``, ``ctw`` in ``[[wall]]``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from dtcrit.errors import InputError
from dtcrit.physics import rotational_springs as rs_
from dtcrit.scenes.fields import _choice, _number
from dtcrit.scenes.model import ROTATIONAL_KEYS

ROLLING_MODELS = ("epsd", "epsd2", "epsd3", "sds", "yade")
TWISTING_MODELS = ("marshall", "sds")
DIRECT_KEYS = ROTATIONAL_KEYS[:4]
"""The direct springs and dashpots ``kr``, ``ktw``, ``cr``, ``ctw``."""
MODEL_KEYS = ROTATIONAL_KEYS[4:]
"""The rolling and twisting models' keys."""
NEEDS = {
    "epsd": ("rolling_friction",), "epsd2": (), "epsd3": ("rolling_friction", "rolling_stiffness_factor"),
    "sds": ("k_roll",), "yade": ("alpha_kr",),
}
OPTIONAL = {
    "epsd": ("rolling_viscous_damping",), "epsd2": (), "epsd3": ("rolling_viscous_damping",), "sds": ("gamma_roll",),
    "yade": ("alpha_ktw",),
}


@dataclass(frozen=True)
class RotationalLaw:
    """The rotational part of ``[contact]`` after validation (module docstring).

    Parameters
    ----------
    kr : float or None
        Rolling spring [N m/rad] given directly.
    ktw : float or None
        Twisting spring [N m/rad] given directly.
    cr : float or None
        Rolling dashpot [N m s/rad] given directly.
    ctw : float or None
        Twisting dashpot [N m s/rad] given directly.
    rolling_model : str or None
        A code's rolling model (``epsd``, ``epsd2``, ``epsd3``, ``sds``, ``yade``).
    twisting_model : str or None
        A code's twisting model (``marshall``, ``sds``).
    params : tuple of (str, float)
        The models' parameters by key (``rolling_friction``, ``k_roll``, ``alpha_kr``, ...).
    """

    kr: float | None = None
    ktw: float | None = None
    cr: float | None = None
    ctw: float | None = None
    rolling_model: str | None = None
    twisting_model: str | None = None
    params: tuple[tuple[str, float], ...] = ()

    @property
    def present(self) -> bool:
        """Whether any rotational key was given."""
        return any(v is not None for v in (self.kr, self.ktw, self.cr, self.ctw, self.rolling_model, self.twisting_model))

    def param(self, name: str, default: float | None = None) -> float | None:
        """A model parameter's value.

        Parameters
        ----------
        name : str
            The key (``k_roll``, ``rolling_friction``, ...).
        default : float or None
            The value when not given.

        Returns
        -------
        float or None
            The value.
        """
        return dict(self.params).get(name, default)


def parse_rotational(prefix: str, table: dict) -> RotationalLaw:
    """Validate the rotational keys of a ``[contact]`` table.

    Refuses negative values, a direct ``kr``/``cr`` (``ktw``/``ctw``) together with a model that
    defines it, missing model parameters and keys the chosen models do not take.

    Parameters
    ----------
    prefix : str
        Key prefix for error messages (e.g. ``"contact."``).
    table : dict
        The ``[contact]`` table as read from the scene file.

    Returns
    -------
    RotationalLaw
        The validated rotational law (all ``None`` when no key is given).

    Raises
    ------
    InputError
        Naming the offending key.
    """
    direct = {k: _number(prefix + k, table[k], allow_zero=True) for k in DIRECT_KEYS if k in table}
    rolling = _choice(prefix + "rolling_model", table["rolling_model"], ROLLING_MODELS, "rolling model") \
        if "rolling_model" in table else None
    twisting = _choice(prefix + "twisting_model", table["twisting_model"], TWISTING_MODELS, "twisting model") \
        if "twisting_model" in table else None
    if rolling is not None and ("kr" in direct or "cr" in direct):
        raise InputError(prefix + ("kr" if "kr" in direct else "cr"),
                         f"given with rolling_model = {rolling!r}, which defines it; give one or the other")
    takes_twist = twisting is not None or rolling == "yade" and "alpha_ktw" in table
    if takes_twist and ("ktw" in direct or "ctw" in direct):
        raise InputError(prefix + ("ktw" if "ktw" in direct else "ctw"), "given with a twisting model, which defines it; "
                         "give one or the other")
    if rolling == "yade" and twisting is not None and "alpha_ktw" in table:
        raise InputError(prefix + "alpha_ktw", "YADE's twisting stiffness and twisting_model both given; give one")
    allowed = set()
    if rolling is not None:
        allowed |= set(NEEDS[rolling] + OPTIONAL[rolling])
        for key in NEEDS[rolling]:
            if key not in table:
                raise InputError(prefix + key, f"missing: rolling_model = {rolling!r} needs {', '.join(NEEDS[rolling])}")
    if twisting == "sds":
        allowed |= {"k_twist", "gamma_twist"}
        if "k_twist" not in table:
            raise InputError(prefix + "k_twist", "missing: twisting_model = 'sds' needs k_twist [N m/rad]")
    if twisting == "marshall":
        allowed |= {"contact_radius"}
    params = []
    for key in MODEL_KEYS:
        if key in ("rolling_model", "twisting_model") or key not in table:
            continue
        if key not in allowed:
            why = (f"rolling_model = {rolling!r}" if rolling else "no rolling_model") + \
                  (f", twisting_model = {twisting!r}" if twisting else "")
            raise InputError(prefix + key, f"not used with {why}")
        params.append((key, _number(prefix + key, table[key], allow_zero=key not in ("contact_radius",))))
    return RotationalLaw(direct.get("kr"), direct.get("ktw"), direct.get("cr"), direct.get("ctw"), rolling, twisting,
                         tuple(params))


def _r_star(r1: float, r2: float | None) -> float:
    return r1 if r2 is None else r1 / (1.0 + r1 / r2) if r1 <= r2 else r2 / (1.0 + r2 / r1)


def resolve_rotational(law: RotationalLaw, kn: float, ks: float, cs: float, r1: float | None, r2: float | None,
                       m1: float, m2: float, delta: float | None, label: str) -> tuple[float, float, float, float]:
    """``(k_r, k_tw, c_r, c_tw)`` of one particle pair, each code's definition in the module docstring.

    Parameters
    ----------
    law : RotationalLaw
        The scene's rotational law.
    kn : float
        Normal spring of the contact [N/m].
    ks : float
        Tangential spring [N/m].
    cs : float
        Tangential dashpot [N s/m] (``marshall`` twisting).
    r1 : float or None
        Radius of particle 1 [m] (``None`` for non-spheres: only direct values allowed).
    r2 : float or None
        Radius of particle 2 [m].
    m1 : float
        Mass of particle 1 [kg].
    m2 : float
        Mass of particle 2 [kg].
    delta : float or None
        The (Hertz) overlap [m] when known, for the contact radius ``a = sqrt(R* delta)``.
    label : str
        Pair label for error messages (``"i-j"``).

    Returns
    -------
    tuple of float
        ``(k_r [N m/rad], k_tw [N m/rad], c_r [N m s/rad], c_tw [N m s/rad])``.

    Raises
    ------
    InputError
        For a code's model on non-spheres or a missing contact radius.
    """
    kr, ktw, cr, ctw = law.kr or 0.0, law.ktw or 0.0, law.cr or 0.0, law.ctw or 0.0
    if law.rolling_model is None and law.twisting_model is None:
        return kr, ktw, cr, ctw
    if r1 is None or r2 is None:
        raise InputError("contact.rolling_model" if law.rolling_model else "contact.twisting_model",
                         f"pair {label}: the codes' rolling and twisting models are defined for spheres; give kr, ktw "
                         "directly for other shapes")
    rs = _r_star(r1, r2)
    p = law.param
    if law.rolling_model in ("epsd", "epsd3"):
        factor = 2.25 if law.rolling_model == "epsd" else p("rolling_stiffness_factor")
        kr = rs_.epsd_rolling_stiffness(factor, kn, p("rolling_friction"), rs)
        cr = rs_.epsd_rolling_dashpot(p("rolling_viscous_damping", 0.0) or 0.0, kr, m1, r1, m2, r2)
    elif law.rolling_model == "epsd2":
        kr, cr = rs_.epsd2_rolling_stiffness(ks, rs), 0.0
    elif law.rolling_model == "sds":
        kr, cr = rs_.sds_rolling(p("k_roll"), p("gamma_roll", 0.0), rs)
    elif law.rolling_model == "yade":
        kr, cr = rs_.yade_rotational_stiffness(p("alpha_kr"), ks, r1, r2), 0.0
        if p("alpha_ktw") is not None:
            ktw, ctw = rs_.yade_rotational_stiffness(p("alpha_ktw"), ks, r1, r2), 0.0
    if law.twisting_model == "sds":
        k_twist, c_twist = p("k_twist"), p("gamma_twist", 0.0)
        assert k_twist is not None and c_twist is not None  # parse_rotational requires k_twist for sds
        ktw, ctw = k_twist, c_twist
    elif law.twisting_model == "marshall":
        a = p("contact_radius")
        if a is None:
            if delta is None:
                raise InputError("contact.contact_radius", "missing: twisting_model = 'marshall' needs the contact radius "
                                 "a [m] (k_tw = k_t a^2/2); it is implied only for Hertz contact (a = sqrt(R* delta_max))")
            a = math.sqrt(rs * delta)
        ktw, ctw = rs_.marshall_twisting(ks, cs, a)
    return kr, ktw, cr, ctw
