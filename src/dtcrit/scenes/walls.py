"""Fixed walls of a scene (``[[wall]]`` tables): planes that particles touch, such as LAMMPS
``fix wall/gran`` or YADE's facets and boxes.

A wall is rigid and immobile, so a particle of mass ``m`` against it has the normal mode
``A = 1/m`` and, for a sphere, the tangential mode ``A = 1/m + R^2/I`` (the contact point's slip
carries the spin with the full radius as arm, as LAMMPS ``fix wall/gran`` applies it).  Keys:
``kn``, ``ks`` [N/m] (required), damping like ``[contact]`` (``cn``/``cs``, ``restitution`` or
``damping_ratio``, mapped with the scene's damping convention and that convention's wall mass),
``particles`` (the particle tables that touch it, counted from 1; default all) and ``name``; and
rotational springs ``kr``, ``ktw`` [N m/rad] with dashpots ``cr``, ``ctw`` [N m s/rad] (default 0) on the
sphere's rotation relative to the wall.  The rolling spring couples to the shear spring at a wall
(:mod:`dtcrit.symbolic.rotational_modes`): ``omega^2 = k_r/I`` is a mode only without shear spring.

``model = "hertz"`` makes a Hertz-Mindlin wall, linearised at its overlap by the tangent stiffness
(:func:`dtcrit.physics.walls.hertz_wall_stiffness`: ``k_n = 2 E* sqrt(R delta)``,
``k_s = 8 G* sqrt(R delta)``, a plane having ``R* = R``) instead of ``kn``, ``ks``: the wall's
``youngs_modulus`` and ``poisson_ratio`` (default: the particle's) and either ``overlap`` [m], the
overlap to linearise at (a particle resting on the wall), or ``velocity`` [m/s], an impact speed
whose largest overlap ``(15 m v^2/(16 E* sqrt(R)))^(2/5)`` is taken (the wall's mass is infinite,
``m* = m``; default: ``[contact] velocity``).  Its damping follows the Hertz convention of the scene
(``liggghts`` by default).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from dtcrit.errors import InputError
from dtcrit.scenes.damping_input import damping_kind, parse_damping
from dtcrit.scenes.fields import _check_keys, _number, _required, _short, _string, _type_name

WALL_KEYS = ("name", "model", "kn", "ks", "cn", "cs", "restitution", "damping_ratio", "particles", "kr", "ktw", "cr", "ctw",
             "youngs_modulus", "poisson_ratio", "overlap", "velocity")
HERTZ_ONLY = ("youngs_modulus", "poisson_ratio", "overlap", "velocity")
KEY_DESCRIPTIONS = {
    "model": '"linear" (default: kn, ks as given) or "hertz" (tangent Hertz-Mindlin stiffness at the overlap)',
    "kn": "normal stiffness [N/m] (linear)", "ks": "tangential stiffness [N/m] (linear; 0: frictionless)",
    "youngs_modulus": "the wall's Young's modulus [Pa] (hertz; default: the particle's)",
    "poisson_ratio": "the wall's Poisson's ratio (hertz; default: the particle's)",
    "overlap": "the overlap [m] to linearise a Hertz wall at (a resting particle)",
    "velocity": "impact speed [m/s] whose largest overlap linearises a Hertz wall (default: [contact] velocity)",
}
"""What each ``[[wall]]`` key means (the keys not listed mean what they mean in ``[contact]``)."""


@dataclass(frozen=True)
class Wall:
    """A fixed plane wall of a scene (one ``[[wall]]`` table) and its contact law with the particles.

    Parameters
    ----------
    number : int
        Position of the table in the file, counted from 1.
    name : str
        The wall's name as given (or a default).
    kn : float
        Normal spring [N/m].
    ks : float
        Tangential spring [N/m].
    cn : float or None
        Normal dashpot [N s/m], when given as a coefficient.
    cs : float or None
        Tangential dashpot [N s/m], when given as a coefficient.
    restitution : float or None
        Coefficient of restitution, when damping is given that way.
    damping_ratio : float or None
        Damping ratio, when damping is given that way.
    particles : tuple of int
        Numbers of the particle types that touch the wall.
    kr : float
        Rolling spring [N m/rad].
    ktw : float
        Twisting spring [N m/rad].
    cr : float or None
        Rolling dashpot [N m s/rad].
    ctw : float or None
        Twisting dashpot [N m s/rad].
    model : str
        ``linear`` or ``hertz`` (then ``kn``, ``ks`` are NaN: they depend on the particle).
    youngs_modulus, poisson_ratio : float or None
        The wall's material of a Hertz wall (None: the particle's).
    overlap : float or None
        The overlap [m] a Hertz wall is linearised at.
    velocity : float or None
        Or the impact speed [m/s] whose largest overlap it is linearised at.
    """

    number: int  # counted from 1
    name: str
    kn: float
    ks: float
    cn: float | None
    cs: float | None
    restitution: float | None
    damping_ratio: float | None
    particles: tuple[int, ...]  # particle numbers that touch it
    kr: float = 0.0  # rolling spring [N m/rad]
    ktw: float = 0.0  # twisting spring [N m/rad]
    cr: float | None = None  # rolling dashpot [N m s/rad]
    ctw: float | None = None  # twisting dashpot [N m s/rad]
    model: str = "linear"  # or "hertz": kn, ks per particle at the overlap (NaN here)
    youngs_modulus: float | None = None  # the wall's E [Pa] (hertz; None: the particle's)
    poisson_ratio: float | None = None  # the wall's nu (hertz; None: the particle's)
    overlap: float | None = None  # the overlap [m] a Hertz wall is linearised at
    velocity: float | None = None  # or the impact speed [m/s] whose largest overlap it is linearised at

    @property
    def cr_value(self) -> float:
        """The rolling dashpot [N m s/rad], 0 when none is given."""
        return self.cr or 0.0

    @property
    def ctw_value(self) -> float:
        """The twisting dashpot [N m s/rad], 0 when none is given."""
        return self.ctw or 0.0

    def springs_text(self) -> str:
        """The wall's springs in words: ``kn = ... N/m, ks = ... N/m``, or a Hertz wall's law.

        Returns
        -------
        str
            The text ``dtcrit step`` prints.
        """
        if self.model == "linear":
            return f"kn = {self.kn:g} N/m, ks = {self.ks:g} N/m"
        at = f"overlap {self.overlap:g} m" if self.overlap is not None else (
            f"impact speed {self.velocity:g} m/s" if self.velocity is not None else "the contact's impact speed")
        material = "" if self.youngs_modulus is None and self.poisson_ratio is None else (
            f", wall E = {self.youngs_modulus if self.youngs_modulus is not None else 'particle'}, "
            f"nu = {self.poisson_ratio if self.poisson_ratio is not None else 'particle'}")
        return f"Hertz-Mindlin tangent stiffness at {at}{material}"

    @property
    def damping(self) -> str:
        """How damping was given: none | coefficients | restitution | damping_ratio."""
        return damping_kind(self.restitution, self.damping_ratio, self.cn, self.cs)


def parse_walls(value: Any, n_particles: int, out_warnings: list | None = None) -> tuple[Wall, ...]:
    """Validate the ``[[wall]]`` tables (``ks > kn`` is accepted with a warning, as in ``[contact]``).

    Parameters
    ----------
    value : dict or list of dict
        The ``wall`` entry of the scene file.
    n_particles : int
        Number of particle types of the scene (a wall's ``particles`` must name some of them).
    out_warnings : list, optional
        List to which ``(key, message)`` warnings are appended.

    Returns
    -------
    tuple of Wall
        The walls, in file order.

    Raises
    ------
    InputError
        When a table is missing a key or has an invalid value.
    """
    tables = [value] if isinstance(value, dict) else value
    if not isinstance(tables, list):
        raise InputError("wall", f"must be [[wall]] tables (got {_type_name(value)}: {_short(value)})")
    walls = tuple(_wall(k + 1, t, n_particles) for k, t in enumerate(tables))
    for w in walls:
        if w.model == "linear" and w.ks > w.kn and out_warnings is not None:
            out_warnings.append((f"wall[{w.number}].ks", f"warning: ks = {w.ks:g} exceeds kn = {w.kn:g}; each mode is "
                                 "still checked with its own stiffness"))
    return walls


def _wall(number: int, table: Any, n_particles: int) -> Wall:
    prefix = f"wall[{number}]."
    if not isinstance(table, dict):
        raise InputError(f"wall[{number}]", f"must be a table (got {_type_name(table)}: {_short(table)})")
    _check_keys(prefix, table, WALL_KEYS, WALL_KEYS, "in a wall")
    model = table.get("model", "linear")
    if model not in ("linear", "hertz"):
        raise InputError(prefix + "model", f'walls are "linear" or "hertz" (got {model!r})')
    if model == "hertz":
        kn = ks = math.nan
        hertz = _hertz_keys(prefix, table)
    else:
        for key in HERTZ_ONLY:
            if key in table:
                raise InputError(prefix + key, 'used by a Hertz wall only (model = "hertz")')
        hertz = {}
        kn = _number(prefix + "kn", _required(prefix, table, "kn", "the wall's normal stiffness kn [N/m]"))
        ks = _number(prefix + "ks", _required(prefix, table, "ks", "the wall's tangential stiffness ks [N/m] (0: frictionless)"),
                     allow_zero=True)
    cn, cs, e, zeta = parse_damping(prefix, table)
    touching = tuple(range(1, n_particles + 1))
    if "particles" in table:
        raw = table["particles"]
        if not isinstance(raw, list) or not raw or any(isinstance(x, bool) or not isinstance(x, int) for x in raw):
            raise InputError(prefix + "particles", f"must be an array of particle table numbers (got {_short(raw)})")
        bad = [x for x in raw if not 1 <= x <= n_particles]
        if bad:
            raise InputError(prefix + "particles", f"no particle table {bad[0]} (the scene has {n_particles}, counted from 1)")
        touching = tuple(sorted(set(raw)))
    name = _string(prefix + "name", table["name"]) if "name" in table else f"wall {number}"
    rot = {k: _number(prefix + k, table[k], allow_zero=True) for k in ("kr", "ktw", "cr", "ctw") if k in table}
    return Wall(number, name, kn, ks, cn, cs, e, zeta, touching, rot.get("kr", 0.0), rot.get("ktw", 0.0), rot.get("cr"),
                rot.get("ctw"), model, **hertz)


def _hertz_keys(prefix: str, table: dict) -> dict:
    """The material and the overlap (or impact speed) of a Hertz wall."""
    for key in ("kn", "ks"):
        if key in table:
            raise InputError(prefix + key, "a Hertz wall's stiffness follows from its material and overlap; remove it")
    if "overlap" in table and "velocity" in table:
        raise InputError(prefix + "overlap", "give the overlap or the impact velocity, not both")
    out = {k: _number(prefix + k, table[k]) for k in ("youngs_modulus", "overlap", "velocity") if k in table}
    if "poisson_ratio" in table:
        out["poisson_ratio"] = _number(prefix + "poisson_ratio", table["poisson_ratio"], lo=-1.0, hi=0.5, hi_open=True)
    return out
