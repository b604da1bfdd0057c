"""Continuum reference of a two-sphere collision: the engines' force laws integrated by SciPy.

Written from the engines' documented/source force laws (see ``support.engines.collisions``), not
from dtcrit: ``solve_ivp`` (DOP853, rtol 1e-12) of the contact ODE from first touch until the
overlap returns to zero, in units of the elastic peak overlap D and of D/v.

* ``head_on(imp)``: ``m* delta'' = -F``, ``F = F_el(delta) + eta(delta) * delta'``,
  clipped at zero when the engine clips (``Impact.clipped``: LAMMPS ``limit_damping``, YADE).
* ``oblique_sliding(imp)``: the plane motion of both spheres under LAMMPS's granular law with the
  contact sliding throughout: normal force as above along the current centre line, tangential
  force ``-mu |F_n| vtr/|vtr|`` with the slip velocity ``vtr = vt + n x (R_i w_i + R_j w_j)`` (full
  radii) and torques ``-(R - delta/2) n x f_s`` on both spheres (``PairGranular::compute``).  It
  refuses a case whose slip velocity reverses or whose trial Mindlin force at first touch is
  below the Coulomb limit (then the contact would stick, which this reference does not model).
* ``oblique_sticking(imp)``: the same plane motion with the contact sticking (friction >= 1e3):
  LAMMPS's ``mindlin`` history ``xi`` and force ``-k_t xi - eta_t vtr``, ``k_t = 8 G* sqrt(R* delta)``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["Reference", "head_on", "oblique_sliding", "oblique_sticking"]

RTOL = 1.0e-12


@dataclass(frozen=True)
class Reference:
    """Continuum outcome: ratios as in ``support.engines.collisions.Outcome``."""

    restitution: float
    peak_overlap: float
    duration: float
    energy_ratio: float
    tangential_restitution: float = math.nan
    spin: float = math.nan


def _normal_force(imp, delta, ddot):
    """Total normal force (repulsive > 0) at overlap delta and overlap rate ddot (SI)."""
    f = imp.elastic_force(delta) + imp.eta(delta) * ddot
    return max(f, 0.0) if imp.clipped else f


def _solve(rhs, y0, tmax, events):
    sol = solve_ivp(rhs, (0.0, tmax), y0, method="DOP853", rtol=RTOL, atol=1e-15, events=events,
                    dense_output=False)
    if sol.status != 1:
        raise RuntimeError(f"the contact did not end within {tmax} (status {sol.status}: {sol.message})")
    return sol


def head_on(imp) -> Reference:
    """Continuum outcome of the head-on impact ``imp``."""
    D, v = imp.elastic_peak, imp.speed
    T = D / v
    scale = T * T / (imp.meff * D)

    def rhs(s, y):
        return [y[1], -scale * _normal_force(imp, D * y[0], v * y[1])]

    def out(s, y):
        return y[0]

    out.terminal, out.direction = True, -1.0

    def peak(s, y):
        return y[1]

    peak.direction = -1.0
    sol = _solve(rhs, [0.0, 1.0], 50.0, [out, peak])
    e = -sol.y_events[0][0][1]
    return Reference(restitution=e, peak_overlap=float(sol.y_events[1][0][0]),
                     duration=sol.t_events[0][0] * T / imp.contact_time, energy_ratio=e * e)


def oblique_sliding(imp) -> Reference:
    """Continuum outcome of the oblique impact ``imp`` under LAMMPS's law, sliding throughout."""
    if imp.damping != "none" or imp.gammat_ratio != 0.0:
        raise ValueError("oblique_sliding: a normal or tangential dashpot makes the onset stick; not modelled")
    # first touch: trial Mindlin force / normal force = 8 G* vt / (4/3 E* v) (both ~ t^(3/2))
    if 6.0 * imp.gstar * imp.tangential_speed / (imp.estar * imp.speed) <= imp.friction:
        raise ValueError("oblique_sliding: the contact sticks at first touch; not modelled")
    return _oblique(imp, stick=False)


def oblique_sticking(imp) -> Reference:
    """Continuum outcome of the oblique impact ``imp`` under LAMMPS's ``mindlin`` law, sticking.

    The tangential displacement history ``xi`` (LAMMPS keeps it in the tangent plane, its magnitude
    preserved as the normal turns) grows at the slip velocity along the tangent; the force is
    ``-k_t xi - eta_t vtr`` with ``k_t = 8 G* sqrt(R* delta)`` (``mindlin NULL``) and
    ``eta_t = gammat_ratio * eta_n``.  Coulomb's limit is taken not to bind (``friction`` >= 1e3:
    it binds only where the normal force vanishes at the very end); a case where it binds before
    the last 1 % of the contact is refused.
    """
    if imp.friction < 1.0e3:
        raise ValueError("oblique_sticking: needs friction >= 1e3 (Coulomb's limit not modelled)")
    return _oblique(imp, stick=True)


def _oblique(imp, *, stick: bool) -> Reference:
    D, v, R, m = imp.elastic_peak, imp.speed, imp.radius, imp.mass
    T = D / v
    inertia = 0.4 * m * R * R
    mu = imp.friction

    def state(y):
        # y = [q_x, q_y, u_x, u_y, W]: r = x1 - x2 = (-2R + D q_x, D q_y); vr = v1 - v2 = v (u_x, u_y);
        # W = spin of each sphere (equal by symmetry) times T
        qx, qy = D * y[0], D * y[1]
        rx, ry = -2.0 * R + qx, qy
        rr = math.hypot(rx, ry)
        delta = (4.0 * R * qx - qx * qx - qy * qy) / (2.0 * R + rr)  # 2R - |r| without cancellation
        n = np.array([rx, ry]) / rr
        return delta, n

    def forces(y):
        delta, n = state(y)
        vr = v * np.array([y[2], y[3]])
        w = y[4] / T
        vnnr = vr @ n
        fn = _normal_force(imp, delta, -vnnr)
        vt = vr - vnnr * n
        vtr = vt + np.array([n[1], -n[0]]) * (2.0 * R * w)  # vt + n x (R w1 + R w2), w along z
        if stick:
            tan = np.array([-n[1], n[0]])
            kt = 8.0 * imp.gstar * math.sqrt(imp.reff * max(delta, 0.0))
            fs = -(kt * D * y[5]) * tan - imp.gammat_ratio * imp.eta(delta) * vtr
        else:
            fs = -mu * abs(fn) * vtr / np.linalg.norm(vtr)
        torque = -(R - 0.5 * delta) * (n[0] * fs[1] - n[1] * fs[0])
        return delta, n, fn, fs, torque, vtr

    def rhs(t, y):
        _, n, fn, fs, torque, vtr = forces(y)
        acc = 2.0 * (fn * n + fs) / m  # d(v1 - v2)/dt
        dy = [y[2], y[3], acc[0] * T / v, acc[1] * T / v, torque / inertia * T * T]
        if stick:  # d(xi/D)/ds = vtr . t / v
            n = state(y)[1]
            dy.append((vtr @ np.array([-n[1], n[0]])) / v)
        return dy

    def out(t, y):
        return state(y)[0] / D

    out.terminal, out.direction = True, -1.0

    def peak(t, y):
        return -(np.array([y[2], y[3]]) @ state(y)[1])  # overlap rate

    peak.direction = -1.0
    y0 = [0.0, 0.0, 1.0, imp.tangential_speed / v, 0.0] + ([0.0] if stick else [])
    sol = solve_ivp(rhs, (0.0, 50.0), y0, method="DOP853", rtol=RTOL, atol=1e-15, events=[out, peak])
    if sol.status != 1:
        raise RuntimeError(f"oblique reference: {sol.message}")
    if stick:
        t_end = sol.t_events[0][0]
        for k in range(sol.y.shape[1]):
            if sol.t[k] < 0.99 * t_end:
                _, _, fn, fs, _, _ = forces(sol.y[:, k])
                if np.linalg.norm(fs) > mu * abs(fn):
                    raise ValueError("oblique_sticking: Coulomb's limit binds before the end; not modelled")
    else:
        slips = [forces(sol.y[:, k])[5] for k in range(sol.y.shape[1])]
        if min(s @ slips[0] for s in slips) <= 0.0:
            raise ValueError("oblique_sliding: the slip velocity reverses during the contact; not modelled")
    yend = sol.y_events[0][0]
    _, n_end = state(yend)
    n0 = np.array([-1.0, 0.0])
    # measure's conventions: d = x2 - x1 = -r, relative velocity v2 - v1 = -vr
    vin = -v * (np.array(y0[2:4]) @ -n0)
    vout = -v * (np.array(yend[2:4]) @ -n_end)
    e = -vout / vin
    slip0 = forces(np.array(y0))[5]
    slip_end = forces(yend)[5]
    et = float((slip_end @ slip0) / (slip0 @ slip0))
    w_end = yend[4] / T
    vt0 = imp.tangential_speed
    ke0 = 0.25 * m * (v * v + vt0 * vt0)  # relative motion of two equal masses: (m/4) |vr|^2
    ke1 = 0.25 * m * v * v * (yend[2] ** 2 + yend[3] ** 2) + inertia * w_end**2
    return Reference(restitution=e, peak_overlap=float(state(sol.y_events[1][0])[0] / D),
                     duration=sol.t_events[0][0] * T / imp.contact_time, energy_ratio=ke1 / ke0,
                     tangential_restitution=et, spin=w_end * R / vt0)

