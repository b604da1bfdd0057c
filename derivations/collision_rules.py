"""Record: the codes' rules for the step of a collision against the step that resolves it.

For a Hertz impact with LIGGGHTS's Hertz-Mindlin dashpot (unclipped, as LIGGGHTS by default; clipped at
zero, as ``limitForce on`` or YADE), stepped by velocity Verlet and leapfrog: the resolution step
``N_res`` (``dtcrit.collisions.resolution_step``, 1 % in restitution and peak overlap, worst entry phase,
every smaller step) beside the steps per collision each code's rule gives
(``dtcrit.physics.collision_rules``), and Burns, Piiroinen & Hanley's (2019) eq. 68 checked against the
time-stepped impact (``collision_errors``) and the linear stability step at the peak overlap.
"""
from __future__ import annotations

import math

from _shared.text import num

from dtcrit.collisions import collision_errors, contact_time, resolution_step
from dtcrit.physics.collision_rules import code_rules
from dtcrit.physics.contact_laws import effective_shear_modulus, effective_youngs_modulus

RECORD = "collision_rules.md"
ENGINES = ("velocity-verlet", "leapfrog")
RESTITUTIONS = (1.0, 0.9, 0.5, 0.1)
TOL = 0.01
# the glass beads of examples/glass_spheres_hertz.toml
RADIUS, DENSITY, YOUNGS, POISSON = 1.0e-3, 2500.0, 63.0e9, 0.22
SPEEDS = (0.1, 1.0, 10.0)


def _contact(v: float) -> dict:
    """t_c, m*, the Hertz terms and the linear stability N (velocity Verlet, undamped: dt = 2/omega) at ``v``."""
    m = DENSITY * 4.0 / 3.0 * math.pi * RADIUS ** 3
    ms, rs = m / 2.0, RADIUS / 2.0
    es = effective_youngs_modulus(YOUNGS, POISSON, YOUNGS, POISSON)
    gs = effective_shear_modulus(YOUNGS, POISSON, YOUNGS, POISSON)
    delta = (15.0 * ms * v * v / (16.0 * es * math.sqrt(rs))) ** 0.4
    t_c = contact_time("hertz", m_eff=ms, E_eff=es, R_eff=rs, v_impact=v)
    kn = 2.0 * es * math.sqrt(rs * delta)
    hertz = dict(E_sqrtR=es * math.sqrt(rs), k1=8.0 * gs * math.sqrt(rs), delta_max=delta)
    return dict(t_c=t_c, m=ms, hertz=hertz, n_stab=t_c * math.sqrt(kn / ms) / 2.0, v=v)


def _rules_n(c: dict, e: float) -> dict:
    particle = dict(radius=RADIUS, density=DENSITY, youngs_modulus=YOUNGS, poisson_ratio=POISSON)
    rules = code_rules(t_c=c["t_c"], m_star=c["m"], v_max=c["v"], hertz=c["hertz"], particle=particle, restitution=e)
    return {r.key: c["t_c"] / r.dt for r in rules if r.dt is not None}


def _table() -> list[str]:
    c = _contact(1.0)
    keys = list(_rules_n(c, 1.0))
    head = "| integrator | force | e | N_res (1 %) | " + " | ".join(f"`{k}`" for k in keys) + " |"
    rows = [head, "| --- " * (4 + len(keys)) + "|"]
    for eng in ENGINES:
        for clip in (False, True):
            for e in RESTITUTIONS:
                n_res = resolution_step(engine=eng, normal="hertz", damping="liggghts", restitution=e, tol=TOL,
                                        clip=clip).steps_per_collision
                cells = []
                for k in keys:
                    n = _rules_n(c, e)[k]
                    cells.append(f"{n:.3g} {'safe' if n >= n_res else '**UNSAFE**'}")
                rows.append(f"| {eng} | {'clipped' if clip else 'unclipped'} | {e:g} | {n_res:.4g} | " + " | ".join(cells) + " |")
    return rows


def _speeds() -> list[str]:
    rows = ["| v [m/s] | t_c [s] | N of EDEM 20 % | N of EDEM 40 % | N of LIGGGHTS 0.1 | N of Burns (e = 1) | N_stab (peak) |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for v in SPEEDS:
        c = _contact(v)
        n = _rules_n(c, 1.0)
        rows.append(f"| {v:g} | {num(c['t_c'], 4)} | {n['edem-rayleigh-0.2']:.3g} | {n['edem-rayleigh-0.4']:.3g} | "
                    f"{n['liggghts-hertz-0.1']:.3g} | {n['burns-2019']:.3g} | {c['n_stab']:.3g} |")
    return rows


def _burns() -> list[str]:
    c = _contact(1.0)
    rows = ["| e | N of Burns eq. 68 | N_stab (peak, undamped) | restitution error | peak-overlap error | energy excess |",
            "| --- | --- | --- | --- | --- | --- |"]
    for e in RESTITUTIONS:
        n_b = _rules_n(c, e)["burns-2019"]
        err = collision_errors(engine="velocity-verlet", normal="hertz", damping="liggghts", restitution=e, steps_per_collision=n_b)
        rows.append(f"| {e:g} | {n_b:.4g} | {c['n_stab']:.4g} | {err['restitution']:.3%} | {err['peak_overlap']:.3%} | "
                    f"{err['energy_gain']:.3%} |")
    return rows


def build() -> str:
    """The record's Markdown text."""
    return "\n".join([
        "# The codes' collision rules against the step that resolves a collision",
        "",
        "Built by `derivations/collision_rules.py`; regenerate with `python3 dev.py generate`.",
        "",
        "A Hertz impact with LIGGGHTS's Hertz-Mindlin dashpot (`2 sqrt(5/6) beta sqrt(S_n m*)`), unclipped or with "
        "the force clipped at zero, stepped by velocity Verlet and leapfrog.  `N_res` is the resolution step in "
        "steps per collision (`t_c/dt`): restitution and peak overlap within 1 % for every entry phase and every "
        "smaller step (`dtcrit.collisions.resolution_step`).  Each rule's column is the N it gives (larger is a "
        "smaller step) and whether it is at least `N_res`.  The LIGGGHTS fractions and `t_c/50` are fixed fractions "
        "of `t_c`; the EDEM (Rayleigh time) and Burns et al. rules depend on the material (and EDEM's on the speed): "
        f"here the glass beads of `examples/glass_spheres_hertz.toml` (R = {RADIUS:g} m, rho = {DENSITY:g} kg/m^3, "
        f"E = {YOUNGS:g} Pa, nu = {POISSON:g}) at 1 m/s.",
        "",
        *_table(),
        "",
        "Velocity Verlet and leapfrog give the same `N_res` (one map, `dtcrit.collisions.stepping`).  Clipping "
        "changes it only where restitution binds (e = 0.1): for e >= 0.5 the peak overlap binds, reached before "
        "the force can turn negative.  LIGGGHTS's `fraction_h` 0.1 (10 steps) resolves only the elastic impact, "
        "0.2 (5 steps) none; `t_c/50` resolves e >= 0.5 but not e = 0.1.",
        "",
        "## EDEM's Rayleigh fractions and the speed",
        "",
        "The Rayleigh time does not depend on the impact speed while `t_c` falls as `v^(-1/5)`, so EDEM's fixed "
        "fraction gives fewer steps per collision the faster the impact (glass beads, the elastic Burns step for comparison):",
        "",
        *_speeds(),
        "",
        "## Burns, Piiroinen & Hanley (2019) against the time-stepped impact",
        "",
        "Eq. 68 with `s_t = 8 G* sqrt(R* delta_max)` (`dtcrit.physics.collision_rules.burns_step`).  In units of `t_c` "
        "it depends only on Poisson's ratio and e (undamped: `dt/t_c = (E* sqrt(R*)/(3.5 k1))^(2/5)/2.868`, "
        "`k1 = 8 G* sqrt(R*)`).  It scales with the speed as `t_c` does.  At its step, velocity Verlet "
        "(worst entry phase, `collision_errors`), with the linear stability limit at the peak overlap "
        "(`N_stab = omega t_c/2`, undamped):",
        "",
        *_burns(),
        "",
        "Burns et al.'s step is about three to eight times shorter than the linear stability limit at the peak "
        "overlap (the impact is stable), yet longer than the resolution step at 1 % for every restitution: it keeps "
        "the impact stable, not its restitution and peak overlap within 1 %.",
        "",
    ])
