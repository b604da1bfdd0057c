"""Errors of a time-stepped impact, worst over the entry phase, and the step that resolves a collision.

The worst case over the continuous entry phase: ``SAMPLE_PHASES`` equally spaced phases, then, per
quantity, a dense local grid around the two worst samples and scipy's bounded minimisation
(``minimize_scalar(method="bounded")``) from the best of it.  The resolution step for a tolerance is
the largest ``dt = t_c/N`` such that every smaller step also keeps each quantity within it: the error
oscillates in N, so N is scanned downward on a geometric grid of relative spacing ``1/GRID`` from
``N_top`` (twice the first doubling at which the sampled error is at most half the tolerance; above
it the error decays as a power of 1/N) to the first violation, and the bracket is refined by
bisection.  A grid point is optimised over the phase only when its sampled error exceeds
``REFINE_ABOVE`` of the tolerance (the optimisation raised the sampled worst case by less than that
in every case measured).  The guarantee rests
on that grid: a violation narrower than ``1/GRID`` in N between two grid points can be missed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from dtcrit.collisions.reference import CollisionOutcome, solve_reference
from dtcrit.collisions.scaled import ScaledLaw
from dtcrit.collisions.stepping import MAX_STEPS_PER_COLLISION, run_lanes
from dtcrit.errors import InputError

SAMPLE_PHASES = 48
LOCAL_POINTS = 16
GRID = 200
QUANTITIES: tuple[str, ...] = ("restitution", "peak_overlap", "duration", "energy_gain")
PHASE_TOP = 1.0 - 1e-12
REFINE_ABOVE = 0.9  # a grid point is optimised over the phase when its sampled error exceeds this share of tol
BISECTIONS = 8


def _errors(r: dict, ref: CollisionOutcome) -> dict:
    """Relative errors per lane; ``energy_gain`` is the excess of exit energy over the continuum's."""
    with np.errstate(all="ignore"):
        out = {
            "restitution": np.abs(r["restitution"] / ref.restitution - 1.0),
            "peak_overlap": np.abs(r["peak_overlap"] / ref.peak_overlap - 1.0),
            "duration": np.abs(r["duration"] / ref.duration - 1.0),
            "energy_gain": np.maximum(r["energy_ratio"] / ref.energy_ratio - 1.0, 0.0),
        }
    return {k: np.where(np.isnan(v), np.inf, v) for k, v in out.items()}


def sampled_errors(scheme: str, law: ScaledLaw, steps, n_phases: int = SAMPLE_PHASES) -> dict:
    """Worst error over ``n_phases`` equally spaced phases, per quantity, for each N of ``steps``.

    Parameters
    ----------
    scheme : str
        A key of ``INTEGRATORS``.
    law : ScaledLaw
        The scaled law.
    steps : array_like
        Steps per collision N.
    n_phases : int
        Number of sampled phases.

    Returns
    -------
    dict
        quantity -> array (len(steps),) of the sampled worst relative error.
    """
    ns = np.atleast_1d(np.asarray(steps, dtype=float))
    ph = np.arange(n_phases) / n_phases
    r = run_lanes(scheme, law, ns[:, None], ph[None, :])
    ref = solve_reference(law)
    return {k: v.reshape(ns.size, n_phases).max(axis=1) for k, v in _errors(r, ref).items()}


def worst_errors(scheme: str, law: ScaledLaw, n: float, quantities=QUANTITIES) -> dict:
    """Worst relative error over the continuous entry phase at N = ``n`` steps per collision.

    Parameters
    ----------
    scheme : str
        A key of ``INTEGRATORS``.
    law : ScaledLaw
        The scaled law.
    n : float
        Steps per collision.
    quantities : tuple of str
        Which of ``QUANTITIES`` to maximise (the others are the sampled maximum).

    Returns
    -------
    dict
        quantity -> worst relative error (``inf`` when a run did not separate or blew up).
    """
    ref = solve_reference(law)
    ph = np.arange(SAMPLE_PHASES) / SAMPLE_PHASES
    errs = _errors(run_lanes(scheme, law, n, ph), ref)
    out = {k: float(v.max()) for k, v in errs.items()}
    width = 1.0 / SAMPLE_PHASES
    for q in quantities:
        if not math.isfinite(out[q]):
            continue
        best_phases = ph[np.argsort(errs[q])[-2:]]
        local = np.clip((best_phases[:, None] + np.linspace(-width, width, LOCAL_POINTS)[None, :]).ravel(), 0.0, PHASE_TOP)
        le = _errors(run_lanes(scheme, law, n, local), ref)[q]
        out[q] = max(out[q], float(le.max()))
        start = float(local[int(np.argmax(le))])
        step = 2.0 * width / (LOCAL_POINTS - 1)

        def neg(phi, q=q):
            return -float(_errors(run_lanes(scheme, law, n, [phi]), ref)[q][0])

        res = minimize_scalar(neg, bounds=(max(0.0, start - step), min(PHASE_TOP, start + step)),
                              method="bounded", options={"xatol": 1e-6})
        out[q] = max(out[q], -float(res.fun))
    return out


@dataclass(frozen=True)
class Resolution:
    """The step that resolves a collision within ``tol``.

    Parameters
    ----------
    steps_per_collision : float
        ``N_res``: every ``N >= N_res`` keeps each quantity within ``tol`` (``inf`` if none up to the cap).
    dt_over_tc : float
        ``1/N_res``.
    tol : float
        The relative tolerance.
    quantities : tuple of str
        The quantities held within it.
    worst : dict
        quantity -> worst relative error over the phase at ``N_res``.
    """

    steps_per_collision: float
    dt_over_tc: float
    tol: float
    quantities: tuple
    worst: dict


def check_tol(tol) -> float:
    """A relative tolerance, checked: a number in (0, 1).

    Parameters
    ----------
    tol : float
        The tolerance.

    Returns
    -------
    float
        ``tol``.
    """
    try:
        t = float(tol)
    except (TypeError, ValueError):
        raise InputError("tol", f"must be a number (got {tol!r})") from None
    if not 0.0 < t < 1.0:
        raise InputError("tol", f"must lie in (0, 1) (got {tol!r})")
    return t


def _ratio(errs: dict, quantities, tol: float) -> float:
    return max(errs[q] for q in quantities) / tol


def resolve(scheme: str, law: ScaledLaw, tol: float, quantities) -> Resolution:
    """The resolution step (module docstring) of ``scheme`` on ``law``.

    Parameters
    ----------
    scheme : str
        A key of ``INTEGRATORS``.
    law : ScaledLaw
        The scaled law.
    tol : float
        Relative tolerance in (0, 1).
    quantities : tuple of str
        Quantities of ``QUANTITIES`` to hold within ``tol``.

    Returns
    -------
    Resolution
        ``N_res`` and the worst errors there.
    """
    tol = check_tol(tol)
    quantities = tuple(quantities)
    bad = [q for q in quantities if q not in QUANTITIES]
    if bad or not quantities:
        raise InputError("quantities", f"must be among {', '.join(QUANTITIES)} (got {quantities!r})")
    n_top = 4.0
    while _ratio({k: v[0] for k, v in sampled_errors(scheme, law, [n_top]).items()}, quantities, tol) > 0.5:
        n_top *= 2.0
        if n_top > MAX_STEPS_PER_COLLISION / 2:
            return Resolution(math.inf, 0.0, tol, quantities, {})
    n_top *= 2.0
    grid = n_top * (1.0 - 1.0 / GRID) ** np.arange(int(math.log(n_top) / -math.log(1.0 - 1.0 / GRID)) + 1)
    grid = grid[grid >= 1.0]
    ok_n, bad_n = n_top, None
    for chunk in np.array_split(grid, max(1, grid.size // 64)):
        samp = sampled_errors(scheme, law, chunk)
        for i, n in enumerate(chunk):
            r = _ratio({k: v[i] for k, v in samp.items()}, quantities, tol)
            if r <= REFINE_ABOVE:
                ok_n = float(n)
                continue
            if r > 1.0 or _ratio(worst_errors(scheme, law, float(n), quantities), quantities, tol) > 1.0:
                bad_n = float(n)
                break
            ok_n = float(n)
        if bad_n is not None:
            break
    if bad_n is not None:
        for _ in range(BISECTIONS):
            mid = math.sqrt(ok_n * bad_n)
            if _ratio(worst_errors(scheme, law, mid, quantities), quantities, tol) > 1.0:
                bad_n = mid
            else:
                ok_n = mid
    worst = worst_errors(scheme, law, ok_n, quantities)
    return Resolution(ok_n, 1.0 / ok_n, tol, quantities, worst)


__all__ = ["QUANTITIES", "SAMPLE_PHASES", "GRID", "Resolution", "sampled_errors", "worst_errors", "resolve", "check_tol"]
