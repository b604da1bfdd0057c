"""Rolling and twisting springs in the scene contact element, checked against an independent assembly.

The 12-DOF (6-DOF at a wall) system is assembled here from the contact-point kinematics and the
relative rotation, along an oblique normal; its largest eigenvalue of ``M^-1 K`` and the spectral radius
of each integrator's amplification matrix (``support.multidof``, the update rule applied to unit
states) are the references.  Nothing here uses dtcrit's modes, kernels or coupled-block solver.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from support.multidof import MatrixForce, spectral_radius
from support.rotational_pair import omega2_max, pair_system, sphere, wall_system
from dtcrit.integrators.schemes import INTEGRATORS
from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step

def scene(r1, r2, rho, contact: str, integrator="velocity-verlet", wall: str = "") -> str:
    parts = "".join(f'[[particle]]\nshape = "sphere"\nradius = {r}\ndensity = {rho}\n' for r in ((r1,) if r2 is None else (r1, r2)))
    pairs = 'pairs = "unlike"\n' if r2 is not None else ""
    return f'integrator = "{integrator}"\nisolated = true\n{pairs}{parts}[contact]\nmodel = "linear"\n{contact}\n{wall}'


# ------------------------------------------------------------------------------------------------
# The acceptance checks: two equal spheres, rolling or twisting governing
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("key,direction", [("kr", "rolling"), ("ktw", "twisting")])
def test_equal_spheres_counter_rotation_governs(key, direction):
    r, rho, k = 0.01, 2500.0, 50.0
    m, inertia = sphere(r, rho)
    res = critical_step(parse_scene(scene(r, None, rho, f"kn = 1e5\nks = 1e4\n{key} = {k}")))
    assert res.governing == "contact rotation"
    assert res.translation.governing_direction.direction == direction
    assert res.dt_crit == pytest.approx(2.0 / math.sqrt(2.0 * k / inertia), rel=1e-13)
    # and the independent eigen-solve of the whole 12-DOF pair agrees
    kr, ktw = (k, 0.0) if key == "kr" else (0.0, k)
    M, K, _ = pair_system(m, inertia, r, m, inertia, r, (1e5, 1e4, kr, ktw), (0, 0, 0, 0))
    assert res.dt_crit == pytest.approx(2.0 / math.sqrt(omega2_max(M, K)), rel=1e-10)


def test_json_names_the_rotational_mode():
    res = critical_step(parse_scene(scene(0.01, None, 2500.0, "kn = 1e5\nks = 1e4\nkr = 50.0")))
    doc = res.to_json()
    assert doc["governing"] == "contact rotation"
    assert doc["contact_rotation"]["direction"] == "rolling"
    assert doc["contact_rotation"]["dt"] == doc["dt_crit"]
    assert doc["translation"]["direction"] in ("normal", "shear")  # the translational block keeps its meaning
    assert doc["pairs"][0]["kr"] == 50.0


# ------------------------------------------------------------------------------------------------
# Unequal spheres (shear and rolling coupled) and walls, over decades
# ------------------------------------------------------------------------------------------------
CASES = [(r1, r2, rho, ks_ratio, kr)
         for r1, r2 in ((1e-3, 1e-3), (1e-3, 3e-3), (0.05, 0.01), (2.0, 0.5))
         for rho in (1000.0, 7800.0)
         for ks_ratio in (0.0, 0.3, 1.0)
         for kr in (1e-6, 1e-2, 1e2)]


@pytest.mark.parametrize("r1,r2,rho,ks_ratio,kr_scale", CASES[::3])
def test_undamped_pair_matches_the_12dof_eigen_solve(r1, r2, rho, ks_ratio, kr_scale):
    kn = 1e6
    ks = ks_ratio * kn
    kr = kr_scale * kn * min(r1, r2) ** 2
    ktw = 0.5 * kr
    text = scene(r1, r2, rho, f"kn = {kn}\nks = {ks}\nkr = {kr!r}\nktw = {ktw!r}")
    res = critical_step(parse_scene(text))
    m1, i1 = sphere(r1, rho)
    m2, i2 = sphere(r2, rho)
    M, K, _ = pair_system(m1, i1, r1, m2, i2, r2, (kn, ks, kr, ktw), (0, 0, 0, 0))
    assert res.dt_isolated == pytest.approx(2.0 / math.sqrt(omega2_max(M, K)), rel=1e-9)


@pytest.mark.parametrize("ks_ratio", [0.0, 0.4, 1.0])
@pytest.mark.parametrize("kr", [1e-3, 1.0, 30.0])
def test_wall_rolling(ks_ratio, kr):
    r, rho, kn = 0.01, 2500.0, 1e5
    m, inertia = sphere(r, rho)
    wall = f"[[wall]]\nkn = {kn}\nks = {ks_ratio * kn}\nkr = {kr}\n"
    text = f'integrator = "leapfrog"\n[[particle]]\nshape = "sphere"\nradius = {r}\ndensity = {rho}\n' \
           f'[contact]\nmodel = "linear"\nkn = 1.0\nks = 0.0\n{wall}'
    res = critical_step(parse_scene(text))
    w = next(p for p in res.pairs if p.contact.wall is not None)
    M, K, _ = wall_system(m, inertia, r, (kn, ks_ratio * kn, kr, 0.0), (0, 0, 0, 0))
    assert w.dt_translation == pytest.approx(2.0 / math.sqrt(omega2_max(M, K)), rel=1e-10)
    if ks_ratio == 0.0:  # without shear spring the rolling mode is kr/I
        rolling = [d for d in w.rotational if d.direction in ("rolling", "shear-rolling")][0]
        assert rolling.dt == pytest.approx(2.0 / math.sqrt(kr / inertia), rel=1e-12)


# ------------------------------------------------------------------------------------------------
# Damped, non-proportional: the amplification matrix of the whole system, every integrator
# ------------------------------------------------------------------------------------------------
DAMPED = [("velocity-verlet", 1e-3, 3e-3), ("leapfrog", 0.05, 0.01), ("symplectic-euler", 1e-3, 1e-3),
          ("velocity-verlet-predicted", 1e-3, 2e-3), ("forward-euler", 1e-3, 2e-3), ("paper-eq40", 1e-3, 3e-3)]


@pytest.mark.parametrize("integrator,r1,r2", DAMPED)
def test_damped_pair_against_the_amplification_matrix(integrator, r1, r2):
    rho, kn, ks = 2500.0, 1e5, 4e4
    m1, i1 = sphere(r1, rho)
    m2, i2 = sphere(r2, rho)
    kr, ktw = 2.0 * ks * r1 * r2, 0.3 * ks * r1 * r2
    mstar = m1 * m2 / (m1 + m2)
    cn, cs = 0.3 * 2 * math.sqrt(kn * mstar), 0.05 * 2 * math.sqrt(ks * mstar)
    istar = i1 * i2 / (i1 + i2)
    cr, ctw = 0.6 * 2 * math.sqrt(kr * istar), 0.2 * 2 * math.sqrt(ktw * istar)
    text = scene(r1, r2, rho, f"kn = {kn}\nks = {ks}\ncn = {cn!r}\ncs = {cs!r}\nkr = {kr!r}\nktw = {ktw!r}\n"
                 f"cr = {cr!r}\nctw = {ctw!r}", integrator)
    dt = critical_step(parse_scene(text)).dt_isolated
    M, K, C = pair_system(m1, i1, r1, m2, i2, r2, (kn, ks, kr, ktw), (cn, cs, cr, ctw))
    # the pair's rigid modes are Jordan blocks at +1: a growth below 1e-6 per step is rounding
    assert spectral_radius(integrator, 0.999 * dt, M, K, C) <= 1.0 + 1e-6
    assert spectral_radius(integrator, 1.001 * dt, M, K, C) > 1.0 + 1e-6


def _grows(integrator, dt, M, K, C, steps=4000) -> bool:
    f = MatrixForce(M, K, C)
    scheme = INTEGRATORS[integrator]
    rng = np.random.default_rng(7)
    state = [rng.standard_normal(M.shape[0])] + [np.zeros(M.shape[0])] * (len(scheme.state) - 1)
    start = np.linalg.norm(state[0])
    for _ in range(steps):
        state = list(scheme.step(tuple(state), dt, f))
        if not np.all(np.isfinite(state[0])) or np.linalg.norm(state[0]) > 1e3 * start:
            return True
    return False


def test_time_stepping_the_pair_bounded_below_growing_above():
    r1, r2, rho = 1e-3, 2.5e-3, 2500.0
    m1, i1 = sphere(r1, rho)
    m2, i2 = sphere(r2, rho)
    k = (1e5, 3e4, 5.0 * 3e4 * r1 * r2, 3e4 * r1 * r2)
    text = scene(r1, r2, rho, f"kn = {k[0]}\nks = {k[1]}\nkr = {k[2]!r}\nktw = {k[3]!r}")
    dt = critical_step(parse_scene(text)).dt_isolated
    M, K, C = pair_system(m1, i1, r1, m2, i2, r2, k, (0, 0, 0, 0))
    # at rest, displaced at random: the rigid-body part of the start stays put (no velocity), the elastic part
    # oscillates (0.99 dt) or grows geometrically (1.01 dt, the coupled shear-rolling mode governs here)
    assert not _grows("velocity-verlet", 0.99 * dt, M, K, C)
    assert _grows("velocity-verlet", 1.01 * dt, M, K, C)


# ------------------------------------------------------------------------------------------------
# Codes' own parameters
# ------------------------------------------------------------------------------------------------
def _pair(text):
    return critical_step(parse_scene(text)).pairs[0].contact


def test_epsd2_is_kt_rstar_squared():
    pc = _pair(scene(0.01, None, 2500.0, 'kn = 1e5\nks = 2e4\nrolling_model = "epsd2"'))
    assert pc.kr == pytest.approx(2e4 * 0.005**2, rel=1e-15) and pc.cr == 0.0


def test_epsd_and_epsd3():
    m, _ = sphere(0.01, 2500.0)
    pc = _pair(scene(0.01, None, 2500.0, 'kn = 1e5\nks = 2e4\nrolling_model = "epsd"\nrolling_friction = 0.1\n'
                     'rolling_viscous_damping = 0.3'))
    kr = 2.25 * 1e5 * 0.01 * 0.005**2
    assert pc.kr == pytest.approx(kr, rel=1e-14)
    i_r = 1.4 * (m * 1e-4) / 2.0
    assert pc.cr == pytest.approx(0.3 * 2 * math.sqrt(i_r * kr), rel=1e-14)
    pc3 = _pair(scene(0.01, None, 2500.0, 'kn = 1e5\nks = 2e4\nrolling_model = "epsd3"\nrolling_friction = 0.1\n'
                      'rolling_stiffness_factor = 1.5'))
    assert pc3.kr == pytest.approx(1.5 * 1e5 * 0.01 * 0.005**2, rel=1e-14)


def test_lammps_sds_and_marshall_and_yade():
    pc = _pair(scene(0.01, None, 2500.0, 'kn = 1e5\nks = 2e4\ncs = 0.4\nrolling_model = "sds"\nk_roll = 300.0\n'
                     'gamma_roll = 0.2\ntwisting_model = "marshall"\ncontact_radius = 1e-3'))
    assert pc.kr == pytest.approx(300.0 * 0.005**2) and pc.cr == pytest.approx(0.2 * 0.005**2)
    assert pc.ktw == pytest.approx(0.5 * 2e4 * 1e-6) and pc.ctw == pytest.approx(0.5 * 0.4 * 1e-6)
    py = _pair(scene(0.01, 0.02, 2500.0, 'kn = 1e5\nks = 2e4\nrolling_model = "yade"\nalpha_kr = 2.0\nalpha_ktw = 0.5'))
    assert py.kr == pytest.approx(2.0 * 2e4 * 0.01 * 0.02) and py.ktw == pytest.approx(0.5 * 2e4 * 0.01 * 0.02)


@pytest.mark.parametrize("contact,key", [
    ("kn = 1e5\nks = 1e4\nkr = -1.0", "contact.kr"),
    ('kn = 1e5\nks = 1e4\nkr = 1.0\nrolling_model = "epsd2"', "contact.kr"),
    ('kn = 1e5\nks = 1e4\nrolling_model = "epsd"', "contact.rolling_friction"),
    ('kn = 1e5\nks = 1e4\ntwisting_model = "marshall"', "contact.contact_radius"),
    ('kn = 1e5\nks = 1e4\nrolling_model = "bogus"', "contact.rolling_model"),
    ("kn = 1e5\nks = 1e4\nk_roll = 3.0", "contact.k_roll"),
])
def test_bad_rotational_input_is_one_line(tmp_path, contact, key):
    import subprocess
    import sys

    path = tmp_path / "s.toml"
    path.write_text(scene(0.01, None, 2500.0, contact))
    p = subprocess.run([sys.executable, "-m", "dtcrit", "step", str(path)], capture_output=True, text=True)
    assert p.returncode == 2 and p.stdout == ""
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"{path}:{key}:"), p.stderr
