"""The ``[contact]`` table of a scene file: the contact model, its springs and damping, the elastic
constants it may give for every particle type, and its rotational springs.

The laws and their keys are described in :mod:`dtcrit.scenes.scene`; a bonded contact is read by
:mod:`dtcrit.scenes.bonds`, the rotational terms by :mod:`dtcrit.scenes.rotational` (imported only when
the table gives one of their keys).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Any

from dtcrit.errors import InputError
from dtcrit.scenes.damping_input import CONVENTIONS, convention_for, parse_damping
from dtcrit.scenes.fields import _check_keys, _choice, _number, _required, _short, _type_name
from dtcrit.scenes.law_damping import check_law_input
from dtcrit.scenes.model import (
    CONTACT_ALL,
    CONTACT_KEYS,
    CONTACT_MODELS,
    NOT_IN_THE_STEP,
    ROTATIONAL_KEYS,
    ContactLaw,
    Particle,
)


def _rotational(prefix: str, table: dict):
    """The contact's rotational springs (``dtcrit.scenes.rotational``, imported only when a key is given)."""
    from dtcrit.scenes.rotational import parse_rotational

    parsed = parse_rotational(prefix, table)
    return parsed if parsed.present else None


def _per_particle(key: str, value: Any, n: int, **limits) -> tuple[float, ...]:
    """A scalar (all particle types) or an array with one entry per particle type."""
    if isinstance(value, list):
        if len(value) != n:
            raise InputError(key, f"give one number, or an array of {n} (one per [[particle]] table; got {len(value)})")
        return tuple(_number(f"{key}[{m + 1}]", v, **limits) for m, v in enumerate(value))
    x = _number(key, value, **limits)
    return (x,) * n


def contact_law(table: Any, particles: list[Particle], out_warnings: list) -> tuple[ContactLaw, list[Particle]]:
    """The scene's ``[contact]`` table: its model, springs, damping and rotational terms, checked.

    Parameters
    ----------
    table : Any
        The ``[contact]`` table as read from the scene file.
    particles : list of Particle
        The scene's particle types; elastic constants given in ``[contact]`` are set on them.
    out_warnings : list
        ``(key, message)`` notes and warnings are appended here.

    Returns
    -------
    law : ContactLaw
        The contact law.
    particles : list of Particle
        The particle types, with the elastic constants of ``[contact]``.

    Raises
    ------
    InputError
        Naming the offending key.
    """
    prefix = "contact."
    if not isinstance(table, dict):
        raise InputError("contact", f"must be a table (got {_type_name(table)}: {_short(table)})")
    model = _choice(prefix + "model", _required(prefix, table, "model", f"one of {', '.join(CONTACT_MODELS)}"), CONTACT_MODELS, "contact model")
    _check_keys(prefix, table, CONTACT_KEYS[model], CONTACT_ALL, f"by the {model} contact model")

    if model == "bond":
        return _bond_contact(prefix, table, particles, out_warnings)
    cn, cs, restitution, zeta = parse_damping(prefix, table)  # one way only
    rotational = _rotational(prefix, table) if any(key in table for key in ROTATIONAL_KEYS) else None
    for key, why in NOT_IN_THE_STEP.items():
        if key in table:
            _number(prefix + key, table[key], allow_zero=True)
            out_warnings.append((prefix + key, f"note: accepted, not used: {why}"))

    # elastic constants: in [contact] (scalar or per particle) or in each [[particle]] table
    n = len(particles)
    for key in ("youngs_modulus", "poisson_ratio"):
        if key in table:
            clash = [p.number for p in particles if getattr(p, key) is not None]
            if clash:
                raise InputError(prefix + key, f"also given in particle[{clash[0]}]; give it in one place only")
    if "youngs_modulus" in table:
        values = _per_particle(prefix + "youngs_modulus", table["youngs_modulus"], n)
        particles = [replace(p, youngs_modulus=v) for p, v in zip(particles, values)]
    if "poisson_ratio" in table:
        values = _per_particle(prefix + "poisson_ratio", table["poisson_ratio"], n, lo=-1.0, hi=0.5, hi_open=True)
        particles = [replace(p, poisson_ratio=v) for p, v in zip(particles, values)]

    convention = None
    if "damping_convention" in table:
        convention = _choice(prefix + "damping_convention", table["damping_convention"], tuple(CONVENTIONS), "damping convention")
    convention_for(convention, model, prefix + "damping_convention")  # refuse a convention the model does not have

    if model == "yade":
        for p in particles:
            if p.kind != "sphere":
                raise InputError(prefix + "model", f"YADE's linear law is defined for spheres (particle[{p.number}] is a {p.kind})")
            if p.youngs_modulus is None:
                raise InputError(prefix + "youngs_modulus", f"missing: YADE's law kn = 2 E1 R1 E2 R2/(E1 R1 + E2 R2) needs "
                                 f"the Young's modulus of every particle (particle[{p.number}] has none)")
        ratio = _number(prefix + "ks_ratio", _required(prefix, table, "ks_ratio", "ks/kn (YADE's FrictMat.poisson)"), allow_zero=True)
        law = ContactLaw("yade", cn=cn, cs=cs, restitution=restitution, damping_ratio=zeta, damping_convention=convention,
                         ks_ratio=ratio, rotational=rotational)
        return law, particles

    if model == "linear":
        kn = _number(prefix + "kn", _required(prefix, table, "kn", "normal contact stiffness kn [N/m]"))
        ks = _number(prefix + "ks", _required(prefix, table, "ks", "shear contact stiffness ks [N/m] (0: frictionless)"),
                     allow_zero=True)
        if ks > kn:
            out_warnings.append(
                (prefix + "ks", f"warning: ks = {ks:g} exceeds kn = {kn:g} (physically k_n >= k_s; Peng et al. 2020, "
                 "Section 4.2); each direction is still checked with its own stiffness")
            )
        law = ContactLaw("linear", kn=kn, ks=ks, cn=cn, cs=cs, restitution=restitution, damping_ratio=zeta,
                         damping_convention=convention, rotational=rotational)
        return law, particles

    # hertz
    for p in particles:
        for key, what in (("youngs_modulus", "Young's modulus [Pa]"), ("poisson_ratio", "Poisson's ratio")):
            if getattr(p, key) is None:
                raise InputError(prefix + key, f"missing: Hertz contact needs the {what} of every particle "
                                 f"(in [contact] or in each [[particle]] table; particle[{p.number}] has none)")
    velocity = _number(prefix + "velocity", _required(prefix, table, "velocity", "impact (characteristic) velocity [m/s]"))
    radius = _number(prefix + "curvature_radius", table["curvature_radius"]) if "curvature_radius" in table else None
    if radius is None and any(p.kind != "sphere" for p in particles):
        other = next(p for p in particles if p.kind != "sphere")
        raise InputError(prefix + "curvature_radius",
                         f"missing: Hertz contact of a {other.kind} needs the effective radius of curvature R* [m] "
                         "of its stiffest contact (it is only implied for spheres)")
    if cn is not None or cs is not None:
        raise InputError(prefix + ("cn" if cn is not None else "cs"), "a Hertz contact takes restitution or damping_ratio "
                         "(its dashpots scale with the overlap), not coefficients")
    coef, factor = check_law_input(prefix, convention, model, {
        "restitution": restitution, "damping_ratio": zeta if restitution is None else None,
        **{k: _number(prefix + k, table[k], allow_zero=True) for k in ("damping_coefficient", "tangential_damping_factor") if k in table}})
    law = ContactLaw("hertz", restitution=restitution, damping_ratio=zeta, velocity=velocity, curvature_radius=radius,
                     damping_convention=convention, rotational=rotational, damping_coefficient=coef, tangential_damping_factor=factor)
    return law, particles


def _bond_contact(prefix: str, table: dict, particles: list[Particle], out_warnings: list) -> tuple[ContactLaw, list[Particle]]:
    """``model = "bond"`` (:mod:`dtcrit.scenes.bonds`)."""
    from dtcrit.scenes.bonds import parse_bond

    bond = parse_bond(prefix, table)
    cn = _number(prefix + "cn", table["cn"], allow_zero=True) if "cn" in table else None
    cs = _number(prefix + "cs", table["cs"], allow_zero=True) if "cs" in table else None
    zeta = _number(prefix + "damping_ratio", table["damping_ratio"], allow_zero=True) if "damping_ratio" in table else None
    if zeta is not None and (cn is not None or cs is not None):
        raise InputError(prefix + "damping_ratio", "conflicting damping specifications: cn/cs and damping_ratio; give exactly one way")
    convention = None
    if "damping_convention" in table:
        convention = _choice(prefix + "damping_convention", table["damping_convention"], tuple(CONVENTIONS), "damping convention")
        convention_for(convention, "linear", prefix + "damping_convention")
    if bond.ks + bond.contact_ks > bond.kn + bond.contact_kn:
        out_warnings.append((prefix + "ks", f"note: the bond's shear spring {bond.ks + bond.contact_ks:g} N/m exceeds its "
                             f"normal spring {bond.kn + bond.contact_kn:g} N/m; each mode is checked with its own stiffness"))
    law = ContactLaw("bond", kn=bond.kn + bond.contact_kn, ks=bond.ks + bond.contact_ks, cn=cn, cs=cs, damping_ratio=zeta,
                     damping_convention=convention, bond=bond)
    return law, particles
