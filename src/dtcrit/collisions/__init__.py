"""The step that resolves a collision: nonlinear impacts time-stepped over every entry phase.

A normal impact under a code's collision law (``dtcrit.physics.collision_laws``), written in units of
the elastic contact time ``t_c`` and the elastic peak overlap (``scaled``), depends only on the
restitution and on clipping; each integrator an engine uses is stepped through it with the contact
starting at any fraction of a step (``stepping``), against the continuum reference (``reference``);
the error at N = t_c/dt steps per collision is the worst over the entry phase, and the resolution
step keeps every smaller step within the tolerance (``resolution``).

API (units: ``restitution`` as the code takes it, see ``scaled.scaled_law``):

* ``contact_time(normal, *, m_eff, k=None, E_eff=None, R_eff=None, v_impact=None)`` -> t_c [s];
* ``step_collision(*, engine, normal, damping, restitution, steps_per_collision, phase, clip=None)``;
* ``reference_collision(*, normal, damping, restitution, clip=None)``;
* ``collision_errors(*, engine, normal, damping, restitution, steps_per_collision, clip=None)``;
* ``resolution_step(*, engine, normal, damping, restitution, tol=0.01, quantities=(...), clip=None)``.

Modules: ``scaled``, ``laws``, ``reference``, ``stepping``, ``resolution``, ``tables``,
``resolution_table``, ``oblique``, ``oblique_resolution``.
"""
from __future__ import annotations

import math

from dtcrit.collisions.reference import CollisionOutcome, solve_reference
from dtcrit.collisions.resolution import QUANTITIES, Resolution, resolve, worst_errors
from dtcrit.collisions.laws import scaled_law
from dtcrit.collisions.scaled import HERTZ_W0, ScaledLaw, scaled_from_physical
from dtcrit.collisions.stepping import scheme_of, step_outcome
from dtcrit.collisions.oblique import oblique_errors  # noqa: F401  (oblique impacts: tangential restitution, spin)
from dtcrit.errors import InputError
from dtcrit.physics.collision_laws import check_normal


def _positive(key: str, value) -> float:
    if value is None or not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise InputError(key, f"must be a positive finite number (got {value!r})")
    return float(value)


def contact_time(normal: str, *, m_eff: float, k: float | None = None, E_eff: float | None = None,
                 R_eff: float | None = None, v_impact: float | None = None) -> float:
    """The undamped (elastic) contact duration ``t_c`` [s].

    hooke: ``pi sqrt(m*/k)``; hertz (``F = (4/3) E* sqrt(R*) delta^(3/2)``):
    ``t_c = (4/5) B(2/5, 1/2) (15/16)^(2/5) (m*^2/(R* E*^2 v))^(1/5) = 2.8682 (m*^2/(R* E*^2 v))^(1/5)``.

    Parameters
    ----------
    normal : str
        ``"hooke"`` or ``"hertz"``.
    m_eff : float
        Effective mass [kg].
    k : float, optional
        Hooke stiffness [N/m].
    E_eff, R_eff : float, optional
        ``E*`` [Pa] and ``R*`` [m] (hertz).
    v_impact : float, optional
        Relative normal impact speed [m/s] (hertz).

    Returns
    -------
    float
        ``t_c`` [s].

    Examples
    --------
    >>> from dtcrit.collisions import contact_time
    >>> round(contact_time("hooke", m_eff=1.0, k=1.0), 12)
    3.14159265359
    """
    normal = check_normal(normal)
    m = _positive("m_eff", m_eff)
    if normal == "hooke":
        return math.pi * math.sqrt(m / _positive("k", k))
    e_s, r_s, v = _positive("E_eff", E_eff), _positive("R_eff", R_eff), _positive("v_impact", v_impact)
    log_d = 0.4 * (math.log(15.0 / 16.0) + math.log(m) + 2.0 * math.log(v) - math.log(e_s) - 0.5 * math.log(r_s))
    return HERTZ_W0 * math.exp(log_d) / v


def step_collision(*, engine: str, normal: str, damping: str, restitution: float, steps_per_collision: float,
                   phase: float, clip: bool | None = None) -> CollisionOutcome:
    """One impact time-stepped by an engine's integrator at N = t_c/dt, contact starting at ``phase``.

    Parameters
    ----------
    engine : str
        An engine of ``integrators.engines.ENGINES`` or a scheme key.
    normal : str
        ``"hooke"`` or ``"hertz"``.
    damping : str
        A key of ``physics.collision_laws.DAMPING_MODELS``.
    restitution : float
        ``e`` in (0, 1] (as the code takes it; ``scaled.scaled_law``).
    steps_per_collision : float
        N = t_c/dt.
    phase : float
        Entry phase in [0, 1).
    clip : bool, optional
        Clip the normal force at zero; default: what the code does.

    Returns
    -------
    CollisionOutcome
        Realised restitution, peak overlap (over the elastic peak), duration (over t_c), energy ratio.
    """
    law = scaled_law(normal, damping, restitution, clip)
    return step_outcome(scheme_of(engine), law, steps_per_collision, phase)


def reference_collision(*, normal: str, damping: str, restitution: float, clip: bool | None = None) -> CollisionOutcome:
    """The continuum impact (``solve_ivp`` DOP853, rtol 1e-12, event detection).

    Parameters
    ----------
    normal, damping : str
        The law's keys.
    restitution : float
        ``e`` in (0, 1].
    clip : bool, optional
        Clip the normal force at zero; default: what the code does.

    Returns
    -------
    CollisionOutcome
        The continuum outcome.
    """
    return solve_reference(scaled_law(normal, damping, restitution, clip))


def collision_errors(*, engine: str, normal: str, damping: str, restitution: float, steps_per_collision: float,
                     clip: bool | None = None) -> dict:
    """Relative errors worst over the continuous entry phase at N = t_c/dt.

    Parameters
    ----------
    engine, normal, damping : str
        As for ``step_collision``.
    restitution : float
        ``e`` in (0, 1].
    steps_per_collision : float
        N.
    clip : bool, optional
        Clip the normal force at zero; default: what the code does.

    Returns
    -------
    dict
        ``restitution``, ``peak_overlap``, ``duration``, ``energy_gain`` (exit energy above the continuum's,
        relative).
    """
    law = scaled_law(normal, damping, restitution, clip)
    return worst_errors(scheme_of(engine), law, float(steps_per_collision))


def resolution_step(*, engine: str, normal: str, damping: str, restitution: float, tol: float = 0.01,
                    quantities=("restitution", "peak_overlap"), clip: bool | None = None) -> Resolution:
    """The largest step t_c/N such that every smaller step keeps ``quantities`` within ``tol``.

    Computed (``resolution.resolve``); the shipped tables (``tables``) hold the same numbers for the
    standard cases and are read when they cover the request.

    Parameters
    ----------
    engine, normal, damping : str
        As for ``step_collision``.
    restitution : float
        ``e`` in (0, 1].
    tol : float
        Relative tolerance in (0, 1).
    quantities : tuple of str
        Among ``restitution``, ``peak_overlap``, ``duration``, ``energy_gain``.
    clip : bool, optional
        Clip the normal force at zero; default: what the code does.

    Returns
    -------
    Resolution
        ``steps_per_collision`` (N_res), ``dt_over_tc``, ``tol``, ``quantities``, ``worst``.
    """
    from dtcrit.collisions.tables import lookup

    scheme = scheme_of(engine)
    hit = lookup(scheme, normal, damping, restitution, tol, tuple(quantities), clip)
    if hit is not None:
        return hit
    return resolve(scheme, scaled_law(normal, damping, restitution, clip), tol, quantities)


__all__ = ["CollisionOutcome", "QUANTITIES", "Resolution", "ScaledLaw", "collision_errors", "contact_time",
           "reference_collision", "resolution_step", "scaled_from_physical", "scaled_law", "step_collision"]
