"""The codes' collision rules (physics.collision_rules) against hand-computed literals (mpmath)."""
from __future__ import annotations

import math

import mpmath as mp
import pytest

from dtcrit.errors import InputError
from dtcrit.physics.collision_rules import (burns_step, code_rules, collision_time_fraction, edem_rayleigh_steps,
                                            liggghts_hertz_steps)

mp.mp.dps = 40


def test_liggghts_fraction_of_the_hertz_time():
    m, r, e, v = mp.mpf("1e-3"), mp.mpf("2e-3"), mp.mpf("3e9"), mp.mpf("1.5")
    t_h = mp.mpf("2.87") * (m ** 2 / (r * e ** 2 * v)) ** mp.mpf("0.2")  # fix_check_timestep_gran.cpp
    got = liggghts_hertz_steps(1e-3, 2e-3, 3e9, 1.5)
    assert got[0.1] == pytest.approx(float(t_h / 10), rel=1e-13)
    assert got[0.2] == pytest.approx(float(t_h / 5), rel=1e-13)


def test_edem_rayleigh_fractions():
    R, rho, E, nu = mp.mpf("1e-3"), mp.mpf(2500), mp.mpf("63e9"), mp.mpf("0.22")
    G = E / (2 * (1 + nu))
    t_r = mp.pi * R * mp.sqrt(rho / G) / (mp.mpf("0.1631") * nu + mp.mpf("0.8766"))  # Li et al. (2005)
    got = edem_rayleigh_steps(1e-3, 2500.0, 63e9, 0.22)
    assert got[0.2] == pytest.approx(float(t_r / 5), rel=1e-13)
    assert got[0.4] == pytest.approx(float(2 * t_r / 5), rel=1e-13)


def test_collision_time_over_50():
    assert collision_time_fraction(1e-4) == pytest.approx(2e-6, rel=1e-15)


@pytest.mark.parametrize("e", [1.0, 0.9, 0.5, 0.1])
def test_burns_root_of_equation_68(e):
    m, k1, v, st = mp.mpf("2e-6"), mp.mpf("4e9"), mp.mpf("0.7"), mp.mpf("3e5")
    le = mp.log(mp.mpf(e))
    beta = le / mp.sqrt(le ** 2 + mp.pi ** 2)
    c = -2 * mp.sqrt(mp.mpf(5) / 6) * beta * mp.sqrt(st * m)

    def f(dt):
        return 1 - mp.mpf("3.5") * dt * c / m - mp.mpf("3.5") * mp.sqrt(v) * k1 * dt ** mp.mpf("2.5") / m

    guess = (m / (mp.mpf("3.5") * mp.sqrt(v) * k1)) ** mp.mpf("0.4")  # the undamped root
    root = mp.findroot(f, (guess * mp.mpf("1e-3"), guess), solver="anderson")
    assert abs(f(root)) < mp.mpf("1e-25")
    assert burns_step(2e-6, 4e9, 0.7, e, 3e5) == pytest.approx(float(root), rel=1e-12)
    if e == 1.0:
        assert burns_step(2e-6, 4e9, 0.7, e, 3e5) == pytest.approx(float(guess), rel=1e-12)


def test_burns_scales_as_v_to_the_minus_one_fifth_undamped():
    a, b = burns_step(1e-6, 1e9, 1.0, 1.0, 1.0), burns_step(1e-6, 1e9, 1e4, 1.0, 1.0)
    assert a / b == pytest.approx(10.0 ** 0.8, rel=1e-12)  # dt^(5/2) sqrt(v) fixed: dt ~ v^(-1/5)


def test_linear_law_has_no_hertz_rules():
    rules = {r.key: r.dt for r in code_rules(t_c=1e-4, m_star=1e-3, v_max=1.0)}
    assert rules["tc-over-50"] == pytest.approx(2e-6)
    assert all(rules[k] is None for k in ("liggghts-hertz-0.1", "liggghts-hertz-0.2", "edem-rayleigh-0.2", "burns-2019"))


@pytest.mark.parametrize("bad", [dict(restitution=1.5), dict(restitution=0.0), dict(v=math.nan), dict(s_t=-1.0)])
def test_bad_input_is_refused(bad):
    args = dict(m_star=1e-6, k1=1e9, v=1.0, restitution=0.5, s_t=1.0) | bad
    with pytest.raises(InputError):
        burns_step(**args)
