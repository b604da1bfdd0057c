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

The search takes the errors as functions (``first_top``, ``descending_grid``, ``scan_down``,
``bisect_down``), so that other impacts (``oblique_resolution``) are held to the same rule.
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


def first_top(sampled_ratio, start: float = 4.0) -> float | None:
    """The top of the downward scan: twice the first doubling of ``start`` whose sampled error is at most half the tolerance.

    Parameters
    ----------
    sampled_ratio : callable
        ``sampled_ratio(ns)`` -> array: the sampled worst error over ``tol`` at each N of the array ``ns``.
    start : float
        The first N tried.

    Returns
    -------
    float or None
        ``N_top``, or None when no doubling up to ``MAX_STEPS_PER_COLLISION/2`` reaches half the tolerance.
    """
    n_top = start
    while sampled_ratio(np.array([n_top]))[0] > 0.5:
        n_top *= 2.0
        if n_top > MAX_STEPS_PER_COLLISION / 2:
            return None
    return n_top * 2.0


def descending_grid(n_top: float, spacing: float = 1.0 / GRID, n_bottom: float = 1.0) -> np.ndarray:
    """The geometric grid ``n_top (1 - spacing)^k`` down to ``n_bottom``.

    Parameters
    ----------
    n_top : float
        First (largest) N.
    spacing : float
        Relative spacing in (0, 1).
    n_bottom : float
        Smallest N kept.

    Returns
    -------
    numpy.ndarray
        The grid, descending.
    """
    grid = n_top * (1.0 - spacing) ** np.arange(int(math.log(n_top / n_bottom) / -math.log(1.0 - spacing)) + 1)
    return grid[grid >= n_bottom]


def scan_down(sampled_ratio, worst_ratio, grid, chunk: int = 64,
              refine_above: float = REFINE_ABOVE) -> tuple[float, float | None]:
    """Scan a descending grid of N to the first violation of the tolerance.

    A grid point whose sampled ratio is at most ``refine_above`` is kept; above it the worst over the
    continuous phase (``worst_ratio``) decides.

    Parameters
    ----------
    sampled_ratio : callable
        ``sampled_ratio(ns)`` -> array of sampled error over tolerance (as ``first_top``).
    worst_ratio : callable
        ``worst_ratio(n)`` -> the worst error over the continuous phase over tolerance at N = ``n``.
    grid : array_like
        Descending N.
    chunk : int
        About this many grid points are sampled per call of ``sampled_ratio``.
    refine_above : float
        Sampled ratio above which the phase is optimised (``REFINE_ABOVE`` for ``SAMPLE_PHASES`` phases).

    Returns
    -------
    tuple of float and (float or None)
        The last N kept (``grid[0]`` when none) and the first violation (None when none).
    """
    grid = np.asarray(grid, dtype=float)
    ok_n, bad_n = float(grid[0]), None
    for part in np.array_split(grid, max(1, grid.size // chunk)):
        ratios = sampled_ratio(part)
        for i, n in enumerate(part):
            r = ratios[i]
            if r <= refine_above:
                ok_n = float(n)
                continue
            if r > 1.0 or worst_ratio(float(n)) > 1.0:
                return ok_n, float(n)
            ok_n = float(n)
    return ok_n, bad_n


def bisect_down(worst_ratio, ok_n: float, bad_n: float, bisections: int = BISECTIONS) -> float:
    """Geometric bisection of the bracket ``[bad_n, ok_n]`` on ``worst_ratio``; the N kept.

    Parameters
    ----------
    worst_ratio : callable
        As ``scan_down``.
    ok_n, bad_n : float
        A kept N and the violation below it.
    bisections : int
        Number of halvings (in log N).

    Returns
    -------
    float
        The smallest N of the bracket found within the tolerance.
    """
    for _ in range(bisections):
        mid = math.sqrt(ok_n * bad_n)
        if worst_ratio(mid) > 1.0:
            bad_n = mid
        else:
            ok_n = mid
    return ok_n


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

    def sampled_ratio(ns):
        samp = sampled_errors(scheme, law, ns)
        return np.array([_ratio({k: v[i] for k, v in samp.items()}, quantities, tol) for i in range(len(ns))])

    def worst_ratio(n):
        return _ratio(worst_errors(scheme, law, n, quantities), quantities, tol)

    n_top = first_top(sampled_ratio)
    if n_top is None:
        return Resolution(math.inf, 0.0, tol, quantities, {})
    ok_n, bad_n = scan_down(sampled_ratio, worst_ratio, descending_grid(n_top))
    if bad_n is not None:
        ok_n = bisect_down(worst_ratio, ok_n, bad_n)
    worst = worst_errors(scheme, law, ok_n, quantities)
    return Resolution(ok_n, 1.0 / ok_n, tol, quantities, worst)


__all__ = ["QUANTITIES", "SAMPLE_PHASES", "GRID", "Resolution", "sampled_errors", "worst_errors", "resolve", "check_tol",
           "first_top", "descending_grid", "scan_down", "bisect_down"]
