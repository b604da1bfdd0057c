"""Text and JSON (schema ``dtcrit-plan/1``, ``src/dtcrit/schemas/dtcrit-plan-1.json``) of a plan."""
from __future__ import annotations

from typing import Any

from dtcrit.json_meta import envelope
from dtcrit.physics.json_numbers import finite_or_none as _finite

__all__ = ["JSON_SCHEMA", "UNITS", "plan_json", "plan_text"]

JSON_SCHEMA = "dtcrit-plan/1"
UNITS = {"target_dt": "s", "binding.dt_crit": "s", "binding.dt_safe": "s", "density_scaling.dt_crit_scaled": "s",
         "density_scaling.added_mass": "kg", "density_scaling.yade_rule_dt_crit": "s",
         "density_scaling.yade_unit_safety_dt_crit": "s",
         "density_scaling.size_classes.*.radius_min": "m", "density_scaling.size_classes.*.radius_max": "m",
         "density_scaling.size_classes.*.mass": "kg", "density_scaling.size_classes.*.added_mass": "kg",
         "density_scaling.size_classes.*.yade_rule_added_mass": "kg", "quasi_static.pressure": "Pa",
         "quasi_static.strain_rate": "1/s", "stiffness_reduction.dt_crit_reduced": "s",
         "collisions.contact_time_now": "s", "collisions.contact_time_density": "s",
         "collisions.contact_time_stiffness": "s", "collisions.velocity": "m/s", "collisions.resolution_dt_now": "s",
         "collisions.resolution_dt_density": "s", "collisions.resolution_dt_stiffness": "s", "cost.duration": "s"}


def _binding(plan: Any) -> dict:
    a = plan.audit
    return {"dt_crit": _finite(a.dt_crit), "dt_safe": _finite(a.dt_safe), "method": a.method,
            "limiting": {"ids": list(a.limiting), "energy_share": _finite(a.limiting_share),
                         "participation_ratio": _finite(a.participation)},
            "governing_mode": None if a.governing_mode is None else a.governing_mode.to_json(),
            "local_damping": None if a.local_damping is None else dict(a.local_damping)}


def _density(plan: Any) -> dict:
    d = plan.density
    ids = [plan.snapshot.packing.particle_id(p) for p in range(len(d.factors)) if d.free[p]]
    return {"ids": ids, "factors": [float(f) for f, free in zip(d.factors, d.free) if free],
            "added_mass_fraction": d.added_mass_fraction, "added_mass": d.added_mass,
            "dt_crit_scaled": d.dt_crit_scaled, "factor_max": float(d.factors.max()), "max_factor": d.max_factor,
            "family": d.family, "bound": d.bound, "bound_added_mass_fraction": d.bound_added_mass_fraction,
            "uniform_factor": d.uniform_factor, "uniform_added_mass_fraction": d.uniform_added_mass_fraction,
            "yade_rule_added_mass_fraction": _finite(d.yade_rule_added_mass_fraction),
            "yade_rule_dt_crit": _finite(d.yade_dt_crit_scaled),
            "yade_rule_stable": None if d.yade_dt_crit_scaled is None else bool(d.yade_dt_crit_scaled >= d.target_dt),
            "yade_safety": d.yade_safety,
            "yade_unit_safety_added_mass_fraction": _finite(d.yade_unit_safety_added_mass_fraction),
            "yade_unit_safety_dt_crit": _finite(d.yade_unit_safety_dt_crit_scaled), "solves": d.solves, "size_classes": list(plan.size_classes)}


def _stiffness(plan: Any) -> dict:
    s = plan.stiffness
    return {"factor": s.factor, "dt_crit_reduced": s.dt_crit_reduced, "hertz": s.hertz,
            "modulus_factor_fixed_overlap": s.modulus_factor_fixed_overlap,
            "modulus_factor_impact": s.modulus_factor_impact, "modulus_factor_fixed_load": s.modulus_factor_fixed_load,
            "contact_duration_factor": s.contact_duration_factor, "peak_overlap_factor": s.peak_overlap_factor,
            "static_overlap_factor": s.static_overlap_factor, "dashpots_scaled": s.damped}


def plan_json(plan: Any) -> dict:
    """The plan as a JSON document (schema ``dtcrit-plan/1``; non-finite numbers as null).

    Parameters
    ----------
    plan : dtcrit.plan.report.SnapshotPlan
        The plan.

    Returns
    -------
    dict
        The document.
    """
    out: dict[str, Any] = envelope(JSON_SCHEMA, UNITS)
    out.update({"snapshot": plan.source, "engine": plan.engine, "integrator": plan.integrator, "law": plan.law,
                "n_particles": plan.n_particles, "n_contacts": plan.n_contacts, "target_dt": plan.target_dt,
                "binding": _binding(plan), "density_scaling": _density(plan), "stiffness_reduction": _stiffness(plan),
                "quasi_static": dict(plan.quasi_static), "collisions": dict(plan.collisions),
                "cost": None if plan.cost is None else dict(plan.cost), "warnings": list(plan.warnings)})
    return out


def _pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.4g} %"


def _binding_lines(plan: Any) -> list[str]:
    from dtcrit.packing.audit.mode_character import describe

    a = plan.audit
    lines = [f"binding step today: dt_crit = {a.dt_crit:.7g} s ({a.method}); target {plan.target_dt:.7g} s "
             f"= {plan.target_dt / a.dt_crit:.4g} x dt_crit"]
    if a.limiting:
        lines.append(f"  bound by particles (ids) {' '.join(str(i) for i in a.limiting)} "
                     f"({100 * a.limiting_share:.3g} % of the governing mode's energy)")
    else:
        lines.append(f"  governing mode spread out (participation ratio {a.participation:.3g})")
    if a.governing_mode is not None:
        lines.append("  " + describe(a.governing_mode))
    return lines


def _density_lines(plan: Any) -> list[str]:
    d = plan.density
    yade = ("n/a (YADE's stepper reads sphere contacts only)" if d.yade_dt_crit_scaled is None else
            f"{_pct(d.yade_rule_added_mass_fraction)}; its exact step {d.yade_dt_crit_scaled:.6g} s "
            f"({'stable' if d.yade_dt_crit_scaled >= d.target_dt else 'UNSTABLE'} at the target)")
    start = "the uniform factor" if d.bound == "uniform" else f"the {d.bound.replace('_', '-')} bound's factors"
    lines = ["", "density scaling (mass and inertia of each body times f >= 1):",
             f"  added mass {_pct(d.added_mass_fraction)} ({d.added_mass:.6g} kg), largest factor {d.factors.max():.5g}; "
             f"exact dt_crit of the scaled packing {d.dt_crit_scaled:.7g} s >= target",
             f"  (confirmed by the exact eigen-solve; start: "
             f"{start}, "
             f"{_pct(d.bound_added_mass_fraction)}; kept: {d.family}; {d.solves} inertia counts and eigen-solves)",
             f"  YADE densityScaling rule (safety {d.yade_safety:g}): {yade}",
             f"  uniform factor {d.uniform_factor:.6g}: {_pct(d.uniform_added_mass_fraction)}",
             f"  {'radius [m]':<24}{'count':>6}{'added mass':>14}{'largest f':>11}{'YADE rule':>14}"]
    for c in plan.size_classes:
        yade_c = "n/a" if c["yade_rule_added_mass"] is None else _pct(c["yade_rule_added_mass"] / c["mass"])
        lines.append(f"  {c['radius_min']:<11.4g}- {c['radius_max']:<11.4g}{c['count']:>6}"
                     f"{_pct(c['added_mass_fraction']):>14}{c['factor_max']:>11.4g}{yade_c:>14}")
    q = plan.quasi_static
    text = f"  inertial number grows by {q['growth_mean']:.4g} (mean density), {q['growth_max']:.4g} (most scaled body)"
    if q["inertial_number_before"] is not None:
        text += f": I = {q['inertial_number_before']:.3g} -> {q['inertial_number_after']:.3g} at {q['strain_rate']:g} 1/s"
    lines.append(text)
    return lines


def _stiffness_lines(plan: Any) -> list[str]:
    s = plan.stiffness
    lines = ["", "stiffness reduction (every spring times s" + (", dashpots times sqrt(s)" if s.damped else "") + "):",
             f"  s = {s.factor:.6g}; exact dt_crit {s.dt_crit_reduced:.7g} s >= target"]
    if s.hertz:
        lines.append(f"  Hertz modulus factor: {s.modulus_factor_fixed_overlap:.4g} at the snapshot's overlaps, "
                     f"{s.modulus_factor_impact:.4g} in impacts, {s.modulus_factor_fixed_load:.4g} under given loads")
    lines.append(f"  contact duration and impact peak overlap x {s.contact_duration_factor:.4g}; overlap under a "
                 f"given load x {s.static_overlap_factor:.4g}")
    c = plan.collisions
    lines.append(f"  shortest contact ({c['law']}): {c['contact_time_now']:.4g} s today ({c['steps_per_collision_now']:.3g} "
                 f"steps of dt_crit); at the target: {c['steps_per_collision_density']:.3g} steps with density scaling, "
                 f"{c['steps_per_collision_stiffness']:.3g} with stiffness reduction")
    if c["resolution_steps"] is not None:
        lines.append(f"  an impact at {c['velocity']:g} m/s is resolved to 1 % by {c['resolution_steps']:.4g} steps per "
                     f"collision: dt <= {c['resolution_dt_now']:.4g} s today, {c['resolution_dt_density']:.4g} s with "
                     f"density scaling, {c['resolution_dt_stiffness']:.4g} s with stiffness reduction")
    elif c.get("resolution_assessed") is False:
        lines.append(f"  an impact at {c['velocity']:g} m/s: collision resolution not assessed for this damped law")
    return lines


def plan_text(plan: Any) -> str:
    """The plan as text.

    Parameters
    ----------
    plan : dtcrit.plan.report.SnapshotPlan
        The plan.

    Returns
    -------
    str
        The lines ``dtcrit plan`` prints.
    """
    lines = [f"snapshot: {plan.source}", f"engine: {plan.engine}; integrator {plan.integrator}",
             f"contact law: {plan.law}", f"particles {plan.n_particles}, contacts {plan.n_contacts}", ""]
    lines += _binding_lines(plan) + _density_lines(plan) + _stiffness_lines(plan)
    if plan.cost is not None:
        c = plan.cost
        lines += ["", f"cost of {c['duration']:g} s: {c['steps_now']:,} steps ({c['particle_steps_now']:.4g} particle-steps) "
                      f"at dt_crit today, {c['steps_after']:,} ({c['particle_steps_after']:.4g}) at the target with "
                      f"either option: {c['speedup']:.4g} x fewer"]
    if plan.warnings:
        lines += [""] + [f"warning: {w}" for w in plan.warnings]
    return "\n".join(lines)
