"""The codes' step estimates (``dtcrit.physics.rules_of_thumb``) against closed forms: the Rayleigh
equation solved by mpmath, the undamped and damped collision times of a spring-dashpot, YADE's constants."""
import math

import mpmath as mp
import numpy as np
import pytest

from dtcrit.physics import rules_of_thumb as rot


def _rayleigh_exact(radius, rho, youngs, nu):
    """pi R / c_R with c_R the root of the Rayleigh equation, 40 digits."""
    with mp.workdps(40):
        nu_ = mp.mpf(nu)
        kappa = (1 - 2 * nu_) / (2 * (1 - nu_))
        f = lambda x: (2 - x**2) ** 2 - 4 * mp.sqrt(1 - x**2) * mp.sqrt(1 - kappa * x**2)  # noqa: E731
        ratio = mp.findroot(f, (mp.mpf("0.8"), mp.mpf("0.99")), solver="anderson")
        c_s = mp.sqrt(mp.mpf(youngs) / (2 * (1 + nu_)) / rho)
        return float(mp.pi * radius / (ratio * c_s))


def test_rayleigh_time_within_its_fit_of_the_exact_wave_time_on_arrays_and_scalars():
    radii = np.array([1e-3, 2e-3, 5e-4])
    nus = [0.0, 0.22, 0.3, 0.45]
    for nu in nus:
        got = rot.rayleigh_time(radii, 2500.0, 6e10, nu)
        assert isinstance(got, np.ndarray)
        for r, t in zip(radii, got):
            assert t == pytest.approx(_rayleigh_exact(r, 2500.0, 6e10, nu), rel=3e-3)
            assert rot.rayleigh_time(float(r), 2500.0, 6e10, nu) == t
    assert isinstance(rot.rayleigh_time(1e-3, 2500.0, 6e10, 0.3), float)


def test_collision_times():
    """Undamped: half a period of sqrt(k/m*), pi sqrt(m*/k); damped: pi / omega_d."""
    assert rot.collision_time(2.0, 8.0) == pytest.approx(math.pi / 2, rel=1e-15)
    assert rot.collision_time(np.array([1.0]), np.array([0.0]))[0] == math.inf
    k, m, zeta = 1e5, 1e-3, 0.3
    c = 2 * zeta * math.sqrt(k * m)
    with mp.workdps(30):
        omega_d = mp.sqrt(mp.mpf(k) / m - (mp.mpf(c) / (2 * m)) ** 2)
        assert rot.damped_collision_time(k, c, m) == pytest.approx(float(mp.pi / omega_d), rel=1e-14)
    assert rot.damped_collision_time(1.0, 2.0, 1.0) is None


def test_yade_global_stiffness_time_stepper_constants():
    """GlobalStiffnessTimeStepper.cpp: dt = 1.41044 sqrt(m/K) x timestepSafetyCoefficient (0.8)."""
    m, k = 2.0, 8.0
    diagonal = rot.diagonal_stiffness_step(m, 1e30, k, 1.0)
    assert diagonal == pytest.approx(math.sqrt(2) * 0.5, rel=1e-15)
    assert rot.yade_gsts_step(diagonal, 0.8) == pytest.approx(1.41044 * 0.5 * 0.8, rel=1e-15)
    assert rot.yade_gsts_step(diagonal) == pytest.approx(1.41044 * 0.5, rel=1e-15)


def test_hertz_contact_time_constant():
    """2.87 (m*^2/(R* E*^2 v))^(1/5), the constant LIGGGHTS prints."""
    m, r, e, v = 1e-5, 1e-3, 1e10, 2.0
    assert rot.hertz_contact_time(m, r, e, v) == pytest.approx(2.87 * (m * m / (r * e * e * v)) ** 0.2, rel=1e-14)
