"""The step estimates DEM codes use, evaluated for a scene beside its verified step (``dtcrit step``).

Rayleigh time and its fractions, Hertz contact duration and its fractions, damped collision time / 50,
the per-body diagonal-stiffness estimate of YADE/PFC, YADE's GlobalStiffnessTimeStepper as it runs
(``dtcrit.packing.bounds.yade_stepper``) and the paper's Eq. (46); the other formulas are
:mod:`dtcrit.physics.rules_of_thumb`.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.integrators.stability import paper_eq46
from dtcrit.physics import rules_of_thumb as rot
from dtcrit.physics.estimate import Estimate


def _min_or_none(values):
    vals = [v for v in values if v is not None]
    return min(vals) if vals else None


def _estimate(key: str, label: str, dt: float | None, note: str) -> Estimate:
    return Estimate(key, dt, "rule of thumb", note, label)


def scene_estimates(scene, steps) -> list[Estimate]:
    """The estimates DEM codes use, for this scene (smallest over particle types, sizes and pairs).

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The scene.
    steps : list of dtcrit.scenes.pair_modes.PairStep
        Its contacts' steps, wall contacts included.

    Returns
    -------
    list of Estimate
        One per rule of thumb; ``dt`` None with the reason in ``detail`` where one does not apply.
    """
    pairs = [s for s in steps if s.contact.wall is None]
    out = []
    parts = scene.particles
    elastic = all(p.youngs_modulus is not None and p.poisson_ratio is not None for p in parts)
    if elastic:
        t_r = min(rot.rayleigh_time(p.shape.equivalent_radius, p.shape.density, p.youngs_modulus, p.poisson_ratio) for p in parts)
        note = "R = equal-volume radius; smallest over particle types"
        out.append(_estimate("rayleigh", "Rayleigh time T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766)", t_r, note))
        for f in rot.RAYLEIGH_FRACTIONS:
            out.append(_estimate(f"rayleigh_{round(f * 100)}", f"{round(f * 100)} % of T_R (EDEM: 20 % at coordination >= 4, up to 40 % below)", f * t_r, note))
    else:
        why = "needs youngs_modulus and poisson_ratio for every particle type"
        out.append(_estimate("rayleigh", "Rayleigh time T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766)", None, why))
        for f in rot.RAYLEIGH_FRACTIONS:
            out.append(_estimate(f"rayleigh_{round(f * 100)}", f"{round(f * 100)} % of T_R (EDEM: 20 % at coordination >= 4, up to 40 % below)", None, why))

    hertz = [p.contact for p in pairs if p.contact.delta_max is not None]
    t_h = min(rot.hertz_contact_time(c.m_star, c.r_star, c.e_star, c.velocity) for c in hertz) if hertz else None
    why = ("m* = m1 m2/(m1 + m2); impact speed v of the scene" if hertz
           else "needs a Hertz contact (youngs_modulus, poisson_ratio, velocity)")
    out.append(_estimate("hertz_time", "Hertz contact duration 2.87 (m*^2/(R* E*^2 v))^(1/5) (LIGGGHTS, EDEM; "
                            "a duration, not a step: codes take a fraction of it)", t_h, why))
    for f in rot.HERTZ_FRACTIONS:
        out.append(_estimate(f"hertz_{round(f * 100)}", f"{round(f * 100)} % of the Hertz contact duration (LIGGGHTS "
                                "check/timestep/gran warns above the fraction its input sets, 10-20 %)",
                                None if t_h is None else f * t_h, why))

    t_c = [rot.damped_collision_time(p.contact.kn, p.contact.cn, p.contact.m_star) for p in pairs]
    t_c50 = _min_or_none(t_c)
    out.append(_estimate(
        "collision_time_50",
        "damped collision time / 50, t_c = pi/sqrt(kn/m* - (cn/(2 m*))^2), m* = m1 m2/(m1 + m2) (MercuryDPM, MFiX)",
        None if t_c50 is None else t_c50 / rot.COLLISION_TIME_DIVISOR,
        "normal direction" if t_c50 is not None else "not underdamped: no collision time",
    ))

    diag, gsts = [], []
    for p in steps:
        k_t = max(p.contact.kn, p.contact.ks)
        sides = [(p.contact.i, p.contact.radius_i)] + ([] if p.contact.wall else [(p.contact.j, p.contact.radius_j)])
        for n, radius in sides:
            part = scene.particle(n)
            s = part.shape_at(radius)
            k_rot = (p.contact.ks if part.kind == "sphere" else k_t) * s.max_arm**2
            diag.append(rot.diagonal_stiffness_step(s.mass, min(s.inertia), k_t, k_rot))
            gsts.append(_gsts_side(part.kind, s, p.contact))
    out.append(_estimate(
        "diagonal_stiffness",
        "per-body diagonal stiffness sqrt(2) sqrt(min(m/K_ii, I/K_rot_ii)) (YADE GlobalStiffnessTimeStepper, PFC; before their safety factor)",
        min(diag),
        "one contact per body: K_ii = max(kn, ks), K_rot_ii = k r_max^2 (ks for a sphere, whose normal force has no arm)",
    ))
    out.append(_estimate(
        "yade_gsts",
        "YADE GlobalStiffnessTimeStepper as it runs: 1.41044 x timestepSafetyCoefficient 0.8 x sqrt(min(m/K_ii, I/K_rot_ii))",
        _min_or_none(gsts) if None not in gsts else None,
        "its defaults; one contact per body, normal along the worst axis: K_ii = max(kn, ks), "
        "K_rot_ii = max(ks r^2 + kr, ktw), r the sphere's (a clump's largest member's) radius"
        if None not in gsts else "YADE's stepper reads sphere contacts: spheres and clumps of spheres only",
    ))

    eq46 = min(min([paper_eq46(p.contact.kn, p.contact.cn, p.A_max)]
                   + ([paper_eq46(p.contact.ks, p.contact.cs, p.A_max)] if p.contact.ks > 0 else [])) for p in pairs)
    out.append(_estimate("paper_eq46", "Peng et al. 2020, Eq. (46) with Eq. (26) A_max (as printed)", eq46,
                            "smallest over pairs and directions"))
    return [_finite(e) for e in out]


def _gsts_side(kind: str, shape, contact) -> float | None:
    """YADE's stepper on one side of a contact (``yade_stepper.single_contact_step``).

    The touching sphere's radius is the arm; None for shapes the stepper does not take.
    """
    if kind == "sphere":
        radius = shape.max_arm
    elif kind == "clump":
        radius = float(np.max(shape.spheres[:, 3]))
    else:
        return None
    from dtcrit.packing.bounds.yade_stepper import single_contact_step  # here: scenes without spheres skip it

    return single_contact_step(shape.mass, shape.inertia, contact.kn, contact.ks, contact.kr, contact.ktw, radius)


def _finite(e: Estimate) -> Estimate:
    """An estimate beyond the float64 range (m/k overflows for a subnormal stiffness) does not apply."""
    if e.dt is None or (math.isfinite(e.dt) and e.dt > 0):
        return e
    return _estimate(e.name, e.label, None, f"{e.dt!r} s: beyond the float64 range for this scene")
