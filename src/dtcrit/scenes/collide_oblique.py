"""Oblique impacts in ``dtcrit collide``: the tangential restitution and rebound spin of two equal spheres.

A scene asks for them with ``[collision] angle_deg`` (the impact's angle from the normal, in [0, 90)
degrees) or ``[collision] tangential_ratio`` (``v_t/v_n``, at least 0), not both; the flag ``--angle``
overrides either.  The impact has the relative speed ``v_max`` at that angle: ``v_n = v_max cos(angle)``
sets its contact time ``t_c(v_n) = t_c(v_max) cos(angle)^(-1/5)`` and its elastic peak overlap
``delta(v_max) cos(angle)^(4/5)`` (Hertz), ``v_t = v_max sin(angle)``.  The oblique core
(``collisions.oblique``) is Hertz + Mindlin with Coulomb's limit, for two equal spheres, stepped by the
velocity-Verlet map (LAMMPS, LIGGGHTS; leapfrog and symplectic Euler step the same positions); its
dimensionless inputs come from the scene: the friction ``[contact] friction``, Poisson's ratio (``k_t/k_n =
2 (1 - nu)/(2 - nu)``, as the scene's Mindlin spring), the radius of gyration ``I/(m R^2)`` of the
particle, the tangential over normal dashpot ``c_s/c_n`` and the peak overlap over the radius.  The
oblique resolution step is ``collisions.oblique_resolution``'s; the errors at the chosen step are
``oblique_errors``'s (worst entry phase, ``REPORT_PHASES`` sampled phases then optimised).

Refused in one line: an angle with walls, with a pair of unequal particle types, with a linear or YADE
law, without ``[contact] friction``, with a law keyed by its damping coefficient (its restitution changes
with the normal speed), with an integrator of another map, a sticking contact with the engine ``yade``
(its incremental shear law equals LAMMPS's history only while sliding), and a contact that changes between
sticking and sliding (``oblique_resolution.regime``: the continuum sticks or slides throughout; with a
normal dashpot the normal force reaches zero before the spheres separate, so a damped contact ends by
slipping, and it is accepted when that slip starts within the last 1 % of the contact, as
``reference_oblique`` accepts it).
"""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import NamedTuple

from dtcrit.collisions.oblique import SAME_MAP, ObliqueCase, oblique_case, oblique_errors
from dtcrit.collisions.oblique_resolution import ObliqueResolution, oblique_resolve, regime
from dtcrit.collisions.stepping import scheme_of
from dtcrit.errors import InputError
from dtcrit.inputs.values import number
from dtcrit.scenes.model import COLLISION_KEYS

__all__ = ["ANGLE_KEYS", "REPORT_PHASES", "parse_angle", "ObliqueRequest", "oblique_request", "ObliquePlan", "oblique_plan"]

ANGLE_KEYS = tuple(k for k in COLLISION_KEYS if k != "v_max")
"""The ``[collision]`` keys that ask for oblique impacts (one of them)."""
REPORT_PHASES = 16  # 8 missed the worst phase by 2 % (sliding at 60 deg, N ~ 9); 16 found it to 1e-9
MAX_OVERLAP_RATIO = 0.1  # the core's bound on delta/R
SAME = 1e-12  # relative difference below which two particle types are equal


def _check_angle(key: str, value) -> float:
    angle = number(key, value, allow_zero=True, hi=90.0, hi_open=True)
    return angle


def parse_angle(table: dict) -> tuple[str, float] | None:
    """The obliquity a ``[collision]`` table asks for.

    Parameters
    ----------
    table : dict
        The ``[collision]`` table.

    Returns
    -------
    tuple of (str, float) or None
        ``("collision.angle_deg" or "collision.tangential_ratio", angle in degrees)``, or None.

    Raises
    ------
    InputError
        Both keys, an angle outside [0, 90) degrees or a negative ratio.
    """
    given = [k for k in ANGLE_KEYS if k in table]
    if len(given) > 1:
        raise InputError("collision.tangential_ratio", "give the impact's obliquity once: angle_deg or tangential_ratio, not both")
    if not given:
        return None
    key = "collision." + given[0]
    if given[0] == "angle_deg":
        return key, _check_angle(key, table["angle_deg"])
    return key, math.degrees(math.atan(number(key, table["tangential_ratio"], allow_zero=True)))


def _equal(a, b) -> bool:
    if a is None or b is None:
        return a is b
    return abs(a - b) <= SAME * max(abs(a), abs(b))


class ObliqueRequest(NamedTuple):
    """An oblique impact asked for and checked against the scene.

    Parameters
    ----------
    key : str
        The key that set the angle (``"angle"`` for the flag, ``"collision.angle_deg"``, ...).
    angle_deg : float
        The angle from the normal [deg], in (0, 90).
    friction : float
        The Coulomb coefficient (``[contact] friction``).
    """

    key: str
    angle_deg: float
    friction: float


def oblique_request(scene, angle_deg: float | None = None) -> ObliqueRequest | None:
    """The oblique impact a ``dtcrit collide`` run asks for, checked against the scene (module docstring).

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The scene.
    angle_deg : float, optional
        The angle from the normal [deg] (the flag; overrides the scene's ``[collision]`` key).

    Returns
    -------
    ObliqueRequest or None
        The request, or None when no angle above zero is asked.

    Raises
    ------
    InputError
        One line naming what is not modelled (walls, unequal pairs, the law, no friction).
    """
    req = ("angle", _check_angle("angle", angle_deg)) if angle_deg is not None else scene.collision_angle
    if req is None or req[1] == 0.0:
        return None
    key, angle = req
    asked = f"{key} = {angle:g} deg"
    if scene.walls:
        raise InputError(f"wall[{scene.walls[0].number}]", f"an oblique impact ({asked}) is modelled for two "
                         "equal spheres, not against a wall")
    law = scene.contact
    if law.model != "hertz":
        raise InputError("contact.model", f"an oblique impact ({asked}) is modelled with a hertz law (Mindlin's tangential "
                         f"spring), not {law.model!r}")
    if getattr(law, "damping_coefficient", None):
        raise InputError("contact.damping_coefficient", f"an oblique impact ({asked}) under a law keyed by its "
                         "coefficient is not modelled: its restitution changes with the normal speed v_max cos(angle)")
    if not law.friction:
        raise InputError("contact.friction", f"an oblique impact ({asked}) needs the friction coefficient: give "
                         "[contact] friction > 0")
    for i, j in scene.pair_numbers():
        p, q = scene.particle(i), scene.particle(j)
        same = p.kind == q.kind == "sphere" and p.radii and q.radii and _equal(p.radii[0], q.radii[0]) and all(
            _equal(getattr(p, a), getattr(q, a)) for a in ("youngs_modulus", "poisson_ratio")) and _equal(
            p.mass_at(p.radii[0]), q.mass_at(q.radii[0]))
        if not same:
            raise InputError(f"particle[{j}]", f"pair {i}-{j}: an oblique impact ({asked}) is modelled for two equal spheres "
                             "(same radius, mass and elastic constants)")
    return ObliqueRequest(key, angle, float(law.friction))


@dataclass(frozen=True)
class ObliquePlan:
    """One pair's oblique impact: its case, its resolution step and how to report errors at a step.

    Parameters
    ----------
    key : str
        The key that asked for the angle.
    angle_deg : float
        The angle from the normal [deg].
    damping : str
        The normal law's damping key (``collisions.laws``).
    restitution : float
        The normal law's restitution.
    engine : str
        The engine or integrator.
    case : ObliqueCase
        The scaled impact.
    v_normal, v_tangential : float
        Entry speeds [m/s].
    t_c : float
        Elastic contact time at ``v_normal`` [s].
    resolution : ObliqueResolution
        Its resolution (``N_res`` per ``t_c``).
    """

    key: str
    angle_deg: float
    damping: str
    restitution: float
    engine: str
    case: ObliqueCase
    v_normal: float
    v_tangential: float
    t_c: float
    resolution: ObliqueResolution

    @property
    def dt_resolution(self) -> float:
        """The oblique resolution step [s]."""
        return self.t_c / self.resolution.steps_per_collision

    def report(self, dt: float) -> dict:
        """The ``oblique`` entry of a pair at the chosen step ``dt`` [s].

        Parameters
        ----------
        dt : float
            The chosen step [s].

        Returns
        -------
        dict
            See the schema ``dtcrit-collide-1.json``, ``oblique``.
        """
        c, n = self.case, self.t_c / dt
        errs = oblique_errors(engine=self.engine, normal="hertz", damping=self.damping, restitution=self.restitution,
                              friction=c.friction, tangential_ratio=c.tangential_ratio, steps_per_collision=n,
                              mode=self.resolution.mode, poisson=c.poisson, gyration=c.gyration,
                              gammat_ratio=c.gammat_ratio, overlap_ratio=c.overlap_ratio, phases=REPORT_PHASES)
        ref = self.resolution.reference
        return {
            "angle_deg": self.angle_deg, "tangential_ratio": c.tangential_ratio, "friction": c.friction,
            "regime": "sliding" if self.resolution.mode == "slide" else "sticking",
            "v_normal": self.v_normal, "v_tangential": self.v_tangential, "t_c": self.t_c,
            "poisson_ratio": c.poisson, "gyration": c.gyration, "tangential_damping_ratio": c.gammat_ratio,
            "overlap_ratio": c.overlap_ratio,
            "reference": {"restitution": float(ref.restitution), "tangential_restitution": float(ref.tangential_restitution),
                          "spin": float(ref.spin)},
            "dt_resolution": self.dt_resolution, "steps_resolution": self.resolution.steps_per_collision,
            "steps_per_collision": n,
            "errors_at_dt": {q: errs[q]["error"] for q in ("tangential_restitution", "spin")},
            "binding": dt >= self.dt_resolution * (1.0 - 1e-12),
        }


def _progress():
    from tqdm import tqdm

    # drawn on standard error, on a terminal only, once the search has run for 2 s
    return tqdm(desc="oblique impacts stepped", unit=" impacts", delay=2.0, file=sys.stderr, leave=False, disable=None)


def oblique_plan(request: ObliqueRequest, pc, p, *, damping: str, restitution: float, v: float, t_c: float,
                 peak: float, tol: float, engine: str) -> ObliquePlan:
    """The oblique impact of one pair of equal spheres and its resolution step (module docstring).

    Parameters
    ----------
    request : ObliqueRequest
        From ``oblique_request``.
    pc : dtcrit.scenes.model.PairContact
        The pair's contact (Hertz; its ``cs/cn`` is the tangential damping ratio).
    p : dtcrit.scenes.model.Particle
        The particle type (both spheres).
    damping, restitution : str, float
        The normal law's damping key and restitution (``collisions.laws.scaled_law``).
    v : float
        The impact speed [m/s].
    t_c, peak : float
        Elastic contact time [s] and peak overlap [m] of the head-on impact at ``v``.
    tol : float
        The tolerance.
    engine : str
        Engine or integrator.

    Returns
    -------
    ObliquePlan
        The pair's oblique impact and its resolution.

    Raises
    ------
    InputError
        An integrator of another map, a peak overlap beyond the core's range, stick-slip, no resolving step.
    """
    key, angle, friction = request
    if scheme_of(engine) not in SAME_MAP:
        raise InputError("integrator", f"an oblique impact ({key}) is modelled for {', '.join(SAME_MAP)}, not {engine!r}")
    cos = math.cos(math.radians(angle))
    radius = pc.radius_i
    ratio = peak * cos ** 0.8 / radius
    if not ratio < MAX_OVERLAP_RATIO:
        raise InputError("v_max", f"{pc.label}: the oblique impact's peak overlap is {ratio:.3g} of the radius; modelled "
                         f"below {MAX_OVERLAP_RATIO:g}")
    if pc.cn <= 0.0 < pc.cs:
        raise InputError("contact.damping_ratio", f"{pc.label}: a tangential dashpot without a normal one is not modelled")
    shape = p.shape_at(radius)
    case = oblique_case(normal="hertz", damping=damping, restitution=restitution, friction=friction,
                        tangential_ratio=math.tan(math.radians(angle)), poisson=p.poisson_ratio,
                        gyration=min(shape.inertia) / (shape.mass * radius * radius),
                        gammat_ratio=pc.cs / pc.cn if pc.cn > 0 else 0.0, overlap_ratio=ratio)
    if engine.lower().startswith("yade") and regime(case, key) == "stick":
        raise InputError("integrator", f"an oblique impact ({key} = {angle:g} deg) that sticks is not modelled for YADE: "
                         "its incremental shear law equals LAMMPS's history only while the contact slides")
    with _progress() as bar:
        res = oblique_resolve(case, tol, key, tick=bar.update)
    if not math.isfinite(res.steps_per_collision):
        raise InputError("tol", f"{pc.label}: no step resolves the oblique impact within {tol:g}; raise --tol")
    return ObliquePlan(key, angle, damping, restitution, engine, case, v * cos, v * math.sin(math.radians(angle)), t_c * cos ** -0.2, res)
