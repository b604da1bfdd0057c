"""The whole plan of a snapshot: the API behind ``dtcrit plan``.

:func:`plan_snapshot` reads a snapshot as ``dtcrit audit`` does, audits it (the binding step and the
particles and springs of its governing mode), plans the density scaling
(:func:`dtcrit.plan.density.plan_density_scaling`) and the stiffness reduction
(:mod:`dtcrit.plan.stiffness`) that reach the target step, and the cost and the change in the physics
of each (:mod:`dtcrit.plan.physics`).  The frozen :class:`SnapshotPlan`'s ``to_json()`` is the document
``dtcrit plan --json`` prints (schema ``dtcrit-plan/1``), ``to_text()`` its text.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from dtcrit.errors import InputError
from dtcrit.physics import rules_of_thumb as rot

from dtcrit.plan.density import DEFAULT_MAX_FACTOR, DensityPlan, plan_density_scaling
from dtcrit.plan.stiffness import StiffnessPlan

__all__ = ["SnapshotPlan", "plan_snapshot"]


@dataclass(frozen=True)
class SnapshotPlan:
    """A snapshot's plan (module docstring); the JSON form is ``dtcrit.plan.output.plan_json``.

    Parameters
    ----------
    source, engine, integrator, law : str
        The snapshot, the engine, the integrator planned for and the contact law in words.
    n_particles, n_contacts : int
        Free particles and contacts.
    target_dt : float
        The target step [s].
    audit : SnapshotAudit
        The audit of the snapshot as it is (``dt_crit``, the limiting particles, the governing mode).
    density : DensityPlan
        The density scaling.
    size_classes : list of dict
        Added mass per radius bin (:func:`dtcrit.plan.physics.size_classes`).
    stiffness : StiffnessPlan
        The stiffness reduction.
    cost : dict or None
        ``duration`` [s], steps and particle-steps today and at the target; None without a duration.
    quasi_static : dict
        ``growth_mean``, ``growth_max`` of the inertial number and, with a strain rate and a pressure,
        ``inertial_number_before``, ``inertial_number_after``, ``pressure`` [Pa].
    collisions : dict
        Shortest contact duration [s] today, after density scaling and after stiffness reduction, and
        the steps per collision at each step.
    warnings : tuple of str
        Where the scaling changes the physics.
    snapshot : Snapshot
        The snapshot read (not part of the JSON).
    """

    source: str
    engine: str
    integrator: str
    law: str
    n_particles: int
    n_contacts: int
    target_dt: float
    audit: Any
    density: DensityPlan
    size_classes: list
    stiffness: StiffnessPlan
    cost: dict | None
    quasi_static: dict
    collisions: dict
    warnings: tuple
    snapshot: Any = field(repr=False, compare=False)

    def to_json(self) -> dict:
        """The JSON document ``dtcrit plan --json`` prints (schema ``dtcrit-plan/1``).

        Returns
        -------
        dict
            The envelope and the plan; non-finite numbers are ``None``.
        """
        from dtcrit.plan.output import plan_json

        return plan_json(self)

    def to_text(self) -> str:
        """The text ``dtcrit plan`` prints.

        Returns
        -------
        str
            The plan without a final newline.
        """
        from dtcrit.plan.output import plan_text

        return plan_text(self)


def _cost(duration: float | None, n: int, dt_now: float, target: float) -> dict | None:
    if duration is None:
        return None
    if not (math.isfinite(duration) and duration > 0):
        raise InputError("duration", f"must be a positive finite number of seconds, got {duration!r}")
    now, after = math.ceil(duration / dt_now), math.ceil(duration / target)
    return {"duration": duration, "steps_now": now, "particle_steps_now": now * n, "steps_after": after,
            "particle_steps_after": after * n, "speedup": now / after}


def _quasi_static(given, plan: DensityPlan, strain_rate, hertz: bool) -> dict:
    from dtcrit.plan.physics import (EQUILIBRIUM_LIMIT, QUASI_STATIC_LIMIT, inertial_number, mean_pressure,
                                     unbalanced_force_ratio)

    out: dict[str, Any] = {"growth_mean": math.sqrt(1.0 + plan.added_mass_fraction), "growth_max": plan.growth,
                           "strain_rate": strain_rate, "pressure": None, "inertial_number_before": None,
                           "inertial_number_after": None, "limit": QUASI_STATIC_LIMIT,
                           "unbalanced_force_ratio": unbalanced_force_ratio(given.packing, given.contacts, hertz,
                                                                            plan.free),
                           "equilibrium_limit": EQUILIBRIUM_LIMIT}
    if strain_rate is None:
        return out
    if not (math.isfinite(strain_rate) and strain_rate > 0):
        raise InputError("strain_rate", f"must be a positive finite number [1/s], got {strain_rate!r}")
    p = mean_pressure(given.packing, given.contacts, hertz, plan.free)
    if p is not None:
        before = inertial_number(strain_rate, given.packing, plan.free, p)
        out.update(pressure=p, inertial_number_before=before, inertial_number_after=before * out["growth_mean"])
    return out


def _resolution(given, step, plan: DensityPlan, both: np.ndarray, hertz: bool) -> tuple | None:
    """``(N_res today and with stiffness reduction, N_res with density scaling)``; None: not assessed.

    A damped law is resolved at its smallest restitution (the most damped contact needs the most steps),
    today and at the scaled masses (a dashpot ``m_eff gamma`` changes the damping ratio with the mass);
    stiffness reduction keeps every damping ratio (``dtcrit.plan.stiffness``).
    """
    from dtcrit.plan.physics import resolution_steps
    from dtcrit.plan.resolution import damping_model, linear_restitution

    model = damping_model(given)
    if model is None:
        return None
    if model == "none":
        n = resolution_steps(given.convention.name, plan.integrator, hertz)
        return n, n
    packing, contacts = step.system(plan.factors)
    e_now = float(linear_restitution(given.packing, given.contacts)[both].min())
    e_dens = float(linear_restitution(packing, contacts)[both].min())
    if not (e_now > 0 and e_dens > 0):  # an overdamped contact does not bounce: no restitution to resolve
        return None
    return (resolution_steps(given.convention.name, plan.integrator, False, model, e_now),
            resolution_steps(given.convention.name, plan.integrator, False, model, e_dens))


def _collisions(given, step, plan: DensityPlan, stiffness: StiffnessPlan, velocity, hertz: bool) -> dict:
    from dtcrit.plan.physics import contact_durations, hertz_durations

    both = plan.free[given.contacts.i] & plan.free[given.contacts.j]
    if not both.any():
        both = np.ones(given.contacts.count, bool)
    impact = hertz and velocity is not None and velocity > 0

    def shortest(factors):
        t = (hertz_durations(given.packing, given.contacts, velocity, factors) if impact else
             contact_durations(given.packing, given.contacts, factors))
        return float(t[both].min())

    now, dens = shortest(None), shortest(plan.factors)
    soft = now * stiffness.contact_duration_factor
    t, dt_now = plan.target_dt, plan.dt_crit
    out: dict[str, Any] = {
        "law": "hertz at the impact speed" if impact else "linear at the snapshot's stiffness",
        "contact_time_now": now, "contact_time_density": dens, "contact_time_stiffness": soft,
        "steps_per_collision_now": now / dt_now, "steps_per_collision_density": dens / t,
        "steps_per_collision_stiffness": soft / t, "lammps_rule_steps": float(rot.COLLISION_TIME_DIVISOR),
        "velocity": velocity, "resolution_steps": None, "resolution_dt_now": None, "resolution_dt_density": None,
        "resolution_dt_stiffness": None, "resolution_assessed": None}
    if velocity is not None:
        found = _resolution(given, step, plan, both, hertz)
        out["resolution_assessed"] = found is not None
        if found is not None:
            n_now, n_dens = found
            out.update(resolution_steps=n_now, resolution_dt_now=now / n_now, resolution_dt_density=dens / n_dens,
                       resolution_dt_stiffness=soft / n_now)
    return out


def _warnings(plan: DensityPlan, quasi: dict, gravity, velocity, collisions: dict, hertz: bool) -> tuple[str, ...]:
    out = []
    f_max = float(plan.factors.max())
    if gravity is not None:
        out.append(f"gravity {gravity:g} m/s^2: YADE's own densityScaling keeps the weight and scales only the inertia, "
                   f"so a body scaled by {f_max:.4g} falls at g/{f_max:.4g}; this plan applied as masses (dtcrit's YADE "
                   f"hook sets state.mass, the LAMMPS recipe and --write-dump the mass column) scales the weight with "
                   f"the mass: the body still falls at g, but its weight and the overlaps under self-weight grow up to "
                   f"{f_max:.4g} x: gravity-driven loading is not what it was")
    if velocity is not None:
        out.append(f"impacts at {velocity:g} m/s: the scaled bodies carry up to {f_max:.4g} x the momentum and kinetic "
                   f"energy, their collisions last up to {f_max ** (0.4 if hertz else 0.5):.4g} x longer "
                   f"(t_c ~ m^{'2/5' if hertz else '1/2'}) and overlap deeper: impacts "
                   f"are not what they were")
    unbalanced = quasi.get("unbalanced_force_ratio")
    if unbalanced is not None and unbalanced > quasi["equilibrium_limit"]:
        out.append(f"the snapshot is not at rest under this contact law (unbalanced force ratio {unbalanced:.3g} > "
                   f"{quasi['equilibrium_limit']:g}): it will move and make new contacts, and the planned step holds for "
                   f"the contacts it has now; plan from a relaxed snapshot or keep a margin")
    after = quasi.get("inertial_number_after")
    if after is not None and after > quasi["limit"]:
        out.append(f"inertial number after scaling {after:.3g} > {quasi['limit']:g}: the flow is no longer quasi-static")
    if collisions["resolution_assessed"] is False:
        out.append("the collision resolution at the target was not assessed: the snapshot's damped contact law has no "
                   "collision model in dtcrit.collisions that this plan maps it to (linear springs with a constant or "
                   "m_eff gamma dashpot are mapped)")
    for option in ("density", "stiffness"):
        limit = collisions[f"resolution_dt_{option}"]
        if limit is not None and plan.target_dt > limit:
            out.append(f"with {'density scaling' if option == 'density' else 'stiffness reduction'} the target step "
                       f"{plan.target_dt:.4g} s exceeds the {limit:.4g} s that resolves the shortest collision's "
                       f"restitution and peak overlap to 1 % (dtcrit.collisions.resolution_step)")
    return tuple(out)


def plan_snapshot(snapshot: str | os.PathLike | Any, target_dt: float, *, max_factor: float = DEFAULT_MAX_FACTOR,
                  duration: float | None = None, strain_rate: float | None = None, gravity: float | None = None,
                  velocity: float | None = None, bins: int = 5, integrator: str | None = None,
                  local_damping: float | None = None, local_damping_law: str | None = None,
                  yade_safety: float = rot.YADE_GSTS_SAFETY, **read: Any) -> SnapshotPlan:
    """The plan of a snapshot: binding step, density scaling, stiffness reduction, cost (module docstring).

    Parameters
    ----------
    snapshot : str or os.PathLike or Snapshot
        A snapshot file (read with :func:`dtcrit.packing.audit.run.read_snapshot` and ``read``) or one already read.
    target_dt : float
        The target step [s].
    max_factor : float
        The largest mass factor of any body.
    duration : float, optional
        Simulated time [s] for the cost.
    strain_rate : float, optional
        Shear strain rate [1/s] for the inertial number.
    gravity : float, optional
        Gravitational acceleration [m/s^2] the simulation applies (a warning: scaling changes its effect).
    velocity : float, optional
        Impact speed [m/s] in the simulation (a warning).
    bins : int
        Radius bins of the size classes.
    integrator, local_damping, local_damping_law : optional
        As ``dtcrit audit`` takes them.
    yade_safety : float
        ``timestepSafetyCoefficient`` of YADE's rule.
    **read
        ``read_snapshot``'s keyword arguments for a file.

    Returns
    -------
    SnapshotPlan
        The plan.

    Raises
    ------
    InputError
        Bad input, nothing to do, or a target unreachable within ``max_factor``.
    """
    from dtcrit.packing.audit.run import audit_snapshot
    from dtcrit.plan.density import read_input, scaled_step_of
    from dtcrit.plan.physics import size_classes
    from dtcrit.plan.resolution import is_hertz
    from dtcrit.plan.stiffness import stiffness_reduction

    for key, value in (("gravity", gravity), ("velocity", velocity)):
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise InputError(key, f"must be a finite number >= 0, got {value!r}")
    if not (isinstance(bins, int) and bins >= 1):
        raise InputError("bins", f"must be a whole number >= 1, got {bins!r}")
    given = read_input(snapshot, read)
    plan = plan_density_scaling(given, target_dt, max_factor, integrator=integrator, local_damping=local_damping,
                                local_damping_law=local_damping_law, yade_safety=yade_safety)
    audit = audit_snapshot(given, integrator=plan.integrator, local_damping=local_damping,
                           local_damping_law=local_damping_law)
    step = scaled_step_of(given, plan.integrator, local_damping, local_damping_law, "auto")
    hertz = is_hertz(given)
    stiffness = stiffness_reduction(step, plan.target_dt, plan.dt_crit, hertz=hertz)
    quasi = _quasi_static(given, plan, strain_rate, hertz)
    collisions = _collisions(given, step, plan, stiffness, velocity, hertz)
    n_free = int(plan.free.sum())
    return SnapshotPlan(
        source=given.source, engine=given.convention.name, integrator=plan.integrator, law=given.law,
        n_particles=n_free, n_contacts=given.contacts.count, target_dt=plan.target_dt, audit=audit, density=plan,
        size_classes=size_classes(given.packing.radii, given.packing.masses, plan.factors, plan.free,
                                  plan.yade_factors, bins),
        stiffness=stiffness, cost=_cost(duration, n_free, plan.dt_crit, plan.target_dt), quasi_static=quasi,
        collisions=collisions, warnings=_warnings(plan, quasi, gravity, velocity, collisions, hertz), snapshot=given)
