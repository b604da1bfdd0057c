"""LAMMPS ``fix wall/gran`` as the per-contact springs and dashpots of its wall contacts.

Given as the input script's own line, ``--wall 'fix ID group wall/gran STYLE ARGS WALLSTYLE ARGS'``
(``src/GRANULAR/fix_wall_gran.cpp``, LAMMPS 29 Sep 2021; docs ``fix_wall_gran``):

* ``hooke``, ``hooke/history``, ``hertz/history`` take ``Kn Kt gamma_n gamma_t xmu dampflag`` with the
  ``pair_style gran/*`` defaults (``Kt NULL`` -> ``2/7 Kn``, ``gamma_t NULL`` -> ``gamma_n/2``,
  ``dampflag 0`` -> no tangential dashpot); the forces are those of the pair style
  (``dtcrit.packing.conventions.pair_styles``) with ``meff = m`` (the wall has infinite mass) and the
  Hertz factor ``sqrt(delta R_eff)``, ``R_eff`` of :func:`dtcrit.physics.walls.lammps_wall_effective_radius`;
* ``granular`` takes the model words of ``pair granular`` (``hooke``, ``hertz``, ``hertz/material``,
  ``damping``, ``tangential``, ``rolling``, ``twisting``; ``dtcrit.packing.conventions.granular_style``)
  with the wall's own material constants (:mod:`dtcrit.physics.walls`); ``dmt`` and ``jkr`` are refused;
* ``xplane``/``yplane``/``zplane lo hi`` (``NULL`` for none) and ``zcylinder r_c``
  (``dtcrit.packing.detection.walls``); ``region`` is refused;
* the slip velocity and the torque use the full radius (arm ``R``);
* the fix's group is not in a dump: every particle touching the wall is taken as in it, which can only
  add springs and lower the step (said in a note when the group is not ``all``);
* the optional keyword ``contacts`` only stores output and is accepted; ``wiggle``, ``shear`` and any
  other keyword (a moving wall, heat) are refused in one line naming them.

A flat wall's normal does not turn as the particle moves: its contacts carry no geometric stiffness.
On ``zcylinder`` the inward normal turns with the lever ``rho`` (the distance to the axis), which
stiffens: it enters as the pre-load term of a contact in tension.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.conventions.granular_style import GranularStyle, parse_granular
from dtcrit.packing.conventions.pair_styles import GranPairStyle, apply_terms, parse_pair_style
from dtcrit.packing.contact_set import Contacts
from dtcrit.packing.detection.walls import AXES, BIG, WallGeometry, wall_contacts
from dtcrit.packing.model import Packing
from dtcrit.packing.wall_bodies import concatenate, merge, with_wall_bodies
from dtcrit.physics.walls import lammps_wall_material_coefficient, lammps_wall_mindlin_coefficient

FLAG = "--wall"
STYLES = ("hooke", "hooke/history", "hertz/history", "granular")
GEOMETRIES = (*AXES, "zcylinder")
OUTPUT_ONLY = ("contacts",)

__all__ = ["LammpsWall", "parse_wall", "add_walls"]


@dataclass(frozen=True)
class LammpsWall:
    """A parsed ``fix wall/gran`` line (module docstring).

    Parameters
    ----------
    style : str
        ``hooke``, ``hooke/history``, ``hertz/history`` or ``granular``.
    law : GranPairStyle or GranularStyle
        The contact law, as the pair style of the same words.
    geometry : WallGeometry
        The wall.
    text : str
        The line as given.
    group : str
        The fix's group (``all`` when the line starts at ``wall/gran``).
    """

    style: str
    law: GranPairStyle | GranularStyle
    geometry: WallGeometry
    text: str
    group: str = "all"

    def describe(self) -> str:
        """The wall in words.

        Returns
        -------
        str
            E.g. ``fix wall/gran hertz/history ... zplane 0 NULL``.
        """
        return f"wall/gran {self.style} on {self.geometry.describe()}"


def _number(word: str, what: str, *, allow_null: bool = False) -> float:
    if allow_null and word == "NULL":
        return np.nan
    try:
        value = float(word)
    except ValueError:
        raise InputError(FLAG, f"{what} must be a number{' or NULL' if allow_null else ''}, found {word!r}") from None
    if not np.isfinite(value):
        raise InputError(FLAG, f"{what} must be finite, found {word!r}")
    return value


def _geometry(words: list[str], k: int) -> tuple[WallGeometry, int]:
    kind = words[k]
    if kind == "zcylinder":
        if len(words) < k + 2:
            raise InputError(FLAG, "zcylinder takes the cylinder's radius")
        rc = _number(words[k + 1], "the zcylinder radius")
        if rc <= 0:
            raise InputError(FLAG, f"the zcylinder radius must be positive, found {words[k + 1]!r}")
        return WallGeometry("zcylinder", radius=rc), k + 2
    if len(words) < k + 3:
        raise InputError(FLAG, f"{kind} takes lo and hi (NULL for none)")
    lo, hi = (_number(words[k + m], f"{kind} {name}", allow_null=True) for m, name in ((1, "lo"), (2, "hi")))
    lo, hi = (-BIG if np.isnan(lo) else lo), (BIG if np.isnan(hi) else hi)
    if lo == -BIG and hi == BIG:
        raise InputError(FLAG, f"{kind}: both planes NULL, no wall")
    return WallGeometry(kind, lo, hi), k + 3


def _law(style: str, args: list[str]) -> GranPairStyle | GranularStyle:
    try:
        if style == "granular":
            if args and args[0] in ("dmt", "jkr"):
                raise InputError(FLAG, f"granular {args[0]}: the wall's adhesive normal model is not modelled")
            return parse_granular(args)
        return parse_pair_style(" ".join([f"gran/{style}", *args]))
    except InputError as exc:
        if exc.key == FLAG:
            raise
        raise InputError(FLAG, f"wall/gran {style}: {exc.reason}") from None


def parse_wall(text: str) -> LammpsWall:
    """Parse the input script's ``fix ... wall/gran`` line (module docstring).

    Parameters
    ----------
    text : str
        The line, e.g. ``fix 2 all wall/gran hertz/history 2e5 NULL 50 NULL 0.5 1 zplane 0 NULL``
        (``fix ID group`` may be left out).

    Returns
    -------
    LammpsWall
        The law and the wall.

    Raises
    ------
    InputError
        Key ``--wall``: an unknown style or wall, malformed numbers, or a keyword that is not modelled.

    Examples
    --------
    >>> w = parse_wall("fix 2 all wall/gran hooke/history 1e5 NULL 0 NULL 0.5 0 zplane 0 NULL")
    >>> w.style, w.geometry.style, round(w.law.kt, 6)
    ('hooke/history', 'zplane', 28571.428571)
    """
    words = str(text).split()
    group = "all"
    if words[:1] == ["fix"]:
        group = words[2] if len(words) > 2 else "all"
        words = words[3:]
    if not words:
        raise InputError(FLAG, "empty: give the fix line, e.g. 'fix 2 all wall/gran hooke/history 1e5 NULL 0 NULL 0.5 0 zplane 0 NULL'")
    if words[0] == "wall/gran/region":
        raise InputError(FLAG, "wall/gran/region: region walls are not modelled")
    if words[0] != "wall/gran":
        raise InputError(FLAG, f"expected a 'wall/gran' fix, found {words[0]!r}")
    if len(words) < 2 or words[1] not in STYLES:
        found = words[1] if len(words) > 1 else "nothing"
        raise InputError(FLAG, f"unknown wall/gran style {found!r}; supported: {', '.join(STYLES)}")
    style = words[1]
    k = 2
    while k < len(words) and words[k] not in (*GEOMETRIES, "region"):
        k += 1
    if k == len(words):
        raise InputError(FLAG, f"no wall: give one of {', '.join(GEOMETRIES)} after the coefficients")
    if words[k] == "region":
        raise InputError(FLAG, "region: region walls are not modelled")
    law = _law(style, words[2:k])
    geometry, k = _geometry(words, k)
    for word in words[k:]:
        if word not in OUTPUT_ONLY:
            raise InputError(FLAG, f"keyword {word!r} is not modelled (a moving wall or another term)")
    return LammpsWall(style, law, geometry, " ".join(words), group)


def _wall_granular(law: GranularStyle) -> GranularStyle:
    """The granular law with the wall's own material constants (``fix_wall_gran.cpp``)."""
    if law.normal == "hertz/material":
        e, nu = law.normal_args["E"], law.normal_args["nu"]
        normal_args = {"kn": lammps_wall_material_coefficient(e, nu), "eta": law.normal_args["eta"]}
        tangential_args = dict(law.tangential_args)
        if law.tangential.startswith("mindlin") and tangential_args["kt"] is None:
            tangential_args["kt"] = lammps_wall_mindlin_coefficient(e, nu)
        law = replace(law, normal="hertz", normal_args=normal_args, tangential_args=tangential_args)
    return law


def _terms(law, packing: Packing, contacts: Contacts):
    if isinstance(law, GranularStyle):
        terms = _wall_granular(law).terms(packing, contacts)
        if law.tangential == "linear_nohistory":  # the wall multiplies its tangential dashpot by meff once more
            terms = replace(terms, cs=terms.cs * packing.masses[contacts.i])
        return terms
    return law.terms(packing, contacts)


def add_walls(packing: Packing, contacts: Contacts, walls: list[LammpsWall], *, preload: bool) -> tuple[Packing, Contacts, list[str]]:
    """The packing and contacts with every wall's contacts added (module docstring).

    Parameters
    ----------
    packing : Packing
        The particles (spheres).
    contacts : Contacts
        The particle contacts, with their terms.
    walls : list of LammpsWall
        The parsed walls.
    preload : bool
        Whether the engine's pre-load enters (the ``zcylinder`` lever term).

    Returns
    -------
    tuple
        ``(packing with one fixed body per wall contact, all contacts, notes)``.
    """
    found = [wall_contacts(packing, wall.geometry, number) for number, wall in enumerate(walls, start=1)]
    grown, touching = with_wall_bodies(packing, merge(found))
    notes = []
    for number, wall in enumerate(walls, start=1):
        mine = touching.subset(np.flatnonzero(np.concatenate([f.wall for f in found]) == number))
        mine = apply_terms(mine, _terms(wall.law, grown, mine), preload=preload)
        if mine.force_n is not None:  # a plane's normal does not turn; a cylinder's inward normal stiffens
            mine = mine.with_normal_force(0.0 if wall.geometry.style != "zcylinder" else -mine.force_n)
        contacts = concatenate(contacts, mine)
        count = found[number - 1].count
        notes.append(f"wall {number} ({wall.describe()}): {count} particle{'s' if count != 1 else ''} touching, "
                     "each against a fixed body of infinite mass (meff = m, arm R)"
                     + ("" if wall.group == "all" else f"; the dump does not say which atoms are in group "
                        f"{wall.group!r}: every particle touching the wall is taken as in it (extra springs only "
                        "lower the step)"))
    return grown, contacts, notes
