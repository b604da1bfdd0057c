"""The Hertz impact ``m d'' = -k_h d^(3/2)`` time-stepped in units of the exact maximum overlap and of
the tangent frequency there (``u'' = -(2/3) u^(3/2)``, entry speed ``sqrt(8/15)``): energy error against
``omega_t dt``, comparable with the linearised bound.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from dtcrit._generated import impact as _gen
from dtcrit.impact.conventions import DEFAULT_ENERGY_THRESHOLD, DEFAULT_PHASES, _json_number, check_energy_threshold
from dtcrit.impact.stepped import entry_phases, simulate_impacts
from dtcrit.impact.sweep import energy_errors, linear_bound, phase_stats, sweep_grid
from dtcrit.integrators.stability import check_integrator


def hertz_study(
    integrator: str,
    omega_dt=None,
    n_phases: int = DEFAULT_PHASES,
    threshold: float = DEFAULT_ENERGY_THRESHOLD,
) -> dict:
    """Undamped Hertz impact stepped at omega_t dt (omega_t: tangent frequency at maximum overlap).

    Reports the exit ratio over phases per step, the energy error (max |v_e^2/v0^2 - 1|), the
    integrator's undamped linear bound tau* applied to the tangent stiffness at maximum overlap, the
    energy error at tau*, and the largest grid step below which the error stays under ``threshold``
    (same quantities for the linear contact at zeta = 0, for comparison).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    omega_dt : float or array_like, optional
        Steps omega_t dt to evaluate; ``sweep_grid()`` when omitted.
    n_phases : int
        Number of equally spaced entry phases per step.
    threshold : float
        Largest accepted energy error ``|v_exit^2/v0^2 - 1|``, in (0, 1).

    Returns
    -------
    dict
        The study, JSON-ready apart from the private ``_``-prefixed arrays the figures use.
    """
    name = check_integrator(integrator)
    thr = check_energy_threshold(threshold)
    grid = sweep_grid() if omega_dt is None else np.atleast_1d(np.asarray(omega_dt, dtype=float))
    phases = entry_phases(n_phases)
    run = simulate_impacts(name, grid, phases, 0.0, "hertz")
    stats = phase_stats(run)
    err = energy_errors(run)
    lin_run = simulate_impacts(name, grid, phases, 0.0, "linear")
    lin_err = energy_errors(lin_run)
    tau_star = linear_bound(name, 0.0)
    out: dict[str, Any] = {
        "integrator": name,
        "exact": {
            "duration": _gen.HERTZ_SCALED_DURATION,
            "duration_dmax_over_v0": _gen.HERTZ_DURATION_FACTOR,
            "exit_ratio": 1.0,
            "units": "time in 1/omega_t, omega_t = sqrt(1.5 k_h dmax^(1/2)/m) (tangent at the exact maximum overlap)",
        },
        "energy_threshold": thr,
        "linearised_bound": tau_star,
        "numerical": [dict(s.as_dict(), energy_error=_json_number(e)) for s, e in zip(stats, err)],
        "largest_omega_dt_within_threshold": _largest_within(grid, err, thr),
        "linear_contact_largest_omega_dt_within_threshold": _largest_within(grid, lin_err, thr),
    }
    if tau_star > 0:
        at = simulate_impacts(name, [tau_star], phases, 0.0, "hertz")
        lin_at = simulate_impacts(name, [tau_star * (1 - 1e-9)], phases, 0.0, "linear")
        e_at = float(energy_errors(at)[0])
        out["energy_error_at_bound"] = _json_number(e_at)
        out["linear_contact_energy_error_at_bound"] = _json_number(float(energy_errors(lin_at)[0]))
        out["bound_keeps_error_below_threshold"] = bool(e_at <= thr)
        largest = out["largest_omega_dt_within_threshold"]
        out["verdict"] = (
            f"at the linearised bound omega_t*dt = {tau_star:.4g} the Hertz energy error is {e_at:.3g} "
            f"({'within' if e_at <= thr else 'above'} the threshold {thr:g}); the error stays within the "
            f"threshold up to omega_t*dt = {largest:.4g} ({largest / tau_star:.3g} of the bound)"
            if largest is not None
            else f"at the linearised bound the Hertz energy error is {e_at:.3g}; no grid step keeps it within {thr:g}"
        )
    else:
        out["energy_error_at_bound"] = None
        out["bound_keeps_error_below_threshold"] = None
        out["verdict"] = "the integrator has no stable step for the undamped linear contact (bound 0)"
    out["_grid"] = grid
    out["_energy_error"] = err
    out["_linear_energy_error"] = lin_err
    return out


def _largest_within(grid, err, thr) -> float | None:
    """Largest grid step such that the error is <= thr at it and at every smaller grid step."""
    ok = np.asarray(err) <= thr
    if not ok[0]:
        return None
    bad = np.nonzero(~ok)[0]
    last = (bad[0] - 1) if bad.size else len(ok) - 1
    return float(np.asarray(grid)[last])
