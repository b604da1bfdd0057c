"""``dtcrit collide --angle``'s oblique resolution step, checked by an impact stepped here.

Two equal glass spheres (R = 1 mm, E = 63 GPa, nu = 0.22, 2500 kg/m^3) collide at 1 m/s with an angle
from the normal; friction 0.1 at 60 deg (the contact slides throughout), 0.5 at 5 deg (it sticks).  The
test steps the impact itself with a plain velocity-Verlet loop of both spheres in SI units, written from
LAMMPS's ``pair_style granular hertz/material ... tangential mindlin NULL 0 mu`` (``PairGranular::compute``,
2021: history projected onto the tangent plane and rescaled, ``xi += v_tr dt`` at every contact step,
Coulomb's cap resetting ``xi``; torque arm ``R - delta/2``) and ``fix nve/sphere`` (half kick, drift,
forces, half kick; ``I = 0.4 m R^2``), at 0.999x and 1.2x the reported step over a dense sweep of entry
phases refined by bounded optimisation.  The continuum it compares with is solved here too (``solve_ivp``,
DOP853, rtol 1e-12): sliding with ``F_t = -mu F_n`` along the slip, or sticking with the tangential
spring on the history ``xi' = v_tr``.  Tangential restitution: exit over entry slip (contact-point)
speed along the entry tangent; spin: the rebound ``omega R/v_t`` of a sphere (absolute error).
"""
from __future__ import annotations

import functools
import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar

from dtcrit.cli import main

R, RHO, E, NU, V = 1.0e-3, 2500.0, 63.0e9, 0.22, 1.0
M = RHO * 4.0 / 3.0 * math.pi * R ** 3
I_ROT = 0.4 * M * R * R
E_STAR = E / (2.0 * (1.0 - NU * NU))
G_STAR = E / (2.0 * (1.0 + NU)) / (2.0 * (2.0 - NU))
R_STAR = R / 2.0
SCENE = f"""
integrator = "velocity-verlet"
[[particle]]
shape = "sphere"
radius = {R}
density = {RHO}
youngs_modulus = {E}
poisson_ratio = {NU}
[contact]
model = "hertz"
velocity = {V}
friction = FRICTION
"""
CASES = {"sliding": (60.0, 0.1), "sticking": (5.0, 0.5)}


def _forces_geometry(x1, x2):
    r = x1 - x2
    d = math.hypot(*r)
    return 2.0 * R - d, r / d


def _slip(vr, n, w_sum):
    """Contact-point slip v_t + n x (R w1 + R w2) z in the plane."""
    vt = vr - (vr @ n) * n
    return vt + R * w_sum * np.array([n[1], -n[0]])


@functools.lru_cache(maxsize=None)
def _stepped(dt, angle, mu, phase):
    """One impact stepped by velocity Verlet as LAMMPS applies it; (tangential restitution, spin)."""
    vn, vt = V * math.cos(math.radians(angle)), V * math.sin(math.radians(angle))
    t_touch = (1.0 - phase) * dt
    x1, x2 = np.array([-2.0 * R - vn * t_touch, -vt * t_touch]), np.zeros(2)
    v1, v2 = np.array([vn, vt]), np.zeros(2)
    w1 = w2 = 0.0
    f, tq1, tq2, xi = np.zeros(2), 0.0, 0.0, np.zeros(2)
    touched, d_prev, r_prev = False, None, None
    for _ in range(100000):
        v1, v2 = v1 + 0.5 * dt * f / M, v2 - 0.5 * dt * f / M
        w1, w2 = w1 + 0.5 * dt * tq1 / I_ROT, w2 + 0.5 * dt * tq2 / I_ROT
        x1, x2 = x1 + dt * v1, x2 + dt * v2
        delta, n = _forces_geometry(x1, x2)
        if delta > 0.0:
            touched = True
            a = math.sqrt(R_STAR * delta)
            fn = 4.0 / 3.0 * E_STAR * a * delta
            kt = 8.0 * G_STAR * a
            crit = mu * fn
            rsht = xi @ n
            if abs(rsht) * kt > 1e-10 * crit:  # LAMMPS's frameupdate
                mag = math.hypot(*xi)
                xi = xi - rsht * n
                prj = math.hypot(*xi)
                xi = xi * (mag / prj) if prj > 0.0 else 0.0 * xi
            xi = xi + _slip(v1 - v2, n, w1 + w2) * dt
            fs = -kt * xi
            fmag = math.hypot(*fs)
            if fmag > crit:
                if math.hypot(*xi) != 0.0:
                    xi = -crit * fs / fmag / kt
                    fs = fs * crit / fmag
                else:
                    fs = 0.0 * fs
            f = fn * n + fs
            tor = n[0] * fs[1] - n[1] * fs[0]
            tq1 = tq2 = -(R - 0.5 * delta) * tor
        else:
            f, tq1, tq2, xi = np.zeros(2), 0.0, 0.0, np.zeros(2)
        v1, v2 = v1 + 0.5 * dt * f / M, v2 - 0.5 * dt * f / M
        w1, w2 = w1 + 0.5 * dt * tq1 / I_ROT, w2 + 0.5 * dt * tq2 / I_ROT
        if touched and delta <= 0.0:
            r_out = r_prev + (x1 - x2 - r_prev) * (d_prev / (d_prev - delta))
            n_out = r_out / math.hypot(*r_out)
            t0 = np.array([0.0, -1.0])  # the entry tangent (n0 = (-1, 0) rotated by +90 deg)
            e_t = (_slip(v1 - v2, n_out, w1 + w2) @ t0) / (np.array([0.0, vt]) @ t0)
            return float(e_t), float(w1 * R / vt)
        d_prev, r_prev = delta, x1 - x2
    raise AssertionError("the spheres did not separate")


def _continuum(angle, mu, regime):
    """Both spheres' plane motion from touch to separation (DOP853, rtol 1e-12); (e_t, spin)."""
    vn, vt = V * math.cos(math.radians(angle)), V * math.sin(math.radians(angle))

    def rhs(_t, y):
        x1, x2, v1, v2, w1, w2, xi = y[0:2], y[2:4], y[4:6], y[6:8], y[8], y[9], y[10]
        delta, n = _forces_geometry(x1, x2)
        delta = max(delta, 0.0)
        a = math.sqrt(R_STAR * delta)
        fn = 4.0 / 3.0 * E_STAR * a * delta
        t = np.array([-n[1], n[0]])
        s = _slip(v1 - v2, n, w1 + w2) @ t
        ft = -8.0 * G_STAR * a * xi if regime == "sticking" else -mu * fn * math.copysign(1.0, s)
        f = fn * n + ft * t
        tq = -(R - 0.5 * delta) * ft
        return [*v1, *v2, *(f / M), *(-f / M), tq / I_ROT, tq / I_ROT, s]

    def apart(_t, y):
        return _forces_geometry(y[0:2], y[2:4])[0]

    apart.terminal, apart.direction = True, -1.0
    eps = 1e-14
    y0 = np.array([-2.0 * R + vn * eps, vt * eps, 0.0, 0.0, vn, vt, 0.0, 0.0, 0.0, 0.0, 0.0])
    sol = solve_ivp(rhs, (eps, 1e-3), y0, method="DOP853", rtol=1e-12, atol=1e-20, events=[apart])
    assert sol.status == 1
    y = sol.y_events[0][0]
    _, n = _forces_geometry(y[0:2], y[2:4])
    e_t = (_slip(y[4:6] - y[6:8], n, y[8] + y[9]) @ np.array([0.0, -1.0])) / -vt
    return float(e_t), float(y[8] * R / vt)


def _worst(dt, angle, mu, ref, tol, which=(0, 1)):
    """Worst over the entry phase of max(|e_t/e_t_ref - 1|, |spin - spin_ref|)/tol (or of the quantities
    ``which`` picks): 96 phases, the three worst refined by bounded optimisation.
    """
    def ratio(p):
        e_t, spin = _stepped(float(dt), angle, mu, float(p))
        return max((abs(e_t / ref[0] - 1.0), abs(spin - ref[1]))[k] for k in which) / tol

    ph = (np.arange(96) + 0.5) / 96
    vals = np.array([ratio(p) for p in ph])
    worst = float(vals.max())
    for k in np.argsort(vals)[-3:]:
        res = minimize_scalar(lambda p: -ratio(p), bounds=(max(ph[k] - 1 / 96, 0.0), min(ph[k] + 1 / 96, 1 - 1e-12)),
                              method="bounded", options={"xatol": 1e-7})
        worst = max(worst, -float(res.fun))
    return worst


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """The two scenes (sliding and sticking), written once."""
    out = {}
    for regime, (angle, mu) in CASES.items():
        path = tmp_path_factory.mktemp(regime) / "scene.toml"
        path.write_text(SCENE.replace("FRICTION", str(mu)))
        out[regime] = path, angle, mu
    return out


def _report(capsys, path, angle):
    assert main(["collide", str(path), "--angle", str(angle), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("regime", list(CASES))
def test_oblique_resolution_step_by_an_impact_stepped_here(regime, reports, capsys):
    """Within tol at 0.999x the oblique resolution step (every phase), outside it just above.

    At a few steps per collision (sliding: N_res ~ 4) the error is not monotone in the step: measured
    here it exceeds tol from 1.005x to 1.1x, is within it again at 1.15x-1.2x and exceeds it at 1.3x,
    so the violation is sought at 1.005x and 1.2x (the largest step whose every smaller step is within
    tol has a violation just above it).
    """
    path, angle, mu = reports[regime]
    doc = _report(capsys, path, angle)
    (pair,) = doc["pairs"]
    obl = pair["oblique"]
    assert obl["regime"] == regime
    ref = _continuum(angle, mu, regime)
    assert obl["reference"]["tangential_restitution"] == pytest.approx(ref[0], rel=1e-8)
    assert obl["reference"]["spin"] == pytest.approx(ref[1], rel=1e-8, abs=1e-8)  # SI positions: ~1e-9 cancellation
    dt_res, tol = obl["dt_resolution"], doc["tol"]
    assert _worst(0.999 * dt_res, angle, mu, ref, tol) <= 1.0
    assert max(_worst(f * dt_res, angle, mu, ref, tol) for f in (1.005, 1.2)) > 1.0
    # the errors reported at the chosen step are those of the impact stepped here
    assert obl["steps_per_collision"] == pytest.approx(obl["t_c"] / pair["dt"], rel=1e-12)
    for k, name in enumerate(("tangential_restitution", "spin")):
        assert obl["errors_at_dt"][name] == pytest.approx(_worst(pair["dt"], angle, mu, ref, 1.0, (k,)), rel=1e-4)
    assert obl["binding"] == (pair["binding"] == "oblique-resolution")
    assert pair["dt"] == pytest.approx(min(pair["dt_stability"], pair["dt_resolution"], dt_res), rel=1e-15)


def test_the_oblique_contact_time_is_hertz_at_the_normal_speed(reports, capsys):
    """t_c at v_n = v cos(angle): 2 (delta_max/v_n) int_0^1 dx/sqrt(1 - x^(5/2)), delta_max from energy."""
    from scipy.integrate import quad

    path, angle, _ = reports["sliding"]
    obl = _report(capsys, path, angle)["pairs"][0]["oblique"]
    vn = V * math.cos(math.radians(angle))
    m_star = M / 2.0
    delta = (15.0 * m_star * vn ** 2 / (16.0 * E_STAR * math.sqrt(R_STAR))) ** 0.4
    integral = quad(lambda x: 1.0 / math.sqrt(1.0 - x ** 2.5), 0.0, 1.0, epsabs=1e-13, epsrel=1e-13)[0]
    assert obl["t_c"] == pytest.approx(2.0 * delta / vn * integral, rel=1e-8)
    assert obl["overlap_ratio"] == pytest.approx(delta / R, rel=1e-10)
    assert obl["v_normal"] == pytest.approx(vn, rel=1e-15)


def test_every_smaller_step_is_within_tol_when_sliding(reports, capsys):
    """Sliding at 60 deg (N_res ~ 4, where the error is not monotone in the step): the impact stepped here
    stays within tol at every step of a 2 % geometric grid from 0.999x down to a third of the step.
    """
    path, angle, mu = reports["sliding"]
    doc = _report(capsys, path, angle)
    dt_res, tol = doc["pairs"][0]["oblique"]["dt_resolution"], doc["tol"]
    ref = _continuum(angle, mu, "sliding")
    for f in 0.999 * 0.98 ** np.arange(55):
        assert _worst(f * dt_res, angle, mu, ref, tol) <= 1.0, f
