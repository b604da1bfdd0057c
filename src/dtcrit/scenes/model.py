"""What a scene describes, once parsed: particle types, the contact law, the pairs that can touch and
the keys a scene file may hold; restitution to damping ratio and the Hertz overlap of an impact.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from dtcrit.errors import InputError

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
