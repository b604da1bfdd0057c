"""The API behind ``dtcrit step``: a scene -> its verified critical time step and what governs it.

For every pair of particle types that can touch (``Scene.pair_numbers``):

* translation (Peng et al. 2020, Sections 3-4): the contact ODE ``xddot = -k A x - c A xdot``
  (Eqs. (29)-(30)) per direction j = normal, shear with its own ``k_j`` and ``c_j``; ``A`` is
  ``dtcrit.bodies.contact.a_bound`` (a verified bound on the largest eigenvalue of the contact's 3x3
  coefficient matrix over all admissible contacts; the paper's printed Eq. (26) ``A_max`` is
  reported beside it).  ``dt_j = critical_dt(integrator, k_j, c_j, A)`` is the exact boundary of
  the integrator's amplification matrix; the pair's translation step is min over j.  (Every
  integrator's step is non-increasing in ``A``, so the bound on ``A`` gives a safe step for all
  contacts; with ``k_n >= k_s`` and equal damping the normal direction governs, as Eq. (48) takes.)
* rotation (Section 5, only when ``omega_max`` is given): ``dt = 2 / (omega_max (B_i + B_j))``,
  Eq. (56), with ``B`` of Eq. (54) (``dtcrit.bodies.contact.b_max``); over all pairs this is Eq. (57).

``dt_crit`` is the smallest of all of these; ``dt_recommended = safety * dt_crit``.  The
estimates DEM codes use (``dtcrit.scenes.estimators``) are computed beside it and flagged ``unsafe`` when
they exceed ``dt_crit``.  :meth:`StepResult.to_json` gives the stable, documented JSON form
(``README.md, section Scene files``).  No SymPy is imported here or below.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from dtcrit.scenes import estimators as est
from dtcrit.scenes.model import PairContact
from dtcrit.scenes.scene import Scene
from dtcrit.integrators.stability import critical_dt, paper_eq46

__all__ = ["DirectionStep", "PairStep", "StepResult", "critical_step", "JSON_SCHEMA"]

JSON_SCHEMA = "dtcrit-step/1"
UNSAFE_RTOL = 1e-9
"""An estimate is flagged unsafe when it exceeds dt_crit by more than this relative margin
(equal values, e.g. the paper's Eq. (46) for undamped spheres, are ties, not violations)."""

TRANSLATION_EQUATIONS = "Peng et al. 2020, Eqs. (26), (29)-(30); exact integrator boundary (amplification matrix, Jury conditions)"
ROTATION_EQUATIONS = "Peng et al. 2020, Eqs. (54), (56)-(57)"


@dataclass(frozen=True)
class DirectionStep:
    direction: str  # normal | shear
    k: float
    c: float
    zeta: float
    regime: str
    dt: float
    reason: str


@dataclass(frozen=True)
class PairStep:
    contact: PairContact
    A_max: float  # Eq. (26) as printed
    A_bound: float  # verified bound used for dt
    normal: DirectionStep
    shear: DirectionStep
    B_sum: float | None  # B_i + B_j (None without omega_max)
    dt_rotation: float | None  # None: no rotation bound (omega_max not given, or B_i + B_j = 0)

    @property
    def label(self) -> str:
        return self.contact.label

    @property
    def governing_direction(self) -> DirectionStep:
        return self.normal if self.normal.dt <= self.shear.dt else self.shear

    @property
    def dt_translation(self) -> float:
        return self.governing_direction.dt


@dataclass(frozen=True)
class EstimateResult:
    estimate: est.Estimate
    unsafe: bool | None  # None when the estimate does not apply


@dataclass(frozen=True)
class StepResult:
    scene: Scene
    pairs: tuple[PairStep, ...]
    dt_crit: float
    governing: str  # translation | rotation
    bound: str  # which bound, in words
    translation: PairStep  # the pair whose translation step is smallest
    rotation: PairStep | None  # the pair whose rotation step is smallest (None: no rotation bound)
    B_max: dict = field(default_factory=dict)  # particle number -> Eq. (54)
    estimates: tuple[EstimateResult, ...] = ()

    @property
    def dt_recommended(self) -> float:
        return self.scene.safety * self.dt_crit

    @property
    def formula(self) -> str:
        from dtcrit._generated.critical_steps import FORMULAS

        return FORMULAS[self.scene.integrator]

    def to_json(self) -> dict:
        """The documented JSON form (schema ``dtcrit-step/1``; see README.md, section Scene files)."""
        sc = self.scene
        t = self.translation
        g = t.governing_direction
        rot = None
        if sc.omega_max is not None:
            r = self.rotation
            rot = {
                "omega_max": sc.omega_max,
                "B_max": max(self.B_max.values()),
                "B_sum": None if r is None else r.B_sum,
                "pair": None if r is None else r.label,
                "dt": None if r is None else r.dt_rotation,
                "equations": ROTATION_EQUATIONS,
            }
        return {
            "schema": JSON_SCHEMA,
            "scene": sc.source,
            "title": sc.title,
            "integrator": sc.integrator,
            "dt_crit": self.dt_crit,
            "safety": sc.safety,
            "dt_recommended": self.dt_recommended,
            "governing": self.governing,
            "bound": self.bound,
            "formula": self.formula,
            "translation": {
                "A_max": t.A_max,
                "A_bound": t.A_bound,
                "dt": t.dt_translation,
                "pair": t.label,
                "direction": g.direction,
                "k": g.k,
                "c": g.c,
                "zeta": g.zeta,
                "regime": g.regime,
                "reason": g.reason,
                "equations": TRANSLATION_EQUATIONS,
            },
            "rotation": rot,
            "estimators": {
                e.estimate.key: {"dt": e.estimate.dt, "unsafe": e.unsafe, "label": e.estimate.label, "note": e.estimate.note}
                for e in self.estimates
            },
            "pairs": [_pair_json(p) for p in self.pairs],
            "particles": [_particle_json(p, self.B_max[p.number]) for p in sc.particles],
            "contact": _contact_json(sc),
            "warnings": [f"{k}: {m}" for k, m in sc.warnings],
        }


def _pair_json(p: PairStep) -> dict:
    c = p.contact
    out = {
        "pair": p.label,
        "m_star": c.m_star,
        "kn": c.kn,
        "ks": c.ks,
        "cn": c.cn,
        "cs": c.cs,
        "A_max": p.A_max,
        "A_bound": p.A_bound,
        "dt_normal": p.normal.dt,
        "dt_shear": p.shear.dt,
        "dt_translation": p.dt_translation,
        "B_sum": p.B_sum,
        "dt_rotation": p.dt_rotation,
    }
    if c.delta_max is not None:
        out.update(e_star=c.e_star, g_star=c.g_star, r_star=c.r_star, delta_max=c.delta_max, velocity=c.velocity)
    return out


def _particle_json(p, b_max: float) -> dict:
    s = p.shape
    return {
        "number": p.number,
        "name": p.name,
        "shape": p.kind,
        "mass": s.mass,
        "density": s.density,
        "inertia": list(s.inertia),
        "half_lengths": list(s.half_lengths),
        "max_arm": s.max_arm,
        "equivalent_radius": s.equivalent_radius,
        "B_max": b_max,
    }


def _contact_json(sc: Scene) -> dict:
    law = sc.contact
    out = {"model": law.model, "damping": law.damping, "damping_ratio": law.damping_ratio, "restitution": law.restitution}
    if law.model == "linear":
        out.update(kn=law.kn, ks=law.ks, cn=law.cn or 0.0, cs=law.cs or 0.0)
    else:
        out.update(velocity=law.velocity, curvature_radius=law.curvature_radius)
    return out


# ----------------------------------------------------------------------------------------------
def _direction(integrator: str, name: str, k: float, c: float, A: float) -> DirectionStep:
    r = critical_dt(integrator, k, c, A)
    return DirectionStep(name, k, c, r.zeta, r.regime, r.dt, r.reason)


def _pair_step(scene: Scene, i: int, j: int, b_max: dict) -> PairStep:
    from dtcrit.bodies import contact

    pc = scene.pair_contact(i, j)
    p1, p2 = scene.particle(i).shape, scene.particle(j).shape
    a_max = float(contact.a_max(p1, p2))
    a_bound = float(contact.a_bound(p1, p2))
    normal = _direction(scene.integrator, "normal", pc.kn, pc.cn, a_bound)
    shear = _direction(scene.integrator, "shear", pc.ks, pc.cs, a_bound)
    b_sum = dt_rot = None
    if scene.omega_max is not None:
        b_sum = b_max[i] + b_max[j]
        if b_sum > 0:
            dt_rot = 2.0 / (scene.omega_max * b_sum)  # Eq. (56)
            if not math.isfinite(dt_rot):
                dt_rot = None
    return PairStep(pc, a_max, a_bound, normal, shear, b_sum, dt_rot)


def critical_step(scene: Scene) -> StepResult:
    """Verified critical time step of ``scene`` (see the module docstring)."""
    from dtcrit.bodies import contact

    b_max = {p.number: float(contact.b_max(p.shape)) for p in scene.particles}
    pairs = tuple(_pair_step(scene, i, j, b_max) for i, j in scene.pair_numbers())
    t = min(pairs, key=lambda p: p.dt_translation)
    with_rot = [p for p in pairs if p.dt_rotation is not None]
    r = min(with_rot, key=lambda p: p.dt_rotation) if with_rot else None
    g = t.governing_direction
    if r is not None and r.dt_rotation < t.dt_translation:
        governing, dt = "rotation", r.dt_rotation
        bound = (f"rotation-dominant, pair {r.label}: dt = 2/(omega_max (B{r.contact.i} + B{r.contact.j})) "
                 f"= 2/({scene.omega_max:g} x {r.B_sum:.6g}) (Peng et al. 2020, Eqs. (54), (56))")
    else:
        governing, dt = "translation", t.dt_translation
        what = "no positive step is stable" if dt == 0.0 else f"exact '{scene.integrator}' boundary"
        bound = (f"translation-dominant, pair {t.label}, {g.direction} direction: {what} with k = {g.k:.6g} N/m, "
                 f"c = {g.c:.6g} N s/m, A = A_bound = {t.A_bound:.6g} 1/kg (zeta = {g.zeta:.6g}, {g.regime})")
    estimates = tuple(
        EstimateResult(e, None if e.dt is None else bool(e.dt > dt * (1.0 + UNSAFE_RTOL)))
        for e in scene_estimates(scene, pairs)
    )
    return StepResult(scene, pairs, dt, governing, bound, t, r, b_max, estimates)


# ----------------------------------------------------------------------------------------------
# Side-by-side estimates
# ----------------------------------------------------------------------------------------------
def _min_or_none(values):
    vals = [v for v in values if v is not None]
    return min(vals) if vals else None


def scene_estimates(scene: Scene, pairs: tuple[PairStep, ...]) -> list[est.Estimate]:
    """The estimates DEM codes use, for this scene (smallest over particle types / pairs)."""
    out = []
    parts = scene.particles
    elastic = all(p.youngs_modulus is not None and p.poisson_ratio is not None for p in parts)
    if elastic:
        t_r = min(est.rayleigh_time(p.shape.equivalent_radius, p.shape.density, p.youngs_modulus, p.poisson_ratio) for p in parts)
        note = "R = equal-volume radius; smallest over particle types"
        out.append(est.Estimate("rayleigh", "Rayleigh time T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766)", t_r, note))
        for f in est.RAYLEIGH_FRACTIONS:
            out.append(est.Estimate(f"rayleigh_{round(f * 100)}", f"{round(f * 100)} % of T_R (EDEM: 20 % at coordination >= 4, up to 40 % below)", f * t_r, note))
    else:
        why = "needs youngs_modulus and poisson_ratio for every particle type"
        out.append(est.Estimate("rayleigh", "Rayleigh time T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766)", None, why))
        for f in est.RAYLEIGH_FRACTIONS:
            out.append(est.Estimate(f"rayleigh_{round(f * 100)}", f"{round(f * 100)} % of T_R (EDEM: 20 % at coordination >= 4, up to 40 % below)", None, why))

    hertz = [p.contact for p in pairs if p.contact.delta_max is not None]
    if hertz:
        t_h = min(est.hertz_contact_time(c.m_star, c.r_star, c.e_star, c.velocity) for c in hertz)
        out.append(est.Estimate("hertz_time", "Hertz contact time 2.87 (m*^2/(R* E*^2 v))^(1/5) (LIGGGHTS, EDEM)", t_h,
                                "m* = m1 m2/(m1 + m2); impact speed v of the scene"))
    else:
        out.append(est.Estimate("hertz_time", "Hertz contact time 2.87 (m*^2/(R* E*^2 v))^(1/5) (LIGGGHTS, EDEM)", None,
                                "needs a Hertz contact (youngs_modulus, poisson_ratio, velocity)"))

    t_c = [est.damped_collision_time(p.contact.kn, p.contact.cn, p.contact.m_star) for p in pairs]
    t_c50 = _min_or_none(t_c)
    out.append(est.Estimate(
        "collision_time_50",
        "damped collision time / 50, t_c = pi/sqrt(kn/m* - (cn/(2 m*))^2), m* = m1 m2/(m1 + m2) (MercuryDPM, MFiX)",
        None if t_c50 is None else t_c50 / est.COLLISION_TIME_DIVISOR,
        "normal direction" if t_c50 is not None else "not underdamped: no collision time",
    ))

    diag = []
    for p in pairs:
        k_t = max(p.contact.kn, p.contact.ks)
        for n in (p.contact.i, p.contact.j):
            part = scene.particle(n)
            s = part.shape
            k_rot = (p.contact.ks if part.kind == "sphere" else k_t) * s.max_arm**2
            diag.append(est.diagonal_stiffness_step(s.mass, min(s.inertia), k_t, k_rot))
    out.append(est.Estimate(
        "diagonal_stiffness",
        "per-body diagonal stiffness sqrt(2) sqrt(min(m/K_ii, I/K_rot_ii)) (YADE GlobalStiffnessTimeStepper, PFC; before their safety factor)",
        min(diag),
        "one contact per body: K_ii = max(kn, ks), K_rot_ii = k r_max^2 (ks for a sphere, whose normal force has no arm)",
    ))

    eq46 = min(min(paper_eq46(p.contact.kn, p.contact.cn, p.A_max), paper_eq46(p.contact.ks, p.contact.cs, p.A_max)) for p in pairs)
    out.append(est.Estimate("paper_eq46", "Peng et al. 2020, Eq. (46) with Eq. (26) A_max (as printed)", eq46,
                            "smallest over pairs and directions"))
    return out
