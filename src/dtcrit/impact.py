"""One-dimensional impact stability: exact and time-stepped impacts (CFL note; Feng 2005).

The CFL note's model of a DEM collision (seed 004, "One-dimensional equations for impact")::

    m d'' = -c d' - k d   for d >= 0 (contact),     m d'' = 0   for d < 0 (separated)

A discrete contact opens and closes within a few steps, so the linear stability bound (which
assumes a persistent contact) does not settle whether a time-stepped impact is stable.  The note's
criterion is the exit speed: ``v_exit <= v_entry``.  This module computes

* the exact impact (``exact_impact``): contact duration and exit/entry speed for both separation
  conventions (see ``dtcrit.symbolic.impact``), from the generated closed forms;
* the time-stepped impact (``simulate_impacts``) with each integrator's own update rule from
  ``dtcrit.schemes``, for arrays of steps ``tau = omega dt`` and entry phases ``phi``;
* the sweep over ``tau`` in (0, 2.2] (``sweep``, ``impact_report``), the undamped closed forms
  (``undamped_exit_ratios``), the Hertz contact (``hertz_study``) and the figures.

Conventions of the simulation (geometric separation, the note's equation):

* units: time ``1/omega`` (``omega = sqrt(k/m)``), overlap ``v0/omega``, speed ``v0``; ``K = 1``,
  ``C = 2 zeta``, step ``tau``;
* the force at a position ``x`` is the spring-dashpot force when ``x >= 0`` and zero when ``x < 0``;
  contact therefore opens and closes *between* steps, by the sign of the overlap at the step where
  the scheme evaluates its force (``x_n`` for Euler and leapfrog variants, ``x_(n+1)`` for velocity
  Verlet).  The dashpot force may be tensile near the end of the contact, as in the note's ODE;
* entry phase ``phi`` in [0, 1): the continuous contact would begin ``phi`` of a step before the
  first step with ``x >= 0``, i.e. that step has ``x_0 = phi tau``; ``phi = 0`` is contact
  beginning exactly on a step (``on_step``).  The run starts one step earlier, in free flight;
* exit: two consecutive positions ``x < 0`` after contact with a receding velocity (then no later
  force acts, for every scheme including the one-step-lagged acceleration of ``paper-eq40``); the
  exit ratio is the free-flight speed divided by ``v0``.  A particle that comes back re-enters
  contact.  A run that has not separated by a cut-off time is reported with ratio 0 and flagged
  (the exact geometric impact never separates for ``zeta >= 1``).

The Hertz contact ``m d'' = -k_h d^(3/2)`` is stepped in units of the exact maximum overlap and of
the tangent frequency ``omega_t`` there (``u'' = -(2/3) u^(3/2)``, entry speed ``sqrt(8/15)``), so its
step variable ``omega_t dt`` is directly comparable with the linearised bound.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from dtcrit._generated import impact as _gen
from dtcrit.errors import InputError
from dtcrit.schemes import INTEGRATORS
from dtcrit.stability import check_integrator, critical_dt

__all__ = [
    "CENTRAL_DIFFERENCE_FAMILY",
    "ExactImpact",
    "HertzExact",
    "ImpactRun",
    "PhaseStats",
    "STANDARD_ZETAS",
    "central_difference_bounds",
    "energy_created_ranges",
    "energy_errors",
    "entry_phases",
    "exact_impact",
    "hertz_dimensional",
    "hertz_exact",
    "hertz_study",
    "impact_report",
    "linear_bound",
    "phase_stats",
    "plot_hertz",
    "plot_phase_curve",
    "plot_sweep",
    "simulate_impacts",
    "sweep",
    "sweep_grid",
    "to_json",
    "undamped_exit_ratios",
    "unit_ratio_steps",
]

STANDARD_ZETAS: tuple[float, ...] = (0.0, 0.05, 0.2)
SWEEP_TOP = 2.2
SWEEP_STEP = 0.005
DEFAULT_PHASES = 128
DEFAULT_ENERGY_THRESHOLD = 0.01
RATIO_RTOL = 1e-9  # relative margin for "ratio > reference" (above rounding of the simulation)
MIN_OMEGA_DT = 1e-4  # below this the step count per impact (> 3e4) makes sweeps impractical
MAX_OMEGA_DT = 1e3
MAX_PHASES = 4096
UNIT_STEPS_FROM = 0.25  # the report checks the isolated steps tau_N >= this (N <= 12)
MAX_CUTOFF = 400.0  # longest simulated contact, units 1/omega
DIVERGED = 1e150  # |state| beyond this: the run has blown up (reported as an infinite ratio)

CENTRAL_DIFFERENCE_FAMILY: tuple[str, ...] = tuple(_gen.CENTRAL_DIFFERENCE_FAMILY)

CONVENTION = (
    "geometric: contact while the overlap d >= 0 (the CFL note's equation); the spring-dashpot "
    "force may be tensile near the end; the time-stepped simulation uses this convention"
)
FORCE_CONVENTION = (
    "force-based: contact force k d + c d' acts only while compressive; released at its first zero"
)
UNITS = "time in 1/omega (omega = sqrt(k/m)), overlap in v0/omega, speeds as ratios to v0"


# ---------------------------------------------------------------------------------------------
# input checks
# ---------------------------------------------------------------------------------------------

def _number(key: str, value) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InputError(key, f"must be a number (got {value!r})") from None
    if not math.isfinite(out):
        raise InputError(key, f"must be finite (got {out})")
    return out


def check_zeta(zeta) -> float:
    z = _number("zeta", zeta)
    if z < 0:
        raise InputError("zeta", f"damping ratio must be >= 0 (got {z})")
    return z


def check_omega_dt(value, key: str = "omega_dt") -> float:
    t = _number(key, value)
    if not MIN_OMEGA_DT <= t <= MAX_OMEGA_DT:
        raise InputError(key, f"must lie in [{MIN_OMEGA_DT:g}, {MAX_OMEGA_DT:g}] (got {t:g})")
    return t


def check_energy_threshold(value) -> float:
    thr = _number("energy_threshold", value)
    if not 0 < thr < 1:
        raise InputError("energy_threshold", f"must lie in (0, 1) (got {thr:g})")
    return thr


def check_phases(n) -> int:
    try:
        k = int(n)
    except (TypeError, ValueError):
        raise InputError("phases", f"must be an integer (got {n!r})") from None
    if k != n or not 1 <= k <= MAX_PHASES:
        raise InputError("phases", f"must be an integer in [1, {MAX_PHASES}] (got {n!r})")
    return k


# ---------------------------------------------------------------------------------------------
# exact impact
# ---------------------------------------------------------------------------------------------

def _regime(zeta: float) -> str:
    if zeta == 0:
        return "undamped"
    return "underdamped" if zeta < 1 else ("critically damped" if zeta == 1 else "overdamped")


def _scalar(kernel, *args) -> float:
    with np.errstate(all="ignore"):
        return float(kernel(*args))


@dataclass(frozen=True)
class ExactImpact:
    """The exact impact in units of 1/omega and v0 (CFL note; ``dtcrit.symbolic.impact``).

    Geometric separation (d returns to 0): ``duration = pi/sqrt(1 - zeta^2)`` and
    ``exit_ratio = exp(-zeta pi/sqrt(1 - zeta^2))`` for ``zeta < 1``; for ``zeta >= 1`` the overlap
    never returns to 0 (``duration = inf``, ``exit_ratio = 0``, the limit).
    Force-based release (force k d + c d' reaches 0): ``force_release_time = 2 g(zeta)`` with
    ``g = arccos(zeta)/sqrt(1 - zeta^2)`` (continued analytically past 1), ``force_exit_ratio =
    exp(-zeta s_f)``; ``force_release_overlap = 2 zeta exp(-zeta s_f)`` is left at release.
    """

    zeta: float
    regime: str
    duration: float
    exit_ratio: float
    separates: bool
    force_release_time: float
    force_exit_ratio: float
    force_release_overlap: float

    def as_dict(self) -> dict:
        return {
            "duration": _json_number(self.duration),
            "exit_ratio": self.exit_ratio,
            "separates": self.separates,
            "regime": self.regime,
            "convention": CONVENTION,
            "force_based": {
                "duration": self.force_release_time,
                "exit_ratio": self.force_exit_ratio,
                "overlap_at_release": self.force_release_overlap,
                "convention": FORCE_CONVENTION,
            },
        }


def exact_impact(zeta) -> ExactImpact:
    """Exact contact duration and exit/entry speed of the linear spring-dashpot impact."""
    z = check_zeta(zeta)
    duration = _scalar(_gen.geometric_duration, z)
    return ExactImpact(
        zeta=z,
        regime=_regime(z),
        duration=duration,
        exit_ratio=_scalar(_gen.geometric_exit_ratio, z),
        separates=math.isfinite(duration),
        force_release_time=_scalar(_gen.force_release_time, z),
        force_exit_ratio=_scalar(_gen.force_exit_ratio, z),
        force_release_overlap=_scalar(_gen.force_release_overlap, z),
    )


@dataclass(frozen=True)
class HertzExact:
    """Undamped Hertz impact ``m d'' = -k_h d^(3/2)``: exit ratio 1; durations in two unit systems."""

    duration: float  # units 1/omega_t, omega_t the linearised frequency at maximum overlap
    duration_dmax_over_v0: float  # units dmax/v0: (4/5) B(2/5, 1/2)
    exit_ratio: float = 1.0
    scaled_speed: float = _gen.HERTZ_SCALED_SPEED  # entry speed in dmax*omega_t
    scaled_coefficient: float = _gen.HERTZ_SCALED_COEFFICIENT  # u'' = -coef u^(3/2)


def hertz_exact() -> HertzExact:
    return HertzExact(duration=_gen.HERTZ_SCALED_DURATION, duration_dmax_over_v0=_gen.HERTZ_DURATION_FACTOR)


def hertz_dimensional(k_h, m, v0) -> dict:
    """Maximum overlap [m], contact duration [s] and tangent frequency at dmax [rad/s] (Hertz)."""
    k_h, m, v0 = (_number(k, x) for k, x in (("k_h", k_h), ("m", m), ("v0", v0)))
    for key, val in (("k_h", k_h), ("m", m), ("v0", v0)):
        if val <= 0:
            raise InputError(key, f"must be positive (got {val})")
    return {
        "max_overlap": float(_gen.hertz_max_overlap(k_h, m, v0)),
        "duration": float(_gen.hertz_duration(k_h, m, v0)),
        "tangent_omega": float(_gen.hertz_tangent_omega(k_h, m, v0)),
    }


# ---------------------------------------------------------------------------------------------
# time-stepped impact
# ---------------------------------------------------------------------------------------------

class SwitchedForce:
    """Acceleration ``-K x^p - C v`` where ``x >= 0`` and 0 where ``x < 0`` (contact by sign of x).

    ``p = 1`` is the CFL note's spring-dashpot law, ``p = 3/2`` (with ``C = 0``) the Hertz law.
    ``dv`` (d force / d v) is set per step from the position at which the force is evaluated; only
    ``leapfrog-centred`` uses it, and it evaluates its force at the start-of-step position.
    """

    def __init__(self, K, C, exponent: float = 1.0):
        self.K = K
        self.C = C
        self.exponent = exponent
        self.dv = -C

    def __call__(self, x, v):
        contact = x >= 0
        if self.exponent == 1.0:
            spring = self.K * x
        else:
            spring = self.K * np.maximum(x, 0.0) ** self.exponent
        return np.where(contact, -spring - self.C * v, 0.0)


STATUS_EXITED, STATUS_NOT_SEPARATED, STATUS_DIVERGED = 0, 1, 2


@dataclass
class ImpactRun:
    """Exit/entry speed ratios with shape ``(len(omega_dt), len(phases))`` and a status per run."""

    omega_dt: np.ndarray
    phases: np.ndarray
    ratios: np.ndarray  # 0 where not separated by the cut-off, inf where diverged
    status: np.ndarray  # STATUS_* codes
    steps: np.ndarray  # steps from the first in-contact step to the exit


def entry_phases(n: int) -> np.ndarray:
    """``n`` equally spaced entry phases ``j/n`` in [0, 1); phase 0 is contact beginning on a step."""
    return np.arange(check_phases(n)) / n


def _cutoff_time(zeta: float, contact: str) -> float:
    if contact == "hertz":
        return 4.0 * _gen.HERTZ_SCALED_DURATION + 20.0
    if zeta < 1:
        t_d = math.pi / (math.sqrt(1 - zeta) * math.sqrt(1 + zeta))
        return min(MAX_CUTOFF, 4.0 * t_d + 20.0)
    slow = zeta + math.sqrt(zeta - 1) * math.sqrt(zeta + 1)  # 1/(slowest decay rate)
    return min(MAX_CUTOFF, 20.0 + 40.0 * slow)


def simulate_impacts(integrator: str, omega_dt, phases, zeta=0.0, contact: str = "linear") -> ImpactRun:
    """Time-step the one-dimensional impact for every (omega_dt, phase) pair (vectorised).

    ``contact``: "linear" (CFL note, damping ratio ``zeta``) or "hertz" (undamped; ``omega_dt`` is then
    ``omega_t dt`` with ``omega_t`` the tangent frequency at the exact maximum overlap).
    """
    name = check_integrator(integrator)
    if contact not in ("linear", "hertz"):
        raise InputError("contact", f"must be 'linear' or 'hertz' (got {contact!r})")
    z = check_zeta(zeta)
    if contact == "hertz" and z != 0:
        raise InputError("zeta", "the Hertz impact is undamped here (zeta must be 0)")
    taus = np.atleast_1d(np.asarray(omega_dt, dtype=float))
    for t in taus:
        check_omega_dt(t)
    phis = np.atleast_1d(np.asarray(phases, dtype=float))
    if np.any((phis < 0) | (phis >= 1)) or not np.all(np.isfinite(phis)):
        raise InputError("phases", "entry phases must lie in [0, 1)")
    integ = INTEGRATORS[name]
    if contact == "linear":
        v0, K, C, p = 1.0, 1.0, 2.0 * z, 1.0
    else:
        v0, K, C, p = _gen.HERTZ_SCALED_SPEED, _gen.HERTZ_SCALED_COEFFICIENT, 0.0, 1.5
    T, P = len(taus), len(phis)
    h = np.repeat(taus, P)
    phi = np.tile(phis, T)
    n_max = np.ceil(_cutoff_time(z, contact) / h).astype(np.int64) + 8
    size = T * P
    ratios = np.zeros(size)
    status = np.full(size, STATUS_NOT_SEPARATED, dtype=np.int8)
    steps = np.zeros(size, dtype=np.int64)

    idx = np.arange(size)
    x = (phi - 1.0) * h * v0  # last free-flight position before the first x >= 0
    v = np.full(size, v0)
    state = (x, v) if len(integ.state) == 2 else (x, v, np.zeros(size))
    prev_neg = np.ones(size, dtype=bool)
    touched = np.zeros(size, dtype=bool)
    force = SwitchedForce(K, C, p)
    n = 0
    with np.errstate(all="ignore"):
        while idx.size:
            force.dv = np.where(state[0] >= 0, -C, 0.0)
            state = integ.step(state, h, force)
            n += 1
            xn, vn = state[0], state[1]
            neg = xn < 0
            touched |= ~neg
            exited = touched & neg & prev_neg & (vn < 0)
            prev_neg = neg
            big = ~(np.abs(xn) < DIVERGED) | ~(np.abs(vn) < DIVERGED)
            timeout = n >= n_max
            done = exited | big | timeout
            if not done.any():
                continue
            ratios[idx[exited]] = -vn[exited] / v0
            status[idx[exited]] = STATUS_EXITED
            gone = big & ~exited
            ratios[idx[gone]] = np.inf
            status[idx[gone]] = STATUS_DIVERGED
            steps[idx[done]] = n - 1
            keep = ~done
            idx, h, n_max, prev_neg, touched = idx[keep], h[keep], n_max[keep], prev_neg[keep], touched[keep]
            state = tuple(s[keep] for s in state)
    shape = (T, P)
    return ImpactRun(taus, phis, ratios.reshape(shape), status.reshape(shape), steps.reshape(shape))


# ---------------------------------------------------------------------------------------------
# closed forms of the undamped time-stepped impact
# ---------------------------------------------------------------------------------------------

def _first_exit(position, phi, tau, m0):
    """Refine the first step m >= 1 with position(m) < 0 from the estimate m0 (rounding near 0)."""
    m = np.maximum(np.asarray(m0, dtype=float), 1.0)
    for _ in range(2):
        back = (m > 1) & (position(m - 1, phi, tau) < 0)
        m = np.where(back, m - 1, m)
        fwd = position(m, phi, tau) >= 0
        m = np.where(fwd, m + 1, m)
    return m


def undamped_exit_ratios(integrator: str, omega_dt, phases) -> np.ndarray | None:
    """Closed-form v_exit/v0 of the undamped time-stepped impact, shape (len(omega_dt), len(phases)).

    Central-difference family (``CENTRAL_DIFFERENCE_FAMILY``, 0 < tau < 2): positions
    ``x_n = A cos(n theta) + B sin(n theta)``, ``cos theta = 1 - tau^2/2``; the exit step m is the first
    with ``x_m < 0`` and the exit phase ``psi = -x_m/(x_(m-1) - x_m)`` gives
    ``ratio = sqrt((1 - tau^2 phi (1 - phi))/(1 - tau^2 psi (1 - psi)))`` (invariant
    ``Q = v^2 + x^2 - tau x v``).  Forward Euler: ``(x_n, v_n) = (1 + tau^2)^(n/2)`` rotation by
    ``n arctan(tau)``; ratio ``|v_m|``.  None for other integrators (no closed form here); NaN where
    ``tau >= 2`` for the family.
    """
    name = check_integrator(integrator)
    taus = np.atleast_1d(np.asarray(omega_dt, dtype=float))[:, None]
    phis = np.atleast_1d(np.asarray(phases, dtype=float))[None, :]
    taus, phis = np.broadcast_arrays(taus, phis)
    with np.errstate(all="ignore"):
        if name in CENTRAL_DIFFERENCE_FAMILY:
            theta = _gen.central_difference_angle(taus)
            a_c = phis * taus
            b_c = (2.0 - phis * taus**2) / np.sqrt(4.0 - taus**2)
            beta = np.arctan2(a_c, b_c)
            m = _first_exit(_gen.central_difference_position, phis, taus, np.floor((np.pi - beta) / theta) + 1)
            x_m = _gen.central_difference_position(m, phis, taus)
            x_b = _gen.central_difference_position(m - 1, phis, taus)
            psi = -x_m / (x_b - x_m)
            out = _gen.central_difference_exit_ratio(phis, psi, taus)
            return np.where(taus < 2.0, out, np.nan)
        if name == "forward-euler":
            alpha = _gen.forward_euler_angle(taus)
            beta = np.arctan(phis * taus)

            def position(k, p, t):
                return _gen.forward_euler_motion(k, p, t)[0]

            m = _first_exit(position, phis, taus, np.floor((np.pi - beta) / alpha) + 1)
            return -_gen.forward_euler_motion(m, phis, taus)[1]
    return None


def central_difference_bounds(omega_dt) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) bound of v_exit/v0 over all entry phases, undamped central difference (tau < 2)."""
    with np.errstate(all="ignore"):
        lo, hi = _gen.central_difference_ratio_bounds(np.asarray(omega_dt, dtype=float))
    return lo, hi


def unit_ratio_steps(tau_min: float = 0.05, tau_max: float = 2.0) -> list[tuple[int, float]]:
    """(N, tau_N = 2 sin(pi/(2N))) in [tau_min, tau_max]: undamped central difference has
    v_exit = v0 for every entry phase exactly at these steps (the contact lasts N steps)."""
    out = []
    n = 1
    while True:
        t = float(_gen.central_difference_unit_step(n))
        if t < tau_min:
            break
        if t <= tau_max:
            out.append((n, t))
        n += 1
    return out


# ---------------------------------------------------------------------------------------------
# statistics over phases, sweeps
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class PhaseStats:
    """v_exit/v0 over the entry phases at one omega*dt."""

    omega_dt: float
    min: float
    mean: float
    max: float
    on_step: float  # phase 0: contact begins exactly on a step
    separated: float  # fraction of phases that separated before the cut-off
    diverged: int  # phases whose state blew up (ratio inf)

    def as_dict(self) -> dict:
        return {k: _json_number(v) for k, v in asdict(self).items()}


def phase_stats(run: ImpactRun) -> list[PhaseStats]:
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
    """omega*dt = k*top/n, k = 1..n with n = round(top/step): a uniform grid over (0, top]."""
    step = check_omega_dt(step, "step")
    n = max(1, int(round(top / step)))
    return np.round(np.arange(1, n + 1) * top / n, 12)


def sweep(integrator: str, zeta, omega_dt=None, n_phases: int = DEFAULT_PHASES, contact: str = "linear"):
    """(ImpactRun, [PhaseStats]) over ``omega_dt`` (default ``sweep_grid()``) and ``n_phases`` phases."""
    grid = sweep_grid() if omega_dt is None else omega_dt
    run = simulate_impacts(integrator, grid, entry_phases(n_phases), zeta, contact)
    return run, phase_stats(run)


def energy_created_ranges(omega_dt, values, reference, rtol: float = RATIO_RTOL) -> list[list[float]]:
    """Contiguous runs [lo, hi] of the grid where ``values > reference (1 + rtol)``."""
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
    """omega*dt at the integrator's exact linear stability bound (0 when no step is stable)."""
    return critical_dt(integrator, 1.0, 2.0 * check_zeta(zeta), 1.0).omega_dt


# ---------------------------------------------------------------------------------------------
# Hertz
# ---------------------------------------------------------------------------------------------

def energy_errors(run: ImpactRun) -> np.ndarray:
    """max over phases of |v_exit^2/v0^2 - 1|, per omega_t*dt (undamped: exact value 0)."""
    with np.errstate(all="ignore"):
        return np.max(np.abs(run.ratios**2 - 1.0), axis=1)


def hertz_study(
    integrator: str,
    omega_dt=None,
    n_phases: int = DEFAULT_PHASES,
    threshold: float = DEFAULT_ENERGY_THRESHOLD,
) -> dict:
    """Undamped Hertz impact stepped at omega_t dt (omega_t: tangent frequency at maximum overlap).

    Reports the exit ratio over phases per step, the energy error (max |v_e^2/v0^2 - 1|), the
    integrator's undamped linear bound tau* applied to the tangent stiffness at maximum overlap, the
    energy error at tau*, and the largest grid step below which the error stays under ``threshold``
    (same quantities for the linear contact at zeta = 0, for comparison).
    """
    name = check_integrator(integrator)
    thr = check_energy_threshold(threshold)
    grid = sweep_grid() if omega_dt is None else np.atleast_1d(np.asarray(omega_dt, dtype=float))
    phases = entry_phases(n_phases)
    run = simulate_impacts(name, grid, phases, 0.0, "hertz")
    stats = phase_stats(run)
    err = energy_errors(run)
    lin_run = simulate_impacts(name, grid, phases, 0.0, "linear")
    lin_err = energy_errors(lin_run)
    tau_star = linear_bound(name, 0.0)
    out = {
        "integrator": name,
        "exact": {
            "duration": _gen.HERTZ_SCALED_DURATION,
            "duration_dmax_over_v0": _gen.HERTZ_DURATION_FACTOR,
            "exit_ratio": 1.0,
            "units": "time in 1/omega_t, omega_t = sqrt(1.5 k_h dmax^(1/2)/m) (tangent at the exact maximum overlap)",
        },
        "energy_threshold": thr,
        "linearised_bound": tau_star,
        "numerical": [dict(s.as_dict(), energy_error=_json_number(e)) for s, e in zip(stats, err)],
        "largest_omega_dt_within_threshold": _largest_within(grid, err, thr),
        "linear_contact_largest_omega_dt_within_threshold": _largest_within(grid, lin_err, thr),
    }
    if tau_star > 0:
        at = simulate_impacts(name, [tau_star], phases, 0.0, "hertz")
        lin_at = simulate_impacts(name, [tau_star * (1 - 1e-9)], phases, 0.0, "linear")
        e_at = float(energy_errors(at)[0])
        out["energy_error_at_bound"] = _json_number(e_at)
        out["linear_contact_energy_error_at_bound"] = _json_number(float(energy_errors(lin_at)[0]))
        out["bound_keeps_error_below_threshold"] = bool(e_at <= thr)
        largest = out["largest_omega_dt_within_threshold"]
        out["verdict"] = (
            f"at the linearised bound omega_t*dt = {tau_star:.4g} the Hertz energy error is {e_at:.3g} "
            f"({'within' if e_at <= thr else 'above'} the threshold {thr:g}); the error stays within the "
            f"threshold up to omega_t*dt = {largest:.4g} ({largest / tau_star:.3g} of the bound)"
            if largest is not None
            else f"at the linearised bound the Hertz energy error is {e_at:.3g}; no grid step keeps it within {thr:g}"
        )
    else:
        out["energy_error_at_bound"] = None
        out["bound_keeps_error_below_threshold"] = None
        out["verdict"] = "the integrator has no stable step for the undamped linear contact (bound 0)"
    out["_grid"] = grid
    out["_energy_error"] = err
    out["_linear_energy_error"] = lin_err
    return out


def _largest_within(grid, err, thr) -> float | None:
    """Largest grid step such that the error is <= thr at it and at every smaller grid step."""
    ok = np.asarray(err) <= thr
    if not ok[0]:
        return None
    bad = np.nonzero(~ok)[0]
    last = (bad[0] - 1) if bad.size else len(ok) - 1
    return float(np.asarray(grid)[last])


# ---------------------------------------------------------------------------------------------
# report
# ---------------------------------------------------------------------------------------------

def _json_number(value):
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


def _zeta_summary(name: str, zeta: float, grid, stats: list[PhaseStats]) -> dict:
    ex = exact_impact(zeta)
    mx = [s.max for s in stats]
    tau_star = linear_bound(name, zeta)
    below = [s.max for s in stats if s.omega_dt < tau_star]
    return {
        "zeta": zeta,
        "exact_exit_ratio": ex.exit_ratio,
        "critical_omega_dt": tau_star,
        "energy_created": {
            "above_exact": energy_created_ranges(grid, mx, ex.exit_ratio),
            "above_one": energy_created_ranges(grid, mx, 1.0),
        },
        "largest_ratio_below_critical": _json_number(max(below)) if below else None,
        "numerical": [s.as_dict() for s in stats],
    }


def impact_report(
    integrator: str,
    zeta=0.0,
    omega_dt=None,
    n_phases: int = DEFAULT_PHASES,
    hertz: bool | None = None,
    energy_threshold: float = DEFAULT_ENERGY_THRESHOLD,
    step: float = SWEEP_STEP,
    standard: bool | None = None,
) -> dict:
    """JSON-ready report for one integrator and damping ratio.

    ``omega_dt=None`` sweeps ``sweep_grid(step)``; a number evaluates that step only.  ``hertz`` and
    ``standard`` (summaries for zeta in ``STANDARD_ZETAS``) default to on for a sweep.
    Keys starting with ``_`` carry arrays for the figures and are not part of the JSON.
    """
    name = check_integrator(integrator)
    z = check_zeta(zeta)
    n_ph = check_phases(n_phases)
    is_sweep = omega_dt is None
    grid = sweep_grid(step) if is_sweep else np.array([check_omega_dt(omega_dt)])
    hertz = is_sweep if hertz is None else hertz
    standard = is_sweep if standard is None else standard
    if hertz:
        check_energy_threshold(energy_threshold)
    ex = exact_impact(z)
    run, stats = sweep(name, z, grid, n_ph)
    report: dict = {
        "integrator": name,
        "zeta": z,
        "units": UNITS,
        "convention": CONVENTION,
        "critical_omega_dt": linear_bound(name, z),
        "exact": ex.as_dict(),
        "phases": n_ph,
        "numerical": [s.as_dict() for s in stats],
        "energy_created": {
            "above_exact": energy_created_ranges(grid, [s.max for s in stats], ex.exit_ratio),
            "above_one": energy_created_ranges(grid, [s.max for s in stats], 1.0),
            "criterion": f"max over entry phases > reference * (1 + {RATIO_RTOL:g}); runs of grid points",
        },
        "_runs": {z: (grid, stats)},
        "_run": run,
    }
    if z == 0:
        closed = undamped_exit_ratios(name, grid, run.phases)
        if closed is not None:
            report["undamped_closed_form"] = _closed_form_section(name, grid, run, closed)
    if standard:
        summaries = []
        for zs in sorted(set(STANDARD_ZETAS) | {z}):
            if zs == z:
                st = stats
            else:
                st = sweep(name, zs, grid, n_ph)[1]
                report["_runs"][zs] = (grid, st)
            summaries.append(_zeta_summary(name, zs, grid, st))
        report["by_zeta"] = summaries
    if hertz:
        report["hertz"] = hertz_study(name, grid, n_ph, energy_threshold)
    return report


def _closed_form_section(name: str, grid, run: ImpactRun, closed: np.ndarray) -> dict:
    ok = np.isfinite(closed) & (run.status == STATUS_EXITED)
    with np.errstate(all="ignore"):
        rel = np.abs(run.ratios - closed) / np.abs(closed)
    section: dict = {
        "max_relative_difference_from_simulation": float(np.max(rel[ok])) if ok.any() else None,
        "compared_runs": int(ok.sum()),
    }
    if name in CENTRAL_DIFFERENCE_FAMILY:
        section["formula"] = (
            "v_e/v0 = sqrt((1 - tau^2 phi(1-phi)) / (1 - tau^2 psi(1-psi))), psi the exit phase; "
            "bounds sqrt(1 - tau^2/4) <= v_e/v0 <= 1/sqrt(1 - tau^2/4); v_e = v0 for every phase at "
            "tau_N = 2 sin(pi/(2N))"
        )
        steps = unit_ratio_steps(max(float(grid[0]), UNIT_STEPS_FROM), 2.0)
        pts = []
        if steps:
            taus = [t for _, t in steps if t < 2.0]
            if taus:
                r = simulate_impacts(name, taus, run.phases, 0.0).ratios
                for (N, t), row in zip([s for s in steps if s[1] < 2.0], r):
                    pts.append({"N": N, "omega_dt": t, "max_abs_ratio_minus_one": float(np.max(np.abs(row - 1)))})
        section["unit_ratio_steps"] = pts
        lo, hi = central_difference_bounds(grid)
        inside = np.all((run.ratios <= hi[:, None] * (1 + 1e-12)) & (run.ratios >= lo[:, None] * (1 - 1e-12)), axis=1)
        section["bounds_hold_on_grid_below_2"] = bool(np.all(inside[grid < 2.0]))
    else:
        section["formula"] = "(x_n, v_n) = (1 + tau^2)^(n/2) R(n arctan tau)(phi tau, 1); v_e/v0 = |v_m|"
    return section


def to_json(report: dict) -> dict:
    """The report without the private (array) entries, recursively."""
    if isinstance(report, dict):
        return {k: to_json(v) for k, v in report.items() if not str(k).startswith("_")}
    if isinstance(report, list):
        return [to_json(v) for v in report]
    return _json_number(report)


# ---------------------------------------------------------------------------------------------
# figures (matplotlib, Agg canvas: no global backend state)
# ---------------------------------------------------------------------------------------------

def _figure(width: float, height: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=110)
    FigureCanvasAgg(fig)
    return fig


def plot_sweep(report: dict, path) -> None:
    """v_exit/v_entry vs omega*dt per damping ratio: min-max band over phases, mean, on-step, exact."""
    name = report["integrator"]
    runs = report["_runs"]
    zs = sorted(runs)
    fig = _figure(7.0, 2.4 * len(zs) + 0.6)
    axes = [fig.add_subplot(len(zs), 1, i + 1) for i in range(len(zs))]
    for ax, z in zip(axes, zs):
        grid, stats = runs[z]
        lo = np.array([s.min for s in stats])
        hi = np.array([s.max for s in stats])
        ax.fill_between(grid, np.minimum(lo, 5), np.minimum(hi, 5), color="C0", alpha=0.25, lw=0, label="min-max over phases")
        ax.plot(grid, [s.mean for s in stats], color="C0", lw=1.2, label="mean over phases")
        ax.plot(grid, [s.on_step for s in stats], color="C1", lw=0.8, ls="--", label="contact begins on a step")
        ex = exact_impact(z)
        ax.axhline(ex.exit_ratio, color="k", lw=1.0, label="exact")
        ax.axhline(1.0, color="0.5", lw=0.6, ls=":")
        tau_star = linear_bound(name, z)
        if tau_star > 0:
            ax.axvline(tau_star, color="C3", lw=0.8, ls="-.", label="linear bound")
        ax.set_ylim(0, 2.0)
        ax.set_xlim(0, float(grid[-1]))
        ax.set_ylabel("v_exit / v_entry")
        ax.set_title(f"{name}, zeta = {z:g}", fontsize=9)
    axes[-1].set_xlabel("omega dt")
    axes[0].legend(fontsize=7, loc="upper left", ncol=2)
    fig.tight_layout()
    fig.savefig(path)


def plot_hertz(study: dict, path) -> None:
    """Hertz impact: v_exit/v_entry band over phases vs omega_t dt, and the energy error vs the step
    (Hertz in omega_t dt, linear contact in omega dt) with the threshold and the linearised bound."""
    grid = study["_grid"]
    rows = study["numerical"]
    fig = _figure(7.0, 5.6)
    ax0 = fig.add_subplot(2, 1, 1)
    lo = np.array([np.inf if r["min"] is None else r["min"] for r in rows])
    hi = np.array([np.inf if r["max"] is None else r["max"] for r in rows])
    ax0.fill_between(grid, np.minimum(lo, 5), np.minimum(hi, 5), color="C0", alpha=0.25, lw=0, label="min-max over phases")
    ax0.plot(grid, [np.nan if r["mean"] is None else r["mean"] for r in rows], color="C0", lw=1.2, label="mean over phases")
    ax0.plot(grid, [np.nan if r["on_step"] is None else r["on_step"] for r in rows], color="C1", lw=0.8, ls="--",
             label="contact begins on a step")
    ax0.axhline(1.0, color="k", lw=1.0, label="exact")
    ax0.set_ylim(0, 2.0)
    ax0.set_xlim(0, float(grid[-1]))
    ax0.set_ylabel("v_exit / v_entry")
    ax0.set_title(f"{study['integrator']}: undamped Hertz impact, step in 1/omega_t (tangent at max overlap)", fontsize=9)
    ax = fig.add_subplot(2, 1, 2)
    floor = 1e-17
    ax.semilogy(grid, np.maximum(study["_energy_error"], floor), label="Hertz (omega_t dt)")
    ax.semilogy(grid, np.maximum(study["_linear_energy_error"], floor), ls="--", label="linear, zeta = 0 (omega dt)")
    ax.axhline(study["energy_threshold"], color="k", lw=0.8, ls=":", label="threshold")
    for a in (ax0, ax):
        if study["linearised_bound"] > 0:
            a.axvline(study["linearised_bound"], color="C3", lw=0.8, ls="-.", label="linearised bound")
    ax.set_ylim(1e-8, 1e3)
    ax.set_xlim(0, float(grid[-1]))
    ax.set_xlabel("omega dt")
    ax.set_ylabel("max |v_e^2/v_0^2 - 1| over phases")
    ax0.legend(fontsize=7, loc="upper left", ncol=2)
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path)


def plot_phase_curve(report: dict, path) -> None:
    """v_exit/v_entry vs entry phase at the single step of a report made with ``omega_dt``."""
    run: ImpactRun = report["_run"]
    fig = _figure(6.0, 3.0)
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(run.phases, run.ratios[0], marker=".", ms=3, lw=0.8)
    ax.axhline(report["exact"]["exit_ratio"], color="k", lw=1.0, label="exact")
    ax.axhline(1.0, color="0.5", lw=0.6, ls=":")
    ax.set_xlabel("entry phase phi")
    ax.set_ylabel("v_exit / v_entry")
    ax.set_title(f"{report['integrator']}, zeta = {report['zeta']:g}, omega dt = {run.omega_dt[0]:g}", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
