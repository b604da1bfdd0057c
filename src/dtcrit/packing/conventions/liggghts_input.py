"""Read a LIGGGHTS input script's granular contact law: ``pair_style gran`` and its ``fix property/global`` materials.

``dtcrit audit DUMP --liggghts-input in.file`` reads (sources: LIGGGHTS-PUBLIC ``src/``)::

    pair_style gran model hertz|hooke [tangential history|no_history|off] [cohesion off]
               [rolling_friction cdt|epsd|epsd2|epsd3|off] [surface default] [SETTING on|off ...]
    fix ID all property/global youngsModulus peratomtype Y1 Y2 ...
    fix ID all property/global poissonsRatio peratomtype nu1 nu2 ...
    fix ID all property/global coefficientRestitution peratomtypepair N e11 e12 ... eNN
    fix ID all property/global coefficientFriction peratomtypepair N mu11 ... muNN
    fix ID all property/global coefficientRollingFriction peratomtypepair N ...       (rolling models)
    fix ID all property/global coefficientRollingViscousDamping peratomtypepair N ... (epsd, epsd3)
    fix ID all property/global rollingStiffness scalar f                              (epsd3)
    fix ID all property/global characteristicVelocity scalar v                        (hooke)

(``contact_models.cpp``: the model keywords in this order; ``fix_property_global.cpp``: one property
per fix).  Comments (``#``), ``&`` continuations and ``variable NAME equal|index|string VALUE`` with
``${NAME}``/``$N`` substitution are understood.  Other commands are skipped when they do not change
the dynamics (``fix nve/sphere``, ``gravity``, ``insert/*``, ``mesh/surface``, ``ave/*``, ...); a fix
that does (``wall/gran``, ``viscous``, ``freeze``, ``multisphere``, any fix not known here), ``dimension 2``,
a non-spherical ``atom_style``, bonds and ``include`` are refused, naming the line: a file with just the
``pair_style`` and ``fix property/global`` lines audits the contacts alone.  The per-contact law is
:mod:`dtcrit.packing.conventions.liggghts_law`.

Settings (``settings.h``; each model's ``registerSettings``): ``tangential_damping`` and
``ktToKnUser`` (hooke) and ``torsionTorque`` (rolling) are modelled; ``computeElasticPotential``
and ``computeDissipatedEnergy`` only record energies.  Anything else that changes the dynamics --
``cohesion`` models, non-default ``surface`` models, other normal/tangential models, ``limitForce on``,
``viscous on``, heating, bonding switches, unknown keywords -- is refused in one line naming
``FILE:LINE``.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Mapping

import numpy as np

from dtcrit.errors import InputError

FLAG = "--liggghts-input"
NORMAL = ("hertz", "hooke")
TANGENTIAL = ("history", "no_history", "off")
ROLLING = ("cdt", "epsd", "epsd2", "epsd3", "off")
MODEL_KEYS = ("model", "tangential", "cohesion", "rolling_friction", "surface")  # contact_models.cpp order
MODELLED = ("tangential_damping", "ktToKnUser", "torsionTorque")
RECORD_ONLY = ("computeElasticPotential", "computeDissipatedEnergy")
REFUSED_ON = {"limitForce": "clips the normal force at zero", "viscous": "velocity-dependent restitution",
              "heating_normal_hertz": "heating", "heating_normal_hooke": "heating",
              "heating_tangential_history": "heating", "heating_tracking": "heating",
              "disableNormalWhenBonded": "bonded contacts", "disableTangentialWhenBonded": "bonded contacts"}
SETTING_DEFAULTS = {"tangential_damping": True, "ktToKnUser": False, "torsionTorque": False}
PER_TYPE = ("youngsModulus", "poissonsRatio")
PER_PAIR = ("coefficientRestitution", "coefficientFriction", "coefficientRollingFriction",
            "coefficientRollingViscousDamping")
SCALARS = ("characteristicVelocity", "rollingStiffness")
FIXES_KEPT = ("property/global", "custom_property/global", "property/atom", "nve/sphere", "gravity",
              "check/timestep/gran", "mesh/surface", "mesh/surface/stress", "move/mesh", "print", "store/state")
FIX_FAMILIES_KEPT = ("insert/", "particletemplate/", "particledistribution/", "ave/")
ALONE = "give a file with just the pair_style and fix property/global lines to audit the contacts alone"


@dataclass(frozen=True)
class Property:
    """One ``fix property/global`` material property as read.

    Parameters
    ----------
    name : str
        The property (``youngsModulus``, ``coefficientRestitution``, ...).
    values : numpy.ndarray
        Per type (1-D, type 1 first), per type pair (2-D) or a 0-D scalar.
    where : str
        ``FILE:LINE`` of its fix.
    """

    name: str
    values: np.ndarray
    where: str


@dataclass(frozen=True)
class LiggghtsInput:
    """A LIGGGHTS ``pair_style gran`` line and its materials (module docstring).

    Parameters
    ----------
    normal : str
        ``hertz`` or ``hooke``.
    tangential : str
        ``history``, ``no_history`` or ``off``.
    rolling : str
        ``cdt``, ``epsd``, ``epsd2``, ``epsd3`` or ``off``.
    settings : Mapping
        The modelled on/off settings (``tangential_damping``, ``ktToKnUser``, ``torsionTorque``).
    properties : Mapping
        The ``fix property/global`` properties by name (:class:`Property`).
    pair_style : str
        The ``pair_style`` line as read.
    where : str
        ``FILE:LINE`` of the ``pair_style`` line.
    """

    normal: str
    tangential: str
    rolling: str
    settings: Mapping[str, bool]
    properties: Mapping[str, Property]
    pair_style: str
    where: str

    def value(self, name: str) -> np.ndarray:
        """A property's values.

        Parameters
        ----------
        name : str
            The property.

        Returns
        -------
        numpy.ndarray
            Its values (per type, per type pair or 0-D).
        """
        return self.properties[name].values


def _logical_lines(text: str, source: str):
    """``(FILE:LINE, words)`` of each command: comments dropped, ``&`` continuations joined."""
    pending: list[str] = []
    start = 0
    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].rstrip()
        if not pending:
            start = n
        if line.endswith("&"):
            pending.append(line[:-1])
            continue
        pending.append(line)
        words = " ".join(pending).split()
        pending = []
        if words:
            yield f"{source}:{start}", words


_VAR = re.compile(r"\$\{([^}]*)\}|\$\((.*?)\)|\$(.)")


def _substitute(words: list[str], variables: dict, where: str) -> list[str]:
    def one(m: re.Match) -> str:
        if m.group(2) is not None:
            raise InputError(where, f"immediate expression $({m.group(2)}) is not evaluated here: write its value")
        name = m.group(1) if m.group(1) is not None else m.group(3)
        if name not in variables:
            raise InputError(where, f"variable {name!r} is not defined by a 'variable NAME equal|index|string VALUE' line")
        return variables[name]
    return " ".join(_VAR.sub(one, w) for w in words).split()


def _variable(words: list[str], variables: dict, where: str) -> None:
    if len(words) >= 4 and words[2] in ("equal", "index", "string"):
        value = " ".join(words[3:]).strip('"').strip("'")
        if words[2] == "equal":
            try:
                value = repr(float(value))
            except ValueError:
                value = f"\0{value}"  # an expression: refused only where it is used
        if words[2] != "index" or words[1] not in variables:  # an index variable is not redefined
            variables[words[1]] = value


def _numbers(words: list[str], what: str, where: str) -> np.ndarray:
    out = []
    for w in words:
        if w.startswith("\0"):
            raise InputError(where, f"{what}: the equal-style expression {w[1:]!r} is not evaluated here: write its value")
        try:
            out.append(float(w))
        except ValueError:
            raise InputError(where, f"{what} must be numbers, found {w!r}") from None
    values = np.array(out, dtype=float)
    if not np.all(np.isfinite(values)) or np.any(values < 0):
        raise InputError(where, f"{what} must be finite numbers >= 0")
    return values


def _property(words: list[str], where: str) -> Property | None:
    """The material of a ``fix ID group property/global NAME STYLE values`` line (None for other names)."""
    if len(words) < 7:
        raise InputError(where, "fix property/global needs NAME STYLE VALUES (fix_property_global.cpp)")
    name, style, rest = words[4], words[5], words[6:]
    if name not in PER_TYPE + PER_PAIR + SCALARS:
        return None
    if name in PER_TYPE:
        if style not in ("peratomtype", "atomtype"):
            raise InputError(where, f"{name} must be given 'peratomtype' (one value per atom type), found {style!r}")
        return Property(name, _numbers(rest, name, where), where)
    if name in SCALARS:
        if style != "scalar" or len(rest) != 1:
            raise InputError(where, f"{name} must be given 'scalar VALUE'")
        return Property(name, _numbers(rest, name, where).reshape(()), where)
    if style not in ("peratomtypepair", "atomtypepair"):
        raise InputError(where, f"{name} must be given 'peratomtypepair N v11 v12 ... vNN', found {style!r}")
    n = _numbers(rest[:1], f"{name} N", where)[0]
    if n != int(n) or n < 1 or len(rest) - 1 != int(n) ** 2:
        raise InputError(where, f"{name} peratomtypepair {rest[0]} needs {rest[0]} x {rest[0]} values, found {len(rest) - 1}")
    matrix = _numbers(rest[1:], name, where).reshape(int(n), int(n))
    if not np.array_equal(matrix, matrix.T):
        raise InputError(where, f"{name}: the per-atomtype-pair matrix must be symmetric (LIGGGHTS refuses it too)")
    return Property(name, matrix, where)


def _check_command(words: list[str], where: str) -> None:
    """Refuse a command that changes the dynamics beyond the pair style: a fix other than the integrator
    ``nve/sphere``, gravity, insertion, meshes without walls and bookkeeping (``wall/gran``, ``viscous``,
    ``freeze``, ``multisphere``, ...), a 2-D or non-spherical model, bonds, an ``include`` not followed.
    """
    cmd = words[0]
    if cmd == "fix" and len(words) > 3:
        style = words[3]
        if style not in FIXES_KEPT and not style.startswith(FIX_FAMILIES_KEPT):
            raise InputError(where, f"fix {style} is not modelled by the audit (walls, forces and integrators other than "
                             f"nve/sphere change the dynamics): {ALONE}")
    elif ((cmd == "dimension" and words[1:] != ["3"]) or (cmd == "atom_style" and words[1:2] not in (["granular"], ["sphere"]))
          or (cmd == "run_style" and words[1:2] != ["verlet"]) or cmd in ("bond_style", "include")):
        raise InputError(where, f"'{' '.join(words)}' is not modelled by the audit: {ALONE}")


def _models(words: list[str], where: str) -> tuple[dict, list[str]]:
    """The ``model/tangential/cohesion/rolling_friction/surface`` choices and the settings words after them."""
    chosen = {"tangential": "off", "cohesion": "off", "rolling_friction": "off", "surface": "default"}
    k, order = 0, 0
    while k + 1 < len(words) and words[k] in MODEL_KEYS[order:]:
        key, value = words[k], words[k + 1]
        order = MODEL_KEYS.index(key) + 1
        chosen[key] = value
        k += 2
    if "model" not in chosen:
        raise InputError(where, "pair_style gran must start with 'model hertz|hooke' (LIGGGHTS 3 syntax); the LAMMPS-style "
                         "gran/* arguments go to --pair-style")
    allowed = {"model": NORMAL, "tangential": TANGENTIAL, "cohesion": ("off",), "rolling_friction": ROLLING,
               "surface": ("default",)}
    for key in MODEL_KEYS:
        if chosen[key] not in allowed[key]:
            raise InputError(where, f"{key} {chosen[key]} is not modelled (dtcrit reads {key} {'|'.join(allowed[key])}): "
                             "its forces change the dynamics")
    return chosen, words[k:]


def _settings(words: list[str], where: str) -> dict:
    settings = dict(SETTING_DEFAULTS)
    if len(words) % 2:
        raise InputError(where, f"pair_style gran: keyword {words[-1]!r} has no value (or a model keyword is out of the "
                         f"order {' '.join(MODEL_KEYS)})")
    for key, value in zip(words[::2], words[1::2]):
        if key in MODEL_KEYS:
            raise InputError(where, f"pair_style gran: '{key}' is out of the order {' '.join(MODEL_KEYS)} (contact_models.cpp)")
        if value not in ("on", "off"):
            raise InputError(where, f"pair_style gran: {key} must be on or off, found {value!r}")
        if key in MODELLED:
            settings[key] = value == "on"
        elif key in REFUSED_ON:
            if value == "on":
                raise InputError(where, f"{key} on is not modelled ({REFUSED_ON[key]}): it changes the dynamics")
        elif key not in RECORD_ONLY:
            raise InputError(where, f"pair_style gran: unknown keyword {key!r}: not modelled")
    return settings


def _needed(chosen: dict) -> tuple[str, ...]:
    need = ["youngsModulus", "poissonsRatio", "coefficientRestitution"]
    if chosen["model"] == "hooke":
        need.append("characteristicVelocity")
    if chosen["tangential"] != "off":
        need.append("coefficientFriction")
    roll = chosen["rolling_friction"]
    if roll != "off":
        need.append("coefficientRollingFriction")
    if roll in ("epsd", "epsd3"):
        need.append("coefficientRollingViscousDamping")
    if roll == "epsd3":
        need.append("rollingStiffness")
    return tuple(need)


def _check_values(props: dict) -> None:
    for name, lo, hi, what in (("poissonsRatio", 0.0, 0.5, "0 <= poissonsRatio <= 0.5"),
                               ("coefficientRestitution", 0.05, 1.0, "0.05 < coefficientRestitution <= 1")):
        if name in props:
            v = props[name].values
            bad = (v < lo) | (v > hi) | ((v <= lo) if name == "coefficientRestitution" else False)
            if np.any(bad):
                raise InputError(props[name].where, f"{what} required (global_properties.cpp), found {v[bad].flat[0]:g}")
    if "youngsModulus" in props and np.any(props["youngsModulus"].values <= 0):
        raise InputError(props["youngsModulus"].where, "youngsModulus must be positive")


def parse_liggghts_input(text: str, source: str = "input") -> LiggghtsInput:
    """The contact law of a LIGGGHTS input script's text (module docstring).

    Parameters
    ----------
    text : str
        The script (or just its ``pair_style gran`` and ``fix property/global`` lines).
    source : str
        Its name in error messages (``SOURCE:LINE``).

    Returns
    -------
    LiggghtsInput
        The models, the modelled settings and the materials.

    Raises
    ------
    InputError
        Naming ``SOURCE:LINE`` for a term that is not modelled, a malformed line, a material given
        twice, or ``SOURCE`` for a missing ``pair_style gran`` or material.
    """
    variables: dict[str, str] = {}
    props: dict[str, Property] = {}
    style: tuple[str, list[str]] | None = None
    for where, words in _logical_lines(text, source):
        if words[0] == "variable":
            _variable(words, variables, where)
            continue
        _check_command(words, where)
        if words[0] not in ("pair_style", "fix"):
            continue
        words = _substitute(words, variables, where)
        if words[0] == "pair_style":
            if style is not None:
                raise InputError(where, f"a second pair_style (the first at {style[0]}): give the input of the run the dump "
                                 "comes from")
            if words[1:2] != ["gran"]:
                raise InputError(where, f"pair_style {' '.join(words[1:2])} is not LIGGGHTS's 'gran': give a LAMMPS style "
                                 "with --pair-style")
            style = (where, words)
        elif len(words) > 3 and words[3] in ("property/global", "custom_property/global"):
            prop = _property(words, where)
            if prop is not None:
                if prop.name in props:
                    raise InputError(where, f"{prop.name} is given twice (first at {props[prop.name].where})")
                props[prop.name] = prop
    if style is None:
        raise InputError(source, "no 'pair_style gran model ...' line")
    where, words = style
    chosen, rest = _models(words[2:], where)
    settings = _settings(rest, where)
    need = _needed(chosen)
    missing = [n for n in need if n not in props]
    if missing:
        raise InputError(source, f"the pair style at {where} needs 'fix ... property/global {missing[0]} ...', "
                                 "which the input does not give")
    _check_values(props)
    return LiggghtsInput(chosen["model"], chosen["tangential"], chosen["rolling_friction"],
                         MappingProxyType(settings), MappingProxyType({n: props[n] for n in need}),
                         " ".join(words), where)


def read_liggghts_input(path) -> LiggghtsInput:
    """The contact law of a LIGGGHTS input file (:func:`parse_liggghts_input`).

    Parameters
    ----------
    path : str or os.PathLike
        The input script, or a file holding just its ``pair_style`` and ``fix property/global`` lines.

    Returns
    -------
    LiggghtsInput
        The models, settings and materials.

    Raises
    ------
    InputError
        ``--liggghts-input`` for an unreadable file; ``FILE:LINE`` for its content.
    """
    try:
        readable = Path(path).is_file()
        text = Path(path).read_text(encoding="utf-8", errors="replace") if readable else ""
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the path
        raise InputError(FLAG, f"{path}: {getattr(exc, 'strerror', None) or exc}") from None
    if not readable:
        raise InputError(FLAG, f"{path} is not a readable file")
    return parse_liggghts_input(text, str(path))
