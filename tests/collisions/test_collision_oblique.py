"""dtcrit's oblique impact against an independent continuum (``support.collision_reference``).

That reference integrates both spheres' plane motion in SI units under LAMMPS's law (its own
equations, written for the engine harness); dtcrit's ``reference_oblique`` and its stepped impact at
fine N must reproduce it.
"""
from __future__ import annotations

from dataclasses import replace

import pytest

from dtcrit.collisions.oblique import oblique_case, oblique_errors, reference_oblique, step_oblique
from dtcrit.errors import InputError
from support.collision_reference import oblique_sliding, oblique_sticking
from support.engines.collisions import design

CASES = {"slide": (0.1, 2.0, oblique_sliding), "stick": (1.0e4, 1.0, oblique_sticking)}


def _pair(mode, n=100, phase=0.3):
    mu, ratio, ref = CASES[mode]
    base = design("hertz", "none", 0.0, dt=1e-6, steps_per_collision=n, phase=phase)
    imp = replace(base, tangential_speed=ratio * base.speed, friction=mu)
    case = oblique_case(normal="hertz", damping="none", restitution=1.0, friction=mu, tangential_ratio=ratio)
    return case, ref(imp)


def _close(a, b, rel, abs_=0.0):
    return abs(a - b) <= rel * abs(b) + abs_


@pytest.mark.parametrize("mode", ["slide", "stick"])
def test_continuum_reference_equals_the_independent_one(mode):
    """Normal and tangential restitution and spin: 1e-9 relative (spin 1e-10 absolute)."""
    case, ref = _pair(mode)
    got = reference_oblique(case, mode)
    assert _close(got.restitution, ref.restitution, 1e-9)
    assert _close(got.tangential_restitution, ref.tangential_restitution, 1e-9)
    assert _close(got.spin, ref.spin, 1e-9, 1e-10)


def test_sliding_stepped_at_fine_n_converges_to_the_independent_continuum():
    """N = 4000, phase 0.37: the stepped sliding impact within 1e-7 of the continuum (second order)."""
    case, ref = _pair("slide")
    got = step_oblique(case, 4000, 0.37)
    for name in ("restitution", "tangential_restitution", "spin"):
        assert _close(getattr(got, name), getattr(ref, name), 1e-7), name


def test_sticking_stepped_converges_at_first_order_to_the_independent_continuum():
    """The history's first-step convention makes sticking first order: the gap shrinks ~4x per 4x N."""
    case, ref = _pair("stick")
    gaps = [abs(step_oblique(case, n, 0.37).tangential_restitution - ref.tangential_restitution) for n in (1000, 4000)]
    assert gaps[1] < 1e-3
    assert 3.0 < gaps[0] / gaps[1] < 5.0


def test_worst_over_phase_is_at_least_every_sampled_phase():
    """``oblique_errors`` (sliding, N = 20): the worst error bounds the errors at sampled phases."""
    out = oblique_errors(engine="lammps", normal="hertz", damping="none", restitution=1.0, friction=0.1,
                         tangential_ratio=2.0, steps_per_collision=20, mode="slide", phases=16)
    case, ref = _pair("slide")
    for p in (0.05, 0.33, 0.61, 0.9):
        got = step_oblique(case, 20, p)
        for name in ("restitution", "tangential_restitution", "spin"):
            err = abs(getattr(got, name) - getattr(ref, name))
            err = err if name == "spin" else err / abs(getattr(ref, name))
            assert err <= out[name]["error"] * (1 + 1e-9) + 1e-12, (name, p)


@pytest.mark.parametrize("kw, key", [({"normal": "hooke"}, "normal"), ({"engine": "chrono"}, "engine"),
                                     ({"friction": -1.0}, "friction")])
def test_unmodelled_inputs_are_refused(kw, key):
    """A hooke normal law, an integrator of another map and a negative friction: one InputError."""
    args = dict(engine="lammps", normal="hertz", damping="none", restitution=1.0, friction=0.1,
                tangential_ratio=2.0, steps_per_collision=20, mode="slide")
    args.update(kw)
    with pytest.raises(InputError) as err:
        oblique_errors(**args)
    assert err.value.key == key


def test_mixed_stick_slip_is_refused_by_the_reference():
    """Sticking with a small friction and sliding with a dashpot are mixed regimes: refused."""
    case = oblique_case(normal="hertz", damping="none", restitution=1.0, friction=0.3, tangential_ratio=0.5)
    with pytest.raises(InputError):
        reference_oblique(case, "stick")
    damped = oblique_case(normal="hertz", damping="yade-mindlin", restitution=0.5, friction=0.1, tangential_ratio=2.0)
    with pytest.raises(InputError):
        reference_oblique(damped, "slide")


@pytest.mark.parametrize("dt, radius, young, poisson", [(1e-6, 1e-3, 1e7, 0.3), (1e-8, 1e-1, 1e9, 0.3),
                                                        (1e-4, 1e-4, 1e6, 0.2), (1e-7, 1e-2, 1e10, 0.45)])
def test_only_the_dimensionless_groups_survive(dt, radius, young, poisson):
    """Speeds, sizes and moduli decades apart (SI continuum of the harness) give dtcrit's scaled outcome.

    What survives is mu, v_t/v_n, Poisson's ratio (k_t/k_n = 2 (1 - nu)/(2 - nu) here against the
    harness's own E* and G*), the radius of gyration (2/5) and delta_el/R (1e-3 here).
    """
    base = design("hertz", "none", 0.0, dt=dt, steps_per_collision=100, phase=0.3, radius=radius, young=young,
                  poisson=poisson)
    for mode, (mu, ratio, harness) in CASES.items():  # sticking sees k_t/k_n; sliding does not
        ref = harness(replace(base, tangential_speed=ratio * base.speed, friction=mu))
        case = oblique_case(normal="hertz", damping="none", restitution=1.0, friction=mu, tangential_ratio=ratio,
                            poisson=poisson)
        got = reference_oblique(case, mode)
        for name in ("restitution", "tangential_restitution", "spin"):
            assert _close(getattr(got, name), getattr(ref, name), 1e-8, 1e-10), (mode, name)
