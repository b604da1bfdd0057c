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
from pathlib import Path
from typing import Any

from dtcrit.errors import InputError
from dtcrit.inputs.files import read_bounded
from dtcrit.scenes.damping_input import CONVENTIONS, convention_for, parse_damping
from dtcrit.bodies.spec import build_shape, density_or_mass, table_dimensions, table_kind
from dtcrit.scenes.fields import _check_keys, _choice, _number, _required, _short, _string, _type_name
from dtcrit.scenes.law_damping import check_law_input
from dtcrit.scenes.laws import resolve_pair
from dtcrit.scenes.model import (
    COLLISION_KEYS,
    CONTACT_ALL,
    CONTACT_KEYS,
    CONTACT_MODELS,
    NOT_IN_THE_STEP,
    PAIRS_CHOICES,
    TOP_KEYS,
    ContactLaw,
    Particle,
    Scene,
)
from dtcrit.scenes.sizes import SizeShapes, size_distribution
from dtcrit.scenes.walls import parse_walls

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
    distribution = size_distribution(prefix, table) if kind == "sphere" else None
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
    shapes = SizeShapes(lambda r: build_shape(prefix, kind, {key: r}, density, mass), distribution.radii)
    dims = {"radius": distribution.radii[0]} if distribution.kind == "single" else {key: list(distribution.radii)}
    return Particle(number, kind, dims, shapes[0], youngs, poisson, name, distribution, shapes)


# ----------------------------------------------------------------------------------------------
# Contact law
# ----------------------------------------------------------------------------------------------
def _per_particle(key: str, value: Any, n: int, **limits) -> tuple[float, ...]:
    """A scalar (all particle types) or an array with one entry per particle type."""
    if isinstance(value, list):
        if len(value) != n:
            raise InputError(key, f"give one number, or an array of {n} (one per [[particle]] table; got {len(value)})")
        return tuple(_number(f"{key}[{m + 1}]", v, **limits) for m, v in enumerate(value))
    x = _number(key, value, **limits)
    return (x,) * n


def _contact(table: Any, particles: list[Particle], out_warnings: list) -> tuple[ContactLaw, list[Particle]]:
    prefix = "contact."
    if not isinstance(table, dict):
        raise InputError("contact", f"must be a table (got {_type_name(table)}: {_short(table)})")
    model = _choice(prefix + "model", _required(prefix, table, "model", f"one of {', '.join(CONTACT_MODELS)}"), CONTACT_MODELS, "contact model")
    _check_keys(prefix, table, CONTACT_KEYS[model], CONTACT_ALL, f"by the {model} contact model")

    if model == "bond":
        return _bond_contact(prefix, table, particles, out_warnings)
    cn, cs, restitution, zeta = parse_damping(prefix, table)  # one way only
    from dtcrit.scenes.rotational import parse_rotational

    parsed = parse_rotational(prefix, table)
    rotational = parsed if parsed.present else None
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
    walls = parse_walls(doc["wall"], len(particles), found) if "wall" in doc else ()

    contact = _required("", doc, "contact", "the [contact] table")
    law, particles = _contact(contact, particles, found)
    if isinstance(contact, dict) and "friction" in contact:  # checked by _contact; used by dtcrit collide's oblique impacts
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
