"""Local (non-viscous, Cundall) damping: the laws, the damping coefficient and what it does to the step.

Local damping scales each force (and torque) component by ``1 -+ alpha`` according to the sign of its
power, so it changes the leapfrog's stable step although it adds no dashpot.  For a linear network
(stiffness ``K``, diagonal mass ``M``, largest undamped angular frequency ``omega_max``) integrated by
leapfrog, ``derivations/records/local_damping.md`` shows

* every step above ``2/(omega_max sqrt(1 + alpha))`` grows from the top mode's flip ray, for both laws
  (proved: along that ray every component's power is negative, so the map is the undamped leapfrog
  with stiffness ``(1 + alpha) K``);
* PFC's law (sign of ``F_i v_i`` at ``v_{n-1/2}``; Itasca PFC manual, "Energy and Dissipation
  Mechanisms") is stable at every step below it (proved by a non-increasing quadratic form);
* YADE's law (``NewtonIntegrator.damping``, ``cundallDamp2nd`` in ``pkg/dem/NewtonIntegrator.cpp``:
  sign at the on-step velocity estimate ``v_{n-1/2} + dt a_n/2``) has the same onset by simulation;
  above it stability comes in windows, never an interval, and no bound below it is proved.

So with local damping the critical step is the undamped ``2/omega_max`` times
:func:`step_factor` ``= 1/sqrt(1 + alpha)``.  NumPy only.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.errors import InputError

LAWS = ("pfc", "yade")
"""The local damping laws: ``pfc`` (sign of ``F v`` at the half step), ``yade`` (sign at the on-step estimate)."""

STATUS = {"pfc": "proved", "yade": "onset"}
"""What ``2/(omega_max sqrt(1 + alpha))`` is for each law: a proved stability limit, or the onset of instability."""

STATEMENT = {
    "pfc": "PFC's law (sign of F.v at v_{n-1/2}): every step below 2/(omega_max sqrt(1+alpha)) is stable and "
           "every step above it grows (proved for a linear network in leapfrog)",
    "yade": "YADE's law (sign of the power at the on-step velocity estimate): every step above "
            "2/(omega_max sqrt(1+alpha)) grows from the top mode (proved); below it the runs stayed bounded "
            "(by simulation, not proved; at alpha 0.8-0.9 some starts on a 5-mass chain grew at 0.93-0.95 of it); "
            "above it stability comes in windows, never an interval",
}
"""One sentence per law: what is known about the step ``2/(omega_max sqrt(1 + alpha))``."""

YADE_MARGIN_ALPHA = 0.8
"""From this coefficient on, runs with YADE's law grew below the onset (0.93-0.95 of it on a 5-mass chain,
``derivations/records/local_damping.md``): the onset is then no safe step."""


def check_established(alpha: float, law: str, key: str = "local_damping") -> None:
    """Refuse YADE's law from :data:`YADE_MARGIN_ALPHA` on, where no safe step is established.

    Parameters
    ----------
    alpha : float
        The local damping coefficient.
    law : str
        Its law (:data:`LAWS`).
    key : str
        The input named in the refusal.

    Raises
    ------
    InputError
        ``law == "yade"`` and ``alpha >= YADE_MARGIN_ALPHA``: runs grew at 0.93-0.95 of the onset.
    """
    if law == "yade" and alpha >= YADE_MARGIN_ALPHA:
        raise InputError(key, f"local damping {alpha:g} with YADE's law: from {YADE_MARGIN_ALPHA:g} on, runs grew at "
                              "0.93-0.95 of the onset 2/(omega_max sqrt(1 + alpha)) (derivations/records/local_damping.md), "
                              "and no safe step is established")


def check_alpha(alpha: float, key: str = "local_damping") -> float:
    """The local damping coefficient as a float in [0, 1), or an ``InputError`` naming ``key``.

    Parameters
    ----------
    alpha : float
        The damping coefficient (YADE ``NewtonIntegrator.damping``, PFC ``damp``).
    key : str
        The parameter to name in the error.

    Returns
    -------
    float
        ``alpha``.

    Raises
    ------
    InputError
        When ``alpha`` is not a finite number in [0, 1) (at 1 a force doing negative work doubles and one
        doing positive work vanishes; the papers' and codes' range is [0, 1)).

    Examples
    --------
    >>> check_alpha(0.7)
    0.7
    """
    try:
        value = float(alpha)
    except (TypeError, ValueError):
        raise InputError(key, f"must be a number in [0, 1), got {alpha!r}") from None
    if not (math.isfinite(value) and 0.0 <= value < 1.0):
        raise InputError(key, f"must lie in [0, 1), got {alpha!r}")
    return value


def check_law(law: str | None, key: str = "local_damping_law") -> str:
    """The law's name, one of :data:`LAWS`, or an ``InputError`` naming ``key``.

    Parameters
    ----------
    law : str or None
        ``"yade"`` or ``"pfc"``.
    key : str
        The parameter to name in the error.

    Returns
    -------
    str
        The law.

    Raises
    ------
    InputError
        For any other value.

    Examples
    --------
    >>> check_law("pfc")
    'pfc'
    """
    if law not in LAWS:
        raise InputError(key, f"must be one of {', '.join(LAWS)}, got {law!r}")
    return str(law)


def step_factor(alpha):
    """``1/sqrt(1 + alpha)``: the critical step with local damping over the undamped ``2/omega_max``.

    Parameters
    ----------
    alpha : float or array_like
        Local damping coefficient, in [0, 1).

    Returns
    -------
    numpy.ndarray
        The factor (a 0-d array for a scalar ``alpha``).

    Examples
    --------
    >>> round(float(step_factor(0.7)), 6)
    0.766965
    """
    return 1.0 / np.sqrt(1.0 + np.asarray(alpha, dtype=float))


def flip_threshold(alpha):
    """``omega_max dt = 2/sqrt(1 + alpha)``: where the top mode's flip ray (stiffness ``(1 + alpha) K``) reaches eigenvalue -1.

    Parameters
    ----------
    alpha : float or array_like
        Local damping coefficient.

    Returns
    -------
    numpy.ndarray
        The threshold (a 0-d array for a scalar ``alpha``).

    Examples
    --------
    >>> float(flip_threshold(0.0))
    2.0
    """
    return 2.0 * step_factor(alpha)
