"""Stiffness reduction to a target step: the factor on every spring, confirmed by the exact solve, and its cost.

Scaling every spring (``kn``, ``ks``, ``kr``, ``ktw``) and every contact's normal force by ``s`` and every
dashpot by ``sqrt(s)`` (each contact keeps its damping ratio, hence its restitution) scales
``K~`` by ``s`` and ``C~`` by ``sqrt(s)``: ``lambda_max(2h sqrt(s) C~ + h^2 s K~) = 4`` is the unscaled
condition at ``h sqrt(s)``, so every critical step of the central-difference family (``dtcrit.plan.exact``)
is divided by ``sqrt(s)`` exactly and ``s = (dt_now / target)^2``.  The factor returned is confirmed by
the exact solve of the reduced packing.

What it changes (derived; ``m`` the effective mass, ``v`` the impact speed):

* linear springs: contact duration ``pi sqrt(m/k)`` and impact peak overlap ``v sqrt(m/k)`` times
  ``s^-1/2``; the overlap under a given load ``F/k`` times ``s^-1``;
* Hertz (``F = 4/3 E* sqrt(R*) delta^3/2``, ``k = 2 E* sqrt(R* delta)``): the modulus factor that gives
  the stiffness factor ``s`` depends on what fixes the overlap -- ``s`` at the snapshot's overlaps,
  ``s^3/2`` under given loads (``delta ~ E^-2/3``, ``k ~ E^2/3``), ``s^5/4`` in impacts (``delta_max ~
  E^-2/5``, ``k ~ E^4/5``); contact duration and impact peak overlap ``~ E^-2/5``, i.e. times ``s^-1/2``
  again, and the overlap under a given load times ``s^-1``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from dtcrit.plan.exact import ScaledStep

__all__ = ["StiffnessPlan", "reduced_contacts", "stiffness_reduction"]


@dataclass(frozen=True)
class StiffnessPlan:
    """The stiffness reduction that reaches the target step (module docstring).

    Parameters
    ----------
    factor : float
        ``s``: every spring and normal force times ``s`` (dashpots times ``sqrt(s)``).
    dt_crit_reduced : float
        The exact critical step of the reduced packing [s] (>= the target).
    hertz : bool
        Whether the contact law is Hertzian (then the modulus factors apply).
    modulus_factor_fixed_overlap, modulus_factor_impact, modulus_factor_fixed_load : float or None
        Hertz: the modulus factor that gives ``s`` at the snapshot's overlaps (``s``), in impacts
        (``s^5/4``) and under given loads (``s^3/2``); None for linear springs.
    contact_duration_factor : float
        Contact duration (and impact peak overlap) times ``s^-1/2``.
    peak_overlap_factor : float
        Impact peak overlap times ``s^-1/2``.
    static_overlap_factor : float
        Overlap under a given load times ``s^-1``.
    damped : bool
        Whether dashpots were scaled by ``sqrt(s)`` with the springs.
    """

    factor: float
    dt_crit_reduced: float
    hertz: bool
    modulus_factor_fixed_overlap: float | None
    modulus_factor_impact: float | None
    modulus_factor_fixed_load: float | None
    contact_duration_factor: float
    peak_overlap_factor: float
    static_overlap_factor: float
    damped: bool


def reduced_contacts(contacts, s: float):
    """The contacts with springs and normal forces times ``s`` and dashpots times ``sqrt(s)``.

    Parameters
    ----------
    contacts : dtcrit.packing.contact_set.Contacts
        The contacts.
    s : float
        The stiffness factor.

    Returns
    -------
    Contacts
        A copy.
    """
    root = math.sqrt(s)
    values = {}
    for name, by in (("kn", s), ("ks", s), ("kr", s), ("ktw", s), ("force_n", s),
                     ("cn", root), ("cs", root), ("cr", root), ("ctw", root)):
        value = getattr(contacts, name)
        if value is not None:
            values[name] = np.asarray(value, float) * by
    return replace(contacts, **values)


def stiffness_reduction(step: ScaledStep, target: float, dt_now: float, *, hertz: bool,
                        margin: float = 1e-6) -> StiffnessPlan:
    """The stiffness factor ``(dt_now / target)^2`` confirmed by the exact solve (module docstring).

    Parameters
    ----------
    step : ScaledStep
        The packing, its contacts, integrator and local damping.
    target : float
        The target step [s].
    dt_now : float
        Today's exact critical step [s].
    hertz : bool
        Whether the contact law is Hertzian.
    margin : float
        The confirmed step is at least ``target (1 + margin)``.

    Returns
    -------
    StiffnessPlan
        The factor and what it changes.
    """
    s = (dt_now / (target * (1.0 + 2.0 * margin))) ** 2
    reduced = ScaledStep(step.packing, reduced_contacts(step.contacts, s), step.integrator, step.local_factor, step.method)
    dt = reduced.dt()
    for _ in range(40):  # the exact division by sqrt(s) holds to rounding; nudge down if the solve disagrees
        if dt >= target * (1.0 + margin):
            break
        s *= 1.0 - 1e-5
        reduced = replace(reduced, contacts=reduced_contacts(step.contacts, s))
        dt = reduced.dt()
    step.solves += reduced.solves
    return StiffnessPlan(
        factor=s, dt_crit_reduced=dt, hertz=hertz,
        modulus_factor_fixed_overlap=s if hertz else None, modulus_factor_impact=s**1.25 if hertz else None,
        modulus_factor_fixed_load=s**1.5 if hertz else None, contact_duration_factor=s**-0.5,
        peak_overlap_factor=s**-0.5, static_overlap_factor=1.0 / s, damped=step.contacts.damped)
