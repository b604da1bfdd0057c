"""Sweeps of the time-stepped impact over ``tau = omega dt`` and entry phase: exit-speed statistics per
step, where energy is created, and the linear stability bound beside them.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from dtcrit.impact.conventions import (
    DEFAULT_PHASES,
    RATIO_RTOL,
    SWEEP_STEP,
    SWEEP_TOP,
    _json_number,
    check_omega_dt,
    check_zeta,
)
from dtcrit.impact.stepped import STATUS_DIVERGED, STATUS_EXITED, ImpactRun, entry_phases, simulate_impacts
from dtcrit.integrators.stability import critical_dt

# ---------------------------------------------------------------------------------------------
# statistics over phases, sweeps
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class PhaseStats:
    """v_exit/v0 over the entry phases at one omega*dt.

    Parameters
    ----------
    omega_dt : float
        The step omega dt.
    min : float
        Smallest exit ratio over the phases.
    mean : float
        Mean exit ratio over the phases.
    max : float
        Largest exit ratio over the phases.
    on_step : float
        Exit ratio at phase 0 (contact beginning exactly on a step).
    separated : float
        Fraction of phases that separated before the cut-off.
    diverged : int
        Number of phases whose state blew up (ratio inf).
    """

    omega_dt: float
    min: float
    mean: float
    max: float
    on_step: float  # phase 0: contact begins exactly on a step
    separated: float  # fraction of phases that separated before the cut-off
    diverged: int  # phases whose state blew up (ratio inf)

    def as_dict(self) -> dict:
        """The JSON form: the fields by name, non-finite numbers as null.

        Returns
        -------
        dict
            One entry per field.
        """
        return {k: _json_number(v) for k, v in asdict(self).items()}


def phase_stats(run: ImpactRun) -> list[PhaseStats]:
    """The exit ratios of a run summarised over the entry phases, one entry per step.

    Parameters
    ----------
    run : ImpactRun
        A run of ``simulate_impacts``.

    Returns
    -------
    list of PhaseStats
        One summary per omega dt of the run, in its order.
    """
    out = []
    for i, t in enumerate(run.omega_dt):
        r = run.ratios[i]
        st = run.status[i]
        on_step = r[run.phases == 0.0]
        out.append(
            PhaseStats(
                omega_dt=float(t),
                min=float(np.min(r)),
                mean=float(np.mean(r)),
                max=float(np.max(r)),
                on_step=float(on_step[0]) if on_step.size else math.nan,
                separated=float(np.mean(st == STATUS_EXITED)),
                diverged=int(np.sum(st == STATUS_DIVERGED)),
            )
        )
    return out


def sweep_grid(step: float = SWEEP_STEP, top: float = SWEEP_TOP) -> np.ndarray:
    """omega*dt = k*top/n, k = 1..n with n = round(top/step): a uniform grid over (0, top].

    Parameters
    ----------
    step : float
        Requested spacing (the grid's spacing is ``top/n``).
    top : float
        Largest step of the grid.

    Returns
    -------
    numpy.ndarray
        The grid, rounded to 12 decimals.
    """
    step = check_omega_dt(step, "step")
    n = max(1, int(round(top / step)))
    return np.round(np.arange(1, n + 1) * top / n, 12)


def sweep(integrator: str, zeta, omega_dt=None, n_phases: int = DEFAULT_PHASES, contact: str = "linear"):
    """(ImpactRun, [PhaseStats]) over ``omega_dt`` (default ``sweep_grid()``) and ``n_phases`` phases.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    zeta : float
        Damping ratio (linear contact).
    omega_dt : array_like, optional
        Steps omega dt; ``sweep_grid()`` when omitted.
    n_phases : int
        Number of equally spaced entry phases.
    contact : str
        ``"linear"`` or ``"hertz"``.

    Returns
    -------
    tuple
        The ``ImpactRun`` and its per-step ``PhaseStats``.
    """
    grid = sweep_grid() if omega_dt is None else omega_dt
    run = simulate_impacts(integrator, grid, entry_phases(n_phases), zeta, contact)
    return run, phase_stats(run)


def energy_created_ranges(omega_dt, values, reference, rtol: float = RATIO_RTOL) -> list[list[float]]:
    """Contiguous runs [lo, hi] of the grid where ``values > reference (1 + rtol)``.

    Parameters
    ----------
    omega_dt : array_like
        The grid of steps.
    values : array_like
        Exit ratios on the grid.
    reference : array_like or float
        Ratio not to exceed (e.g. the exact impact's).
    rtol : float
        Relative tolerance above the reference.

    Returns
    -------
    list of list of float
        ``[lo, hi]`` grid steps bounding each run where energy is created.
    """
    t = np.asarray(omega_dt, dtype=float)
    above = np.asarray(values, dtype=float) > np.asarray(reference, dtype=float) * (1 + rtol)
    out: list[list[float]] = []
    start = None
    for i, flag in enumerate(above):
        if flag and start is None:
            start = i
        if not flag and start is not None:
            out.append([float(t[start]), float(t[i - 1])])
            start = None
    if start is not None:
        out.append([float(t[start]), float(t[-1])])
    return out


def linear_bound(integrator: str, zeta) -> float:
    """omega*dt at the integrator's exact linear stability bound (0 when no step is stable).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    zeta : float
        Damping ratio (C = 2 zeta with K = 1).

    Returns
    -------
    float
        The critical omega dt of the persistent contact.
    """
    return critical_dt(integrator, 1.0, 2.0 * check_zeta(zeta), 1.0).omega_dt


# ---------------------------------------------------------------------------------------------
# Hertz
# ---------------------------------------------------------------------------------------------

def energy_errors(run: ImpactRun) -> np.ndarray:
    """Largest energy error over phases, max |v_exit^2/v0^2 - 1|, per omega_t*dt (undamped: exact value 0).

    Parameters
    ----------
    run : ImpactRun
        A run of ``simulate_impacts``.

    Returns
    -------
    numpy.ndarray
        One error per step of the run.
    """
    with np.errstate(all="ignore"):
        return np.max(np.abs(run.ratios**2 - 1.0), axis=1)
