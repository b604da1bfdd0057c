"""Scene files: one TOML document describing a DEM contact problem, parsed and validated.

A scene names one or two particle types, the contact law between them, the integrator, and
optionally the largest angular velocity ``omega_max`` and a safety factor (the format is documented
in ``README.md, section Scene files``).  Parsing uses the standard library's ``tomllib`` only: no text from a file
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

import difflib
import json
import math
import re
import tomllib
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from dtcrit.errors import InputError

__all__ = [
    "Scene",
    "Particle",
    "ContactLaw",
    "PairContact",
    "load_scene",
    "parse_scene",
    "scene_from_dict",
    "damping_ratio_from_restitution",
    "hertz_max_overlap",
    "SHAPE_KEYS",
]

# ----------------------------------------------------------------------------------------------
# The vocabulary of a scene
# ----------------------------------------------------------------------------------------------
TOP_KEYS = ("integrator", "omega_max", "safety", "pairs", "title", "particle", "contact")
PAIRS_CHOICES = ("all", "unlike")

# shape -> the dimension keys it needs (TOML key, expected length or None for a scalar)
SHAPE_KEYS: dict[str, tuple[tuple[str, int | None], ...]] = {
    "sphere": (("radius", None),),
    "ellipsoid": (("semi_axes", 3),),
    "superquadric": (("semi_axes", 3), ("exponents", 2)),
    "box": (("half_lengths", 3),),
    "polyhedron": (("vertices", -1),),
}
PARTICLE_COMMON = ("shape", "density", "mass", "youngs_modulus", "poisson_ratio", "name")
PARTICLE_ALL = tuple(dict.fromkeys(PARTICLE_COMMON + tuple(k for v in SHAPE_KEYS.values() for k, _ in v)))

CONTACT_MODELS = ("linear", "hertz")
DAMPING_KEYS = ("cn", "cs", "restitution", "damping_ratio")
CONTACT_KEYS = {
    "linear": ("model", "kn", "ks", "cn", "cs", "restitution", "damping_ratio", "youngs_modulus", "poisson_ratio"),
    "hertz": ("model", "youngs_modulus", "poisson_ratio", "velocity", "restitution", "damping_ratio", "curvature_radius"),
}
CONTACT_ALL = tuple(dict.fromkeys(CONTACT_KEYS["linear"] + CONTACT_KEYS["hertz"]))


# ----------------------------------------------------------------------------------------------
# Contact mechanics used to resolve a contact law (independently checked in tests/test_scene_*.py)
# ----------------------------------------------------------------------------------------------
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


def hertz_max_overlap(m_star: float, e_star: float, r_star: float, velocity: float) -> float:
    """Largest overlap of a Hertz impact at relative normal speed ``velocity`` [m].

    Energy balance 1/2 m* v^2 = (8/15) E* sqrt(R*) delta^(5/2) for F = (4/3) E* sqrt(R*) delta^(3/2):
    delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5), evaluated in logarithms (no overflow).
    """
    log_d = 0.4 * (math.log(15.0 / 16.0) + math.log(m_star) + 2.0 * math.log(velocity) - math.log(e_star) - 0.5 * math.log(r_star))
    return math.exp(log_d)


@dataclass(frozen=True)
class PairContact:
    """The linear(ised) contact of one pair of particle types (Peng et al. 2020, Eq. (29))."""

    i: int  # particle numbers, counted from 1
    j: int
    m_star: float  # m_i m_j / (m_i + m_j) [kg]
    kn: float  # [N/m]
    ks: float
    cn: float  # [N s/m]
    cs: float
    zeta: float | None  # damping ratio used for cn, cs (None when given as coefficients)
    e_star: float | None = None  # Hertz: effective modulus [Pa]
    g_star: float | None = None  # Hertz: effective shear modulus [Pa]
    r_star: float | None = None  # Hertz: effective radius [m]
    delta_max: float | None = None  # Hertz: largest overlap [m]
    velocity: float | None = None  # Hertz: impact speed [m/s]

    @property
    def label(self) -> str:
        return f"{self.i}-{self.j}"


@dataclass(frozen=True)
class Particle:
    """One particle type of a scene: its shape object and (optional) elastic constants."""

    number: int  # 1 or 2
    kind: str
    dimensions: dict  # the dimension entries as given (validated)
    shape: Any  # a dtcrit.bodies object
    youngs_modulus: float | None
    poisson_ratio: float | None
    name: str

    @property
    def mass(self) -> float:
        return self.shape.mass

    def describe(self) -> str:
        dims = ", ".join(f"{k} = {_fmt_dim(v)}" for k, v in self.dimensions.items() if k != "vertices")
        if "vertices" in self.dimensions:
            dims = f"{len(self.dimensions['vertices'])} vertices"
        return f"{self.kind} ({dims}), mass {self.shape.mass:.6g} kg"


def _fmt_dim(v) -> str:
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(f"{x:g}" for x in v) + "]"
    return f"{v:g}"


@dataclass(frozen=True)
class ContactLaw:
    """The ``[contact]`` table after validation."""

    model: str  # linear | hertz
    kn: float | None = None
    ks: float | None = None
    cn: float | None = None  # given coefficients (linear only)
    cs: float | None = None
    restitution: float | None = None
    damping_ratio: float | None = None  # given, or derived from restitution
    velocity: float | None = None
    curvature_radius: float | None = None

    @property
    def damping(self) -> str:
        """How damping was given: none | coefficients | restitution | damping_ratio."""
        if self.restitution is not None:
            return "restitution"
        if self.damping_ratio is not None:
            return "damping_ratio"
        if (self.cn or 0.0) > 0 or (self.cs or 0.0) > 0:
            return "coefficients"
        return "none"

    @property
    def damped(self) -> bool:
        if self.damping == "coefficients":
            return True
        return (self.damping_ratio or 0.0) > 0.0


@dataclass(frozen=True)
class Scene:
    """A validated scene (see module docstring); build with :func:`load_scene` or :func:`parse_scene`."""

    source: str
    integrator: str
    particles: tuple[Particle, ...]
    contact: ContactLaw
    omega_max: float | None = None
    safety: float = 1.0
    pairs: str = "all"
    title: str | None = None
    warnings: tuple[tuple[str, str], ...] = field(default_factory=tuple)

    @property
    def identical(self) -> bool:
        """One particle type (a single ``[[particle]]`` table)."""
        return len(self.particles) == 1

    def pair_numbers(self) -> tuple[tuple[int, int], ...]:
        """The pairs of particle types that can touch: (1, 1) for one type; (1, 1), (1, 2), (2, 2)
        for two (``pairs = "all"``), or only (1, 2) (``pairs = "unlike"``)."""
        if self.identical:
            return ((1, 1),)
        if self.pairs == "unlike":
            return ((1, 2),)
        return ((1, 1), (1, 2), (2, 2))

    def particle(self, number: int) -> Particle:
        return self.particles[number - 1]

    def pair_contact(self, i: int, j: int) -> PairContact:
        """Resolve the contact law for particle types ``i`` and ``j`` (counted from 1)."""
        p, q = self.particle(i), self.particle(j)
        m_star = _harmonic(p.mass, q.mass)
        law = self.contact
        if law.model == "linear":
            kn, ks = law.kn, law.ks
            extra = {}
        else:
            e_star = 1.0 / ((1.0 - p.poisson_ratio**2) / p.youngs_modulus + (1.0 - q.poisson_ratio**2) / q.youngs_modulus)
            g_p = p.youngs_modulus / (2.0 * (1.0 + p.poisson_ratio))
            g_q = q.youngs_modulus / (2.0 * (1.0 + q.poisson_ratio))
            g_star = 1.0 / ((2.0 - p.poisson_ratio) / g_p + (2.0 - q.poisson_ratio) / g_q)
            if law.curvature_radius is not None:
                r_star = law.curvature_radius
            else:  # spheres (checked at parse time)
                r_star = _harmonic(p.dimensions["radius"], q.dimensions["radius"])
            delta = hertz_max_overlap(m_star, e_star, r_star, law.velocity)
            root = math.sqrt(r_star * delta)
            kn = 2.0 * e_star * root
            ks = 8.0 * g_star * root
            extra = dict(e_star=e_star, g_star=g_star, r_star=r_star, delta_max=delta, velocity=law.velocity)
            for key, value in (("contact.youngs_modulus", kn), ("contact.youngs_modulus", ks)):
                if not (math.isfinite(value) and value > 0.0):
                    raise InputError(key, f"pair {i}-{j}: the Hertz tangent stiffness {value!r} is outside double precision")
        if law.damping == "coefficients":
            cn, cs, zeta = law.cn or 0.0, law.cs or 0.0, None
        else:
            zeta = law.damping_ratio or 0.0
            cn = 2.0 * zeta * math.sqrt(kn) * math.sqrt(m_star)
            cs = 2.0 * zeta * math.sqrt(ks) * math.sqrt(m_star)
        return PairContact(i, j, m_star, kn, ks, cn, cs, zeta, **extra)


def _harmonic(x: float, y: float) -> float:
    """x y / (x + y) without overflow: 1 / (1/x + 1/y) for positive finite x, y."""
    return x / (1.0 + x / y) if x <= y else y / (1.0 + y / x)


# ----------------------------------------------------------------------------------------------
# Value checks: each names its key
# ----------------------------------------------------------------------------------------------
def _type_name(value: Any) -> str:
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, (int, float)):
        return "a number"
    return f"a {type(value).__name__} value"  # dates and times


def _number(key: str, value: Any, *, allow_zero: bool = False, lo: float | None = None, hi: float | None = None,
            hi_open: bool = False) -> float:
    """A finite number; positive (or non-negative), optionally within [lo, hi] / [lo, hi)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(key, f"must be a number (got {_type_name(value)}: {_short(value)})")
    try:
        x = float(value)
    except OverflowError:
        raise InputError(key, f"must be a finite number (got an integer with {len(str(value))} digits)") from None
    if not math.isfinite(x):
        raise InputError(key, f"must be finite (got {x})")
    if lo is None:
        if x < 0 or (x == 0 and not allow_zero):
            raise InputError(key, f"must be {'non-negative' if allow_zero else 'positive'} (got {x:g})")
    else:
        if x <= lo:
            raise InputError(key, f"must be greater than {lo:g} (got {x:g})")
    if hi is not None and (x > hi or (hi_open and x == hi)):
        raise InputError(key, f"must be {'less than' if hi_open else 'at most'} {hi:g} (got {x:g})")
    return x


def _string(key: str, value: Any) -> str:
    if not isinstance(value, str):
        raise InputError(key, f"must be a string (got {_type_name(value)}: {_short(value)})")
    return value


def _choice(key: str, value: Any, choices: tuple[str, ...], what: str) -> str:
    text = _string(key, value)
    if text in choices:
        return text
    if text.lower() in choices:
        return text.lower()
    close = difflib.get_close_matches(text.lower(), choices, n=1, cutoff=0.5)
    hint = f" (did you mean '{close[0]}'?)" if close else ""
    raise InputError(key, f"unknown {what} {_short(text)}{hint}; choose one of {', '.join(choices)}")


def _vector(key: str, value: Any, length: int) -> list[float]:
    if not isinstance(value, list):
        raise InputError(key, f"must be an array of {length} numbers (got {_type_name(value)}: {_short(value)})")
    if len(value) != length:
        raise InputError(key, f"must have {length} entries (got {len(value)})")
    return [_number(f"{key}[{n + 1}]", v) for n, v in enumerate(value)]


def _vertices(key: str, value: Any) -> list[list[float]]:
    if not isinstance(value, list) or not value:
        raise InputError(key, f"must be an array of [x, y, z] points (got {_type_name(value)}: {_short(value)})")
    if len(value) < 4:
        raise InputError(key, f"needs at least 4 points (got {len(value)})")
    out = []
    for n, point in enumerate(value):
        k = f"{key}[{n + 1}]"
        if not isinstance(point, list) or len(point) != 3:
            raise InputError(k, f"must be an [x, y, z] array of 3 numbers (got {_short(point)})")
        coords = []
        for m, v in enumerate(point):
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise InputError(f"{k}[{m + 1}]", f"must be a number (got {_type_name(v)}: {_short(v)})")
            try:
                x = float(v)
            except OverflowError:
                raise InputError(f"{k}[{m + 1}]", "must be a finite number") from None
            if not math.isfinite(x):
                raise InputError(f"{k}[{m + 1}]", f"must be finite (got {x})")
            coords.append(x)
        out.append(coords)
    return out


def _short(value: Any, limit: int = 40) -> str:
    text = repr(value)
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _key_text(key: str) -> str:
    """A key as TOML would write it: bare when possible, else quoted with ASCII escapes."""
    return key if _BARE_KEY.match(key) else json.dumps(key)


def _check_keys(prefix: str, table: dict, allowed: tuple[str, ...], vocabulary: tuple[str, ...], where: str) -> None:
    """Reject keys outside ``allowed``; suggest the nearest key (preferring the allowed ones)."""
    for key in table:
        if key in allowed:
            continue
        path = f"{prefix}{_key_text(key)}"
        if key in vocabulary:
            raise InputError(path, f"not used {where}; valid keys here: {', '.join(allowed)}")
        close = difflib.get_close_matches(str(key), allowed, n=1, cutoff=0.6) or difflib.get_close_matches(
            str(key).lower(), allowed, n=1, cutoff=0.5
        )
        hint = f" (did you mean '{close[0]}'?)" if close else ""
        raise InputError(path, f"unknown key{hint}; valid keys here: {', '.join(allowed)}")


def _required(prefix: str, table: dict, key: str, what: str) -> Any:
    if key not in table:
        raise InputError(f"{prefix}{key}", f"missing: {what}")
    return table[key]


# ----------------------------------------------------------------------------------------------
# Particles
# ----------------------------------------------------------------------------------------------
# key names used by dtcrit.bodies -> scene key
_SHAPE_ARG_TO_KEY = {
    "sphere": {"radius": "radius"},
    "ellipsoid": {"a": "semi_axes", "b": "semi_axes", "c": "semi_axes"},
    "superquadric": {"a": "semi_axes", "b": "semi_axes", "c": "semi_axes", "eps1": "exponents", "eps2": "exponents"},
    "box": {"a": "half_lengths", "b": "half_lengths", "c": "half_lengths"},
    "polyhedron": {"vertices": "vertices"},
}


def _build_shape(prefix: str, kind: str, dims: dict, density: float | None, mass: float | None):
    import dtcrit.bodies as shapes  # NumPy only at import

    if kind == "sphere":
        args = (dims["radius"],)
        cls = shapes.Sphere
    elif kind == "ellipsoid":
        args, cls = tuple(dims["semi_axes"]), shapes.Ellipsoid
    elif kind == "superquadric":
        args, cls = tuple(dims["semi_axes"]) + tuple(dims["exponents"]), shapes.Superquadric
    elif kind == "box":
        args, cls = tuple(dims["half_lengths"]), shapes.Box
    else:
        args, cls = (dims["vertices"],), shapes.ConvexPolyhedron
    size_key = next(iter(dims))
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            shape = cls(*args, density=density, mass=mass)
    except InputError as exc:
        key = _SHAPE_ARG_TO_KEY[kind].get(exc.key, exc.key)
        reason = exc.reason
        if exc.key in ("a", "b", "c") and "a >= b >= c" in reason:
            reason += "; list the axes largest first (Peng et al. 2020, Section 3, assumption 3)"
        raise InputError(f"{prefix}{key}", reason) from None
    except (ValueError, ArithmeticError) as exc:  # numerical trouble inside the shape
        raise InputError(f"{prefix}{size_key}", f"cannot build the {kind}: {' '.join(str(exc).split())}") from None
    issues = getattr(shape, "assumption_issues", ())
    if issues:
        raise InputError(
            f"{prefix}{size_key}",
            "breaks Peng et al. 2020, Section 3, assumption 3: " + "; ".join(issues),
        )
    del caught  # other warnings from the shape layer are not the user's concern
    return shape


def _particle(number: int, table: Any) -> Particle:
    prefix = f"particle[{number}]."
    if not isinstance(table, dict):
        raise InputError(f"particle[{number}]", f"must be a table (got {_type_name(table)}: {_short(table)})")
    kind = _choice(f"{prefix}shape", _required(prefix, table, "shape", f"one of {', '.join(SHAPE_KEYS)}"), tuple(SHAPE_KEYS), "shape")
    needed = SHAPE_KEYS[kind]
    allowed = tuple(dict.fromkeys(("shape",) + tuple(k for k, _ in needed) + PARTICLE_COMMON[1:]))
    _check_keys(prefix, table, allowed, PARTICLE_ALL, f"by a {kind}")
    dims: dict[str, Any] = {}
    for key, length in needed:
        value = _required(prefix, table, key, f"a {kind} needs {', '.join(k for k, _ in needed)}")
        if length is None:
            dims[key] = _number(prefix + key, value)
        elif length == -1:
            dims[key] = _vertices(prefix + key, value)
        else:
            dims[key] = _vector(prefix + key, value, length)
    if "density" in table and "mass" in table:
        raise InputError(f"{prefix}mass", "give density or mass, not both")
    if "density" not in table and "mass" not in table:
        raise InputError(f"{prefix}density", "missing: give density [kg/m^3] or mass [kg]")
    density = _number(prefix + "density", table["density"]) if "density" in table else None
    mass = _number(prefix + "mass", table["mass"]) if "mass" in table else None
    youngs = _number(prefix + "youngs_modulus", table["youngs_modulus"]) if "youngs_modulus" in table else None
    poisson = (
        _number(prefix + "poisson_ratio", table["poisson_ratio"], lo=-1.0, hi=0.5, hi_open=True)
        if "poisson_ratio" in table
        else None
    )
    name = _string(prefix + "name", table["name"]) if "name" in table else f"particle {number}"
    shape = _build_shape(prefix, kind, dims, density, mass)
    return Particle(number, kind, dims, shape, youngs, poisson, name)


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

    # damping: coefficients, restitution or damping ratio (one way only)
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

    if model == "linear":
        kn = _number(prefix + "kn", _required(prefix, table, "kn", "normal contact stiffness kn [N/m]"))
        ks = _number(prefix + "ks", _required(prefix, table, "ks", "shear contact stiffness ks [N/m]"))
        if ks > kn:
            out_warnings.append(
                (prefix + "ks", f"warning: ks = {ks:g} exceeds kn = {kn:g} (physically k_n >= k_s; Peng et al. 2020, "
                 "Section 4.2); each direction is still checked with its own stiffness")
            )
        law = ContactLaw("linear", kn=kn, ks=ks, cn=cn, cs=cs, restitution=restitution, damping_ratio=zeta)
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
    law = ContactLaw("hertz", restitution=restitution, damping_ratio=zeta, velocity=velocity, curvature_radius=radius)
    return law, particles


# ----------------------------------------------------------------------------------------------
# Entry points
# ----------------------------------------------------------------------------------------------
def scene_from_dict(doc: Any, source: str = "<scene>") -> Scene:
    """Validate a parsed TOML document (a dict) and build the :class:`Scene`."""
    from dtcrit.integrators.stability import check_integrator

    if not isinstance(doc, dict):
        raise InputError("scene", "must be a TOML table")
    _check_keys("", doc, TOP_KEYS, TOP_KEYS, "at the top level")
    integrator = check_integrator(_string("integrator", _required("", doc, "integrator", "the integrator name")))
    omega_max = _number("omega_max", doc["omega_max"]) if "omega_max" in doc else None
    safety = _number("safety", doc["safety"], hi=1.0) if "safety" in doc else 1.0
    pairs = _choice("pairs", doc["pairs"], PAIRS_CHOICES, "pairs setting") if "pairs" in doc else "all"
    title = _string("title", doc["title"]) if "title" in doc else None

    tables = _required("", doc, "particle", "one or two [[particle]] tables")
    if isinstance(tables, dict):
        tables = [tables]
    if not isinstance(tables, list):
        raise InputError("particle", f"must be one or two [[particle]] tables (got {_type_name(tables)}: {_short(tables)})")
    if not 1 <= len(tables) <= 2:
        raise InputError("particle", f"give one [[particle]] table (identical particles) or two (got {len(tables)})")
    particles = [_particle(n + 1, t) for n, t in enumerate(tables)]
    if "pairs" in doc and len(particles) == 1 and pairs != "all":
        raise InputError("pairs", "'unlike' needs two [[particle]] tables")

    found: list[tuple[str, str]] = []
    law, particles = _contact(_required("", doc, "contact", "the [contact] table"), particles, found)
    scene = Scene(source, integrator, tuple(particles), law, omega_max, safety, pairs, title, tuple(found))
    for i, j in scene.pair_numbers():  # resolve every pair now so that bad numbers surface here
        pc = scene.pair_contact(i, j)
        for name in ("kn", "ks", "cn", "cs"):
            value = getattr(pc, name)
            if not math.isfinite(value):
                raise InputError(f"contact.{name}", f"pair {i}-{j}: {name} = {value!r} is outside double precision")
    return scene


def parse_scene(text: str, source: str = "<scene>") -> Scene:
    """Parse TOML text (never evaluated as code) and validate it."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError("toml", f"not a valid TOML document: {' '.join(str(exc).split())}") from None
    except RecursionError:
        raise InputError("toml", "not a valid scene: arrays or tables nested too deeply") from None
    return scene_from_dict(doc, source)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file; unreadable or non-UTF-8 files raise ``InputError('file', ...)``."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InputError("file", f"cannot read the scene file: {reason}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError("file", f"not UTF-8 text (byte {exc.start}); a scene is a TOML text file") from None
    return parse_scene(text, str(path))
