"""``dtcrit collide``'s report: per contact of a scene, the step that resolves its collision against the
linear stability step and the codes' rules.

Per pair of particle types (their smallest sizes) and per wall: the elastic contact time ``t_c``
(``contact_time``) and peak overlap at the largest impact speed, the linear stability step of the
scene's integrator at the tangent stiffness of that peak (``scenes.pair_modes.pair_step``), the
resolution step ``t_c/N_res`` (``resolution_step``), which of the two binds, the integrator's energy
verdict at the binding step (``collision_errors``'s ``energy_gain``), and the codes' rules
(``physics.collision_rules``) rated against the binding step.

The scene's damping maps to the collision core's keys: a linear law's constant dashpot is the
``hooke`` law with ``e = exp(-pi zeta/sqrt(1 - zeta^2))``, ``zeta = c_n/(2 sqrt(k_n m*))`` (any convention);
a Hertz law with the ``liggghts`` or ``edem`` convention (the same ``2 sqrt(5/6) beta sqrt(S_n m*)``
dashpot) is ``("hertz", "liggghts")`` with the scene's restitution; no damping is ``"none"``.
A Hertz law convention (``scenes.law_damping``: ``lammps-tsuji(-2021)``, ``lammps-coeff-restitution``,
``yade-mindlin``, ``mercurydpm`` with ``restitution``; ``lammps-viscoelastic``, ``lammps-mass-velocity`` with
``damping_coefficient``) is its own core law, keyed by ``e`` or, for a coefficient, by the continuum restitution
of the impact at ``v_max`` (``collisions.reference``); its dashpots scale to the peak overlap as ``delta^q``.
Other Hertz damping (``pfc``, coefficients) is refused in one line naming it.
"""
from __future__ import annotations

import math
from dataclasses import replace

from dtcrit.collisions import collision_errors, contact_time, reference_collision, resolution_step, step_collision
from dtcrit.collisions.resolution import check_tol
from dtcrit.collisions.stepping import scheme_of
from dtcrit.errors import InputError
from dtcrit.physics.collision_rules import code_rules
from dtcrit.scenes.collide_oblique import oblique_plan, oblique_request
from dtcrit.scenes.law_damping import LAW_CONVENTIONS, continuum_restitution, dashpot_exponent
from dtcrit.scenes.laws import resolve_pair, resolve_wall
from dtcrit.scenes.pair_modes import pair_step

__all__ = ["collide_report", "ENERGY_TOL"]

ENERGY_TOL = 1e-9
"""Relative exit-energy excess over the continuum's above which the integrator is said to gain energy."""
VERDICT_PHASES = 16


def _energy_verdict(engine: str, normal: str, damping: str, e: float, n: float, worst: float) -> str:
    """Whether the stepped impact at N = ``n`` leaves with more energy than the continuum's, over the entry phase."""
    if worst <= ENERGY_TOL:
        return "never gains energy"
    ref = reference_collision(normal=normal, damping=damping, restitution=e).energy_ratio
    every = all(step_collision(engine=engine, normal=normal, damping=damping, restitution=e, steps_per_collision=n,
                               phase=k / VERDICT_PHASES).energy_ratio > ref * (1.0 + ENERGY_TOL) for k in range(VERDICT_PHASES))
    return f"gains energy in {'every' if every else 'some'} entry phase{'' if every else 's'} (up to {worst:.2%})"


def _restitution_from_zeta(zeta: float, key: str) -> float:
    if zeta >= 1.0:
        raise InputError(key, f"normal damping ratio {zeta:.4g} >= 1: the contact does not rebound")
    return 1.0 if zeta <= 0.0 else math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta * zeta))


def _is_hertz(pc, wall) -> bool:
    return pc.delta_max is not None or (wall is not None and wall.model == "hertz")


def _law_key(scene, pc, wall, m_eff: float, hz: dict, v: float) -> tuple[str, str, float]:
    """(normal, damping, restitution) of the core under a law convention (``scenes.law_damping``).

    A law that takes ``e`` is keyed by it; one that takes ``eta_n0`` by its continuum restitution at ``v``.
    """
    law = LAW_CONVENTIONS[pc.convention]
    if law.takes == "restitution":
        e = (wall.restitution if wall is not None else scene.contact.restitution)
        return ("hertz", "none", 1.0) if e is None else ("hertz", law.core, e)
    coef = None if wall is not None else scene.contact.damping_coefficient
    if not coef:
        return "hertz", "none", 1.0
    r_star = pc.r_star if pc.r_star is not None else pc.radius_i
    e = continuum_restitution(pc.convention, restitution=None, coefficient=coef, m_eff=m_eff,
                              E_eff=hz["E_sqrtR"] / math.sqrt(r_star), R_eff=r_star, v=v)
    if not e > 0.0:
        raise InputError("contact.damping_coefficient", f"{pc.label}: with eta_n0 = {coef:g} the impact at {v:g} m/s does not "
                         "rebound (overdamped)")
    return "hertz", law.core, min(e, 1.0)


def _damping_key(pc, wall, m_eff: float) -> tuple[str, str, float]:
    """(normal, damping, restitution) of the core for a resolved contact (module docstring)."""
    hertz = _is_hertz(pc, wall)
    key = f"wall[{wall.number}]" if wall is not None else "contact"
    if not hertz:
        zeta = pc.cn / (2.0 * math.sqrt(pc.kn * m_eff)) if pc.cn > 0 else 0.0
        e = _restitution_from_zeta(zeta, key + ".damping_ratio")
        return "hooke", ("none" if e == 1.0 else "liggghts"), e
    conv = pc.convention
    if pc.cn <= 0.0:
        return "hertz", "none", 1.0
    if conv not in ("liggghts", "edem") or pc.zeta is None:
        what = f"damping convention {conv!r}" if pc.zeta is not None else "damping given as coefficients"
        raise InputError(key + ".damping_convention", f"a Hertz collision with {what} is not modelled by dtcrit collide "
                         "(supported: liggghts, edem with restitution or damping_ratio)")
    return "hertz", "liggghts", _restitution_from_zeta(pc.zeta, key + ".damping_ratio")


def _linearised_overlap(scene, pc, wall, m: float) -> float:
    """The overlap whose tangent stiffness the scene resolved ``pc`` at (``scenes.laws``, ``scenes.hertz_walls``)."""
    if wall is None:
        return pc.delta_max
    if wall.overlap is not None:
        return wall.overlap
    v0 = wall.velocity if wall.velocity is not None else scene.contact.velocity
    return math.sqrt(15.0 * m * v0 * v0 / (8.0 * pc.kn))  # (4/15) k_n delta^2 = m v^2/2 at the peak


def _hertz_terms(pc, d0: float, m: float, v: float) -> dict:
    """``E* sqrt(R*)``, ``k1 = 8 G* sqrt(R*)`` and the peak overlap at ``v`` from the tangent stiffnesses at ``d0``."""
    K = (2.0 / 3.0) * pc.kn / math.sqrt(d0)  # F = K delta^(3/2), k_n = (3/2) K sqrt(delta)
    delta = (1.25 * m * v * v / K) ** 0.4
    return dict(E_sqrtR=0.75 * K, k1=pc.ks / math.sqrt(d0), delta_max=delta, scale=math.sqrt(delta / d0))


def _particle_props(parts) -> dict | None:
    props = [(p.radii[0], p) for p in parts if p.radii]
    if not props or any(p.youngs_modulus is None or p.poisson_ratio is None for _, p in props):
        return None
    r, p = min(props, key=lambda t: t[0])
    density = p.shape_at(r).mass / (4.0 / 3.0 * math.pi * r ** 3)
    return dict(radius=r, density=density, youngs_modulus=p.youngs_modulus, poisson_ratio=p.poisson_ratio)


def _contacts(scene):
    for i, j in scene.pair_numbers():
        p, q = scene.particle(i), scene.particle(j)
        yield resolve_pair(scene, i, j), p, q, None  # the smallest sizes: the shortest contact time
    for w in scene.walls:
        for i in w.particles:
            yield resolve_wall(scene, w, i), scene.particle(i), None, w


def _entry(scene, pc, p, q, wall, v, tol: float, engine: str, oblique=None) -> dict:
    for part in (p, q):
        if part is not None and part.kind != "sphere":
            raise InputError(f"particle[{part.number}].shape", f"dtcrit collide models collisions of spheres, not {part.kind}")
    m = pc.m_star if wall is None else p.mass_at(pc.radius_i)  # against a fixed wall: the particle's mass
    hz = _hertz_terms(pc, _linearised_overlap(scene, pc, wall, m), m, v) if _is_hertz(pc, wall) else None
    if hz is not None and pc.convention in LAW_CONVENTIONS:
        normal, damping, e = _law_key(scene, pc, wall, m, hz, v)
        q_c = dashpot_exponent(pc.convention)
    else:
        normal, damping, e = _damping_key(pc, wall, m)
        q_c = 0.25
    if hz is None:
        t_c, peak = contact_time("hooke", m_eff=m, k=pc.kn), v * math.sqrt(m / pc.kn)
    else:
        t_c = contact_time("hertz", m_eff=m, E_eff=hz["E_sqrtR"], R_eff=1.0, v_impact=v)
        peak = hz["delta_max"]
        radius = min(r for r in (pc.radius_i, pc.radius_j) if r is not None and r > 0)
        if not peak < radius:
            raise InputError("v_max", f"{pc.label}: the peak overlap at {v:g} m/s, {peak:.4g} m, is not below the "
                                      f"radius {radius:.4g} m: Hertz's law does not describe this impact")
        s, sq = hz["scale"], hz["scale"] ** (2.0 * q_c)  # springs ~ delta^(1/2), dashpots ~ delta^q
        pc = replace(pc, kn=pc.kn * s, ks=pc.ks * s, cn=pc.cn * sq, cs=pc.cs * sq)
    ps = pair_step(scheme_of(engine), pc, p.shape_at(pc.radius_i), q.shape_at(pc.radius_j) if q is not None else None,
                   p.kind, q.kind if q is not None else None)
    dt_stab = ps.dt_translation
    res = resolution_step(engine=engine, normal=normal, damping=damping, restitution=e, tol=tol)
    if not math.isfinite(res.steps_per_collision):  # no step resolves it: never fall back to stability alone
        raise InputError("tol", f"{pc.label}: no step resolves this collision within {tol:g} "
                                f"({', '.join(res.quantities)}) with {engine}; raise --tol")
    dt_res = t_c / res.steps_per_collision
    obl = None if oblique is None else oblique_plan(oblique, pc, p, damping=damping, restitution=e, v=v, t_c=t_c, peak=peak,
                                                    tol=tol, engine=engine)  # scenes.collide_oblique
    dt = min(dt_stab, dt_res, math.inf if obl is None else obl.dt_resolution)
    n_bind = t_c / dt
    errs = collision_errors(engine=engine, normal=normal, damping=damping, restitution=e, steps_per_collision=n_bind)
    rules = code_rules(t_c=t_c, m_star=m, v_max=v, hertz=hz, restitution=e,
                       particle=_particle_props([p] if q is None else [p, q]))
    return {
        "pair": pc.label, "wall": pc.wall, "normal": normal, "damping": damping, "restitution": e,
        "damping_convention": pc.convention,
        "restitution_continuum": reference_collision(normal=normal, damping=damping, restitution=e).restitution,
        "cn_at_peak": pc.cn, "cs_at_peak": pc.cs,
        "m_eff": m, "v_max": v, "t_c": t_c, "peak_overlap": peak, "dt_stability": dt_stab,
        "dt_resolution": dt_res if dt_res > 0 else None, "steps_resolution": res.steps_per_collision if dt_res > 0 else None, "dt": dt, "steps_per_collision": n_bind,
        "binding": "oblique-resolution" if obl is not None and obl.dt_resolution < min(dt_res, dt_stab) else
                   "resolution" if dt_res > 0 and dt_res <= dt_stab else "stability",
        "energy_gain": errs["energy_gain"], "gains_energy": errs["energy_gain"] > ENERGY_TOL,
        "energy_verdict": _energy_verdict(engine, normal, damping, e, n_bind, errs["energy_gain"]),
        "errors_at_dt": {k: errs[k] for k in ("restitution", "peak_overlap", "duration")},
        "rules": [{"key": r.key, "label": r.label, "dt": r.dt, "source": r.source,
                   "ratio": None if r.dt is None else r.dt / dt,
                   "verdict": None if r.dt is None else ("safe" if r.dt <= dt else "UNSAFE")} for r in rules],
        **({} if obl is None else {"oblique": obl.report(dt)}),
    }


def collide_report(scene, *, tol: float = 0.01, engine: str | None = None, v_max: float | None = None,
                   angle_deg: float | None = None) -> dict:
    """The collision report of a scene (module docstring).

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The parsed scene (a ``linear``, ``yade`` or ``hertz`` contact law).
    tol : float
        Relative tolerance in (0, 1) on restitution and peak overlap.
    engine : str, optional
        Engine or integrator whose stepping is resolved (default: the scene's integrator).
    v_max : float, optional
        Largest impact speed [m/s] (default: the scene's ``[collision] v_max``, else its ``[contact] velocity``).
    angle_deg : float, optional
        Angle of the impact from the normal [deg] in [0, 90) (default: the scene's ``[collision] angle_deg``
        or ``tangential_ratio``): above zero, each pair also reports its oblique impact
        (``scenes.collide_oblique``).

    Returns
    -------
    dict
        ``integrator``, ``tol``, ``v_max``, ``pairs`` (one entry per contact) and ``dt`` (the smallest
        binding step) [s].

    Raises
    ------
    InputError
        No impact speed, a law without collisions (bonds), an unsupported damping convention, a bad tolerance.
    """
    tol = check_tol(tol)
    law = scene.contact
    if law.model not in ("linear", "yade", "hertz"):
        raise InputError("contact.model", f"dtcrit collide needs a colliding contact law (linear, yade or hertz), not {law.model!r}")
    if law.rotational is not None:
        raise InputError("contact.rolling", "rolling/twisting springs change a collision and are not modelled by dtcrit collide")
    v = v_max if v_max is not None else scene.collision_v_max if scene.collision_v_max is not None else law.velocity
    if v is None:
        raise InputError("contact.velocity", "dtcrit collide needs the largest impact speed: give [collision] v_max, "
                         "[contact] velocity (Hertz) or --v-max [m/s]")
    if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
        raise InputError("v_max", f"must be a positive finite speed (got {v!r})")
    engine = engine or scene.integrator
    oblique = oblique_request(scene, angle_deg)
    pairs = [_entry(scene, pc, p, q, w, float(v), tol, engine, oblique) for pc, p, q, w in _contacts(scene)]
    return {"integrator": engine, "tol": tol, "v_max": float(v), "pairs": pairs, "dt": min(e["dt"] for e in pairs)}
