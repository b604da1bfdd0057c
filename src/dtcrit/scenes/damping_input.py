"""How a scene gives damping: ``cn``/``cs``, ``restitution`` or ``damping_ratio``, and which code's
convention maps it (``[contact] damping_convention``).

The conventions themselves (how each code turns a damping ratio into dashpots) are
:mod:`dtcrit.physics.damping_conventions`; this module validates the scene's keys.
"""
from __future__ import annotations

from dtcrit.errors import InputError
from dtcrit.physics.damping_conventions import (CONVENTIONS, DEFAULT_CONVENTION, Convention, damping_ratio_from_restitution,
                                                liggghts_hertz)
from dtcrit.scenes.law_damping import is_law_convention, law_convention

__all__ = ["DAMPING_KEYS", "CONVENTIONS", "DEFAULT_CONVENTION", "convention_for", "damping_kind", "parse_damping"]

DAMPING_KEYS = ("cn", "cs", "restitution", "damping_ratio")


def convention_for(name: str | None, model: str, key: str = "contact.damping_convention") -> Convention:
    """The convention a scene uses: the one named, or the default of the contact model.

    Parameters
    ----------
    name : str or None
        The ``damping_convention`` given, None for the model's default.
    model : str
        The contact model (``linear``, ``yade``, ``hertz``).
    key : str
        The key named in the error when the convention is unknown or does not fit the model.

    Returns
    -------
    Convention
        The convention (:mod:`dtcrit.physics.damping_conventions`).
    """
    chosen = DEFAULT_CONVENTION[model] if name is None else name
    if chosen not in CONVENTIONS:
        raise InputError(key, f"unknown damping convention {chosen!r}; choose one of {', '.join(CONVENTIONS)}")
    conv = CONVENTIONS[chosen]
    if model not in conv.models:
        raise InputError(key, f"the {chosen!r} convention is defined for {', '.join(conv.models)} contacts, not {model}")
    if chosen == "liggghts" and model == "hertz":
        return liggghts_hertz()
    if is_law_convention(chosen, model):
        return law_convention(chosen)
    return conv


def damping_kind(restitution, damping_ratio, cn, cs) -> str:
    """How damping was given: ``none``, ``coefficients``, ``restitution`` or ``damping_ratio``.

    Parameters
    ----------
    restitution, damping_ratio : float or None
        The values given.
    cn, cs : float or None
        The dashpots given [N s/m].

    Returns
    -------
    str
        The kind.
    """
    if restitution is not None:
        return "restitution"
    if damping_ratio is not None:
        return "damping_ratio"
    return "coefficients" if (cn or 0.0) > 0 or (cs or 0.0) > 0 else "none"


def parse_damping(prefix: str, table: dict) -> tuple[float | None, float | None, float | None, float | None]:
    """The damping of a table that gives it one way only (``cn``/``cs``, ``restitution`` or ``damping_ratio``).

    Parameters
    ----------
    prefix : str
        The table's key prefix in error messages (``contact.``, ``wall[1].``).
    table : dict
        The TOML table.

    Returns
    -------
    tuple
        ``(cn, cs, restitution, damping_ratio)``; a restitution coefficient sets the damping ratio
        ``zeta(e)`` (:func:`dtcrit.physics.damping_conventions.damping_ratio_from_restitution`).
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
