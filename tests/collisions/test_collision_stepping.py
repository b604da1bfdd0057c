"""The time-stepped impact against closed forms and independent checks.

* undamped linear contact, central-difference family: the exit ratio closed form of ``dtcrit.impact``
  (``undamped_exit_ratios``, derived from the invariant of the discrete map) at ``omega dt = pi/N``;
* extended Taylor (Chrono DEM-Engine): ``det G = 1 + (omega dt)^2/2`` per step, so an undamped linear
  contact of N steps gains ``e - 1 -> pi^2/(4N)``; every phase gains energy;
* velocity Verlet's order: 2 undamped, 1 with a dashpot (peak overlap at N and 2N);
* the phase optimisation finds at least the worst of a dense independent phase sampling.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import dtcrit.impact as imp
from dtcrit.collisions import collision_errors, reference_collision, step_collision
from dtcrit.collisions.laws import scaled_law
from dtcrit.collisions.stepping import run_lanes
from dtcrit.errors import InputError


@settings(max_examples=30, deadline=None)
@given(scheme=st.sampled_from(["velocity-verlet", "leapfrog", "symplectic-euler"]),
       n=st.floats(3.0, 400.0), phase=st.floats(0.0, 0.999))
def test_undamped_linear_matches_the_closed_form(scheme, n, phase):
    closed = imp.undamped_exit_ratios(scheme, [math.pi / n], [phase])[0, 0]
    r = run_lanes(scheme, scaled_law("hooke", "none", 1.0), [n], [phase])
    assert r["restitution"][0] == pytest.approx(closed, rel=1e-10)


def test_velocity_verlet_and_leapfrog_step_the_same_impact():
    """LAMMPS (v_{n+1/2} to the dashpot after the drift), YADE (v_{n-1/2} before it) and MFiX's symplectic Euler
    (v first with the force at (x_n, v_n), then x) are one map of the positions."""
    for e in (0.9, 0.3):
        a = step_collision(engine="lammps", normal="hertz", damping="liggghts", restitution=e, steps_per_collision=7.3, phase=0.41)
        b = step_collision(engine="yade", normal="hertz", damping="liggghts", restitution=e, steps_per_collision=7.3, phase=0.41)
        c = step_collision(engine="mfix", normal="hertz", damping="liggghts", restitution=e, steps_per_collision=7.3, phase=0.41)
        assert a.restitution == pytest.approx(b.restitution, rel=1e-13) == c.restitution


def test_extended_taylor_gains_energy_at_the_predicted_rate():
    phases = np.arange(32) / 32
    n = 800.0
    r = run_lanes("extended-taylor", scaled_law("hooke", "none", 1.0), [n], phases)
    assert np.all(r["restitution"] > 1.0)
    assert np.mean(r["restitution"] - 1.0) * n == pytest.approx(math.pi**2 / 4, rel=0.02)
    for e in (1.0, 0.9, 0.5):  # Hertz and damped: a gain in every phase as well
        law = scaled_law("hertz", "liggghts", e)
        ref = reference_collision(normal="hertz", damping="liggghts", restitution=e)
        gain = run_lanes("extended-taylor", law, [100.0], phases)["restitution"] / ref.restitution - 1.0
        assert np.all(gain > 0.0)


@pytest.mark.parametrize("damping, e, order", [("none", 1.0, 2.0), ("liggghts", 0.9, 1.0), ("lammps-mass-velocity", 0.9, 1.0)])
def test_velocity_verlet_order(damping, e, order):
    """Second order undamped; first order with a dashpot, which sees the half-step-old velocity v_{n+1/2}."""
    phases = np.arange(64) / 64
    law = scaled_law("hertz", damping, e)
    ref = reference_collision(normal="hertz", damping=damping, restitution=e)
    err = [np.mean(np.abs(run_lanes("velocity-verlet", law, [n], phases)["peak_overlap"] - ref.peak_overlap))
           for n in (100.0, 200.0)]
    assert err[0] / err[1] == pytest.approx(2.0**order, rel=0.1)


@pytest.mark.parametrize("engine, n", [("lammps", 9.0), ("chrono", 40.0), ("yade", 23.5)])
def test_the_optimised_phase_is_at_least_a_dense_sampling(engine, n):
    errs = collision_errors(engine=engine, normal="hertz", damping="yade-mindlin", restitution=0.5, steps_per_collision=n)
    scheme = {"lammps": "velocity-verlet", "chrono": "extended-taylor", "yade": "leapfrog"}[engine]
    law = scaled_law("hertz", "yade-mindlin", 0.5)
    ref = reference_collision(normal="hertz", damping="yade-mindlin", restitution=0.5)
    dense = run_lanes(scheme, law, [n], (np.arange(2000) + 0.5) / 2000)
    assert errs["restitution"] >= np.max(np.abs(dense["restitution"] / ref.restitution - 1)) * (1 - 1e-6)
    assert errs["peak_overlap"] >= np.max(np.abs(dense["peak_overlap"] / ref.peak_overlap - 1)) * (1 - 1e-6)


@pytest.mark.parametrize("kwargs, key", [
    ({"engine": "edem"}, "engine"), ({"engine": "gromacs"}, "engine"), ({"phase": 1.0}, "phase"),
    ({"steps_per_collision": 0.5}, "steps_per_collision"), ({"restitution": 0.0}, "restitution"),
])
def test_bad_input(kwargs, key):
    base = {"engine": "lammps", "normal": "hertz", "damping": "liggghts", "restitution": 0.5,
            "steps_per_collision": 10.0, "phase": 0.2}
    base.update(kwargs)
    with pytest.raises(InputError) as err:
        step_collision(**base)
    assert err.value.location.key == key


def test_no_dashpot_with_a_restitution_below_one_is_refused():
    with pytest.raises(InputError) as err:
        reference_collision(normal="hertz", damping="none", restitution=0.5)
    assert err.value.location.key == "restitution"
