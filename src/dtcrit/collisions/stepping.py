"""An impact time-stepped with each integrator's own update rule (``dtcrit.integrators.schemes``).

Conventions (those of ``dtcrit.impact.stepped``, generalised to the collision laws): units ``t_c`` and
``delta_el``; the force acts where the overlap ``u >= 0`` at the point the scheme evaluates it, with the
velocity the scheme hands to the force (velocity Verlet ``v_{n+1/2}`` as LAMMPS/LIGGGHTS, leapfrog
``v_{n-1/2}`` as YADE, extended Taylor ``v_n`` as Chrono DEM-Engine; see ``integrators.engines``);
entry phase ``phase`` in [0, 1): the continuum contact begins ``phase`` of a step before the first step
with ``u >= 0`` (that step has ``u = phase h w0``); the run starts one step earlier in free flight;
exit: two consecutive ``u < 0`` after contact with a receding velocity.  Outcomes: restitution
``-v_exit/w0``, peak overlap (largest sampled overlap), duration (from the continuum entry to the
exit crossing interpolated linearly between the last two positions), energy ratio.

Velocity Verlet with ``v_{n+1/2}`` to the dashpot, leapfrog with ``v_{n-1/2}`` and symplectic Euler step
the same positions (one map written three ways), so LAMMPS, LIGGGHTS, YADE, MFiX and Kratos's default
resolve a collision alike.
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit.collisions.reference import CollisionOutcome
from dtcrit.collisions.scaled import ScaledLaw
from dtcrit.errors import InputError
from dtcrit.integrators.engines import resolve_integrator
from dtcrit.integrators.schemes import INTEGRATORS

MAX_STEPS_PER_COLLISION = 1e5
CUTOFF = 12.0  # longest simulated contact, units t_c
BLOWN = 1e8


class LawForce:
    """``f(u, w) = -(kappa u^p + g u^q w)`` for ``u >= 0`` (clipped at 0 when the law clips), else 0.

    ``dv`` (d f/d w, read by ``leapfrog-centred``) is set on each call from the overlap it was given.

    Parameters
    ----------
    law : ScaledLaw
        The scaled law.
    """

    def __init__(self, law: ScaledLaw):
        self.law = law
        self.dv = 0.0

    def __call__(self, u, w):
        """The acceleration at overlaps ``u`` and rates ``w``.

        Parameters
        ----------
        u, w : numpy.ndarray
            Overlaps and their rates.

        Returns
        -------
        numpy.ndarray
            The accelerations.
        """
        L = self.law
        up = np.maximum(u, 0.0)
        c = L.g * up**L.q if L.q else np.full_like(up, L.g)
        f = L.kappa * (up if L.p == 1.0 else up**L.p) + c * w
        if L.clip:
            f = np.maximum(f, 0.0)
        contact = u >= 0
        self.dv = np.where(contact, -c, 0.0)
        return np.where(contact, -f, 0.0)


def scheme_of(engine: str) -> str:
    """The scheme key an engine name or scheme key stands for (``integrators.engines.ENGINES``).

    Parameters
    ----------
    engine : str
        An engine of ``ENGINES`` or a scheme key of ``INTEGRATORS``.

    Returns
    -------
    str
        The scheme key.
    """
    key, _ = resolve_integrator(engine, "engine")
    if key not in INTEGRATORS:
        raise InputError("engine", f"unknown engine or scheme {engine!r}")
    return key


def run_lanes(scheme: str, law: ScaledLaw, steps, phases) -> dict:
    """Time-step one impact per lane (pairs of steps per collision N and entry phases), vectorised.

    Parameters
    ----------
    scheme : str
        A key of ``INTEGRATORS``.
    law : ScaledLaw
        The scaled law.
    steps : array_like
        N = t_c/dt per lane.
    phases : array_like
        Entry phase per lane, in [0, 1).

    Returns
    -------
    dict
        Arrays ``restitution``, ``peak_overlap``, ``duration``, ``energy_ratio`` per lane (NaN when the
        run did not separate by the cut-off, inf when it blew up).
    """
    n_arr, phi = np.broadcast_arrays(np.asarray(steps, dtype=float), np.asarray(phases, dtype=float))
    n_arr, phi = n_arr.ravel(), phi.ravel()
    if np.any(~np.isfinite(n_arr)) or np.any(n_arr < 1) or np.any(n_arr > MAX_STEPS_PER_COLLISION):
        raise InputError("steps_per_collision", f"must lie in [1, {MAX_STEPS_PER_COLLISION:g}]")
    if np.any(~((phi >= 0) & (phi < 1))):
        raise InputError("phase", "must lie in [0, 1)")
    size = n_arr.size
    h = 1.0 / n_arr
    w0 = law.w0
    integ = INTEGRATORS[scheme]
    x = (phi - 1.0) * h * w0
    v = np.full(size, w0)
    state = (x, v) if len(integ.state) == 2 else (x, v, np.zeros(size))
    out = {k: np.full(size, np.nan) for k in ("restitution", "peak_overlap", "duration")}
    idx = np.arange(size)
    n_max = np.ceil(CUTOFF * n_arr).astype(np.int64) + 8
    prev_neg = np.ones(size, dtype=bool)
    touched = np.zeros(size, dtype=bool)
    peak = np.zeros(size)
    cross = np.full(size, np.nan)
    x_prev = x.copy()
    force = LawForce(law)
    n = 0
    with np.errstate(all="ignore"):
        while idx.size:
            state = integ.step(state, h, force)
            n += 1
            xn, vn = state[0], state[1]
            neg = xn < 0
            touched |= ~neg
            peak = np.maximum(peak, xn)
            down = (x_prev >= 0) & neg
            t_n = (n + phi - 1.0) * h  # time of step n from the continuum entry
            cross = np.where(down, t_n - h + h * x_prev / (x_prev - xn), cross)
            x_prev = xn
            exited = touched & neg & prev_neg & (vn < 0)
            prev_neg = neg
            big = ~(np.abs(xn) < BLOWN) | ~(np.abs(vn) < BLOWN)
            done = exited | big | (n >= n_max)
            if not done.any():
                continue
            e_idx = idx[exited]
            out["restitution"][e_idx] = -vn[exited] / w0
            out["peak_overlap"][e_idx] = peak[exited]
            out["duration"][e_idx] = cross[exited]
            gone = big & ~exited
            out["restitution"][idx[gone]] = np.inf
            keep = ~done
            idx, h, phi, n_max = idx[keep], h[keep], phi[keep], n_max[keep]
            prev_neg, touched, peak, cross, x_prev = prev_neg[keep], touched[keep], peak[keep], cross[keep], x_prev[keep]
            state = tuple(s[keep] for s in state)
    out["energy_ratio"] = out["restitution"] ** 2
    return out


def step_outcome(scheme: str, law: ScaledLaw, steps_per_collision: float, phase: float) -> CollisionOutcome:
    """One time-stepped impact as a ``CollisionOutcome`` (``run_lanes`` with one lane).

    Parameters
    ----------
    scheme : str
        A key of ``INTEGRATORS``.
    law : ScaledLaw
        The scaled law.
    steps_per_collision : float
        N = t_c/dt.
    phase : float
        Entry phase in [0, 1).

    Returns
    -------
    CollisionOutcome
        The realised restitution, peak overlap, duration and energy ratio.
    """
    r = run_lanes(scheme, law, [float(steps_per_collision)], [float(phase)])
    return CollisionOutcome(*(float(r[k][0]) for k in ("restitution", "peak_overlap", "duration", "energy_ratio")))


__all__ = ["LawForce", "scheme_of", "run_lanes", "step_outcome", "MAX_STEPS_PER_COLLISION"]
_ = math
