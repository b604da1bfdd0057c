"""One-dimensional impact stability: exact and time-stepped impacts (CFL note; Feng 2005).

The CFL note's model of a DEM collision (seed 004, "One-dimensional equations for impact")::

    m d'' = -c d' - k d   for d >= 0 (contact),     m d'' = 0   for d < 0 (separated)

A discrete contact opens and closes within a few steps, so the linear stability bound (which
assumes a persistent contact) does not settle whether a time-stepped impact is stable.  The note's
criterion is the exit speed: ``v_exit <= v_entry``.  This package computes

* the exact impact (``exact_impact``): contact duration and exit/entry speed for both separation
  conventions (see ``dtcrit.symbolic.impact``), from the generated closed forms;
* the time-stepped impact (``simulate_impacts``) with each integrator's own update rule from
  ``dtcrit.integrators.schemes``, for arrays of steps ``tau = omega dt`` and entry phases ``phi``;
* the sweep over ``tau`` in (0, 2.2] (``sweep``, ``impact_report``), the undamped closed forms
  (``undamped_exit_ratios``), the Hertz contact (``hertz_study``) and the figures.

Conventions of the simulation (geometric separation, the note's equation):

* units: time ``1/omega`` (``omega = sqrt(k/m)``), overlap ``v0/omega``, speed ``v0``; ``K = 1``,
  ``C = 2 zeta``, step ``tau``;
* the force at a position ``x`` is the spring-dashpot force when ``x >= 0`` and zero when ``x < 0``;
  contact therefore opens and closes *between* steps, by the sign of the overlap at the step where
  the scheme evaluates its force (``x_n`` for Euler and leapfrog variants, ``x_(n+1)`` for velocity
  Verlet).  The dashpot force may be tensile near the end of the contact, as in the note's ODE;
* entry phase ``phi`` in [0, 1): the continuous contact would begin ``phi`` of a step before the
  first step with ``x >= 0``, i.e. that step has ``x_0 = phi tau``; ``phi = 0`` is contact
  beginning exactly on a step (``on_step``).  The run starts one step earlier, in free flight;
* exit: two consecutive positions ``x < 0`` after contact with a receding velocity (then no later
  force acts, for every scheme including the one-step-lagged acceleration of ``paper-eq40``); the
  exit ratio is the free-flight speed divided by ``v0``.  A particle that comes back re-enters
  contact.  A run that has not separated by a cut-off time is reported with ratio 0 and flagged
  (the exact geometric impact never separates for ``zeta >= 1``).

The Hertz contact ``m d'' = -k_h d^(3/2)`` is stepped in units of the exact maximum overlap and of
the tangent frequency ``omega_t`` there (``u'' = -(2/3) u^(3/2)``, entry speed ``sqrt(8/15)``), so its
step variable ``omega_t dt`` is directly comparable with the linearised bound.

Modules: ``conventions`` (units, constants, checks), ``exact``, ``stepped``, ``sweep``, ``hertz``,
``report`` (``dtcrit impact``), ``plots``.
"""
from dtcrit.impact.conventions import (
    CENTRAL_DIFFERENCE_FAMILY,
    CONVENTION,
    DEFAULT_ENERGY_THRESHOLD,
    DEFAULT_PHASES,
    DIVERGED,
    FORCE_CONVENTION,
    MAX_CUTOFF,
    MAX_OMEGA_DT,
    MAX_PHASES,
    MIN_OMEGA_DT,
    RATIO_RTOL,
    STANDARD_ZETAS,
    SWEEP_STEP,
    SWEEP_TOP,
    UNIT_STEPS_FROM,
    UNITS,
    check_energy_threshold,
    check_omega_dt,
    check_phases,
    check_zeta,
)
from dtcrit.impact.exact import ExactImpact, HertzExact, exact_impact, hertz_dimensional, hertz_exact
from dtcrit.impact.hertz import hertz_study
from dtcrit.impact.plots import plot_hertz, plot_phase_curve, plot_sweep
from dtcrit.impact.report import impact_report, to_json
from dtcrit.impact.stepped import (
    STATUS_DIVERGED,
    STATUS_EXITED,
    STATUS_NOT_SEPARATED,
    ImpactRun,
    SwitchedForce,
    central_difference_bounds,
    entry_phases,
    simulate_impacts,
    undamped_exit_ratios,
    unit_ratio_steps,
)
from dtcrit.impact.sweep import (
    PhaseStats,
    energy_created_ranges,
    energy_errors,
    linear_bound,
    phase_stats,
    sweep,
    sweep_grid,
)

__all__ = [
    "CENTRAL_DIFFERENCE_FAMILY",
    "CONVENTION",
    "DEFAULT_ENERGY_THRESHOLD",
    "DEFAULT_PHASES",
    "DIVERGED",
    "ExactImpact",
    "FORCE_CONVENTION",
    "HertzExact",
    "ImpactRun",
    "MAX_CUTOFF",
    "MAX_OMEGA_DT",
    "MAX_PHASES",
    "MIN_OMEGA_DT",
    "PhaseStats",
    "RATIO_RTOL",
    "STANDARD_ZETAS",
    "STATUS_DIVERGED",
    "STATUS_EXITED",
    "STATUS_NOT_SEPARATED",
    "SWEEP_STEP",
    "SWEEP_TOP",
    "SwitchedForce",
    "UNITS",
    "UNIT_STEPS_FROM",
    "central_difference_bounds",
    "check_energy_threshold",
    "check_omega_dt",
    "check_phases",
    "check_zeta",
    "energy_created_ranges",
    "energy_errors",
    "entry_phases",
    "exact_impact",
    "hertz_dimensional",
    "hertz_exact",
    "hertz_study",
    "impact_report",
    "linear_bound",
    "phase_stats",
    "plot_hertz",
    "plot_phase_curve",
    "plot_sweep",
    "simulate_impacts",
    "sweep",
    "sweep_grid",
    "to_json",
    "undamped_exit_ratios",
    "unit_ratio_steps",
]
