"""Critical time steps of explicit integrators for the linear contact ODE (runtime; no SymPy).

``critical_dt(integrator, k, c, A)`` evaluates the exact boundary derived by ``dtcrit.symbolic``
(amplification matrix of the update rule, Jury conditions; Peng et al. 2020, Section 4.2) through
the generated kernels in ``dtcrit._generated.critical_steps``.

Numerics (``dtcrit.integrators.precise``): the kernels are homogeneous of degree -1 in ``omega = sqrt(k A)``
and ``gamma = c A/2``; inputs are split into mantissa and exponent and both rates rescaled by the
same power of two (exact), so any float64 inputs work; forward Euler near critical damping and
the Eq. (40) cubic use error-free residuals and an identity of the cubic.  Arrays go chunk by chunk
through ``precise.fast_steps`` (unscaled rates where nothing can overflow, the scaled forms elsewhere).  A step that lies beyond
or below the float64 range is refused with ``InputError``, never returned as inf or 0.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.integrators import precise
from dtcrit._generated import critical_steps as _gen
from dtcrit.errors import InputError
from dtcrit.inputs.text import did_you_mean
from dtcrit.integrators.engines import ENGINES, resolve_integrator
from dtcrit.integrators.schemes import INTEGRATORS, NAMES, USER_INTEGRATORS
from dtcrit.numerics.scaling import scaled_rates  # re-exported: omega, gamma on a power-of-two scale

__all__ = ["CriticalStep", "critical_dt", "critical_dt_array", "dashpot_dt", "mode_dt", "paper_eq46", "scaled_rates", "INTEGRATORS"]


@dataclass(frozen=True)
class CriticalStep:
    """Result of ``critical_dt``: ``dt`` in seconds (0.0 when no dt > 0 is stable).

    Parameters
    ----------
    integrator : str
        The scheme key.
    dt : float
        The exact critical step [s].
    reason : str
        Why the step is what it is (e.g. no stable step undamped).
    formula : str
        The closed form or route the step comes from.
    omega : float
        ``sqrt(k A)`` [rad/s].
    zeta : float
        Damping ratio ``c A / (2 omega)``.
    regime : str
        ``undamped``, ``underdamped``, ``critically damped`` or ``overdamped``.
    """

    integrator: str
    dt: float
    reason: str
    formula: str
    omega: float  # sqrt(k A) [rad/s]
    zeta: float  # damping ratio c A / (2 omega)
    regime: str  # undamped | underdamped | critically damped | overdamped

    @property
    def omega_dt(self) -> float:
        """The dimensionless critical step ``omega dt``."""
        return self.dt * self.omega


def check_integrator(name: str) -> str:
    """The scheme key of ``name``: a built-in or registered user scheme, or a DEM code's name
    (``dtcrit.integrators.engines.resolve_integrator``); InputError otherwise.

    Parameters
    ----------
    name : str
        A scheme key or a DEM code's name.

    Returns
    -------
    str
        The scheme key.
    """
    name, _note = resolve_integrator(name)
    if name in INTEGRATORS or name in USER_INTEGRATORS:
        return name
    hint = did_you_mean(str(name), NAMES + tuple(ENGINES))
    raise InputError("integrator", f"unknown integrator {name!r}{hint}; choose one of {', '.join(NAMES)}")


def _check_positive(key: str, value, allow_zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(key, f"must be a number (got {value!r})") from None
    if not math.isfinite(v):
        raise InputError(key, f"must be finite (got {v})")
    if v < 0 or (v == 0 and not allow_zero):
        raise InputError(key, f"must be {'non-negative' if allow_zero else 'positive'} (got {v})")
    return v


# no stable dt > 0 when c = 0: read from the generated boundaries (tau_crit(0) = 0)
UNSTABLE_UNDAMPED = tuple(n for n in NAMES if float(_gen.DT_KERNELS[n](1.0, 0.0)) == 0.0)


def _exact_steps(name: str, k, c, A) -> np.ndarray:
    return precise.fast_closed_form(name, k, c, A)


def refuse_unrepresentable(integrator: str, dt: np.ndarray, k, c, A) -> np.ndarray:
    """Raise InputError where the exact step lies beyond float64 (inf) or below it (0
    although the contact has a stable step: every scheme has one when damped, and all but forward
    Euler and the Eq. (40) scheme have one when undamped).  Subnormal steps are returned.

    Parameters
    ----------
    integrator : str
        A scheme key or a DEM code's name (:func:`check_integrator`).
    dt : numpy.ndarray
        The exact steps [s].
    k : float
        Contact stiffness [N/m] (> 0).
    c : float
        Viscous damping [N s/m] (>= 0).
    A : float
        Inverse inertia coefficient [1/kg] (> 0; e.g. ``dtcrit.a_bound`` or Eq. (26)'s ``A_max``).

    Returns
    -------
    numpy.ndarray
        ``dt`` unchanged.
    """
    k, c, A = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (k, c, A)))
    has_step = (c > 0) | (integrator not in UNSTABLE_UNDAMPED)
    bad = ~np.isfinite(dt) | ((dt == 0) & has_step)
    if np.any(bad):
        i = np.unravel_index(int(np.flatnonzero(bad)[0]), np.shape(bad))
        where = "below" if np.isfinite(dt[i]) else "beyond"
        raise InputError(
            "k",
            f"the critical step of '{integrator}' lies {where} the float64 range "
            f"(k = {k[i]:g}, c = {c[i]:g}, A = {A[i]:g}); rescale the units and retry",
        )
    return dt


def critical_dt_array(integrator: str, k, c, A) -> np.ndarray:
    """Vectorised exact critical step [s] for arrays of k [N/m], c [N s/m], A [1/kg].

    Within 4 ulp of the exact step for every float64 input (tests/integrators/test_stability_engine.py, the
    bench's extreme-case suite); refuses (InputError) a step outside the float64 range.

    Parameters
    ----------
    integrator : str
        A scheme key or a DEM code's name (:func:`check_integrator`).
    k : float or numpy.ndarray
        Contact stiffness [N/m] (> 0).
    c : float or numpy.ndarray
        Viscous damping [N s/m] (>= 0).
    A : float or numpy.ndarray
        Inverse inertia coefficient [1/kg] (> 0; e.g. ``dtcrit.a_bound`` or Eq. (26)'s ``A_max``).

    Returns
    -------
    numpy.ndarray
        The critical steps [s], shape ``broadcast(k, c, A).shape``.

    Examples
    --------
    >>> import numpy as np
    >>> from dtcrit import critical_dt_array
    >>> dt = critical_dt_array("velocity-verlet", np.array([1.0, 4.0]), 0.0, 1.0)
    >>> dt.round(12).tolist()
    [2.0, 1.0]
    """
    name = check_integrator(integrator)
    k, c, A = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (k, c, A)))
    if name not in _gen.DT_KERNELS:  # a user-written scheme: no emitted closed form
        from dtcrit.integrators.spectral_route import critical_dt_spectral

        return np.vectorize(lambda *a: critical_dt_spectral(name, *a), otypes=[float])(k, c, A)
    shape = k.shape
    k, c, A = (np.ravel(v) for v in (k, c, A))
    dt, checked = precise.fast_steps(name, k, c, A)
    if not checked:  # a chunk took the scaled forms, or holds a step float64 cannot (or need not) hold
        refuse_unrepresentable(name, dt, k, c, A)
    return dt.reshape(shape)


def _regime(zeta: float) -> str:
    if zeta == 0:
        return "undamped"
    return "underdamped" if zeta < 1 else ("critically damped" if zeta == 1 else "overdamped")


def _governing_condition(integrator: str, zeta: float) -> str:
    if integrator not in _gen.GOVERNING:
        return "spectral radius of the amplification matrix (bisection at 50 digits)"
    for zeta_hi, label in _gen.GOVERNING[integrator]:
        if zeta <= zeta_hi:
            return label
    return _gen.GOVERNING[integrator][-1][1]


def critical_dt(integrator: str, k, c, A) -> CriticalStep:
    """Exact critical step of ``integrator`` for ``xddot = -k A x - c A xdot`` (Peng et al. 2020, Eq. (30)).

    Parameters
    ----------
    integrator : str
        A scheme key or a DEM code's name (:func:`check_integrator`).
    k : float
        Contact stiffness [N/m] (> 0).
    c : float
        Viscous damping [N s/m] (>= 0).
    A : float
        Inverse inertia coefficient [1/kg] (> 0; e.g. ``dtcrit.a_bound`` or Eq. (26)'s ``A_max``).

    Returns
    -------
    CriticalStep
        The step [s] with its regime and formula.

    Examples
    --------
    >>> from dtcrit import critical_dt
    >>> step = critical_dt("velocity-verlet", k=1e6, c=0.0, A=2.0)   # omega = sqrt(k A)
    >>> round(step.dt * (1e6 * 2.0) ** 0.5, 12)   # the undamped bound omega dt = 2
    2.0
    """
    name = check_integrator(integrator)
    k = _check_positive("k", k)
    c = _check_positive("c", c, allow_zero=True)
    A = _check_positive("A", A)
    w, g, s = scaled_rates(k, c, A)
    w, g, s = float(w), float(g), int(s)
    zeta = g / w if math.isfinite(g) else math.inf
    omega = math.ldexp(w, s) if s < 1000 else math.inf
    dt = float(critical_dt_array(name, k, c, A))
    regime = _regime(zeta)
    if dt > 0:
        reason = (
            f"{regime} (zeta = {zeta:.6g}): the spectral radius of the '{name}' amplification matrix "
            f"reaches 1 at dt = {dt:.6g} s; governing Jury condition: {_governing_condition(name, zeta)}"
        )
    else:
        reason = (
            f"no dt > 0 is stable: the '{name}' scheme is unstable for every step when {regime} "
            f"(zeta = {zeta:.6g}); the spectral radius exceeds 1 for all dt > 0"
        )
    return CriticalStep(name, dt, reason, _formula(name), omega, zeta, regime)


def _formula(name: str) -> str:
    if name in _gen.FORMULAS:
        return _gen.FORMULAS[name]
    return "omega*dt = first tau at which the spectral radius of the amplification matrix of the rules exceeds 1"


def dashpot_dt(integrator: str, c, A) -> float:
    """Exact critical step [s] of a mode with a dashpot and no spring, ``xddot = -c A xdot`` (e.g. the
    tangential dashpot of LAMMPS ``gran/hooke``): the generated boundary at ``omega = 0``.

    The kernels are homogeneous of degree -1 in ``(omega, gamma)`` with ``gamma = c A/2``, so their
    value at ``omega = 0`` is the k -> 0 limit: ``2/(c A)`` for the central-difference family and
    forward Euler, ``1/(c A)`` for ``velocity-verlet-predicted`` and ``paper-eq40``; ``inf`` (stable for
    every step) for ``leapfrog-centred``.  Checked against the spectral radius of the update rule with
    ``K = 0`` in ``tests/scenes/test_step_modes.py``.

    Parameters
    ----------
    integrator : str
        A scheme key or a DEM code's name (:func:`check_integrator`).
    c : float
        Viscous damping [N s/m] (> 0).
    A : float
        Inverse inertia coefficient [1/kg] (> 0).

    Returns
    -------
    float
        The critical step [s].
    """
    name = check_integrator(integrator)
    c = _check_positive("c", c)
    A = _check_positive("A", A)
    if name not in _gen.DT_KERNELS:  # a user-written scheme: no emitted closed form
        from dtcrit.integrators.spectral_route import dashpot_dt_spectral

        return dashpot_dt_spectral(name, c, A)
    with np.errstate(all="ignore"):
        dt = float(np.asarray(_exact_steps(name, np.zeros(1), np.array([c]), np.array([A])))[0])
    if dt == 0.0 or math.isnan(dt):
        raise InputError("c", f"the dashpot step of '{name}' lies below the float64 range (c = {c:g}, A = {A:g})")
    return dt


def mode_dt(integrator: str, k, c, A) -> CriticalStep:
    """Exact critical step of one contact mode ``xddot = -k A x - c A xdot`` with ``k >= 0``.

    ``k > 0``: :func:`critical_dt`.  ``k = 0, c > 0``: :func:`dashpot_dt`.  ``k = c = 0``: the mode
    is free (no force acts along it) and sets no limit: ``dt = inf``.

    Parameters
    ----------
    integrator : str
        A scheme key or a DEM code's name (:func:`check_integrator`).
    k : float
        Stiffness of the mode [N/m] (>= 0).
    c : float
        Viscous damping [N s/m] (>= 0).
    A : float
        Inverse inertia coefficient [1/kg] (> 0).

    Returns
    -------
    CriticalStep
        The step [s] (inf for a free mode).
    """
    name = check_integrator(integrator)
    k = _check_positive("k", k, allow_zero=True)
    c = _check_positive("c", c, allow_zero=True)
    if k > 0:
        return critical_dt(name, k, c, A)
    if c == 0:
        return CriticalStep(name, math.inf, "no spring and no dashpot: a free mode sets no limit", _formula(name),
                            0.0, 0.0, "free")
    dt = dashpot_dt(name, c, A)
    reason = (f"dashpot without spring (c A = {c * A:.6g} 1/s): the '{name}' update is stable while dt <= {dt:.6g} s"
              if math.isfinite(dt) else f"dashpot without spring: the '{name}' update is stable for every step")
    return CriticalStep(name, dt, reason, _formula(name), 0.0, math.inf, "dashpot only")


def paper_eq46(k, c, A) -> float:
    """The paper's printed critical step, Peng et al. 2020, Eq. (46), for comparison only.

    It is the boundary where a *real* eigenvalue of Eq. (40)'s amplification matrix reaches -1;
    it is not a stability bound of that scheme (see derivations/records/sec4_stability.md).

    Parameters
    ----------
    k : float
        Contact stiffness [N/m] (> 0).
    c : float
        Viscous damping [N s/m] (>= 0).
    A : float
        Inverse inertia coefficient [1/kg] (> 0; e.g. ``dtcrit.a_bound`` or Eq. (26)'s ``A_max``).

    Returns
    -------
    float
        Eq. (46)'s step [s].

    Examples
    --------
    >>> from dtcrit import paper_eq46
    >>> round(paper_eq46(4.0, 0.0, 1.0), 12)   # undamped: 2/sqrt(k A)
    1.0
    """
    k = _check_positive("k", k)
    c = _check_positive("c", c, allow_zero=True)
    A = _check_positive("A", A)
    w, g, s = scaled_rates(k, c, A)
    # Eq. (46) = (c A + sqrt(c^2 A^2 + 4 k A)) / (k A) = 2 (gamma + hypot(gamma, omega)) / omega^2
    w, g, s = float(w), float(g), int(s)
    return math.ldexp(2.0 * (g + math.hypot(g, w)) / (w * w), -s)
