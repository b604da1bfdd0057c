"""The impact report of ``dtcrit impact``: per damping ratio, the sweep against the exact impact and the
linear bound, the undamped closed forms, and its JSON form (schema ``dtcrit-impact/1``,
``dtcrit/schemas/dtcrit-impact-1.json``; its keys on the reference page
``docs/reference/generated/json-dtcrit-impact-1``, the envelope in ``docs/explanation/conventions.md``).
"""
from __future__ import annotations

import numpy as np

from dtcrit.impact.conventions import (
    CENTRAL_DIFFERENCE_FAMILY,
    CONVENTION,
    DEFAULT_ENERGY_THRESHOLD,
    DEFAULT_PHASES,
    RATIO_RTOL,
    STANDARD_ZETAS,
    SWEEP_STEP,
    UNIT_STEPS_FROM,
    UNITS,
    _json_number,
    check_energy_threshold,
    check_omega_dt,
    check_phases,
    check_zeta,
)
from dtcrit.impact.exact import exact_impact
from dtcrit.impact.hertz import hertz_study
from dtcrit.impact.stepped import (
    STATUS_EXITED,
    ImpactRun,
    central_difference_bounds,
    simulate_impacts,
    undamped_exit_ratios,
    unit_ratio_steps,
)
from dtcrit.impact.sweep import PhaseStats, energy_created_ranges, linear_bound, sweep, sweep_grid
from dtcrit.integrators.stability import check_integrator
from dtcrit.json_meta import envelope

JSON_SCHEMA = "dtcrit-impact/1"
_STEP = "omega*dt, omega = sqrt(k/m) (rows of hertz: omega_t*dt)"
_RATIO = "v_exit/v_entry"
JSON_UNITS = {
    "omega_dt": _STEP, "critical_omega_dt": "omega*dt", "above_exact": "omega*dt (ranges [from, to])",
    "above_one": "omega*dt (ranges [from, to])", "linearised_bound": "omega_t*dt",
    "largest_omega_dt_within_threshold": "omega_t*dt", "linear_contact_largest_omega_dt_within_threshold": "omega*dt",
    "duration": "1/omega (in hertz.exact: 1/omega_t)", "overlap_at_release": "v0/omega", "duration_dmax_over_v0": "dmax/v0",
    "exit_ratio": _RATIO, "exact_exit_ratio": _RATIO, "min": _RATIO, "mean": _RATIO, "max": _RATIO, "on_step": _RATIO,
    "largest_ratio_below_critical": _RATIO,
}
"""The scale of every scaled quantity of an impact document (the study is nondimensional: ``scaling``); the
other numbers are counts, fractions, damping ratios and relative errors."""


def _zeta_summary(name: str, zeta: float, grid, stats: list[PhaseStats]) -> dict:
    ex = exact_impact(zeta)
    mx = [s.max for s in stats]
    tau_star = linear_bound(name, zeta)
    below = [s.max for s in stats if s.omega_dt < tau_star]
    return {
        "zeta": zeta,
        "exact_exit_ratio": ex.exit_ratio,
        "critical_omega_dt": tau_star,
        "energy_created": {
            "above_exact": energy_created_ranges(grid, mx, ex.exit_ratio),
            "above_one": energy_created_ranges(grid, mx, 1.0),
        },
        "largest_ratio_below_critical": _json_number(max(below)) if below else None,
        "numerical": [s.as_dict() for s in stats],
    }


def impact_report(
    integrator: str,
    zeta=0.0,
    omega_dt=None,
    n_phases: int = DEFAULT_PHASES,
    hertz: bool | None = None,
    energy_threshold: float = DEFAULT_ENERGY_THRESHOLD,
    step: float = SWEEP_STEP,
    standard: bool | None = None,
) -> dict:
    """JSON-ready report for one integrator and damping ratio.

    ``omega_dt=None`` sweeps ``sweep_grid(step)``; a number evaluates that step only.  ``hertz`` and
    ``standard`` (summaries for zeta in ``STANDARD_ZETAS``) default to on for a sweep.
    Keys starting with ``_`` carry arrays for the figures and are not part of the JSON.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    zeta : float
        Damping ratio of the linear contact.
    omega_dt : float, optional
        One step omega dt to evaluate; a sweep over ``sweep_grid(step)`` when omitted.
    n_phases : int
        Number of equally spaced entry phases per step.
    hertz : bool, optional
        Add the undamped Hertz study (default: on for a sweep).
    energy_threshold : float
        Largest accepted energy error of the Hertz study, in (0, 1).
    step : float
        Spacing of the sweep's grid in omega dt.
    standard : bool, optional
        Add summaries for the damping ratios ``STANDARD_ZETAS`` (default: on for a sweep).

    Returns
    -------
    dict
        The report (see ``to_json`` for its public form).

    Examples
    --------
    >>> from dtcrit import impact_report
    >>> rep = impact_report("velocity-verlet", zeta=0.1, omega_dt=0.5)
    >>> rep["integrator"], rep["critical_omega_dt"] > 0.5
    ('velocity-verlet', True)
    """
    name = check_integrator(integrator)
    z = check_zeta(zeta)
    n_ph = check_phases(n_phases)
    is_sweep = omega_dt is None
    grid = sweep_grid(step) if is_sweep else np.array([check_omega_dt(omega_dt)])
    hertz = is_sweep if hertz is None else hertz
    standard = is_sweep if standard is None else standard
    if hertz:
        check_energy_threshold(energy_threshold)
    ex = exact_impact(z)
    run, stats = sweep(name, z, grid, n_ph)
    report: dict = {
        "integrator": name,
        "zeta": z,
        "scaling": UNITS,
        "convention": CONVENTION,
        "critical_omega_dt": linear_bound(name, z),
        "exact": ex.as_dict(),
        "phases": n_ph,
        "numerical": [s.as_dict() for s in stats],
        "energy_created": {
            "above_exact": energy_created_ranges(grid, [s.max for s in stats], ex.exit_ratio),
            "above_one": energy_created_ranges(grid, [s.max for s in stats], 1.0),
            "criterion": f"max over entry phases > reference * (1 + {RATIO_RTOL:g}); runs of grid points",
        },
        "_runs": {z: (grid, stats)},
        "_run": run,
    }
    if z == 0:
        closed = undamped_exit_ratios(name, grid, run.phases)
        if closed is not None:
            report["undamped_closed_form"] = _closed_form_section(name, grid, run, closed)
    if standard:
        summaries = []
        for zs in sorted(set(STANDARD_ZETAS) | {z}):
            if zs == z:
                st = stats
            else:
                st = sweep(name, zs, grid, n_ph)[1]
                report["_runs"][zs] = (grid, st)
            summaries.append(_zeta_summary(name, zs, grid, st))
        report["by_zeta"] = summaries
    if hertz:
        report["hertz"] = hertz_study(name, grid, n_ph, energy_threshold)
    return report


def _closed_form_section(name: str, grid, run: ImpactRun, closed: np.ndarray) -> dict:
    ok = np.isfinite(closed) & (run.status == STATUS_EXITED)
    with np.errstate(all="ignore"):
        rel = np.abs(run.ratios - closed) / np.abs(closed)
    section: dict = {
        "max_relative_difference_from_simulation": float(np.max(rel[ok])) if ok.any() else None,
        "compared_runs": int(ok.sum()),
    }
    if name in CENTRAL_DIFFERENCE_FAMILY:
        section["formula"] = (
            "v_e/v0 = sqrt((1 - tau^2 phi(1-phi)) / (1 - tau^2 psi(1-psi))), psi the exit phase; "
            "bounds sqrt(1 - tau^2/4) <= v_e/v0 <= 1/sqrt(1 - tau^2/4); v_e = v0 for every phase at "
            "tau_N = 2 sin(pi/(2N))"
        )
        steps = unit_ratio_steps(max(float(grid[0]), UNIT_STEPS_FROM), 2.0)
        pts = []
        if steps:
            taus = [t for _, t in steps if t < 2.0]
            if taus:
                r = simulate_impacts(name, taus, run.phases, 0.0).ratios
                for (N, t), row in zip([s for s in steps if s[1] < 2.0], r):
                    pts.append({"N": N, "omega_dt": t, "max_abs_ratio_minus_one": float(np.max(np.abs(row - 1)))})
        section["unit_ratio_steps"] = pts
        lo, hi = central_difference_bounds(grid)
        inside = np.all((run.ratios <= hi[:, None] * (1 + 1e-12)) & (run.ratios >= lo[:, None] * (1 - 1e-12)), axis=1)
        section["bounds_hold_on_grid_below_2"] = bool(np.all(inside[grid < 2.0]))
    else:
        section["formula"] = "(x_n, v_n) = (1 + tau^2)^(n/2) R(n arctan tau)(phi tau, 1); v_e/v0 = |v_m|"
    return section


def _plain(value):
    """``value`` without the private (array) entries, recursively; non-finite numbers become null."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items() if not str(k).startswith("_")}
    if isinstance(value, list):
        return [_plain(v) for v in value]
    return _json_number(value)


def to_json(report: dict) -> dict:
    """The documented JSON form of a report (schema ``dtcrit-impact/1``): the envelope of every dtcrit JSON
    (:func:`dtcrit.json_meta.envelope`), then the report without its private entries.

    Parameters
    ----------
    report : dict
        A report made by ``impact_report``.

    Returns
    -------
    dict
        The JSON document; non-finite numbers become null.
    """
    return {**envelope(JSON_SCHEMA, JSON_UNITS), **_plain(report)}
