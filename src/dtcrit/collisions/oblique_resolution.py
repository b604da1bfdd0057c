"""The step that resolves an oblique impact of two equal spheres: tangential restitution and rebound spin.

The oblique impact (``collisions.oblique``: Hertz normal law, Mindlin tangential spring with Coulomb's
limit, stepped as LAMMPS/YADE step it) is held to the rule of ``collisions.resolution``: the resolution
step is the largest ``dt = t_c/N`` such that every smaller step keeps the tangential restitution (relative
error) and the rebound spin (absolute error, in units of ``v_t/R``) within the tolerance, the error being
the worst over the entry phase.  The search is ``resolution``'s (``first_top``, ``descending_grid``,
``scan_down``, ``bisect_down``) with the errors of this module; since an oblique impact is stepped one
phase at a time in Python, the grid is scanned coarsely (relative spacing ``1/COARSE``), the coarse
bracket of the first violation finely (``1/FINE``), and the fine bracket bisected ``BISECTIONS`` times.
The error at N is sampled at ``SAMPLE_PHASES`` entry phases; wherever it exceeds ``REFINE_ABOVE`` of the
tolerance, the worst over the continuous phase decides (the larger of the two quantities' ratios to the
tolerance, maximised by bounded optimisation around the worst sample, as ``oblique_errors`` does per
quantity).  The guarantee rests on the grids: a violation narrower than ``1/COARSE`` in N above the
coarse bracket, or ``1/FINE`` within it, can be missed.

The continuum reference (``reference_oblique``) models a contact that sticks or slides throughout, not
stick-slip; ``regime`` picks it: a damped contact whose onset slides is refused (damped sliding impacts are not
modelled); sliding throughout when there is no dashpot, the onset slides
(``(3/2) (k_t/k_n) v_t/v_n > mu``) and the slip cannot reverse: in sliding the slip speed falls by
``(1 + 1/k_g^2) mu`` times the normal velocity change, at most ``(1 + e) v_n`` with ``e <= 1``, so
``v_t/v_n > 2 (1 + 1/k_g^2) mu`` (with a margin ``SLIDE_MARGIN``; rigid-body impact theory, e.g. Maw,
Barber & Fawcett 1976, Wear 38, 101); otherwise sticking, which the reference refuses when Coulomb's
limit binds before the last 1 % of the contact.  Anything in between is refused in one line.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from dtcrit.collisions.oblique import ObliqueCase, ObliqueOutcome, reference_oblique, step_oblique
from dtcrit.collisions.resolution import bisect_down, check_tol, descending_grid, first_top, scan_down
from dtcrit.errors import InputError

QUANTITIES: tuple[str, ...] = ("tangential_restitution", "spin")
SAMPLE_PHASES = 8
REFINE_ABOVE = 0.75  # 8 sampled phases fell short of the optimised worst by up to ~10 % (stick, N ~ 250)
XATOL = 1e-4
COARSE = 4
FINE = 40
BISECTIONS = 4
SLIDE_MARGIN = 1.01

__all__ = ["QUANTITIES", "ObliqueResolution", "regime", "oblique_error", "oblique_resolve"]


@dataclass(frozen=True)
class ObliqueResolution:
    """The step that resolves an oblique impact within ``tol``.

    Parameters
    ----------
    steps_per_collision : float
        ``N_res``: every ``N >= N_res`` keeps both quantities within ``tol`` (``inf``: none up to the cap).
    tol : float
        The tolerance.
    mode : str
        ``"slide"`` or ``"stick"``: the continuum regime.
    reference : ObliqueOutcome
        The continuum outcome.
    """

    steps_per_collision: float
    tol: float
    mode: str
    reference: ObliqueOutcome


def regime(case: ObliqueCase, key: str = "angle_deg") -> str:
    """The continuum regime of ``case`` that the reference models (module docstring), or a refusal.

    Parameters
    ----------
    case : ObliqueCase
        The oblique impact.
    key : str
        The input key named by a refusal (the angle's).

    Returns
    -------
    str
        ``"slide"`` or ``"stick"`` (the latter may still be refused by ``reference_oblique``).

    Raises
    ------
    InputError
        A contact that slides at first touch and whose slip can reverse (stick-slip), or that slides at
        first touch with a dashpot (damped sliding is not modelled).
    """
    ratio_t = 2.0 * (1.0 - case.poisson) / (2.0 - case.poisson)
    dashpot = case.law.g != 0.0 or case.gammat_ratio != 0.0
    if 1.5 * ratio_t * case.tangential_ratio <= case.friction:
        return "stick"
    if dashpot:
        raise InputError(key, f"v_t/v_n = {case.tangential_ratio:.4g}: the contact slides at first touch; damped "
                              f"sliding impacts are not modelled (it sticks at first touch for "
                              f"v_t/v_n <= {case.friction / (1.5 * ratio_t):.4g})")
    slide_above = 2.0 * (1.0 + 1.0 / case.gyration) * case.friction
    if case.tangential_ratio > SLIDE_MARGIN * slide_above:
        return "slide"
    raise InputError(key, f"v_t/v_n = {case.tangential_ratio:.4g}: the contact slides at first touch and can stick later "
                          f"(stick-slip is not modelled; it slides throughout for v_t/v_n > {SLIDE_MARGIN * slide_above:.4g}, "
                          f"sticks at first touch for v_t/v_n <= {case.friction / (1.5 * ratio_t):.4g})")


def _reference(case: ObliqueCase, mode: str, key: str) -> ObliqueOutcome:
    try:
        return reference_oblique(case, mode)
    except InputError as exc:
        if exc.key != "friction":
            raise
        raise InputError(key, f"v_t/v_n = {case.tangential_ratio:.4g}: the contact sticks at first touch and slides "
                              "before the last 1 % of it (stick-slip is not modelled)") from None


def oblique_error(got: ObliqueOutcome, ref: ObliqueOutcome, name: str) -> float:
    """The error of one quantity as ``oblique_errors`` measures it.

    Parameters
    ----------
    got, ref : ObliqueOutcome
        Stepped and continuum outcomes.
    name : str
        ``"tangential_restitution"`` (relative error) or ``"spin"`` (absolute, in units of ``v_t/R``).

    Returns
    -------
    float
        The error.
    """
    a, b = getattr(got, name), getattr(ref, name)
    return float(abs(a - b) if name == "spin" else abs(a - b) / abs(b))


class _Errors:
    """Errors over tolerance of the stepped impact at (N, phase), cached; ``tick`` counts stepped impacts."""

    def __init__(self, case: ObliqueCase, ref: ObliqueOutcome, tol: float, tick=None):
        self.case, self.ref, self.tol, self.tick = case, ref, tol, tick
        self.cache: dict[tuple[float, float], dict[str, float]] = {}

    def at(self, n: float, phase: float) -> dict:
        k = (float(n), float(phase))
        if k not in self.cache:
            try:
                got = step_oblique(self.case, n, phase)
                self.cache[k] = {q: oblique_error(got, self.ref, q) / self.tol for q in QUANTITIES}
            except InputError:  # did not separate by the cut-off
                self.cache[k] = {q: math.inf for q in QUANTITIES}
            if self.tick is not None:
                self.tick(1)
        return self.cache[k]

    def ratio(self, n: float, phase: float) -> float:
        return max(self.at(n, phase).values())

    def sampled(self, ns) -> np.ndarray:
        ph = (np.arange(SAMPLE_PHASES) + 0.5) / SAMPLE_PHASES
        return np.array([max(self.ratio(n, p) for p in ph) for n in np.atleast_1d(ns)])

    def worst(self, n: float) -> float:
        """Max over the quantities and the phase: from the worst sample, bounded optimisation within a sample."""
        ph = (np.arange(SAMPLE_PHASES) + 0.5) / SAMPLE_PHASES
        vals = [self.ratio(n, p) for p in ph]
        k = int(np.argmax(vals))
        lo, hi = max(ph[k] - 1.0 / SAMPLE_PHASES, 0.0), min(ph[k] + 1.0 / SAMPLE_PHASES, 1.0 - 1e-12)
        best = minimize_scalar(lambda p: -self.ratio(n, p), bounds=(lo, hi), method="bounded", options={"xatol": XATOL})
        return max(vals[k], -float(best.fun))


def oblique_resolve(case: ObliqueCase, tol: float, key: str = "angle_deg", tick=None) -> ObliqueResolution:
    """The oblique resolution step (module docstring) of the velocity-Verlet map on ``case``.

    Parameters
    ----------
    case : ObliqueCase
        The oblique impact (``oblique.oblique_case``).
    tol : float
        Tolerance in (0, 1): relative on the tangential restitution, absolute on the spin (units ``v_t/R``).
    key : str
        The input key a refusal names.
    tick : callable, optional
        Called with 1 for every impact stepped (progress).

    Returns
    -------
    ObliqueResolution
        ``N_res``, the regime and the continuum outcome.

    Raises
    ------
    InputError
        Stick-slip (``regime``) or a bad tolerance.
    """
    tol = check_tol(tol)
    mode = regime(case, key)
    ref = _reference(case, mode, key)
    errs = _Errors(case, ref, tol, tick)
    top = first_top(errs.sampled)
    if top is None:
        return ObliqueResolution(math.inf, tol, mode, ref)
    ok_n, bad_n = scan_down(errs.sampled, errs.worst, descending_grid(top, 1.0 / COARSE), refine_above=REFINE_ABOVE)
    if bad_n is not None:  # the coarse bracket [bad_n, ok_n] scanned finely, then bisected
        ok_f, bad_f = scan_down(errs.sampled, errs.worst, descending_grid(ok_n, 1.0 / FINE, bad_n),
                                refine_above=REFINE_ABOVE)
        ok_n = bisect_down(errs.worst, ok_f, bad_f if bad_f is not None else bad_n, BISECTIONS)
    return ObliqueResolution(ok_n, tol, mode, ref)

