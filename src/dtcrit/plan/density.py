"""Density scaling with the least added mass whose critical step the exact eigen-solve confirms above a target step.

:func:`plan_density_scaling` is the API behind ``dtcrit plan``'s density scaling:

1. the *sufficient* per-body factors of the Gershgorin and block-diagonal bounds (``dtcrit.plan.bounds``):
   with either set the scaled packing's critical step is at least the target (``lambda_max <= 4``),
   whatever the eigen-solver says;
2. tightened with the *exact* critical step of the scaled packing (``dtcrit.plan.exact``, the audit's
   solve): four monotone families of factors, each from 1 (no scaling) to a set whose step is known to reach the target, are
   bisected on their parameter -- the better bound's factors interpolated towards 1, each bound's
   per-body demand and YADE's each scaled by a common number and floored at 1 -- and the least added
   mass over them and the exact uniform factor is kept;
3. every answer is one whose exact critical step is at least ``target x (1 + CONFIRM_MARGIN)``: a
   plan the exact solve did not confirm is never returned.

Every step is of the packing with the scaled masses *and* the contacts the engine's law gives at them
(``dtcrit.plan.rederive``): LAMMPS recomputes ``c_n = m_eff gamma_n`` every step, so a dashpot grows
with the masses, and the step planned is the one ``dtcrit audit`` computes for ``--write-dump``'s file.

YADE's rule (``NewtonIntegrator.densityScaling`` with ``GlobalStiffnessTimeStepper.targetDt``,
``pkg/dem/GlobalStiffnessTimeStepper.cpp`` ``findTimeStepFromBody``): each body's acceleration is
multiplied by ``densityScaling = (dt_b / targetDt)^2``, ``dt_b`` its stepper step at the safety ``s``
(``dtcrit.packing.bounds.yade_stepper``: ``1.41044 s sqrt(min(m/K, I/K_rot))``), i.e. a mass factor
``targetDt^2 / dt_b^2`` where that exceeds 1.  That is what YADE 2023.02a applies, read back from
``state.densityScaling`` after a run to 1e-6 (``tests/engines/test_engine_density_scaling.py``); a
copy of the source read elsewhere (SudoDEM) multiplies by ``s`` once more, which YADE does not do.
On its first call the bodies that need no scaling get ``1/1.0001`` (0.01 % lighter) and each later
call lightens them by 1.0001 more; the rule here is the first call's with those bodies at 1.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from dtcrit.errors import InputError
from dtcrit.physics import rules_of_thumb as rot

from dtcrit.plan.exact import ScaledStep, check_target, confirmed_uniform, free_bodies, scaled_packing

__all__ = ["CONFIRM_MARGIN", "DEFAULT_MAX_FACTOR", "DensityPlan", "plan_density_scaling", "yade_rule_factors"]

CONFIRM_MARGIN = 1e-6
"""A plan's exact critical step is at least ``target x (1 + CONFIRM_MARGIN)``: room for the eigen-solver's
own rounding, so an independent solve of the scaled packing finds it at or above the target."""
DEFAULT_MAX_FACTOR = 100.0
"""The largest mass factor of any body (``--max-factor``)."""
BISECTION_RTOL = 1e-3
"""Each family's parameter is bisected to this relative width."""


@dataclass(frozen=True)
class DensityPlan:
    """Per-body mass (and inertia) factors whose exact critical step is at least ``target_dt x (1 + CONFIRM_MARGIN)``.

    Parameters
    ----------
    target_dt : float
        The target step [s].
    dt_crit : float
        The packing's exact critical step today [s] (as ``dtcrit audit`` reports it).
    factors : numpy.ndarray
        ``(N,)`` factors >= 1 on each body's mass and principal moments, in the snapshot's body order.
    dt_crit_scaled : float
        The exact critical step of the scaled packing [s] (its contacts at the scaled masses),
        >= ``target_dt x (1 + CONFIRM_MARGIN)``.
    added_mass_fraction : float
        ``sum m_p (f_p - 1) / sum m_p`` over the free bodies.
    family : str
        Which family gave the least added mass (``bound interpolation``, ``block_diagonal demand``,
        ``gershgorin demand``, ``YADE demand``, ``uniform``).
    bound : str
        The bound whose factors are the guaranteed start (``gershgorin`` or ``block_diagonal``; ``uniform``
        when neither bound gets below 4 within ``max_factor``, possible with dashpots ``m_eff gamma``).
    bound_factors : numpy.ndarray
        ``(N,)`` its sufficient factors (critical step >= the target by the bound alone: ``lambda_max <= 4``).
    bound_added_mass_fraction : float
        Their added mass fraction.
    uniform_factor : float
        The least common factor of every free body that reaches the target (exact).
    uniform_added_mass_fraction : float
        ``uniform_factor - 1``.
    yade_factors : numpy.ndarray or None
        ``(N,)`` YADE's per-body factors (module docstring), None when the stepper cannot be computed.
    yade_rule_added_mass_fraction : float or None
        Their added mass fraction.
    yade_dt_crit_scaled : float or None
        The exact critical step of the packing scaled by YADE's rule [s] (below the target: unstable there).
    yade_safety : float
        The ``timestepSafetyCoefficient`` of YADE's rule.
    yade_unit_safety_added_mass_fraction : float or None
        The added mass fraction of YADE's rule at safety 1, ``max(1, (targetDt / dt_b)^2)``.
    yade_unit_safety_dt_crit_scaled : float or None
        The exact critical step of the packing scaled by that rule [s].
    integrator : str
        The integrator planned for.
    max_factor : float
        The largest factor allowed.
    solves : int
        Inertia counts (``dtcrit.plan.exact.ScaledStep.certified_stable``) and exact eigen-solves spent.
    free : numpy.ndarray
        ``(N,)`` which bodies are free particles (walls and fixed bodies keep factor 1).
    masses : numpy.ndarray
        ``(N,)`` the unscaled masses [kg].
    """

    target_dt: float
    dt_crit: float
    factors: np.ndarray
    dt_crit_scaled: float
    added_mass_fraction: float
    family: str
    bound: str
    bound_factors: np.ndarray
    bound_added_mass_fraction: float
    uniform_factor: float
    uniform_added_mass_fraction: float
    yade_factors: np.ndarray | None
    yade_rule_added_mass_fraction: float | None
    yade_dt_crit_scaled: float | None
    yade_safety: float
    yade_unit_safety_added_mass_fraction: float | None
    yade_unit_safety_dt_crit_scaled: float | None
    integrator: str
    max_factor: float
    solves: int
    free: np.ndarray = field(repr=False)
    masses: np.ndarray = field(repr=False)

    @property
    def added_mass(self) -> float:
        """The added mass [kg], ``sum m_p (f_p - 1)`` over the free bodies."""
        return float(np.sum((self.masses * (self.factors - 1.0))[self.free]))

    @property
    def growth(self) -> float:
        """``sqrt(max f_p)``: the largest growth of a body's inertial time ``sqrt(m)`` (and inertial number)."""
        return math.sqrt(float(self.factors.max()))


def added_fraction(masses: np.ndarray, factors: np.ndarray, free: np.ndarray) -> float:
    """``sum m_p (f_p - 1) / sum m_p`` over the free bodies.

    Parameters
    ----------
    masses, factors : numpy.ndarray
        ``(N,)`` masses [kg] and factors.
    free : numpy.ndarray
        ``(N,)`` which bodies count.

    Returns
    -------
    float
        The added mass fraction.
    """
    m = masses[free]
    return float(np.sum(m * (factors[free] - 1.0)) / np.sum(m))


def yade_rule_factors(snapshot, target: float, safety: float = rot.YADE_GSTS_SAFETY) -> np.ndarray | None:
    """YADE's per-body factors ``max(1, targetDt^2 / dt_b^2)`` at the target (module docstring).

    Parameters
    ----------
    snapshot : dtcrit.packing.audit.results.Snapshot
        The snapshot (a YADE export's own stepper input, else its sphere contacts).
    target : float
        ``targetDt`` [s].
    safety : float
        ``timestepSafetyCoefficient`` (YADE's default 0.8).

    Returns
    -------
    numpy.ndarray or None
        ``(N,)`` factors, or None when the stepper cannot be computed (bodies other than spheres).
    """
    from dtcrit.packing.bounds.yade_stepper import from_contacts, yade_stepper
    from dtcrit.packing.bounds.yade_stepper_export import from_snapshot

    inp = from_snapshot(snapshot) or from_contacts(snapshot.packing, snapshot.contacts)
    step = yade_stepper(inp, safety)
    if step.dt is None or step.per_body.shape != (snapshot.packing.n,):
        return None
    with np.errstate(divide="ignore"):
        return np.maximum(1.0, target * target / step.per_body**2)


def _bisect(phi: Callable[[float], np.ndarray], ok: Callable[[np.ndarray], tuple[bool, float]],
            hi: float) -> tuple[np.ndarray, float] | None:
    """The smallest ``s`` in ``[0, hi]`` (to ``BISECTION_RTOL``) whose ``phi(s)`` is confirmed; None if ``phi(hi)`` is not."""
    good, dt = ok(phi(hi))
    if not good:
        return None
    best, lo = (phi(hi), dt), 0.0
    while hi - lo > BISECTION_RTOL * hi:
        mid = 0.5 * (lo + hi)
        f = phi(mid)
        good, dt = ok(f)
        if good:
            hi, best = mid, (f, dt)
        else:
            lo = mid
    return best


def read_input(snapshot, read: dict):
    """The snapshot itself, or the file read with ``read_snapshot(snapshot, **read)``.

    Parameters
    ----------
    snapshot : str or os.PathLike or Snapshot
        A file or a snapshot already read.
    read : dict
        ``read_snapshot``'s keyword arguments.

    Returns
    -------
    Snapshot
        The snapshot; a file's with how its law was given (``dtcrit.plan.rederive.with_law_inputs``), so
        that the law can be applied to the scaled masses.
    """
    from dtcrit.packing.audit.results import Snapshot
    from dtcrit.packing.audit.run import read_snapshot

    from dtcrit.plan.rederive import with_law_inputs

    if isinstance(snapshot, Snapshot):
        return snapshot
    if str(snapshot).lower().endswith(".toml"):
        raise InputError("snapshot", "plan needs a snapshot (a LAMMPS/LIGGGHTS dump or a YADE export), not a scene: the "
                                     "planned masses are confirmed by the exact step of the scaled packing, which a scene "
                                     "does not have (dtcrit step gives a scene's step)")
    return with_law_inputs(read_snapshot(snapshot, **read), read)


def scaled_step_of(given, integrator, local_damping, local_damping_law, method) -> ScaledStep:
    """The exact-step evaluator of a snapshot with its integrator and the audit's local damping.

    Parameters
    ----------
    given : Snapshot
        The snapshot.
    integrator : str or None
        Override of the engine's integrator.
    local_damping, local_damping_law : float and str or None
        As ``dtcrit audit`` takes them (``dtcrit.packing.audit.local_damping.resolve``).
    method : str
        Eigen-solver.

    Returns
    -------
    ScaledStep
        The evaluator.
    """
    from dtcrit.packing.audit import local_damping as damping
    from dtcrit.plan.rederive import rebuilder

    local = damping.resolve(given.meta, given.source, local_damping, local_damping_law)
    integrator = integrator or given.convention.integrator
    if local is not None and integrator not in damping.MODELLED_INTEGRATORS:
        raise InputError("local_damping", f"local damping is modelled with {', '.join(damping.MODELLED_INTEGRATORS)} "
                                          f"only, not {integrator!r}")
    return ScaledStep(given.packing, given.contacts, integrator, 1.0 if local is None else local.factor, method,
                      rebuild=rebuilder(given))


def _families(demands, bounds: dict, bound: str, free: np.ndarray, yade: np.ndarray | None,
              max_factor: float) -> dict:
    """The monotone families of factors, each ``name -> (phi, hi)`` with ``phi(0)`` no scaling (module docstring)."""
    def capped(f: np.ndarray) -> np.ndarray:
        return np.minimum(max_factor, f)

    def threshold(d: np.ndarray, top: np.ndarray | None) -> tuple:
        d = np.where(free, d, 0.0)
        if top is None or top.max() > max_factor:
            hi = max_factor / max(float(d[d > 0].min(initial=1.0)), 1e-300)
        else:  # the demand at the unscaled masses times hi covers the bound's own factors (terms at F)
            up = (top > 1.0) & (d > 0)  # the scaled bodies: with fixed terms top = d there and hi = 1
            hi = max(1.0, float(np.max(top[up] / d[up], initial=1.0)))
        return (lambda s: capped(np.maximum(1.0, s * d))), hi

    f_bound = bounds[bound]
    families = {"bound interpolation": ((lambda t: capped(1.0 + t * (f_bound - 1.0))), 1.0)}
    for name in ("block_diagonal", "gershgorin"):
        families[f"{name} demand"] = threshold(getattr(demands, name), bounds.get(name))
    if yade is not None:
        families["YADE demand"] = threshold(yade, np.full(1, np.inf))
    return families


def _confirmed(step: ScaledStep, factors: np.ndarray, target: float, max_factor: float) -> tuple[np.ndarray, float]:
    """The factors and their exact critical step, raised by 1 % of their excess at a time until it is at least
    ``target x (1 + CONFIRM_MARGIN)``.
    """
    need = target * (1.0 + CONFIRM_MARGIN)
    for _ in range(20):
        dt = step.dt(factors)
        if dt >= need:
            return factors, dt
        factors = np.minimum(max_factor, 1.0 + 1.01 * (factors - 1.0))
    raise InputError("target_dt", f"the exact solve did not confirm a plan for {target:.6g} s (eigen-solver trouble)")


def plan_density_scaling(snapshot: str | os.PathLike | Any, target_dt: float, max_factor: float = DEFAULT_MAX_FACTOR,
                         *, integrator: str | None = None, local_damping: float | None = None,
                         local_damping_law: str | None = None, yade_safety: float = rot.YADE_GSTS_SAFETY,
                         method: str = "auto", **read: Any) -> DensityPlan:
    """Per-body mass and inertia factors with the least added mass found, critical step confirmed above ``target_dt``.

    Parameters
    ----------
    snapshot : str or os.PathLike or Snapshot
        A snapshot file (read with :func:`dtcrit.packing.audit.run.read_snapshot` and ``read``) or one already read.
    target_dt : float
        The target step [s].
    max_factor : float
        The largest factor of any body.
    integrator : str, optional
        Override the engine's integrator (the central-difference family: ``dtcrit.plan.exact.MODELLED``).
    local_damping, local_damping_law : float and str, optional
        Local damping as ``dtcrit audit`` takes it: the step times ``1/sqrt(1 + alpha)``.
    yade_safety : float
        ``timestepSafetyCoefficient`` of YADE's rule.
    method : str
        Eigen-solver of the exact solves.
    **read
        ``read_snapshot``'s keyword arguments for a file.

    Returns
    -------
    DensityPlan
        ``factors`` (ordered as the snapshot's bodies), ``dt_crit_scaled >= target_dt x (1 + CONFIRM_MARGIN)``
        and the comparisons.

    Raises
    ------
    InputError
        ``target_dt`` not above today's critical step (nothing to do), unreachable within ``max_factor``,
        or a term the plan does not model.

    Examples
    --------
    >>> from dtcrit.plan import plan_density_scaling
    >>> plan = plan_density_scaling("examples/packings/random_lognormal_60.dump", 1e-5,
    ...                             pair_style="gran/hooke/history 1e5 NULL 0 NULL 0.5 0")
    >>> plan.dt_crit_scaled >= 1e-5, plan.factors.shape, plan.added_mass_fraction < plan.yade_rule_added_mass_fraction
    (True, (60,), True)
    """
    target = check_target(target_dt)
    if not (isinstance(max_factor, (int, float)) and math.isfinite(max_factor) and max_factor > 1):
        raise InputError("max_factor", f"must be a finite number above 1, got {max_factor!r}")
    given = read_input(snapshot, read)
    step = scaled_step_of(given, integrator, local_damping, local_damping_law, method)
    dt_now = step.dt()
    if dt_now >= target:
        raise InputError("target_dt", f"nothing to do: the current critical step {dt_now:.6g} s already meets the "
                                      f"target {target:.6g} s")
    packing, free = given.packing, free_bodies(given.packing)
    need = target * (1.0 + CONFIRM_MARGIN)

    def ok(f: np.ndarray) -> tuple[bool, float]:
        proved = step.certified_stable(f, need)
        if proved is not None:
            return proved, math.nan
        dt = step.dt(f)
        return dt >= need, dt

    f_uniform, dt_uniform = confirmed_uniform(step, target, free, ok, dt_now, max_factor, CONFIRM_MARGIN)
    if f_uniform > max_factor:
        raise InputError("max_factor", f"the target {target:.6g} s is unreachable within a mass factor of {max_factor:g}: "
                                       + (f"it takes {f_uniform:.6g} on every body" if math.isfinite(f_uniform) else
                                          f"{max_factor:g} on every body does not reach it (dashpots m_eff gamma grow "
                                          f"with the mass)") + f" (today's critical step {dt_now:.6g} s)")
    from dtcrit.plan.bounds import body_demands, sufficient_factors

    h = step.undamped_target(target)
    demands = body_demands(packing, given.contacts, h, dashpots=step.dashpots)
    sufficient = {name: sufficient_factors(step.system, packing.n, h, name, free, dashpots=step.dashpots,
                                           max_factor=max_factor) for name in ("gershgorin", "block_diagonal")}
    bounds = {name: np.where(free, f, 1.0) for name, f in sufficient.items() if f is not None}
    if not bounds:  # neither bound gets below 4 within max_factor: start from the uniform factor instead
        bounds = {"uniform": np.where(free, f_uniform, 1.0)}
    bound = min(bounds, key=lambda name: added_fraction(packing.masses, bounds[name], free))
    f_bound = bounds[bound]
    yade = yade_rule_factors(given, target, yade_safety)
    yade = None if yade is None else np.where(free, yade, 1.0)

    results = {"uniform": (np.where(free, f_uniform, 1.0), dt_uniform)}
    for name, (phi, hi) in _families(demands, bounds, bound, free, yade, max_factor).items():
        found = _bisect(phi, ok, hi)
        if found is not None:
            results[name] = found
    family = min(results, key=lambda name: added_fraction(packing.masses, results[name][0], free))
    factors, dt_scaled = _confirmed(step, results[family][0], target, max_factor)
    yade_dt = step.dt(yade) if yade is not None else None
    unit = yade_rule_factors(given, target, 1.0)
    unit = None if unit is None else np.where(free, unit, 1.0)
    return DensityPlan(
        target_dt=target, dt_crit=dt_now, factors=factors, dt_crit_scaled=dt_scaled,
        added_mass_fraction=added_fraction(packing.masses, factors, free), family=family, bound=bound,
        bound_factors=f_bound, bound_added_mass_fraction=added_fraction(packing.masses, f_bound, free),
        uniform_factor=f_uniform, uniform_added_mass_fraction=f_uniform - 1.0, yade_factors=yade,
        yade_rule_added_mass_fraction=None if yade is None else added_fraction(packing.masses, yade, free),
        yade_dt_crit_scaled=yade_dt, yade_safety=yade_safety,
        yade_unit_safety_added_mass_fraction=None if unit is None else added_fraction(packing.masses, unit, free),
        yade_unit_safety_dt_crit_scaled=None if unit is None else step.dt(unit), integrator=step.integrator, max_factor=float(max_factor),
        solves=step.solves + step.certificates, free=free, masses=packing.masses)


__all__ += ["added_fraction", "read_input", "scaled_packing", "scaled_step_of"]
