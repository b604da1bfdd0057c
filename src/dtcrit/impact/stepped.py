"""Time-stepped impacts: each integrator's own update rule (``dtcrit.integrators.schemes``) through a
contact that opens and closes between steps, for arrays of steps ``tau = omega dt`` and entry phases.

Conventions (geometric separation, the CFL note's equation): the force is the spring-dashpot force
when the overlap ``x >= 0`` and zero when ``x < 0``, judged where the scheme evaluates its force; entry
phase ``phi`` in [0, 1) puts the first contact step at ``x_0 = phi tau``; exit is two consecutive
``x < 0`` with a receding velocity.  Undamped central-difference closed forms beside it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit._generated import impact as _gen
from dtcrit.errors import InputError
from dtcrit.impact.conventions import (
    CENTRAL_DIFFERENCE_FAMILY,
    DIVERGED,
    MAX_CUTOFF,
    check_omega_dt,
    check_phases,
    check_zeta,
)
from dtcrit.integrators.schemes import INTEGRATORS, LinearForce
from dtcrit.integrators.stability import check_integrator

# ---------------------------------------------------------------------------------------------
# time-stepped impact
# ---------------------------------------------------------------------------------------------

class SwitchedForce(LinearForce):
    """Acceleration ``-K x^p - C v`` where ``x >= 0`` and 0 where ``x < 0`` (contact by sign of x).

    ``p = 1`` is the CFL note's spring-dashpot law, ``p = 3/2`` (with ``C = 0``) the Hertz law.
    ``dv`` (d force / d v) is set per step from the position at which the force is evaluated; only
    ``leapfrog-centred`` uses it, and it evaluates its force at the start-of-step position.

    Parameters
    ----------
    K : float or numpy.ndarray
        Spring coefficient per unit mass (1 in the note's units).
    C : float or numpy.ndarray
        Viscous coefficient per unit mass (``2 zeta`` in the note's units).
    exponent : float
        Power ``p`` of the overlap in the spring term.
    """

    def __init__(self, K, C, exponent: float = 1.0):
        super().__init__(K, C)  # K, C and dv = -C, as for the persistent linear contact
        self.exponent = exponent

    def __call__(self, x, v):
        """The acceleration at overlap ``x`` and velocity ``v`` (0 out of contact, ``x < 0``).

        Parameters
        ----------
        x : numpy.ndarray
            Overlaps (positive in contact).
        v : numpy.ndarray
            Velocities.

        Returns
        -------
        numpy.ndarray
            ``-K x^p - C v`` where ``x >= 0``, else 0.
        """
        contact = x >= 0
        if self.exponent == 1.0:
            spring = self.K * x
        else:
            spring = self.K * np.maximum(x, 0.0) ** self.exponent
        return np.where(contact, -spring - self.C * v, 0.0)


STATUS_EXITED, STATUS_NOT_SEPARATED, STATUS_DIVERGED = 0, 1, 2


@dataclass
class ImpactRun:
    """Exit/entry speed ratios with shape ``(len(omega_dt), len(phases))`` and a status per run.

    Parameters
    ----------
    omega_dt : numpy.ndarray
        The steps omega dt (rows).
    phases : numpy.ndarray
        The entry phases in [0, 1) (columns).
    ratios : numpy.ndarray
        v_exit/v0 per run; 0 where not separated by the cut-off, inf where diverged.
    status : numpy.ndarray
        ``STATUS_EXITED``, ``STATUS_NOT_SEPARATED`` or ``STATUS_DIVERGED`` per run.
    steps : numpy.ndarray
        Steps from the first in-contact step to the exit, per run.
    """

    omega_dt: np.ndarray
    phases: np.ndarray
    ratios: np.ndarray  # 0 where not separated by the cut-off, inf where diverged
    status: np.ndarray  # STATUS_* codes
    steps: np.ndarray  # steps from the first in-contact step to the exit


def entry_phases(n: int) -> np.ndarray:
    """``n`` equally spaced entry phases ``j/n`` in [0, 1); phase 0 is contact beginning on a step.

    Parameters
    ----------
    n : int
        Number of phases, in [1, ``MAX_PHASES``].

    Returns
    -------
    numpy.ndarray
        The phases ``0, 1/n, ..., (n-1)/n``.
    """
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

    Parameters
    ----------
    integrator : str
        Name of the scheme; its own update rule (``dtcrit.integrators.schemes``) steps the impact.
    omega_dt : array_like
        Steps tau = omega dt.
    phases : array_like
        Entry phases in [0, 1).
    zeta : float
        Damping ratio (linear contact only).
    contact : str
        ``"linear"`` or ``"hertz"``.

    Returns
    -------
    ImpactRun
        Exit ratios, status and step counts per (step, phase).
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

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    omega_dt : array_like
        Steps tau = omega dt.
    phases : array_like
        Entry phases in [0, 1).

    Returns
    -------
    numpy.ndarray or None
        The exit ratios, or None for a scheme without a closed form here.
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
    """(lower, upper) bound of v_exit/v0 over all entry phases, undamped central difference (tau < 2).

    Parameters
    ----------
    omega_dt : array_like
        Steps tau = omega dt.

    Returns
    -------
    tuple of numpy.ndarray
        The lower and upper bounds per step (NaN where tau >= 2).
    """
    with np.errstate(all="ignore"):
        lo, hi = _gen.central_difference_ratio_bounds(np.asarray(omega_dt, dtype=float))
    return lo, hi


def unit_ratio_steps(tau_min: float = 0.05, tau_max: float = 2.0) -> list[tuple[int, float]]:
    """(N, tau_N = 2 sin(pi/(2N))) in [tau_min, tau_max]: undamped central difference has
    v_exit = v0 for every entry phase exactly at these steps (the contact lasts N steps).

    Parameters
    ----------
    tau_min : float
        Smallest step to list.
    tau_max : float
        Largest step to list.

    Returns
    -------
    list of tuple of (int, float)
        ``(N, tau_N)`` pairs, N increasing (tau decreasing).
    """
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
