"""The continuum impact of a scaled law: ``solve_ivp`` (DOP853, rtol 1e-12) with event detection.

Events: the peak (``u' = 0``), the exit (``u = 0`` descending) and, for a clipped law, the instant the
total force reaches zero while receding (after it the force stays zero: the dashpot term
``g u^q u'`` outgrows ``kappa u^p`` as ``u -> 0`` because ``q < p``, so the contact flies free).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from dtcrit.collisions.scaled import ScaledLaw
from dtcrit.errors import NotConvergedError


@dataclass(frozen=True)
class CollisionOutcome:
    """One impact's outcome.

    Parameters
    ----------
    restitution : float
        Exit speed over entry speed (realised).
    peak_overlap : float
        Largest overlap over the elastic peak overlap.
    duration : float
        Contact duration over the elastic contact time ``t_c`` (until the overlap returns to zero;
        with clipping, until the force is released plus the free flight back to zero overlap).
    energy_ratio : float
        Exit kinetic energy over entry kinetic energy (``restitution^2``).
    """

    restitution: float
    peak_overlap: float
    duration: float
    energy_ratio: float


def _rhs(law: ScaledLaw):
    def f(_t, y):
        u, w = y
        up = max(u, 0.0)
        force = law.kappa * up**law.p + law.g * up**law.q * w
        if law.clip:
            force = max(force, 0.0)
        return [w, -force]
    return f


def solve_reference(law: ScaledLaw) -> CollisionOutcome:
    """The continuum impact of ``law`` (module docstring), tolerance rtol 1e-12, atol 1e-14.

    Parameters
    ----------
    law : ScaledLaw
        The scaled law.

    Returns
    -------
    CollisionOutcome
        Restitution, peak overlap, duration (units ``t_c``) and energy ratio.
    """
    return _solve(law)


@lru_cache(maxsize=4096)
def _solve(law: ScaledLaw) -> CollisionOutcome:
    def peak(_t, y):
        return y[1]

    def exit_(_t, y):
        return y[0]

    def release(_t, y):
        u = max(y[0], 0.0)
        return law.kappa * u**law.p + law.g * u**law.q * y[1] if y[1] < 0 else 1.0

    for event, terminal in ((peak, False), (exit_, True), (release, True)):
        setattr(event, "terminal", terminal)  # solve_ivp reads these attributes of an event function
        setattr(event, "direction", -1)

    events = [peak, exit_] + ([release] if law.clip and law.g > 0 else [])
    # start a hair inside the contact (u'(0) = w0, exact to first order) so that u = 0 is not an event at t = 0
    t0 = 1e-9
    y0 = [law.w0 * t0, law.w0 - law.g * (law.w0 * t0) ** law.q * law.w0 * t0 if law.q == 0 else law.w0]
    sol = solve_ivp(_rhs(law), (t0, 200.0), y0, method="DOP853", rtol=1e-12, atol=1e-14, events=events)
    if sol.t_events[0].size == 0:
        raise NotConvergedError("peak overlap", 0.0, math.inf, "solve_ivp DOP853", "the continuum impact reached no peak")
    u_peak = float(sol.y_events[0][0][0])
    if sol.t_events[1].size:
        t_end, w_end = float(sol.t_events[1][0]), float(sol.y_events[1][0][1])
    elif law.clip and law.g > 0 and sol.t_events[2].size:
        t_rel, (u_rel, w_end) = float(sol.t_events[2][0]), sol.y_events[2][0]
        t_end = t_rel + float(u_rel) / -float(w_end)
        w_end = float(w_end)
    else:
        return CollisionOutcome(0.0, u_peak, math.inf, 0.0)  # the overlap never returns (overdamped)
    e = -w_end / law.w0
    return CollisionOutcome(e, u_peak, t_end, e * e)


def group_for_restitution(base: ScaledLaw, e: float) -> float:
    """The damping group ``g`` whose continuum impact has restitution ``e`` (Brent's method).

    Parameters
    ----------
    base : ScaledLaw
        The law (its ``g`` is ignored).
    e : float
        Target restitution in (0, 1].

    Returns
    -------
    float
        ``g``.
    """
    if e >= 1.0:
        return 0.0

    def miss(g):
        return _solve(ScaledLaw(base.p, base.q, base.kappa, float(g), base.clip, base.w0)).restitution - e

    hi = 1.0
    while miss(hi) > 0:
        hi *= 2.0
        if hi > 1e6:
            raise NotConvergedError("damping group", hi, math.inf, "brentq", f"no damping group up to {hi:g} gives restitution {e:g}")
    return float(brentq(miss, 0.0, hi, xtol=1e-15, rtol=4e-15))


def linear_closed_form(zeta: float) -> CollisionOutcome:
    """Closed form of the linear spring-dashpot impact (damping ratio ``zeta < 1``), units ``t_c``, ``delta_el``.

    ``e = exp(-zeta pi/sqrt(1 - zeta^2))``; peak at ``omega t_p = atan(sqrt(1 - zeta^2)/zeta)/sqrt(1 - zeta^2)``,
    ``u_max = exp(-zeta omega t_p) sin(sqrt(1 - zeta^2) omega t_p)/sqrt(1 - zeta^2)``; duration
    ``1/sqrt(1 - zeta^2)``.

    Parameters
    ----------
    zeta : float
        Damping ratio in [0, 1).

    Returns
    -------
    CollisionOutcome
        The exact outcome.
    """
    s = math.sqrt(1.0 - zeta * zeta)
    wt = math.atan2(s, zeta) / s
    e = math.exp(-zeta * math.pi / s)
    return CollisionOutcome(e, math.exp(-zeta * wt) * math.sin(s * wt) / s, 1.0 / s, e * e)


__all__ = ["CollisionOutcome", "solve_reference", "group_for_restitution", "linear_closed_form"]
_ = np  # NumPy arrays come back from solve_ivp
