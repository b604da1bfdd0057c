"""The scene-key registry: every key of a scene file, per table, with what it means.

The key lists are the parsers' own (``dtcrit.scenes.model.TOP_KEYS``, ``CONTACT_KEYS``,
``dtcrit.bodies.spec.PARTICLE_ALL``, ``dtcrit.scenes.walls.WALL_KEYS``, ...), read here, so a key a
parser accepts is in the registry; :func:`scene_tables` refuses to build it when a key has no
description.  The descriptions are the "meaning" columns of the scene-key tables; the reference
page of the documentation (``docs/_ext/dtcrit_docs.py``) is generated from :func:`scene_tables`.
"""
from __future__ import annotations

from dataclasses import dataclass

from dtcrit.bodies.spec import PARTICLE_ALL, PARTICLE_COMMON, SHAPE_KEYS, SPHERE_SIZE_KEYS
from dtcrit.integrators import user_rules
from dtcrit.scenes import local_damping
from dtcrit.scenes.model import COLLISION_KEYS, CONTACT_ALL, CONTACT_KEYS, TOP_KEYS
from dtcrit.scenes.sizes import LOGNORMAL_KEYS
from dtcrit.scenes.walls import KEY_DESCRIPTIONS as WALL_DESCRIPTIONS, WALL_KEYS

__all__ = ["SceneKey", "SceneTable", "scene_tables", "bodies_file_tables", "DESCRIPTIONS", "BODIES_DESCRIPTIONS"]

_TOP = {
    "integrator": "the time integrator: a scheme of ``dtcrit.integrators.schemes`` (``velocity-verlet``, "
                  "``velocity-verlet-predicted``, ``leapfrog``, ``leapfrog-centred``, ``symplectic-euler``, "
                  "``forward-euler``, ``paper-eq40``, ``extended-taylor``, ``adams-bashforth-2``), a DEM code's "
                  "name (``\"chrono\"``, ``\"yade\"``, ...: see the code-to-integrator table), or an "
                  "``[integrator]`` table of update rules (required)",
    "omega_max": "largest particle angular speed [rad/s] (> 0); without it the rotation-dominant bound "
                 "(Peng et al. 2020, Eqs. (54), (56)-(57)) is not evaluated",
    "safety": "safety factor in [1e-6, 1] [-], default 1: the recommended step is ``safety * dt_crit``",
    "pairs": "``\"all\"`` (every pair of particle types i <= j touches; default) or ``\"unlike\"`` (only i < j)",
    "title": "a label printed with the result",
    "coordination_max": "the largest number of contacts a particle can have (a positive whole number; 12 is the "
                        "kissing number of equal spheres).  With it ``dt_crit`` holds for any packing of these "
                        "particles with at most that many contacts each; without it, for any packing at all (the "
                        "largest coordination the shapes and sizes allow)",
    "overlap_max": "the largest overlap in the packing as a fraction of ``R_i + R_j`` [-] (default 0.05), an "
                   "assumption of the packing bounds (other shapes: the particles shrunk by ``1 - overlap_max`` "
                   "about their centres do not overlap)",
    "isolated": "``true``: ``dt_crit`` is the isolated-contact step (two particles alone), not safe in a packing; "
                "default ``false``.  Not together with ``coordination_max``",
    "particle": "one or more ``[[particle]]`` tables: the particle types (required)",
    "contact": "the ``[contact]`` table: the contact law between particles (required)",
    "wall": "``[[wall]]`` tables: fixed walls and their contact law with the particles",
    "collision": "the ``[collision]`` table, read by ``dtcrit collide``",
    "local_damping": local_damping.KEYS["local_damping"] + " (YADE ``NewtonIntegrator.damping``, PFC ``damp``); "
                     "leapfrog only, without dashpots or ``omega_max``",
    "local_damping_law": "with ``local_damping``: " + local_damping.KEYS["local_damping_law"],
}

_PARTICLE = {
    "shape": "``sphere``, ``ellipsoid``, ``superquadric``, ``box``, ``polyhedron`` or ``clump`` (required)",
    "radius": "sphere radius R [m]",
    "radii": "a discrete size distribution: the radii [m], with ``fractions``.  For linear and YADE laws "
             "(without rotational springs, bonds or given YADE dashpots) the smallest and largest radius of each "
             "type carry every extreme; otherwise every pair of sizes is evaluated, at most 5000 pairs",
    "fractions": "the number fractions of ``radii`` [-] (summing to 1)",
    "lognormal": "a lognormal size distribution, the table ``{median, sigma, min, max}``: 33 log-spaced radii "
                 "between the cut-offs",
    "semi_axes": "``[a, b, c]`` [m], largest first (a >= b >= c, the paper's assumption 3)",
    "exponents": "``[eps1, eps2]`` in [0.01, 2] (convex) [-]; surface "
                 "``(abs(x/a)^(2/eps2) + abs(y/b)^(2/eps2))^(eps2/eps1) + abs(z/c)^(2/eps1) = 1``",
    "half_lengths": "``[a, b, c]`` [m], largest first",
    "vertices": "``[[x, y, z], ...]`` [m]: at least 4 points of a convex, centrally symmetric polyhedron "
                "(any frame)",
    "spheres": "``[[x, y, z, r], ...]`` [m]: the member spheres in the body frame; mass, centre and inertia of "
               "the union with overlaps counted once; ``A_bound`` uses ``r_max^2/I_min``",
    "density": "density [kg/m^3]; exactly one of ``density`` and ``mass`` (a size distribution needs the density)",
    "mass": "mass [kg]; exactly one of ``density`` and ``mass``",
    "youngs_modulus": "Young's modulus [Pa] (optional; needed for Hertz contact and the Rayleigh-time estimate, "
                      "may be given in ``[contact]`` instead)",
    "poisson_ratio": "Poisson's ratio [-] (-1 < nu < 0.5; optional, as ``youngs_modulus``)",
    "name": "optional label",
}

_LOGNORMAL = {
    "median": "median radius [m]",
    "sigma": "standard deviation of ln R [-] (0 allowed)",
    "min": "smallest radius kept (lower cut-off) [m]",
    "max": "largest radius kept (upper cut-off) [m]",
}

_CONTACT = {
    "model": "``linear``, ``yade``, ``hertz`` or ``bond``",
    "kn": "normal stiffness [N/m] (linear: required; bond: the bond's normal spring, LAMMPS bpm/rotational K_r)",
    "ks": "tangential stiffness [N/m]; ``ks = 0`` is frictionless (a tangential dashpot without spring is "
          "allowed); ``ks > kn`` is accepted with a warning (bond: K_s)",
    "ks_ratio": "``ks/kn`` [-] (YADE's ``FrictMat.poisson``); ``kn = 2 E1 R1 E2 R2/(E1 R1 + E2 R2)`` per contact "
                "(Ip2_FrictMat_FrictMat_FrictPhys), spheres only",
    "cn": "normal viscous damping coefficient [N s/m] (default 0)",
    "cs": "tangential viscous damping coefficient [N s/m] (default 0)",
    "restitution": "restitution coefficient e in (0, 1] [-]: damping ratio "
                   "``zeta = -ln e / sqrt(pi^2 + ln^2 e)``, mapped per direction by ``damping_convention``",
    "damping_ratio": "damping ratio zeta >= 0 [-], mapped per direction by ``damping_convention``",
    "damping_convention": "how ``restitution`` / ``damping_ratio`` become dashpots: ``lammps`` (default for "
                          "linear), ``liggghts`` (default for hertz), ``edem`` (hertz only), ``mercurydpm``, "
                          "``yade`` (default for yade), ``pfc`` (default for bond); for hertz also one code's "
                          "own damping law: ``lammps-tsuji``, ``lammps-tsuji-2021``, ``lammps-coeff-restitution``, "
                          "``lammps-viscoelastic``, ``lammps-mass-velocity``, ``yade-mindlin`` (see the collide "
                          "how-to, Damping laws of Hertz contacts)",
    "damping_coefficient": "LAMMPS ``eta_n0`` of ``lammps-viscoelastic`` [1/(m s)] (F = eta_n0 a m* delta') or of "
                           "``lammps-mass-velocity`` [1/s] (F = eta_n0 m* delta'); not together with ``restitution``",
    "tangential_damping_factor": "c_t/c_n [-]: LAMMPS ``x_gammat`` (required for the ``lammps-*`` damping "
                                 "laws), MercuryDPM's slidingDissipation/dissipation (default 2/7); refused "
                                 "for ``yade-mindlin``",
    "youngs_modulus": "Young's modulus [Pa]: one number for all particle types or an array with one entry per "
                      "``[[particle]]`` table (hertz, yade; linear: optional)",
    "poisson_ratio": "Poisson's ratio [-]: one number or an array with one entry per ``[[particle]]`` table",
    "velocity": "impact (characteristic) relative speed v [m/s] at whose largest overlap the Hertz law is "
                "linearised",
    "friction": "friction coefficient [-]: accepted with a note by ``dtcrit step`` (it caps a sliding "
                "contact's tangential force and does not enter the sticking linear step); ``dtcrit collide`` "
                "uses it for oblique impacts",
    "curvature_radius": "effective radius R* of the stiffest contact [m]; implied ``R1 R2/(R1 + R2)`` for "
                        "spheres, required otherwise",
    "kr": "rolling spring [N m/rad] on the relative rotation perpendicular to the normal",
    "ktw": "twisting spring [N m/rad] on the relative rotation about the normal",
    "cr": "rolling dashpot [N m s/rad]",
    "ctw": "twisting dashpot [N m s/rad]",
    "rolling_model": "a code's own rolling model instead of ``kr``, ``cr``: ``epsd`` (LIGGGHTS "
                     "``k_r = 2.25 k_n mu_r^2 R*^2``), ``epsd2`` (``k_r = k_t R*^2``), ``epsd3`` "
                     "(``k_r = f k_n mu_r^2 R*^2``), ``sds`` (LAMMPS ``granular``: ``k_roll R*^2``), ``yade`` "
                     "(Ip2_CohFrictMat_CohFrictMat_CohFrictPhys: ``k_r = alpha_kr k_s R1 R2``)",
    "rolling_friction": "rolling friction coefficient mu_r [-] (``epsd``, ``epsd3``)",
    "rolling_viscous_damping": "rolling viscous damping eta_r [-]: ``c_r = eta_r 2 sqrt(I_r k_r)`` (``epsd``, "
                               "``epsd3``)",
    "rolling_stiffness_factor": "factor f [-] of ``epsd3``: ``k_r = f k_n mu_r^2 R*^2``",
    "k_roll": "rolling stiffness of LAMMPS's ``sds`` rolling model [N/m]: ``k_r = k_roll R*^2``",
    "gamma_roll": "rolling damping of LAMMPS's ``sds`` rolling model [N s/m]: ``c_r = gamma_roll R*^2``",
    "alpha_kr": "YADE's ``alphaKr`` [-]: ``k_r = alpha_kr k_s R1 R2`` (``rolling_model = \"yade\"``)",
    "alpha_ktw": "YADE's ``alphaKtw`` [-]: ``k_tw = alpha_ktw k_s R1 R2`` (``rolling_model = \"yade\"``)",
    "twisting_model": "``marshall`` (LAMMPS: ``k_tw = k_t a^2/2``, ``c_tw = eta_t a^2/2``, "
                      "``a = sqrt(R* delta_max)`` for Hertz, else ``contact_radius``) or ``sds`` "
                      "(``k_twist``, ``gamma_twist``)",
    "k_twist": "twisting stiffness of the ``sds`` twisting model [N m/rad]",
    "gamma_twist": "twisting damping of the ``sds`` twisting model [N m s/rad]",
    "contact_radius": "contact radius a [m] of the ``marshall`` twisting model for non-Hertz contacts",
    "bond_youngs_modulus": "the bond's Young's modulus E [Pa] (PFC linear parallel bond: ``kn_bar = E/L``)",
    "bond_shear_modulus": "the bond's shear modulus G [Pa]: ``ks_bar = G/L``",
    "bond_poisson_ratio": "the bond's Poisson's ratio [-]: ``G = E/(2 (1 + nu))``",
    "bond_stiffness_ratio": "the bond's stiffness ratio kappa [-]: ``ks_bar = kn_bar/kappa``",
    "bond_radius": "the bond's radius r [m]: ``A = pi r^2``, ``I = pi r^4/4``, ``J = pi r^4/2``; "
                   "``kn = kn_bar A``, ``ks = ks_bar A``, ``kr = kn_bar I``, ``ktw = ks_bar J``",
    "bond_length": "the bond's length L [m]",
    "contact_kn": "normal stiffness [N/m] of the grains' own contact, in parallel with the bond",
    "contact_ks": "tangential stiffness [N/m] of the grains' own contact, in parallel with the bond",
}

_WALL = {
    "name": "optional label",
    "particles": "the particle types (numbers, counted from 1) that touch the wall (default: all)",
    "model": WALL_DESCRIPTIONS["model"],
    "restitution": "restitution coefficient e in (0, 1] [-], as in ``[contact]``",
    "damping_ratio": "damping ratio zeta >= 0 [-], as in ``[contact]``",
}

_COLLISION = {
    "v_max": "the largest impact speed [m/s] whose collisions the step must resolve (``dtcrit collide``; "
             "default: a Hertz law's ``[contact] velocity``; optional when an angle key is given)",
    "angle_deg": "the impact's angle from the contact normal [degrees] in [0, 90); above 0 ``dtcrit collide`` "
                 "resolves oblique impacts of equal spheres (``--angle`` overrides it); not with "
                 "``tangential_ratio``",
    "tangential_ratio": "v_t/v_n at entry [-] (>= 0): the oblique request given as a ratio; not with "
                        "``angle_deg``",
}

_INTEGRATOR = {
    "name": "the scheme's name (letters, digits, ``_.-``)",
    "state": "the state variables, position first, then velocity, then any history variables "
             "(e.g. ``[\"x\", \"v\"]``)",
    "update": "the update rules in order (e.g. ``[\"v = v + h*f(x, v)\", \"x = x + h*v\"]``); later rules see "
              "updated values; read with Python's ``ast`` against an allow-list (numbers, ``+ - * /``, "
              "``h``, ``f(...)``)",
}


_BODIES_TOP = {
    "schema": "``\"dtcrit-bodies/1\"`` (required)",
    "box": "the simulation box, or null for none",
    "bodies": "the bodies, one object each (required)",
    "contacts": "optional: each touching pair's springs; every listed pair must touch and every touching pair "
                "must be listed (``kn = ks = 0`` leaves one out).  Without it ``--kn``/``--ks`` (or ``--youngs``) apply",
}
_BODIES_BOX = {
    "lo": "lower corner ``[x, y, z]`` [m]",
    "hi": "upper corner ``[x, y, z]`` [m]",
    "periodic": "per axis, whether the box is periodic ``[bool, bool, bool]``",
}
_BODIES_BODY = {
    "id": "a distinct integer: the body's name in messages and contacts",
    "shape": "the body's shape: the keys of a scene's ``[[particle]]`` table (below), one particle",
    "position": "``[x, y, z]`` [m]: the origin of the frame the shape's dimensions are given in (the centre of a "
                "sphere, ellipsoid, superquadric or box; the origin of a polyhedron's ``vertices`` or a clump's "
                "``spheres``)",
    "orientation": "optional unit quaternion ``[qw, qx, qy, qz]`` [-], body to world (``v_world = R(q) v_body``, "
                   "Peng et al. 2020, Eq. (7)); default ``[1, 0, 0, 0]``",
}
_BODIES_CONTACT = {
    "id1": "the id of the first body",
    "id2": "the id of the second body",
    "kn": "normal stiffness of the contact [N/m]",
    "ks": "tangential stiffness of the contact [N/m]",
}
BODIES_DESCRIPTIONS: dict[str, dict[str, str]] = {
    "bodies-top": _BODIES_TOP, "bodies-box": _BODIES_BOX, "bodies-body": _BODIES_BODY, "bodies-contact": _BODIES_CONTACT,
}
"""Table anchor -> key -> description of a ``dtcrit-bodies/1`` file (``dtcrit packing BODIES.json``)."""


@dataclass(frozen=True)
class SceneKey:
    """One key of a scene table.

    Parameters
    ----------
    name : str
        The key as written in the scene file.
    description : str
        What it means, with its unit in brackets (``[-]`` dimensionless).
    applies : str
        Where it applies (``"all"`` or the shapes / contact models that accept it).
    """

    name: str
    description: str
    applies: str


@dataclass(frozen=True)
class SceneTable:
    """One table of a scene file and its keys.

    Parameters
    ----------
    name : str
        The table as written in TOML (``"top level"``, ``"[[particle]]"``, ...).
    anchor : str
        A short identifier for links (``"particle"``).
    keys : tuple of SceneKey
        Its keys, in the parser's order.
    applies_to : str
        What the ``applies`` column names (``"shapes"``, ``"models"``, or ``""`` for none).
    """

    name: str
    anchor: str
    keys: tuple[SceneKey, ...]
    applies_to: str = ""


DESCRIPTIONS: dict[str, dict[str, str]] = {
    "top": _TOP, "particle": _PARTICLE, "lognormal": _LOGNORMAL, "contact": _CONTACT, "wall": _WALL,
    "collision": _COLLISION, "integrator": _INTEGRATOR,
}
"""Table anchor -> key -> description (the ``[[wall]]`` keys not listed mean what they mean in ``[contact]``)."""


def _shapes_of(key: str) -> str:
    if key in PARTICLE_COMMON:
        return "all"
    shapes = [shape for shape, keys in SHAPE_KEYS.items() if key in dict(keys)]
    if key in SPHERE_SIZE_KEYS:
        shapes.append("sphere")
    return ", ".join(dict.fromkeys(shapes))


def _models_of(key: str) -> str:
    models = [model for model, keys in CONTACT_KEYS.items() if key in keys]
    return "all" if len(models) == len(CONTACT_KEYS) else ", ".join(models)


def _describe(anchor: str, key: str, fallback: dict[str, str] | None = None) -> str:
    for table in (DESCRIPTIONS.get(anchor) or BODIES_DESCRIPTIONS[anchor], WALL_DESCRIPTIONS if anchor == "wall" else {}, fallback or {}):
        if key in table:
            return table[key]
    raise KeyError(f"scene key {key!r} of table {anchor!r} has no description in dtcrit.scenes.keys")


def scene_tables() -> tuple[SceneTable, ...]:
    """Every table of a scene file with every key its parser accepts, each described.

    Returns
    -------
    tuple of SceneTable
        Top level, ``[[particle]]``, ``lognormal``, ``[contact]``, ``[[wall]]``, ``[collision]``,
        ``[integrator]``; the keys come from the parsers' key lists.

    Raises
    ------
    KeyError
        A key a parser accepts has no description here.

    Examples
    --------
    >>> tables = scene_tables()
    >>> [t.anchor for t in tables][:4]
    ['top', 'particle', 'lognormal', 'contact']
    >>> next(k for k in tables[3].keys if k.name == "ks_ratio").applies
    'yade'
    """
    def keys(anchor, names, applies=lambda key: "", fallback=None):
        return tuple(SceneKey(k, _describe(anchor, k, fallback), applies(k)) for k in names)

    return (
        SceneTable("top level", "top", keys("top", TOP_KEYS)),
        SceneTable("[[particle]]", "particle", keys("particle", PARTICLE_ALL, _shapes_of), "shapes"),
        SceneTable("[[particle]] lognormal = {...}", "lognormal", keys("lognormal", LOGNORMAL_KEYS)),
        SceneTable("[contact]", "contact", keys("contact", CONTACT_ALL, _models_of), "models"),
        SceneTable("[[wall]]", "wall", keys("wall", WALL_KEYS, fallback=_CONTACT)),
        SceneTable("[collision]", "collision", keys("collision", COLLISION_KEYS)),
        SceneTable("[integrator]", "integrator", keys("integrator", user_rules.KEYS)),
    )



def bodies_file_tables() -> tuple[SceneTable, ...]:
    """Every table of a ``dtcrit-bodies/1`` file (``dtcrit packing BODIES.json``) with every key its reader accepts.

    Returns
    -------
    tuple of SceneTable
        Top level, ``box``, ``bodies[]``, ``bodies[].shape`` (a ``[[particle]]`` table without size
        distributions or elastic constants) and ``contacts[]``, from the reader's key lists
        (``dtcrit.packing.readers.bodies_file``, ``bodies_array``).

    Raises
    ------
    KeyError
        A key the reader accepts has no description here.

    Examples
    --------
    >>> [t.name for t in bodies_file_tables()][:2]
    ['top level', 'box']
    """
    from dtcrit.packing.readers import bodies_array, bodies_file

    def keys(anchor, names, fallback=None, applies=lambda key: ""):
        return tuple(SceneKey(k, _describe(anchor, k, fallback), applies(k)) for k in names)

    shape_keys = tuple(k for k in PARTICLE_ALL if k not in bodies_array.REFUSED_SHAPE_KEYS)
    return (
        SceneTable("top level", "bodies-top", keys("bodies-top", bodies_file.TOP_KEYS)),
        SceneTable("box", "bodies-box", keys("bodies-box", bodies_file.BOX_KEYS)),
        SceneTable("bodies[]", "bodies-body", keys("bodies-body", bodies_array.BODY_KEYS)),
        SceneTable("bodies[].shape", "bodies-shape", keys("particle", shape_keys, None, _shapes_of), "shapes"),
        SceneTable("contacts[]", "bodies-contact", keys("bodies-contact", bodies_file.CONTACT_KEYS)),
    )
