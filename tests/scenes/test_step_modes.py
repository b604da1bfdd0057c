"""`dtcrit step` for spheres is the exact step of the contact system, mode by mode.

References are independent of dtcrit's modes and closed forms: the amplification matrix of the
whole 12-DOF two-sphere system (6-DOF sphere against a wall), built by applying each integrator's
update rule to unit state vectors with the full matrices M, K, C (``support.multidof``), whose
spectral radius must stay <= 1 at 0.99 x the printed step and exceed 1 at 1.01 x.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from support.multidof import spectral_radius, sphere_on_wall, two_spheres
from hypothesis import given, settings
from hypothesis import strategies as st

from dtcrit.integrators.schemes import INTEGRATORS
from dtcrit.integrators.stability import dashpot_dt, mode_dt
from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step

STABLE = 1.0 + 1e-7  # rigid-body modes sit at |z| = 1 (Jordan blocks): allow their rounding
GROWS = 1.0 + 1e-4
DAMPED_ANYWHERE = ("symplectic-euler", "leapfrog", "leapfrog-centred", "velocity-verlet", "velocity-verlet-predicted")


def _scene(integrator, spheres, contact, walls=""):
    parts = "".join(f'[[particle]]\nshape = "sphere"\nradius = {r!r}\ndensity = {rho!r}\n' for r, rho in spheres)
    return parse_scene(f'integrator = "{integrator}"\n{parts}[contact]\nmodel = "linear"\n{contact}\n{walls}')


def _solid(r, rho):
    m = rho * 4.0 / 3.0 * math.pi * r**3
    return m, 0.4 * m * r * r


def _bracket(name, dt, M, K, C):
    below, above = spectral_radius(name, 0.99 * dt, M, K, C), spectral_radius(name, 1.01 * dt, M, K, C)
    assert below <= STABLE, (name, dt, below)
    assert above > GROWS, (name, dt, above)


@pytest.mark.parametrize("name", sorted(INTEGRATORS))
def test_dashpot_without_spring_against_the_update_rule(name):
    """k = 0, c > 0 (LAMMPS gran/hooke's tangential dashpot): the update rule's own matrix decides."""
    c, A = 3.0, 0.7
    M, K, C = np.eye(1), np.zeros((1, 1)), np.array([[c * A]])
    dt = dashpot_dt(name, c, A)
    if math.isinf(dt):
        assert all(spectral_radius(name, h, M, K, C) <= STABLE for h in (1.0, 1e3, 1e9))
    else:
        _bracket(name, dt, M, K, C)
    assert mode_dt(name, 0.0, 0.0, A).dt == math.inf


decades = st.floats(-3, 3)


@settings(max_examples=25)
@given(st.sampled_from(DAMPED_ANYWHERE), decades, decades, decades, decades, st.floats(-4, 4), st.floats(-3, 0.7),
       st.floats(-3, 0.7), st.sampled_from([0.0, 1e-3, 0.3, 1.0, 5.0]))
def test_two_spheres_exact_modes_against_the_twelve_dof_system(name, lr1, lr2, lrho1, lrho2, lk, lzn, lzs, ratio):
    """Unequal spheres, any ks/kn (0 included), non-proportional damping over decades."""
    r1, r2, rho1, rho2 = 10.0**lr1, 10.0**lr2, 10.0**lrho1, 10.0**lrho2
    kn = 10.0**lk
    ks = ratio * kn
    m1, I1 = _solid(r1, rho1)
    m2, I2 = _solid(r2, rho2)
    mstar = m1 * m2 / (m1 + m2)
    cn = 2 * 10.0**lzn * math.sqrt(kn * mstar)
    cs = 2 * 10.0**lzs * math.sqrt(max(ks, kn * 1e-3) * mstar)
    s = _scene(name, [(r1, rho1), (r2, rho2)], f"kn = {kn!r}\nks = {ks!r}\ncn = {cn!r}\ncs = {cs!r}")
    step = next(p for p in critical_step(s).pairs if p.label == "1-2")
    M, K, C = two_spheres(m1, I1, r1, m2, I2, r2, kn, ks, cn, cs)
    # the pair's step: its own modes only (the 1-1 and 2-2 pairs are other contacts)
    _bracket(name, step.dt_translation, M, K, C)
    assert step.method == "exact modes"


@pytest.mark.parametrize("name", ["velocity-verlet", "leapfrog", "symplectic-euler", "velocity-verlet-predicted"])
@pytest.mark.parametrize("ks_ratio,cs_ratio", [(0.0, 0.0), (2 / 7, 0.5), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)])
def test_sphere_against_a_wall(name, ks_ratio, cs_ratio):
    r, rho, kn = 0.002, 2500.0, 1e5
    m, I = _solid(r, rho)
    cn = 2 * 0.3 * math.sqrt(kn * m)
    wall = f"[[wall]]\nkn = {kn!r}\nks = {ks_ratio * kn!r}\ncn = {cn!r}\ncs = {cs_ratio * cn!r}\n"
    s = _scene(name, [(r, rho)], "kn = 1.0\nks = 1.0", wall)  # soft particle contacts: the wall governs
    res = critical_step(s)
    w = next(p for p in res.pairs if p.contact.wall is not None)
    assert w.normal.A == pytest.approx(1 / m, rel=1e-15)
    assert w.shear.A == pytest.approx(1 / m + r * r / I, rel=1e-15)
    assert res.dt_isolated == w.dt_translation
    M, K, C = sphere_on_wall(m, I, r, kn, ks_ratio * kn, cn, cs_ratio * cn)
    _bracket(name, w.dt_translation, M, K, C)


def test_equal_spheres_undamped_closed_forms():
    """Normal A = 2/m, tangential A = 7/m: velocity Verlet's 2/sqrt(kA) per mode, to 1e-15."""
    r, rho, kn, ks = 0.001, 2500.0, 1e5, 2e4
    m, _ = _solid(r, rho)
    s = _scene("velocity-verlet", [(r, rho)], f"kn = {kn!r}\nks = {ks!r}")
    (p,) = critical_step(s).pairs
    assert p.normal.dt == pytest.approx(2 / math.sqrt(kn * 2 / m), rel=1e-15)
    assert p.shear.dt == pytest.approx(2 / math.sqrt(ks * 7 / m), rel=1e-15)
    assert critical_step(s).dt_isolated == min(p.normal.dt, p.shear.dt)
