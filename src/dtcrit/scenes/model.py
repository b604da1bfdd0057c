"""What a scene describes, once parsed: particle types, the contact law, walls, the pairs that can touch
and the keys a scene file may hold.
"""
from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Any

# the keys of a [[particle]] table are the shape parser's (re-exported: part of a scene's vocabulary)
from dtcrit.bodies.spec import PARTICLE_ALL, PARTICLE_COMMON, SHAPE_KEYS, SPHERE_SIZE_KEYS  # noqa: F401
from dtcrit.scenes.damping_input import damping_kind

# ----------------------------------------------------------------------------------------------
# The vocabulary of a scene
# ----------------------------------------------------------------------------------------------
TOP_KEYS = ("integrator", "omega_max", "safety", "pairs", "title", "coordination_max", "overlap_max", "isolated", "particle", "contact",
            "wall", "local_damping", "local_damping_law", "collision")
PAIRS_CHOICES = ("all", "unlike")
COLLISION_KEYS = ("v_max", "angle_deg", "tangential_ratio")
"""The keys of the ``[collision]`` table (read by ``dtcrit collide``)."""

CONTACT_MODELS = ("linear", "yade", "hertz", "bond")
ROTATIONAL_KEYS = ("kr", "ktw", "cr", "ctw", "rolling_model", "rolling_friction", "rolling_viscous_damping",
                   "rolling_stiffness_factor", "k_roll", "gamma_roll", "alpha_kr", "alpha_ktw", "twisting_model", "k_twist",
                   "gamma_twist", "contact_radius")
"""Rotational springs and dashpots of every contact model (:mod:`dtcrit.scenes.rotational`)."""
BOND_KEYS = ("model", "kn", "ks", "kr", "ktw", "cn", "cs", "cr", "ctw", "damping_ratio", "damping_convention",
             "bond_youngs_modulus", "bond_shear_modulus", "bond_poisson_ratio", "bond_stiffness_ratio", "bond_radius",
             "bond_length", "contact_kn", "contact_ks")
"""The ``bond`` model's keys (:mod:`dtcrit.scenes.bonds`)."""
CONTACT_KEYS = {
    "linear": ("model", "kn", "ks", "cn", "cs", "restitution", "damping_ratio", "damping_convention", "youngs_modulus",
               "poisson_ratio", "friction"),
    "yade": ("model", "youngs_modulus", "ks_ratio", "cn", "cs", "restitution", "damping_ratio", "damping_convention",
             "poisson_ratio", "friction"),
    "hertz": ("model", "youngs_modulus", "poisson_ratio", "velocity", "restitution", "damping_ratio", "damping_convention",
              "curvature_radius", "friction", "damping_coefficient", "tangential_damping_factor"),
}
NOT_IN_THE_STEP = {
    "friction": "the friction coefficient caps the tangential force when a contact slides; the linear step is that "
                "of the sticking contact (its tangential spring), which friction does not change",
}
"""DEM keys that a scene may carry but that do not enter the critical step: accepted with a note saying why."""
CONTACT_KEYS = {model: keys + ROTATIONAL_KEYS for model, keys in CONTACT_KEYS.items()}
CONTACT_KEYS["bond"] = BOND_KEYS
CONTACT_ALL = tuple(dict.fromkeys(CONTACT_KEYS["linear"] + CONTACT_KEYS["yade"] + CONTACT_KEYS["hertz"] + BOND_KEYS))


@dataclass(frozen=True)
class PairContact:
    """The linear(ised) contact of one pair of particle types (Peng et al. 2020, Eq. (29)).

    Parameters
    ----------
    i, j : int
        Particle numbers, counted from 1 (``j = 0`` against a wall).
    m_star : float
        Effective mass ``m_i m_j / (m_i + m_j)`` [kg].
    kn, ks : float
        Normal / tangential spring [N/m].
    cn, cs : float
        Normal / tangential dashpot [N s/m].
    zeta : float or None
        The damping ratio the user gave (None when given as coefficients).
    radius_i, radius_j : float or None
        Sphere radii of this contact [m] (None for other shapes).
    zeta_n, zeta_s : float or None
        Damping ratio per direction as the damping convention defines it (``zeta_s`` None: no
        tangential spring).
    convention : str or None
        The damping convention (``dtcrit.scenes.damping_input``).
    wall : str or None
        The wall's name for a particle-wall contact.
    wall_number : int or None
        The wall's number, counted from 1.
    e_star, g_star : float or None
        Hertz: effective Young's and shear moduli [Pa].
    r_star : float or None
        Hertz: effective radius [m].
    delta_max : float or None
        Hertz: largest overlap [m].
    velocity : float or None
        Hertz: impact speed [m/s].
    kr, ktw : float
        Rolling / twisting spring [N m/rad] (``dtcrit.scenes.rotational``).
    cr, ctw : float
        Rolling / twisting dashpot [N m s/rad].
    """

    i: int  # particle numbers, counted from 1
    j: int
    m_star: float  # m_i m_j / (m_i + m_j) [kg]
    kn: float  # [N/m]
    ks: float
    cn: float  # [N s/m]
    cs: float
    zeta: float | None  # the damping ratio the user gave (None when given as coefficients)
    radius_i: float | None = None  # sphere radii of this contact [m] (None for other shapes)
    radius_j: float | None = None
    zeta_n: float | None = None  # damping ratio per direction as the damping convention defines it
    zeta_s: float | None = None  # (None: no tangential spring)
    convention: str | None = None  # the damping convention (dtcrit.physics.damping_conventions)
    wall: str | None = None  # the wall's name for a particle-wall contact (then j == 0)
    wall_number: int | None = None
    e_star: float | None = None  # Hertz: effective modulus [Pa]
    g_star: float | None = None  # Hertz: effective shear modulus [Pa]
    r_star: float | None = None  # Hertz: effective radius [m]
    delta_max: float | None = None  # Hertz: largest overlap [m]
    velocity: float | None = None  # Hertz: impact speed [m/s]
    kr: float = 0.0  # rolling spring [N m/rad] (dtcrit.scenes.rotational)
    ktw: float = 0.0  # twisting spring [N m/rad]
    cr: float = 0.0  # rolling dashpot [N m s/rad]
    ctw: float = 0.0  # twisting dashpot [N m s/rad]

    @property
    def rotational(self) -> bool:
        """Whether the contact has rotational springs or dashpots."""
        return any(v > 0 for v in (self.kr, self.ktw, self.cr, self.ctw))

    @property
    def label(self) -> str:
        """``"i-j"``, or ``"i-wallN"`` against wall N."""
        return f"{self.i}-wall{self.wall_number}" if self.wall is not None else f"{self.i}-{self.j}"


@dataclass(frozen=True)
class Particle:
    """One particle type of a scene: its shape object and (optional) elastic constants.

    Parameters
    ----------
    number : int
        Position of the ``[[particle]]`` table, counted from 1.
    kind : str
        Shape kind (``"sphere"``, ``"ellipsoid"``, ``"clump"``, ...).
    dimensions : dict
        The dimension entries as given (validated).
    shape : object
        A ``dtcrit.bodies`` object (for a size distribution: its smallest sphere).
    youngs_modulus : float or None
        Young's modulus [Pa] (Hertz contacts).
    poisson_ratio : float or None
        Poisson's ratio (Hertz contacts).
    name : str
        The particle type's name.
    sizes : dtcrit.scenes.sizes.SizeDistribution, optional
        Spheres: the radii of the type.
    shapes : sequence
        Spheres: one body per radius of ``sizes``.
    """

    number: int  # counted from 1
    kind: str
    dimensions: dict  # the dimension entries as given (validated)
    shape: Any  # a dtcrit.bodies object (for a size distribution: its smallest sphere)
    youngs_modulus: float | None
    poisson_ratio: float | None
    name: str
    sizes: Any = None  # spheres: a dtcrit.scenes.sizes.SizeDistribution
    shapes: Any = ()  # spheres: one Sphere per radius of ``sizes`` (a SizeShapes: built when first used)

    @property
    def mass(self) -> float:
        """Mass of the type's shape [kg] (the smallest sphere of a size distribution)."""
        return self.shape.mass

    @property
    def radii(self) -> tuple[float, ...]:
        """The sphere radii evaluated (ascending); empty for other shapes."""
        return self.sizes.radii if self.sizes is not None else ()

    def shape_at(self, radius: float | None):
        """The body at ``radius`` (spheres of a size distribution), else the one shape.

        Parameters
        ----------
        radius : float or None
            One of the distribution's radii [m]; None for the type's shape.

        Returns
        -------
        object
            The ``dtcrit.bodies`` object.
        """
        if radius is None or not len(self.shapes):
            return self.shape
        k = bisect.bisect_left(self.radii, radius)  # the radii are ascending
        if k == len(self.radii) or self.radii[k] != radius:
            raise ValueError(f"radius {radius!r} is not one of the distribution's")
        return self.shapes[k]

    def mass_at(self, radius: float | None) -> float:
        """Mass of the body at ``radius`` [kg].

        Parameters
        ----------
        radius : float or None
            One of the distribution's radii [m]; None for the type's shape.

        Returns
        -------
        float
            The mass.
        """
        return self.shape_at(radius).mass

    def describe(self) -> str:
        """One line for the text report: the dimensions as given and the mass.

        Returns
        -------
        str
            The description.
        """
        if self.kind == "clump":
            return f"clump ({len(self.dimensions['spheres'])} spheres, overlaps counted once), mass {self.shape.mass:.6g} kg"
        dims = ", ".join(f"{k} = {_fmt_dim(v)}" for k, v in self.dimensions.items() if k != "vertices")
        if "vertices" in self.dimensions:
            corners = len(self.shape.vertices)
            given = len(self.dimensions["vertices"])
            dims = f"{corners} vertices" + ("" if corners == given else f" ({given} points given)")
        if self.sizes is not None and self.sizes.kind != "single":
            masses = f"masses {self.shapes[0].mass:.6g}..{self.shapes[-1].mass:.6g} kg"
            return f"{self.kind} ({self.sizes.describe()}), {masses}"
        return f"{self.kind} ({dims}), mass {self.shape.mass:.6g} kg"


def _fmt_dim(v) -> str:
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(f"{x:g}" for x in v) + "]"
    return f"{v:g}"


@dataclass(frozen=True)
class ContactLaw:
    """The ``[contact]`` table after validation.

    Parameters
    ----------
    model : str
        ``"linear"``, ``"yade"``, ``"hertz"`` or ``"bond"``.
    kn, ks : float or None
        Normal / tangential spring [N/m].
    cn, cs : float or None
        Given normal / tangential dashpot [N s/m] (linear only).
    restitution : float or None
        Coefficient of restitution, when given.
    damping_ratio : float or None
        Damping ratio, given or derived from the restitution.
    velocity : float or None
        Hertz: impact speed [m/s].
    curvature_radius : float or None
        Hertz: effective radius of curvature [m], when given.
    damping_convention : str or None
        The damping convention (None: the model's default, ``dtcrit.scenes.damping_input``).
    ks_ratio : float or None
        YADE: ``ks/kn``.
    rotational : dtcrit.scenes.rotational.RotationalLaw, optional
        Rolling and twisting springs (None: none).
    bond : dtcrit.scenes.bonds.BondLaw, optional
        The bond of ``model = "bond"``.
    damping_coefficient : float or None
        Hertz under ``lammps-viscoelastic`` / ``lammps-mass-velocity``: LAMMPS's ``eta_n0`` [1/(m s)] / [1/s]
        (``dtcrit.scenes.law_damping``).
    tangential_damping_factor : float or None
        Hertz under a law convention: ``c_s/c_n`` (LAMMPS ``x_gammat``; ``dtcrit.scenes.law_damping``).
    friction : float or None
        The Coulomb coefficient ``[contact] friction``, when given (not in the step; ``dtcrit collide``'s
        oblique impacts use it).
    """

    model: str  # linear | yade | hertz
    kn: float | None = None
    ks: float | None = None
    cn: float | None = None  # given coefficients (linear only)
    cs: float | None = None
    restitution: float | None = None
    damping_ratio: float | None = None  # given, or derived from restitution
    velocity: float | None = None
    curvature_radius: float | None = None
    damping_convention: str | None = None  # None: the model's default (dtcrit.physics.damping_conventions)
    ks_ratio: float | None = None  # yade: ks / kn
    rotational: Any = None  # dtcrit.scenes.rotational.RotationalLaw (None: no rotational springs)
    bond: Any = None  # dtcrit.scenes.bonds.BondLaw for model = "bond"
    damping_coefficient: float | None = None  # hertz, law conventions taking eta_n0 (dtcrit.scenes.law_damping)
    tangential_damping_factor: float | None = None  # hertz, law conventions: c_s/c_n
    friction: float | None = None  # [contact] friction: dtcrit.scenes.collide_oblique

    @property
    def damping(self) -> str:
        """How damping was given: none | coefficients | restitution | damping_ratio | coefficient (``eta_n0``)."""
        if self.damping_coefficient is not None:
            return "coefficient"
        return damping_kind(self.restitution, self.damping_ratio, self.cn, self.cs)

    @property
    def damped(self) -> bool:
        """Whether the law has any damping (coefficients, or a positive damping ratio)."""
        if self.damping == "coefficients":
            return True
        if self.damping == "coefficient":
            return (self.damping_coefficient or 0.0) > 0.0
        return (self.damping_ratio or 0.0) > 0.0


@dataclass(frozen=True)
class Scene:
    """A validated scene (see module docstring); build with :func:`load_scene` or :func:`parse_scene`.

    Parameters
    ----------
    source : str
        Path of the scene file (or a label for a scene given as text).
    integrator : str
        Name of the scheme.
    particles : tuple of Particle
        The particle types.
    contact : ContactLaw
        The contact law.
    omega_max : float, optional
        Largest angular speed [rad/s] (enables the rotation-dominant bound).
    safety : float
        Factor applied to the critical step for the recommended step.
    pairs : str
        ``"all"`` or ``"unlike"``: which pairs of types can touch.
    title : str, optional
        The scene's title.
    warnings : tuple of tuple of str
        ``(key, message)`` warnings found while validating.
    walls : tuple of dtcrit.scenes.walls.Wall
        The fixed walls.
    coordination_max : int, optional
        Given largest number of contacts of a particle.
    overlap_max : float
        Largest overlap in a packing, as a fraction of ``R_i + R_j``.
    isolated : bool
        The headline is the isolated-contact step (else the step for any packing).
    local_damping : tuple of (float, str) or None
        Local (Cundall) damping ``(alpha, law)``: the step times ``1/sqrt(1 + alpha)``
        (:mod:`dtcrit.scenes.local_damping`).
    collision_v_max : float or None
        The ``[collision]`` table's ``v_max``: the largest impact speed [m/s] ``dtcrit collide`` resolves
        (:mod:`dtcrit.scenes.collide`).
    collision_angle : tuple of (str, float) or None
        The ``[collision]`` table's obliquity: the key given (``collision.angle_deg`` or
        ``collision.tangential_ratio``) and the impact's angle from the normal [deg]
        (:mod:`dtcrit.scenes.collide_oblique`).
    """

    source: str
    integrator: str
    particles: tuple[Particle, ...]
    contact: ContactLaw
    omega_max: float | None = None
    safety: float = 1.0
    pairs: str = "all"
    title: str | None = None
    warnings: tuple[tuple[str, str], ...] = field(default_factory=tuple)
    walls: tuple = ()  # dtcrit.scenes.walls.Wall
    coordination_max: int | None = None
    overlap_max: float = 0.05  # largest overlap in a packing, as a fraction of R_i + R_j (the dense sphere bound)
    isolated: bool = False  # the headline is the isolated-contact step (else the step for any packing)
    local_damping: tuple[float, str] | None = None  # (alpha, law): dtcrit.scenes.local_damping
    collision_v_max: float | None = None  # [collision] v_max [m/s]: dtcrit.scenes.collide
    collision_angle: tuple[str, float] | None = None  # [collision] angle_deg/tangential_ratio: scenes.collide_oblique

    @property
    def identical(self) -> bool:
        """One particle type (a single ``[[particle]]`` table) of one size."""
        return len(self.particles) == 1 and len(self.particles[0].radii) <= 1

    def pair_numbers(self) -> tuple[tuple[int, int], ...]:
        """The pairs of particle types that can touch: every ``(i, j)`` with ``i <= j``
        (``pairs = "all"``), or only ``i < j`` (``pairs = "unlike"``).

        Returns
        -------
        tuple of tuple of int
            The pairs of particle numbers (counted from 1).
        """
        n = len(self.particles)
        if self.pairs == "unlike" and n > 1:
            return tuple((i, j) for i in range(1, n + 1) for j in range(i + 1, n + 1))
        return tuple((i, j) for i in range(1, n + 1) for j in range(i, n + 1))

    def particle(self, number: int) -> Particle:
        """The particle type with the given number.

        Parameters
        ----------
        number : int
            Particle number, counted from 1.

        Returns
        -------
        Particle
            The type.
        """
        return self.particles[number - 1]


def _harmonic(x: float, y: float) -> float:
    """The harmonic product x y / (x + y) without overflow: 1 / (1/x + 1/y) for positive finite x, y."""
    return x / (1.0 + x / y) if x <= y else y / (1.0 + y / x)
