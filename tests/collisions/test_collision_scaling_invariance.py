"""Scale invariance: impacts time-stepped in PHYSICAL units (SI), speeds over five decades and sizes over three,
give the same scaled outcome as the scaled law (restitution, peak/delta_el, duration/t_c) to ~1e-9.

The physical run is written here on its own: the scheme's update rule with the physical force of
``collision_law`` divided by the mass, ``t_c`` and ``delta_el`` from the energy balance.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dtcrit.collisions.laws import scaled_law
from dtcrit.collisions.scaled import scaled_from_physical
from dtcrit.collisions.stepping import run_lanes
from dtcrit.integrators.schemes import INTEGRATORS
from dtcrit.physics.collision_laws import collision_law

RHO, YOUNG, NU = 2500.0, 7e9, 0.25


class Accel:
    def __init__(self, law):
        self.law, self.dv = law, 0.0

    def __call__(self, x, v):
        return -self.law.force(x, v) / self.law.m_eff


def physical_run(scheme, law, v0, dt, phase, max_steps=100000):
    """(restitution, peak [m], duration [s]) of one physical impact, contact starting ``phase`` of a step before
    the first step with overlap >= 0."""
    integ = INTEGRATORS[scheme]
    x = (phase - 1.0) * dt * v0
    state = (x, v0) if len(integ.state) == 2 else (x, v0, 0.0)
    f = Accel(law)
    peak, cross, touched, prev_neg, n, x_prev = 0.0, None, False, True, 0, x
    while n < max_steps:
        state = integ.step(state, dt, f)
        n += 1
        xn, vn = float(state[0]), float(state[1])
        peak = max(peak, xn)
        if x_prev >= 0 > xn:
            cross = (n + phase - 2.0) * dt + dt * x_prev / (x_prev - xn)
        touched |= xn >= 0
        if touched and xn < 0 and prev_neg and vn < 0:
            return -vn / v0, peak, cross
        prev_neg, x_prev = xn < 0, xn
    return math.nan, peak, math.nan  # not separated within the cut-off


def scales(law, v0):
    if law.exponent == 1.0:
        w = math.sqrt(law.stiffness / law.m_eff)
        return math.pi / w, v0 / w
    d_el = (5.0 * law.m_eff * v0**2 / (4.0 * law.stiffness)) ** 0.4  # m v^2/2 = (2/5) K d^(5/2)
    t_c = 2.0 * d_el / v0 * 1.4716375921623523  # int_0^1 du/sqrt(1 - u^(5/2)) (mpmath, 16 digits)
    return t_c, d_el


def make_law(kind, radius, e):
    m_eff = RHO * 4.0 / 3.0 * math.pi * radius**3 / 2.0
    e_star, r_star = YOUNG / (2.0 * (1.0 - NU**2)), radius / 2.0
    if kind == "hooke":
        return collision_law("hooke", "liggghts", m_eff=m_eff, k=1e3 * YOUNG * radius / 1e3, restitution=e)
    return collision_law("hertz", kind, m_eff=m_eff, E_eff=e_star, R_eff=r_star, restitution=e)


def check(scheme, kind, radius, v0, e, phase, n=12.0):
    law = make_law(kind, radius, e)
    t_c, d_el = scales(law, v0)
    e_p, peak, dur = physical_run(scheme, law, v0, t_c / n, phase, math.ceil(12.0 * n) + 8)
    scaled = scaled_law(law.normal, kind if kind != "hooke" else "liggghts", e)  # from e alone
    assert scaled_from_physical(law, v0).g == pytest.approx(scaled.g, rel=1e-12, abs=1e-15)
    r = run_lanes(scheme, scaled, [n], [phase])
    if not math.isfinite(e_p):  # both runs still in contact after 12 t_c (a heavy dashpot at a coarse step)
        assert not math.isfinite(r["restitution"][0])
        return e_p
    assert e_p == pytest.approx(r["restitution"][0], rel=1e-9, abs=1e-12)
    assert peak / d_el == pytest.approx(r["peak_overlap"][0], rel=1e-9)
    assert dur / t_c == pytest.approx(r["duration"][0], rel=1e-9)
    return e_p


@pytest.mark.parametrize("scheme", ["velocity-verlet", "leapfrog", "extended-taylor"])
@pytest.mark.parametrize("kind", ["liggghts", "yade-mindlin", "lammps-tsuji", "hooke"])
def test_same_scaled_outcome_over_decades(scheme, kind):
    outcomes = [check(scheme, kind, radius, v0, 0.6, 0.3)
                for v0 in (1e-3, 1e-1, 1e1, 1e2) for radius in (1e-4, 1e-3, 1e-2, 1e-1)]
    assert np.ptp(outcomes) < 1e-9 * max(outcomes)


@settings(max_examples=40, deadline=None)
@given(scheme=st.sampled_from(["velocity-verlet", "leapfrog", "extended-taylor", "symplectic-euler"]),
       kind=st.sampled_from(["liggghts", "yade-mindlin", "lammps-tsuji", "lammps-coeff-restitution", "hooke"]),
       log_r=st.floats(-4.0, -1.0), log_v=st.floats(-3.0, 2.0), e=st.floats(0.05, 1.0), phase=st.floats(1e-6, 0.999),  # phase 0 is a rounding tie: contact on the step or the next
       n=st.floats(5.0, 60.0))
def test_scaled_outcome_at_random_sizes_and_speeds(scheme, kind, log_r, log_v, e, phase, n):
    check(scheme, kind, 10.0**log_r, 10.0**log_v, e, phase, n)
