"""The time-stepped impact against independent implementations and the undamped closed forms.

* an independent implementation of every integrator in exact rational arithmetic (``Fraction``),
  written from the schemes' textbook descriptions (leapfrog in position form), with its own
  contact switching and exit detection;
* an independent 40-digit mpmath leapfrog for the Hertz contact;
* the closed forms of ``dtcrit.symbolic.impact`` (central-difference family, forward Euler) vs the
  simulation over steps and phases spanning decades;
* Feng's isolated steps tau_N = 2 sin(pi/(2N)), the phase bounds and the sweep book-keeping.
"""
import math
from fractions import Fraction as Fr

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import dtcrit.impact as imp
from dtcrit.errors import InputError
from dtcrit.integrators.schemes import NAMES

FAMILY = imp.CENTRAL_DIFFERENCE_FAMILY


# ----------------------------------------------------------------------------------------------
# independent exact-arithmetic impact
# ----------------------------------------------------------------------------------------------

def _force(x, v, C):
    """Unit-stiffness spring-dashpot acceleration, switched off for x < 0."""
    return -x - C * v if x >= 0 else Fr(0)


def _exact_ratio(name, tau, zeta, phi, max_steps=400):
    """Exit/entry speed of the impact, in Fractions.  Entry: last free position (phi - 1) tau, speed 1."""
    h, C = Fr(tau), 2 * Fr(zeta)
    x_prev = (Fr(phi) - 1) * h  # free flight
    if name in ("leapfrog", "symplectic-euler", "leapfrog-centred"):
        # position form: x_{n+1} = 2 x_n - x_{n-1} + h^2 a_n, with the free-flight history x_{-2}
        xs = [x_prev - h, x_prev]
        for _ in range(max_steps):
            x0, x1 = xs[-2], xs[-1]
            v_lag = (x1 - x0) / h  # v_{n-1/2}
            if name == "leapfrog-centred" and x1 >= 0:
                # a = -x_n - C (x_{n+1} - x_{n-1})/(2h), solved for x_{n+1}
                x2 = (2 * x1 - x0 - h * h * x1 + C * h / 2 * x0) / (1 + C * h / 2)
            else:
                x2 = 2 * x1 - x0 + h * h * _force(x1, v_lag, C)
            xs.append(x2)
            v = (x2 - x1) / h
            if len(xs) > 3 and x2 < 0 and x1 < 0 and v < 0 and any(q >= 0 for q in xs):
                return -v
        raise AssertionError("no exit")
    if name in ("velocity-verlet", "velocity-verlet-predicted"):
        x, v, a = x_prev, Fr(1), Fr(0)
        seen, prev_neg = False, True
        for _ in range(max_steps):
            v_half = v + h / 2 * a
            x_new = x + h * v_half
            v_damp = v_half if name == "velocity-verlet" else v + h * a
            a = _force(x_new, v_damp, C)
            v = v_half + h / 2 * a
            x = x_new
            seen |= x >= 0
            if seen and x < 0 and prev_neg and v < 0:
                return -v
            prev_neg = x < 0
        raise AssertionError("no exit")
    if name in ("forward-euler", "paper-eq40"):
        x, v, a_lag = x_prev, Fr(1), Fr(0)
        seen, prev_neg = False, True
        for _ in range(max_steps):
            if name == "forward-euler":
                x, v = x + h * v, v + h * _force(x, v, C)
            else:  # acceleration row lags one step (Peng et al. 2020, Eq. (40) as printed)
                x, v, a_lag = x + h * v, v + h * a_lag, _force(x, v, C)
            seen |= x >= 0
            if seen and x < 0 and prev_neg and v < 0:
                return -v
            prev_neg = x < 0
        raise AssertionError("no exit")
    if name in ("extended-taylor", "adams-bashforth-2"):
        # force (dashpot included) at (x_n, v_n); a_old is the previous step's force (0 in free flight)
        x, v, a_old = x_prev, Fr(1), Fr(0)
        seen, prev_neg = False, True
        for _ in range(max_steps):
            a = _force(x, v, C)
            if name == "extended-taylor":  # second-order Taylor polynomial in x, first-order in v
                x, v = x + h * v + h * h / 2 * a, v + h * a
            else:  # v by Adams-Bashforth 2, x by the trapezoidal rule, written out in the old values
                x, v, a_old = x + h * v + h * h / 4 * (3 * a - a_old), v + h / 2 * (3 * a - a_old), a
            seen |= x >= 0
            if seen and x < 0 and prev_neg and v < 0:
                return -v
            prev_neg = x < 0
        raise AssertionError("no exit")
    raise KeyError(name)


CASES = [
    (Fr(1, 2), Fr(0), Fr(0)),
    (Fr(1, 2), Fr(1, 20), Fr(1, 3)),
    (Fr(6, 5), Fr(0), Fr(3, 4)),
    (Fr(6, 5), Fr(1, 5), Fr(0)),
    (Fr(19, 10), Fr(1, 20), Fr(3, 4)),
    (Fr(1, 10), Fr(1, 5), Fr(5, 8)),
    (Fr(3, 2), Fr(1, 5), Fr(1, 3)),
]


@pytest.mark.parametrize("name", NAMES)
def test_simulation_matches_exact_rational_implementation(name):
    """Same exit speed as the independent Fraction implementation, to rounding (rel 1e-12)."""
    for tau, zeta, phi in CASES:
        exact = _exact_ratio(name, tau, zeta, phi)
        run = imp.simulate_impacts(name, [float(tau)], [float(phi)], float(zeta))
        assert run.status[0, 0] == imp.STATUS_EXITED
        got = run.ratios[0, 0]
        assert got == pytest.approx(float(exact), rel=1e-12), (name, tau, zeta, phi)


def test_phase_sweep_statistics_match_exact_rational_implementation():
    """min / mean / max / on_step over 8 phases, against the Fraction implementation."""
    phases = imp.entry_phases(8)
    for name in ("leapfrog", "velocity-verlet-predicted", "forward-euler"):
        for tau, zeta in ((Fr(7, 10), Fr(1, 20)), (Fr(13, 10), Fr(1, 5))):
            exact = [float(_exact_ratio(name, tau, zeta, Fr(j, 8))) for j in range(8)]
            (s,) = imp.phase_stats(imp.simulate_impacts(name, [float(tau)], phases, float(zeta)))
            assert s.min == pytest.approx(min(exact), rel=1e-12)
            assert s.max == pytest.approx(max(exact), rel=1e-12)
            assert s.mean == pytest.approx(sum(exact) / 8, rel=1e-12)
            assert s.on_step == pytest.approx(exact[0], rel=1e-12)
            assert s.separated == 1.0


# ----------------------------------------------------------------------------------------------
# undamped closed forms
# ----------------------------------------------------------------------------------------------

taus_family = st.floats(-3, math.log10(1.999)).map(lambda e: 10.0**e)
phis = st.floats(0, 1, exclude_max=True)


@given(tau=taus_family, phi=phis)
def test_central_difference_closed_form_matches_simulation(tau, phi):
    """sqrt((1 - tau^2 phi(1-phi))/(1 - tau^2 psi(1-psi))) for all five schemes of the family
    (identical when undamped), tau from 1e-3 to 1.999."""
    closed = imp.undamped_exit_ratios("leapfrog", [tau], [phi])[0, 0]
    for name in FAMILY:
        got = imp.simulate_impacts(name, [tau], [phi], 0.0).ratios[0, 0]
        assert got == pytest.approx(closed, rel=1e-9), name
    lo, hi = imp.central_difference_bounds(tau)
    assert lo * (1 - 1e-12) <= closed <= hi * (1 + 1e-12)


@given(tau=st.floats(-3, math.log10(2.2)).map(lambda e: 10.0**e), phi=phis)
def test_forward_euler_closed_form_matches_simulation(tau, phi):
    closed = imp.undamped_exit_ratios("forward-euler", [tau], [phi])[0, 0]
    got = imp.simulate_impacts("forward-euler", [tau], [phi], 0.0).ratios[0, 0]
    assert got == pytest.approx(closed, rel=1e-9)
    assert got > 1.0  # forward Euler always gains energy in an undamped impact


def test_on_step_entry_never_loses_energy_undamped():
    """phi = 0 gives Q_in = 1, so ratio = 1/sqrt(1 - tau^2 psi(1 - psi)) >= 1 (central difference)."""
    grid = imp.sweep_grid(0.01, 1.99)
    r = imp.simulate_impacts("velocity-verlet", grid, [0.0], 0.0).ratios[:, 0]
    assert np.all(r >= 1 - 1e-12)


@pytest.mark.parametrize("N", [2, 3, 4, 5, 8, 13])
def test_feng_isolated_steps_give_exit_speed_equal_to_entry(N):
    """At tau_N = 2 sin(pi/(2N)) (the contact lasts N steps) v_exit = v0 for every phase; between
    consecutive tau_N some phase gains energy (Feng 2005, as summarised in the CFL note)."""
    phases = imp.entry_phases(97)
    t_n = 2 * math.sin(math.pi / (2 * N))
    for name in ("leapfrog", "velocity-verlet"):
        r = imp.simulate_impacts(name, [t_n], phases, 0.0).ratios[0]
        assert np.max(np.abs(r - 1)) < 1e-11
        t_mid = 0.5 * (t_n + 2 * math.sin(math.pi / (2 * (N + 1))))
        r_mid = imp.simulate_impacts(name, [t_mid], phases, 0.0).ratios[0]
        assert r_mid.max() > 1 + 1e-4 and r_mid.min() < 1 - 1e-4
    assert [n for n, _ in imp.unit_ratio_steps(t_n * 0.999, t_n * 1.001)] == [N]


def test_damping_removes_energy_creation_at_small_steps():
    """zeta = 0.05 / 0.2: max over phases stays below 1 up to omega*dt ~ 1 (central difference)."""
    grid = imp.sweep_grid(0.02)
    for zeta, safe in ((0.05, 1.0), (0.2, 1.2)):
        _, stats = imp.sweep("leapfrog", zeta, grid, 64)
        assert all(s.max < 1 for s in stats if s.omega_dt <= safe)
        assert any(s.max > 1 for s in stats if s.omega_dt > safe)


# ----------------------------------------------------------------------------------------------
# Hertz: independent high-precision stepping
# ----------------------------------------------------------------------------------------------

def _mp_hertz_leapfrog(tau, phi, dps=40):
    """Position-form leapfrog of u'' = -(2/3) u^(3/2) (u >= 0) at 40 digits; returns v_exit/v0."""
    with mp.workdps(dps):
        h = mp.mpf(tau)
        v0 = mp.sqrt(mp.mpf(8) / 15)
        c = mp.mpf(2) / 3
        xs = [(mp.mpf(phi) - 2) * h * v0, (mp.mpf(phi) - 1) * h * v0]
        for _ in range(100000):
            x1 = xs[-1]
            acc = -c * x1 ** mp.mpf(1.5) if x1 >= 0 else mp.mpf(0)
            xs.append(2 * x1 - xs[-2] + h * h * acc)
            v = (xs[-1] - xs[-2]) / h
            if xs[-1] < 0 and xs[-2] < 0 and v < 0 and any(q >= 0 for q in xs):
                return float(-v / v0)
    raise AssertionError("no exit")


@pytest.mark.parametrize("tau,phi", [(0.05, 0.3), (0.5, 0.0), (1.3, 0.71), (1.99, 0.5)])
def test_hertz_simulation_matches_mpmath(tau, phi):
    got = imp.simulate_impacts("leapfrog", [tau], [phi], 0.0, contact="hertz").ratios[0, 0]
    assert got == pytest.approx(_mp_hertz_leapfrog(tau, phi), rel=1e-11)


def test_hertz_energy_error_converges_and_linearised_bound_verdict():
    study = imp.hertz_study("velocity-verlet", imp.sweep_grid(0.02), 32, threshold=0.01)
    err = study["_energy_error"]
    grid = study["_grid"]
    # second order: the error at small steps shrinks at least like tau^2 (factor 10 in tau -> >= 30)
    i_small, i_big = np.argmin(np.abs(grid - 0.02)), np.argmin(np.abs(grid - 0.2))
    assert err[i_big] / err[i_small] > 30
    assert study["linearised_bound"] == pytest.approx(2.0)
    assert study["energy_error_at_bound"] > 1.0  # the linearised bound does not bound the energy error
    assert study["bound_keeps_error_below_threshold"] is False
    largest = study["largest_omega_dt_within_threshold"]
    assert 0.2 < largest < 1.0
    assert np.all(err[grid <= largest] <= 0.01)


# ----------------------------------------------------------------------------------------------
# book-keeping and input checks
# ----------------------------------------------------------------------------------------------

def test_energy_created_ranges():
    t = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
    v = [0.9, 1.1, 1.2, 1.0, 1.3, 1.3]
    assert imp.energy_created_ranges(t, v, 1.0) == [[0.2, 0.3], [0.5, 0.6]]
    assert imp.energy_created_ranges(t, v, 2.0) == []
    assert imp.energy_created_ranges(t, v, 0.0) == [[0.1, 0.6]]


def test_sweep_grid_and_phases():
    g = imp.sweep_grid()
    assert g[0] == pytest.approx(0.005) and g[-1] == 2.2 and len(g) == 440
    p = imp.entry_phases(8)
    assert p[0] == 0.0 and p[-1] == 7 / 8


def test_overdamped_geometric_impact_is_reported_not_separated():
    """zeta = 2, a stable step: the exact overlap never returns to 0 and neither does the simulation."""
    run = imp.simulate_impacts("velocity-verlet", [0.1], imp.entry_phases(4), 2.0)
    assert np.all(run.status == imp.STATUS_NOT_SEPARATED) and np.all(run.ratios == 0)


def test_diverging_runs_are_flagged():
    run = imp.simulate_impacts("forward-euler", [0.5], [0.0, 0.5], 1000.0)
    assert np.all(run.status == imp.STATUS_DIVERGED) and np.all(np.isinf(run.ratios))
    (s,) = imp.phase_stats(run)
    assert s.as_dict()["max"] is None and s.diverged == 2


@pytest.mark.parametrize(
    "kwargs,key",
    [
        (dict(integrator="leapfrg"), "integrator"),
        (dict(zeta=-1.0), "zeta"),
        (dict(zeta=float("nan")), "zeta"),
        (dict(omega_dt=[0.0]), "omega_dt"),
        (dict(omega_dt=[float("inf")]), "omega_dt"),
        (dict(phases=[1.0]), "phases"),
        (dict(contact="hertz", zeta=0.1), "zeta"),
        (dict(contact="spring"), "contact"),
    ],
)
def test_bad_arguments(kwargs, key):
    args = dict(integrator="leapfrog", omega_dt=[0.5], phases=[0.0], zeta=0.0, contact="linear")
    args.update(kwargs)
    with pytest.raises(InputError) as info:
        imp.simulate_impacts(args["integrator"], args["omega_dt"], args["phases"], args["zeta"], args["contact"])
    assert info.value.key == key


@pytest.mark.parametrize("n", [0, -3, 2.5, 10**6])
def test_bad_phase_count(n):
    with pytest.raises(InputError) as info:
        imp.entry_phases(n)
    assert info.value.key == "phases"
