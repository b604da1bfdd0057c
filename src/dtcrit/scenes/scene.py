"""Scene files: one TOML document describing a DEM contact problem, parsed and validated.

A scene names one or two particle types, the contact law between them, the integrator, and
optionally the largest angular velocity ``omega_max`` and a safety factor (the format is documented
in ``docs/howto/step.md``, section "The scene format", every key on the Scene keys reference page).
Parsing uses the standard library's ``tomllib`` only: no text from a file
is ever evaluated as code (no ``eval``, ``sympify`` or ``parse_expr``).

Every problem is reported as ``dtcrit.errors.InputError(key, reason)`` where ``key`` is the path of
the offending entry, e.g. ``contact.kn`` or ``particle[2].semi_axes`` (particle tables are counted
from 1, as the paper's particles 1 and 2).  Unknown keys name the nearest valid key.  Problems
that do not make the scene wrong but deserve attention (``ks > kn``) are collected in
``Scene.warnings`` as ``(key, message)`` pairs.

The contact laws resolve, for each pair of particle types, to per-direction linear stiffness and
viscous damping ``(k_n, k_s, c_n, c_s)`` (Peng et al. 2020, Eq. (29)):

* ``linear``: ``kn``, ``ks`` given; damping as coefficients ``cn``/``cs`` [N s/m], or a
  restitution coefficient ``e`` or damping ratio ``zeta`` turned into ``c_j = 2 zeta sqrt(k_j m*)``
  with ``m* = m1 m2/(m1 + m2)`` and ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``;
* ``hertz`` (Hertz normal, Mindlin no-slip tangential): the tangent stiffnesses at the largest
  overlap of an impact at ``velocity``, ``k_n = 2 E* sqrt(R* delta_max)`` and
  ``k_s = 8 G* sqrt(R* delta_max)`` with ``delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5)``,
  damping from ``restitution`` / ``damping_ratio`` as above with the tangent stiffnesses.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from dtcrit.errors import InputError
from dtcrit.inputs.files import read_bounded
from dtcrit.bodies.spec import build_shape, density_or_mass, table_dimensions, table_kind
from dtcrit.scenes.contact_table import contact_law
from dtcrit.scenes.fields import _check_keys, _choice, _number, _required, _short, _string, _type_name
from dtcrit.scenes.laws import resolve_pair
from dtcrit.scenes.model import COLLISION_KEYS, PAIRS_CHOICES, TOP_KEYS, Particle, Scene

if TYPE_CHECKING:
    from pathlib import Path


# ----------------------------------------------------------------------------------------------
# Particles
# ----------------------------------------------------------------------------------------------
def _particle(number: int, table: Any) -> Particle:
    """A ``[[particle]]`` table: its shape by the one shape parser (``dtcrit.bodies.spec``), a sphere's
    size distribution (``dtcrit.scenes.sizes``), the elastic constants and the name.
    """
    prefix = f"particle[{number}]."
    kind = table_kind(prefix, table)
    dims = table_dimensions(prefix, table, kind)
    distribution = _size_distribution(prefix, table) if kind == "sphere" else None
    density, mass = density_or_mass(prefix, table, per_size=distribution is not None and distribution.kind != "single")
    youngs = _number(prefix + "youngs_modulus", table["youngs_modulus"]) if "youngs_modulus" in table else None
    poisson = (
        _number(prefix + "poisson_ratio", table["poisson_ratio"], lo=-1.0, hi=0.5, hi_open=True)
        if "poisson_ratio" in table
        else None
    )
    name = _string(prefix + "name", table["name"]) if "name" in table else f"particle {number}"
    if distribution is None:
        shape = build_shape(prefix, kind, dims, density, mass)
        return Particle(number, kind, dims, shape, youngs, poisson, name)
    key = "radius" if distribution.kind == "single" else ("radii" if distribution.kind == "discrete" else "lognormal")
    from dtcrit.scenes.sizes import SizeShapes

    shapes = SizeShapes(lambda r: build_shape(prefix, kind, {key: r}, density, mass), distribution.radii)
    dims = {"radius": distribution.radii[0]} if distribution.kind == "single" else {key: list(distribution.radii)}
    return Particle(number, kind, dims, shapes[0], youngs, poisson, name, distribution, shapes)


def _size_distribution(prefix: str, table: dict):
    """A sphere's sizes (``dtcrit.scenes.sizes``, imported only for spheres)."""
    from dtcrit.scenes.sizes import size_distribution

    return size_distribution(prefix, table)


def _walls(tables: Any, n_particles: int, found: list) -> tuple:
    """The ``[[wall]]`` tables (``dtcrit.scenes.walls``, imported only for scenes with walls)."""
    from dtcrit.scenes.walls import parse_walls

    return parse_walls(tables, n_particles, found)


# ----------------------------------------------------------------------------------------------
# Entry points
# ----------------------------------------------------------------------------------------------
def _integrator(value) -> tuple[str, str]:
    """(scheme key, note) of the ``integrator`` entry: a scheme key, a DEM code's name (resolved by
    ``dtcrit.integrators.engines``: the note says which scheme it means), or an ``[integrator]`` table
    of update rules (``dtcrit.integrators.user_rules``: parsed from an allow-listed AST, never evaluated,
    and registered for this run).
    """
    from dtcrit.integrators.engines import resolve_integrator
    from dtcrit.integrators.stability import check_integrator

    if isinstance(value, dict):
        from dtcrit.integrators.user_rules import parse_integrator, register

        name = register(parse_integrator(value, "integrator"))
        return name, (f"note: user-written scheme '{name}': its step is the exact stability boundary of the "
                      "amplification matrix its rules define")
    scheme, note = resolve_integrator(_string("integrator", value))
    return check_integrator(scheme), (f"note: {note}" if note else "")


def scene_from_dict(doc: Any, source: str = "<scene>") -> Scene:
    """Validate a parsed TOML document and build the :class:`Scene` (module docstring).

    Parameters
    ----------
    doc : Any
        The document as ``tomllib`` returns it (a dict).
    source : str
        The scene's name (its file), kept in ``Scene.source``.

    Returns
    -------
    Scene
        The validated scene; each problem raises one ``InputError`` keyed by its entry.
    """
    if not isinstance(doc, dict):
        raise InputError("scene", "must be a TOML table")
    _check_keys("", doc, TOP_KEYS, TOP_KEYS, "at the top level")
    integrator, integrator_note = _integrator(_required("", doc, "integrator", "the integrator name (or a table)"))
    omega_max = _number("omega_max", doc["omega_max"]) if "omega_max" in doc else None
    safety = _number("safety", doc["safety"], hi=1.0) if "safety" in doc else 1.0
    if safety < MIN_SAFETY:
        raise InputError("safety", f"{safety:g} is below {MIN_SAFETY:g}: a step a million times below the critical one "
                         "is not a safety margin (codes use 0.1-0.9; subnormal factors lose their digits)")
    pairs = _choice("pairs", doc["pairs"], PAIRS_CHOICES, "pairs setting") if "pairs" in doc else "all"
    title = _string("title", doc["title"]) if "title" in doc else None
    if title is not None and len(title) > MAX_TITLE:
        raise InputError("title", f"{len(title)} characters: at most {MAX_TITLE} (it is printed and put into emitted code)")

    coordination = None
    if "coordination_max" in doc:
        raw = doc["coordination_max"]
        if isinstance(raw, bool) or not isinstance(raw, int) or raw < 1:
            raise InputError("coordination_max", f"must be a positive whole number of contacts per particle (got {_short(raw)})")
        if raw > MAX_COORDINATION:
            raise InputError("coordination_max", f"{raw} contacts per particle: at most {MAX_COORDINATION}")
        coordination = raw

    isolated = False
    if "isolated" in doc:
        isolated = doc["isolated"]
        if not isinstance(isolated, bool):
            raise InputError("isolated", f"must be true or false (got {_short(isolated)})")
        if isolated and coordination is not None:
            raise InputError("isolated", "isolated = true asks for the isolated-contact step, coordination_max for a "
                             "packing's: give one of them")

    overlap = 0.05
    if "overlap_max" in doc:
        overlap = _number("overlap_max", doc["overlap_max"], allow_zero=True, hi=1.0, hi_open=True)

    tables = _required("", doc, "particle", "one or more [[particle]] tables")
    if isinstance(tables, dict):
        tables = [tables]
    if not isinstance(tables, list) or not tables:
        raise InputError("particle", f"must be one or more [[particle]] tables (got {_type_name(tables)}: {_short(tables)})")
    particles = [_particle(n + 1, t) for n, t in enumerate(tables)]
    if "pairs" in doc and len(particles) == 1 and pairs != "all":
        raise InputError("pairs", "'unlike' needs two or more [[particle]] tables")
    found: list[tuple[str, str]] = [("integrator", integrator_note)] if integrator_note else []
    walls = _walls(doc["wall"], len(particles), found) if "wall" in doc else ()

    contact = _required("", doc, "contact", "the [contact] table")
    law, particles = contact_law(contact, particles, found)
    if isinstance(contact, dict) and "friction" in contact:  # checked by contact_law; used by dtcrit collide's oblique impacts
        law = replace(law, friction=float(contact["friction"]))
    if law.model == "hertz" and any(p.sizes is not None and p.sizes.kind == "lognormal" for p in particles):
        found.append(("contact.model", "warning: Hertz stiffness over a lognormal size range is evaluated at "
                      f"{len(next(p for p in particles if p.sizes is not None and p.sizes.kind == 'lognormal').radii)} "
                      "log-spaced radii between the cut-offs (no monotonicity is proved for Hertz)"))
    import dtcrit.scenes.local_damping as local_damping

    scene = Scene(source, integrator, tuple(particles), law, omega_max, safety, pairs, title, tuple(found), walls, coordination,
                  overlap, isolated, local_damping.parse(doc), *_collision(doc))
    from dtcrit.scenes.laws import resolve_wall

    checks = [(f"pair {i}-{j}", resolve_pair(scene, i, j)) for i, j in scene.pair_numbers()]
    checks += [(f"wall[{w.number}]", resolve_wall(scene, w, i)) for w in walls for i in w.particles]
    for where, pc in checks:  # resolve every contact now so that bad numbers surface here
        for name in ("kn", "ks", "cn", "cs"):
            value = getattr(pc, name)
            if not math.isfinite(value):
                key = f"wall[{pc.wall_number}].{name}" if pc.wall is not None else f"contact.{name}"
                raise InputError(key, f"{where}: {name} = {value!r} is outside double precision")
    local_damping.check(scene, checks)
    return scene


def _collision(doc: dict) -> tuple[float | None, tuple[str, float] | None]:
    """The ``[collision]`` table's ``v_max`` [m/s] (the largest impact speed ``dtcrit collide`` resolves) and
    obliquity (``angle_deg`` or ``tangential_ratio``: :mod:`dtcrit.scenes.collide_oblique`).
    """
    if "collision" not in doc:
        return None, None
    table = doc["collision"]
    if not isinstance(table, dict):
        raise InputError("collision", "must be a table: [collision] with v_max = SPEED")
    from dtcrit.scenes.collide_oblique import parse_angle

    _check_keys("collision.", table, COLLISION_KEYS, COLLISION_KEYS, "in [collision]")
    angle = parse_angle(table)
    if angle is not None and "v_max" not in table:
        return None, angle
    return _number("collision.v_max", _required("collision.", table, "v_max", "largest impact speed [m/s]")), angle


def parse_scene(text: str, source: str = "<scene>") -> Scene:
    """Parse a scene's TOML text (never evaluated as code) and validate it.

    Parameters
    ----------
    text : str
        The TOML text.
    source : str
        The scene's name (its file), kept in ``Scene.source``.

    Returns
    -------
    Scene
        The validated scene; bad TOML raises ``InputError('toml', ...)``.

    Examples
    --------
    >>> from dtcrit import parse_scene, critical_step
    >>> scene = parse_scene('''
    ... integrator = "velocity-verlet"
    ... [[particle]]
    ... shape = "sphere"
    ... radius = 0.001
    ... density = 2500.0
    ... [contact]
    ... model = "linear"
    ... kn = 1e4
    ... ks = 8e3
    ... ''')
    >>> round(critical_step(scene).dt_crit, 12) > 0
    True
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("toml", f"not a valid TOML document: {' '.join(str(exc).split())}") from None
    except RecursionError:
        raise InputError("toml", "not a valid scene: arrays or tables nested too deeply") from None
    return scene_from_dict(doc, source)


MAX_SCENE_BYTES = 8 << 20
"""A scene file is a few kilobytes; 8 MiB leaves room for polyhedra with very many vertices."""
MAX_TITLE = 200
MIN_SAFETY = 1e-6
"""Smallest accepted safety factor: below it ``dt_recommended`` is no longer a margin on ``dt_crit`` (and a
subnormal factor, e.g. 1e-320, keeps only a few significant digits)."""
MAX_COORDINATION = 100_000
"""Far above any packing (a sphere among ones 100 times smaller touches about 40,000)."""


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file.

    Parameters
    ----------
    path : str or pathlib.Path
        The scene file (UTF-8 TOML, at most ``MAX_SCENE_BYTES``).

    Returns
    -------
    Scene
        The validated scene; unreadable, too large or non-UTF-8 files raise ``InputError('file', ...)``.

    Examples
    --------
    >>> from dtcrit import load_scene
    >>> scene = load_scene("examples/paper_ellipsoids.toml")
    >>> scene.integrator
    'velocity-verlet'
    """
    try:
        data = read_bounded(path, MAX_SCENE_BYTES)  # never more: /dev/zero is not a scene
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InputError("file", f"cannot read the scene file: {reason}") from None
    except ValueError:  # a NUL character in the path
        raise InputError("file", "cannot read the scene file: the path contains a NUL character") from None
    if len(data) > MAX_SCENE_BYTES:
        raise InputError("file", f"more than {MAX_SCENE_BYTES} bytes: larger than a scene file can be")
    try:
        text = data.decode("utf-8-sig")  # a UTF-8 byte-order mark is accepted
    except UnicodeDecodeError as exc:
        raise InputError("file", f"not UTF-8 text (byte {exc.start}); a scene is a TOML text file") from None
    return parse_scene(text, str(path))
