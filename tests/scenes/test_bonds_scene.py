"""Bonded particles (``[contact] model = "bond"``): the springs from the bond's material and cylinder as
PFC's linear parallel bond defines them (computed here from its definitions), the bond's modes against an
independent eigen-solve of the 12-DOF pair, the bond in parallel with the contact, and bad input."""
from __future__ import annotations

import math
import subprocess
import sys

import pytest

from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step
from support.rotational_pair import omega2_max, pair_system, sphere

R, RHO = 0.005, 2600.0
HEAD = f'integrator = "velocity-verlet"\nisolated = true\n[[particle]]\nshape = "sphere"\nradius = {R}\ndensity = {RHO}\n[contact]\nmodel = "bond"\n'


def test_parallel_bond_from_material():
    E, rb, L, kappa = 5e9, 0.6 * R, 2 * R, 2.5
    res = critical_step(parse_scene(HEAD + f"bond_youngs_modulus = {E}\nbond_radius = {rb}\nbond_length = {L}\n"
                                           f"bond_stiffness_ratio = {kappa}\n"))
    pc = res.pairs[0].contact
    area, second, polar = math.pi * rb**2, math.pi * rb**4 / 4, math.pi * rb**4 / 2
    kn_bar, ks_bar = E / L, E / L / kappa
    assert (pc.kn, pc.ks, pc.kr, pc.ktw) == pytest.approx((kn_bar * area, ks_bar * area, kn_bar * second, ks_bar * polar),
                                                          rel=1e-14)
    m, inertia = sphere(R, RHO)
    M, K, _ = pair_system(m, inertia, R, m, inertia, R, (pc.kn, pc.ks, pc.kr, pc.ktw), (0, 0, 0, 0))
    assert res.dt_crit == pytest.approx(2.0 / math.sqrt(omega2_max(M, K)), rel=1e-10)


def test_shear_from_poisson_ratio():
    E, nu, rb, L = 1e9, 0.25, R, 2 * R
    pc = critical_step(parse_scene(HEAD + f"bond_youngs_modulus = {E}\nbond_radius = {rb}\nbond_length = {L}\n"
                                          f"bond_poisson_ratio = {nu}\n")).pairs[0].contact
    G = E / (2 * (1 + nu))
    assert pc.ks == pytest.approx(G * math.pi * rb**2 / L, rel=1e-14)
    assert pc.ktw == pytest.approx(G * math.pi * rb**4 / 2 / L, rel=1e-14)


@pytest.mark.parametrize("key,k", [("kr", 40.0), ("ktw", 40.0)])
def test_bond_bending_or_twisting_governs(key, k):
    springs = {"kn": 1e5, "ks": 1e4, "kr": 1e-3, "ktw": 1e-3, key: k}
    res = critical_step(parse_scene(HEAD + "".join(f"{n} = {v}\n" for n, v in springs.items())))
    _, inertia = sphere(R, RHO)
    assert res.translation.governing_direction.direction == ("rolling" if key == "kr" else "twisting")
    assert res.dt_crit == pytest.approx(2.0 / math.sqrt(2.0 * k / inertia), rel=1e-13)


def test_bond_in_parallel_with_the_contact():
    alone = critical_step(parse_scene(HEAD + "kn = 1e5\nks = 1e4\nkr = 0\nktw = 0\n")).pairs[0].contact
    both = critical_step(parse_scene(HEAD + "kn = 1e5\nks = 1e4\nkr = 0\nktw = 0\ncontact_kn = 3e5\ncontact_ks = 2e4\n"))
    assert (both.pairs[0].contact.kn, both.pairs[0].contact.ks) == (alone.kn + 3e5, alone.ks + 2e4)
    m, _ = sphere(R, RHO)
    assert both.dt_crit == pytest.approx(2.0 / math.sqrt(4e5 * 2.0 / m), rel=1e-13)  # the normal mode, A_n = 2/m


def test_bond_damping_ratio_maps_every_spring():
    res = critical_step(parse_scene(HEAD + "kn = 1e5\nks = 1e4\nkr = 2.0\nktw = 1.0\ndamping_ratio = 0.2\n"))
    pc = res.pairs[0].contact
    m, inertia = sphere(R, RHO)
    assert pc.cn == pytest.approx(2 * 0.2 * math.sqrt(1e5 * m / 2), rel=1e-13)  # PFC convention, m* = m/2
    assert pc.cr == pytest.approx(2 * 0.2 * math.sqrt(2.0 * inertia / 2), rel=1e-13)


@pytest.mark.parametrize("body,key", [
    ("bond_youngs_modulus = 1e9\nbond_radius = 0.001\nbond_stiffness_ratio = 2.0\n", "contact.bond_length"),
    ("kn = 1e5\nks = 1e4\nkr = -1.0\nktw = 0\n", "contact.kr"),
    ("kn = 1e5\nks = 1e4\nkr = 1.0\n", "contact.ktw"),
    ("kn = 1e5\nks = 1e4\nkr = 1\nktw = 1\nbond_radius = 0.001\n", "contact.bond_radius"),
    ("bond_youngs_modulus = 1e9\nbond_radius = 0.001\nbond_length = 0.01\n", "contact.bond_stiffness_ratio"),
])
def test_bad_bond_input_is_one_line(tmp_path, body, key):
    path = tmp_path / "b.toml"
    path.write_text(HEAD + body)
    p = subprocess.run([sys.executable, "-m", "dtcrit", "step", str(path)], capture_output=True, text=True)
    assert p.returncode == 2 and p.stdout == ""
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"{path}:{key}:"), p.stderr
