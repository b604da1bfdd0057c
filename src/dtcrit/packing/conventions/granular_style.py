"""LAMMPS ``pair_style granular`` as per-contact springs and dashpots (LAMMPS docs ``pair_granular``;
source ``src/GRANULAR/pair_granular.cpp``).

Given as ``--pair-style 'granular MODEL ARGS ... [tangential ...] [damping ...] [rolling ...] [twisting ...]'``:
the words of the ``pair_coeff`` line after ``* *`` (one coefficient set for every type pair).  With
``a = sqrt(R* delta)``, ``R* = R_i R_j/(R_i + R_j)``, ``m_eff = m_i m_j/(m_i + m_j)``:

* normal ``hooke kn eta``: ``F = kn delta`` (tangent ``kn``); ``hertz kn eta``: ``F = kn a delta``
  (tangent ``3/2 kn a``); ``hertz/material E eta nu`` and ``dmt E eta nu gamma``:
  ``F = 4/3 E_eff a delta`` (``- 4 pi gamma R*`` for DMT; tangent ``2 E_eff a``), ``E_eff = E/(2 (1 - nu^2))``
  for one material;
* ``damping velocity``: ``eta_n = eta``; ``mass_velocity``: ``eta m_eff``; ``viscoelastic`` (default):
  ``eta a m_eff``; ``tsuji``: ``alpha(e) sqrt(m_eff k)`` with ``e = eta`` and ``k = F/delta``;
* ``tangential linear_nohistory x mu``: dashpot ``x eta_n`` only; ``linear_history kt x mu``: spring
  ``kt``; ``mindlin kt|NULL x mu`` (and ``mindlin_rescale``): spring ``kt a``, or ``8 G_eff a`` for NULL
  with ``G_eff = E/(4 (2 - nu)(1 + nu))``; ``mu = 0`` removes the tangential force (Coulomb limit 0);
* ``rolling sds k gamma mu``: the pseudo-force ``k xi_roll`` on ``v_roll = -R* (w_i - w_j) x n`` with
  torque ``R* n x F``: rolling stiffness ``k R*^2`` [N m/rad], dashpot ``gamma R*^2``;
* ``twisting sds k gamma mu``: ``k`` and ``gamma`` directly; ``twisting marshall``: ``k_t a^2/2`` and
  ``eta_t a^2/2`` from the tangential spring and dashpot.

Kinematics: the slip velocity uses the full radius, the torque the arm ``R - delta/2`` (checked in
``tests/engines/test_engine_lammps_pairs.py``); ``dtcrit.packing.conventions.engines`` uses their symmetric equivalent, arms
``sqrt(R (R - delta/2))``, exact for two equal spheres.  ``jkr`` (its stiffness follows the
hysteretic JKR branch) is refused, and so is every keyword the audit does not model
(:data:`GRANULAR_TERMS`): ``heat`` other than ``none`` (an explicit heat conduction with its own step),
``limit_damping`` where it can act (``if (limit_damping && Fntot < 0) Fntot = 0``: with a normal
dashpot or the DMT pull-off), damping and tangential models not listed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError
from dtcrit.physics import contact_laws as cl
from dtcrit.physics.contact_laws import same_material_moduli
from dtcrit.physics.damping_conventions import tsuji_alpha
from dtcrit.physics.rotational_springs import marshall_twisting, sds_rolling

from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.conventions.law_terms import FLAG, ContactTerms, number
from dtcrit.packing.uniform_values import entries

NORMAL_ARGS = {"hooke": ("kn", "eta"), "hertz": ("kn", "eta"), "hertz/material": ("E", "eta", "nu"),
               "dmt": ("E", "eta", "nu", "gamma")}
TANGENTIAL_ARGS = {"linear_nohistory": ("x", "mu"), "linear_history": ("kt", "x", "mu"),
                   "mindlin": ("kt", "x", "mu"), "mindlin_rescale": ("kt", "x", "mu")}
DAMPING = ("velocity", "mass_velocity", "viscoelastic", "tsuji")

#: every model and keyword of ``pair_coeff`` for ``pair_style granular`` (LAMMPS pair_granular docs):
#: what the audit does with it
GRANULAR_TERMS = {
    **{f"normal {name}": "modelled" for name in NORMAL_ARGS},
    "normal jkr": "refused (hysteretic JKR branch)",
    **{f"damping {name}": "modelled" for name in DAMPING},
    "damping coeff_restitution": "refused (not modelled)",
    **{f"tangential {name}": "modelled (contacts taken as sticking)" for name in TANGENTIAL_ARGS},
    "tangential mindlin/force": "refused (not modelled)",
    "tangential mindlin_rescale/force": "refused (not modelled)",
    "rolling none": "modelled (no term)",
    "rolling sds": "modelled",
    "twisting none": "modelled (no term)",
    "twisting marshall": "modelled",
    "twisting sds": "modelled",
    "heat none": "modelled (no term)",
    "heat area": "refused (heat conduction: its own explicit step, not audited)",
    "heat radius": "refused (heat conduction: its own explicit step, not audited)",
    "limit_damping": "refused when it can act: eta > 0 or the dmt normal model",
}


@dataclass(frozen=True)
class GranularStyle:
    """A parsed LAMMPS ``pair_style granular`` coefficient set (module docstring).

    Parameters
    ----------
    normal : str
        Normal model (``hooke``, ``hertz``, ``hertz/material``, ...).
    normal_args : dict
        Its coefficients by name (e.g. ``k``, ``damp``; ``E``, ``nu`` for material models).
    tangential : str
        Tangential model (``linear_history``, ...).
    tangential_args : dict
        Its coefficients by name.
    damping : str
        Damping model (``velocity``, ``mass_velocity``, ``viscoelastic``, ``tsuji``).
    rolling : dict or None
        ``rolling sds`` coefficients, ``None`` without rolling.
    twisting : tuple or None
        ``(model, coefficients)`` of the twisting model, ``None`` without twisting.
    text : str
        The ``pair_coeff`` words.
    """

    normal: str
    normal_args: dict
    tangential: str
    tangential_args: dict
    damping: str
    rolling: dict | None
    twisting: tuple[str, dict] | None
    text: str
    arm = "granular"  # slip velocity with the full radius, torque with R - delta/2 (module docstring)

    def describe(self) -> str:
        """The style in words, for reports.

        Returns
        -------
        str
            The description.
        """
        return f"LAMMPS pair_style granular, pair_coeff * * {self.text}"

    def material(self) -> tuple[float, float] | None:
        """Young's modulus and Poisson's ratio of a material normal model.

        Returns
        -------
        tuple of float or None
            ``(E [Pa], nu)`` when the normal model takes them, else ``None``.
        """
        return (self.normal_args["E"], self.normal_args["nu"]) if "E" in self.normal_args else None

    def _material(self) -> tuple[float, float]:
        return same_material_moduli(self.normal_args["E"], self.normal_args["nu"])

    def terms(self, packing: Packing, contacts: Contacts) -> ContactTerms:
        """Every contact's springs, dashpots and normal force under this style (module docstring).

        Parameters
        ----------
        packing : Packing
            The particles (masses).
        contacts : Contacts
            The sphere contacts (overlaps, effective radii).

        Returns
        -------
        ContactTerms
            The per-contact terms.
        """
        m = packing.masses
        m_eff = cl.reduced(m[contacts.i], m[contacts.j])
        delta = contacts.overlap
        r_star = contacts.radius_eff
        a = np.sqrt(r_star * delta)
        if self.normal == "hooke":
            force, kn = self.normal_args["kn"] * delta, float(self.normal_args["kn"])
        elif self.normal == "hertz":
            force, kn = self.normal_args["kn"] * a * delta, cl.lammps_hertz_tangent_stiffness(self.normal_args["kn"], a)
        else:
            e_eff, _ = self._material()
            force, kn = 4.0 / 3.0 * e_eff * a * delta, cl.hertz_normal_stiffness(e_eff, a)
            if self.normal == "dmt":
                force = force - 4.0 * math.pi * self.normal_args["gamma"] * r_star
        eta = self.normal_args["eta"]
        secant = np.divide(force if self.normal != "dmt" else force + 4.0 * math.pi * self.normal_args["gamma"] * r_star,
                           delta, out=np.zeros_like(delta), where=delta > 0)
        eta_n = {"velocity": float(eta), "mass_velocity": eta * m_eff, "viscoelastic": eta * a * m_eff,
                 "tsuji": tsuji_alpha(eta) * np.sqrt(m_eff * secant)}[self.damping]
        t = self.tangential_args
        on = 1.0 if t["mu"] > 0 else 0.0
        if self.tangential == "linear_nohistory":
            ks = 0.0
        elif self.tangential == "linear_history":
            ks = float(t["kt"])
        elif t["kt"] is None:
            ks = cl.mindlin_tangent_stiffness(self._material()[1], a)
        else:
            ks = t["kt"] * a
        ks, cs = on * ks, on * t["x"] * eta_n
        kr = cr = ktw = ctw = None
        if self.rolling is not None and self.rolling["mu"] > 0:
            kr, cr = sds_rolling(self.rolling["k"], self.rolling["gamma"], r_star)
        if self.twisting is not None:
            kind, tw = self.twisting
            if kind == "marshall":
                ktw, ctw = marshall_twisting(ks, cs, a)
            elif tw["mu"] > 0:
                ktw, ctw = float(tw["k"]), float(tw["gamma"])
        count = contacts.count  # a number below is one value for every contact, held once
        kr, ktw, cr, ctw = (None if v is None else entries(v, count) for v in (kr, ktw, cr, ctw))
        return ContactTerms(entries(kn, count), entries(ks, count), entries(eta_n, count), entries(cs, count), force,
                            kr=kr, ktw=ktw, cr=cr, ctw=ctw)


def _take(words: list[str], k: int, names: tuple[str, ...], what: str, *, nullable=("kt",)) -> tuple[dict, int]:
    if len(words) < k + len(names):
        raise InputError(FLAG, f"{what} takes {len(names)} values ({' '.join(names)}), found {len(words) - k}")
    vals = {n: number(words[k + m], f"{what} {n}", allow_null=n in nullable) for m, n in enumerate(names)}
    return vals, k + len(names)


def parse_granular(words: list[str]) -> GranularStyle:
    """Parse the ``pair_coeff`` words of ``pair_style granular`` (module docstring).

    Parameters
    ----------
    words : list of str
        The words after ``pair_coeff`` (a leading ``* *`` is skipped), e.g.
        ``hooke 1e4 0.5 tangential linear_history 1e4 1 0.5 damping mass_velocity``.

    Returns
    -------
    GranularStyle
        The parsed models and coefficients.

    Raises
    ------
    InputError
        For an unknown or unsupported model (``jkr``) or a malformed coefficient.
    """
    if words[:2] == ["*", "*"]:
        words = words[2:]
    if not words:
        raise InputError(FLAG, "granular: give the pair_coeff words after '* *', e.g. 'granular hooke 1e4 0.5 "
                               "tangential linear_history 1e4 1 0.5 damping mass_velocity'")
    normal = words[0]
    if normal == "jkr":
        raise InputError(FLAG, "granular jkr is not supported (its stiffness follows the hysteretic JKR branch): "
                               "give a --contacts table")
    if normal not in NORMAL_ARGS:
        raise InputError(FLAG, f"granular: unknown normal model {normal!r}; supported: {', '.join(NORMAL_ARGS)}")
    normal_args, k = _take(words, 1, NORMAL_ARGS[normal], normal, nullable=())
    tangential: str | None = None
    tangential_args: dict | None = None
    rolling: dict | None = None
    twisting: tuple[str, dict] | None = None
    damping = "viscoelastic"
    limit = False
    while k < len(words):
        key = words[k]
        if key == "tangential":
            if k + 1 >= len(words) or words[k + 1] not in TANGENTIAL_ARGS:
                found = words[k + 1] if k + 1 < len(words) else "nothing"
                raise InputError(FLAG, f"granular: unknown tangential model {found!r}; supported: {', '.join(TANGENTIAL_ARGS)}")
            tangential = words[k + 1]
            tangential_args, k = _take(words, k + 2, TANGENTIAL_ARGS[tangential], tangential)
            if tangential.startswith("mindlin") and tangential_args["kt"] is None and normal in ("hooke", "hertz"):
                raise InputError(FLAG, f"granular: mindlin with kt NULL needs a material normal model, not {normal}")
        elif key == "damping":
            if k + 1 >= len(words) or words[k + 1] not in DAMPING:
                found = words[k + 1] if k + 1 < len(words) else "nothing"
                raise InputError(FLAG, f"granular: damping {found!r} is not modelled by the audit; modelled: "
                                       f"{', '.join(DAMPING)}")
            damping, k = words[k + 1], k + 2
        elif key == "rolling":
            if words[k + 1:k + 2] == ["none"]:
                k += 2
                continue
            if words[k + 1:k + 2] != ["sds"]:
                raise InputError(FLAG, f"granular: rolling {' '.join(words[k + 1:k + 2]) or 'nothing'!r} is not modelled "
                                       "by the audit; modelled: 'sds k gamma mu', 'none'")
            rolling, k = _take(words, k + 2, ("k", "gamma", "mu"), "rolling sds")
        elif key == "twisting":
            model = words[k + 1] if k + 1 < len(words) else ""
            if model == "none":
                k += 2
            elif model == "marshall":
                twisting, k = ("marshall", {}), k + 2
            elif model == "sds":
                vals, k = _take(words, k + 2, ("k", "gamma", "mu"), "twisting sds")
                twisting = ("sds", vals)
            else:
                raise InputError(FLAG, f"granular: twisting {model or 'nothing'!r} is not modelled by the audit; "
                                       "modelled: 'marshall', 'sds k gamma mu', 'none'")
        elif key == "limit_damping":
            limit, k = True, k + 1
        elif key == "heat":
            model = words[k + 1] if k + 1 < len(words) else "nothing"
            if model != "none":
                raise InputError(FLAG, f"granular: heat {model!r} integrates heat conduction with its own explicit "
                                       "step, which the audit does not model (only 'heat none')")
            k += 2
        else:
            raise InputError(FLAG, f"granular: unknown keyword {key!r}")
    if tangential is None or tangential_args is None:
        raise InputError(FLAG, "granular: the tangential model is required ('tangential linear_history kt x mu', ...)")
    if limit and (normal_args["eta"] > 0 or normal == "dmt"):
        raise InputError(FLAG, "granular: limit_damping clamps the normal force at zero (here it can act: "
                               f"{'the dmt pull-off' if normal == 'dmt' else 'a normal dashpot'}), which the audit "
                               "does not model")
    return GranularStyle(normal, normal_args, tangential, tangential_args, damping, rolling, twisting, " ".join(words))
