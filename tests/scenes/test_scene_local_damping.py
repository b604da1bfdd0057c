"""Local (Cundall) damping in a scene (``local_damping``, ``local_damping_law``): the step of two equal
spheres in closed form over ``sqrt(1 + alpha)``, checked by time-stepping the pair with both laws
(``dtcrit.integrators.local_damping``), and the refusals of what is not modelled.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from dtcrit.errors import InputError
from dtcrit.integrators import local_damping as L
from dtcrit.scenes import parse_scene
from dtcrit.scenes.timestep import critical_step

R, RHO, KN = 1e-3, 2500.0, 1e4
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO


def _scene(top: str, contact: str = "", integrator: str = "leapfrog") -> str:
    return (f'integrator = "{integrator}"\nisolated = true\n{top}\n[[particle]]\nshape = "sphere"\nradius = {R!r}\n'
            f'density = {RHO!r}\n[contact]\nmodel = "linear"\nkn = {KN!r}\nks = 0.0\n{contact}')


@pytest.mark.parametrize("law", ["yade", "pfc"])
@pytest.mark.parametrize("alpha", [0.2, 0.7])
def test_the_pair_step_is_the_flip_threshold_and_time_stepping_agrees(law, alpha):
    dt = critical_step(parse_scene(_scene(f'local_damping = {alpha}\nlocal_damping_law = "{law}"'))).dt_crit
    omega = math.sqrt(2.0 * KN / MASS)  # the pair's normal mode: k (1/m + 1/m)
    assert dt == pytest.approx(2.0 / (omega * math.sqrt(1.0 + alpha)), rel=1e-12)
    # the relative coordinate of the pair: one mass m/2 on a spring kn to a wall
    K, inv_mass = L.chain([MASS / 2.0], [KN])
    rng = np.random.default_rng(5)
    x0, u0 = rng.standard_normal((8, 1)), rng.standard_normal((8, 1)) * omega
    assert not L.grows(x0, u0, 0.999 * dt, K, inv_mass, alpha, law, 4000).any()
    flip = np.ones((1, 1))
    assert L.grows(flip, 2.0 * flip / (1.001 * dt), 1.001 * dt, K, inv_mass, alpha, law, 4000).all()


def test_without_local_damping_or_at_zero_the_step_is_the_undamped_one():
    plain = critical_step(parse_scene(_scene(""))).dt_crit
    zero = critical_step(parse_scene(_scene('local_damping = 0.0\nlocal_damping_law = "pfc"'))).dt_crit
    assert plain == zero == pytest.approx(2.0 / math.sqrt(2.0 * KN / MASS), rel=1e-12)


def test_a_code_name_that_runs_leapfrog_is_accepted_and_the_bound_says_so():
    result = critical_step(parse_scene(_scene('local_damping = 0.7\nlocal_damping_law = "yade"', integrator="yade")))
    assert "local damping alpha = 0.7" in result.bound and "windows" in result.bound
    assert all(r.ratio == pytest.approx(r.estimate.dt / result.dt_crit) for r in result.estimates if r.estimate.dt)


@pytest.mark.parametrize("top, contact, integrator, words", [
    ('local_damping = 0.7\nlocal_damping_law = "yade"', "", "velocity-verlet", "velocity-verlet"),
    ('local_damping = 0.7\nlocal_damping_law = "yade"', "cn = 0.01\n", "leapfrog", "dashpots"),
    ('local_damping = 0.7\nlocal_damping_law = "pfc"\nomega_max = 10.0', "", "leapfrog", "omega_max"),
    ("local_damping = 0.7", "", "leapfrog", "local_damping_law"),
    ("local_damping = 1.0\nlocal_damping_law = \"pfc\"", "", "leapfrog", "[0, 1)"),
    ("local_damping = true\nlocal_damping_law = \"pfc\"", "", "leapfrog", "[0, 1)"),
    ("local_damping = -0.1\nlocal_damping_law = \"pfc\"", "", "leapfrog", "[0, 1)"),
])
def test_what_is_not_modelled_is_refused_naming_the_key(top, contact, integrator, words):
    with pytest.raises(InputError) as exc:
        parse_scene(_scene(top, contact, integrator))
    assert exc.value.key == "local_damping" and words in exc.value.reason


def test_an_unknown_law_or_a_law_alone_is_refused():
    for top in ('local_damping = 0.3\nlocal_damping_law = "cundall"', 'local_damping_law = "yade"'):
        with pytest.raises(InputError) as exc:
            parse_scene(_scene(top))
        assert exc.value.key == "local_damping_law"
