"""Scenes the way DEM users describe them: damping conventions of the codes, any number of particle
types, size distributions, walls, YADE's per-contact law; and their bad inputs.

Expected values are computed here from the codes' published formulas (README, "Damping
conventions") and from the exact sphere modes, never read back from dtcrit.
"""
from __future__ import annotations

import math

import pytest

from dtcrit.cli import main
from dtcrit.integrators.stability import critical_dt
from dtcrit.scenes.scene import parse_scene
from dtcrit.scenes.timestep import critical_step

R, RHO, KN, KS = 0.001, 2500.0, 1e5, 4e4
M = RHO * 4 / 3 * math.pi * R**3
SPHERE = f'[[particle]]\nshape = "sphere"\nradius = {R!r}\ndensity = {RHO!r}\n'


def _zeta(e):
    return -math.log(e) / math.sqrt(math.pi**2 + math.log(e) ** 2)


def _scene(contact, top="", particles=SPHERE, walls=""):
    return parse_scene(f'integrator = "velocity-verlet"\n{top}{particles}[contact]\nmodel = "linear"\n'
                       f'kn = {KN!r}\nks = {KS!r}\n{contact}\n{walls}')


@pytest.mark.parametrize("convention,cs_of", [
    ("lammps", lambda z, mstar: 0.5 * 2 * z * math.sqrt(KN * mstar)),  # gammat = gamman/2
    ("liggghts", lambda z, mstar: 2 * z * math.sqrt(KN * mstar)),  # gammat = gamman
    ("mercurydpm", lambda z, mstar: 2 / 7 * 2 * z * math.sqrt(KN * mstar)),
    ("yade", lambda z, mstar: 2 * z * math.sqrt(KS * 2 / 7 * mstar)),
    ("pfc", lambda z, mstar: 2 * z * math.sqrt(KS * mstar)),
])
def test_restitution_maps_per_direction_as_each_code_does(convention, cs_of):
    s = _scene(f'restitution = 0.9\ndamping_convention = "{convention}"')
    (p,) = critical_step(s).pairs
    mstar = M / 2
    z = _zeta(0.9)
    assert p.contact.cn == pytest.approx(2 * z * math.sqrt(KN * mstar), rel=1e-14)
    assert p.contact.cs == pytest.approx(cs_of(z, mstar), rel=1e-14)
    assert p.contact.zeta_n == pytest.approx(0.0335184, rel=1e-5)  # the zeta the user gave, not cA/(2 omega)
    # the step: each mode with its own dashpot, A_n = 2/m, A_s = 7/m
    assert p.normal.dt == pytest.approx(critical_dt("velocity-verlet", KN, p.contact.cn, 2 / M).dt, rel=1e-15)
    assert p.shear.dt == pytest.approx(critical_dt("velocity-verlet", KS, p.contact.cs, 7 / M).dt, rel=1e-15)


def test_default_convention_is_lammps_and_the_regime_follows_the_given_zeta(capsys):
    s = _scene("damping_ratio = 1.0")
    res = critical_step(s)
    (p,) = res.pairs
    assert p.contact.convention == "lammps" and p.normal.zeta == 1.0 and p.normal.regime == "critically damped"
    assert p.normal.zeta_mode == pytest.approx(1.0, rel=1e-15)  # normal mode of two spheres: A_n = 1/m*
    assert p.contact.cs == pytest.approx(p.contact.cn / 2, rel=1e-15)


def test_edem_convention_is_for_hertz_only():
    with pytest.raises(ValueError, match="defined for hertz"):
        _scene('restitution = 0.5\ndamping_convention = "edem"')


def test_three_particle_types_take_the_minimum_over_every_pair():
    parts = "".join(f'[[particle]]\nshape = "sphere"\nradius = {r!r}\ndensity = {RHO!r}\n' for r in (1e-3, 2e-3, 0.5e-3))
    res = critical_step(_scene("", particles=parts))
    labels = {p.label for p in res.pairs}
    assert labels == {"1-1", "1-2", "1-3", "2-2", "2-3", "3-3"}
    m = [RHO * 4 / 3 * math.pi * r**3 for r in (1e-3, 2e-3, 0.5e-3)]
    expect = min(min(2 / math.sqrt(KN * (1 / a + 1 / b)), 2 / math.sqrt(KS * 3.5 * (1 / a + 1 / b))) for a in m for b in m)
    assert res.dt_isolated == pytest.approx(expect, rel=1e-14)


def test_discrete_sizes_and_lognormal_cut_offs():
    disc = (f'[[particle]]\nshape = "sphere"\nradii = [0.002, 0.0005, 0.001]\nfractions = [0.2, 0.3, 0.5]\n'
            f'density = {RHO!r}\n')
    m_small = RHO * 4 / 3 * math.pi * 0.0005**3
    expect = 2 / math.sqrt(KS * 7 / m_small)  # the two smallest spheres, tangential (7 KS > 2 KN here)
    assert critical_step(_scene("", particles=disc)).dt_isolated == pytest.approx(expect, rel=1e-14)
    logn = (f'[[particle]]\nshape = "sphere"\nlognormal = {{median = 0.001, sigma = 0.4, min = 0.0005, max = 0.003}}\n'
            f'density = {RHO!r}\n')
    res = critical_step(_scene("", particles=logn))
    assert res.dt_isolated == pytest.approx(expect, rel=1e-14)
    assert res.translation.contact.radius_i == res.translation.contact.radius_j == 0.0005


def test_yade_law_per_contact():
    parts = (f'[[particle]]\nshape = "sphere"\nradii = [0.001, 0.003]\nfractions = [0.5, 0.5]\ndensity = {RHO!r}\n'
             'youngs_modulus = 1e8\n')
    s = parse_scene(f'integrator = "leapfrog"\n{parts}[contact]\nmodel = "yade"\nks_ratio = 0.25\n')
    res = critical_step(s)
    steps = []
    for r1 in (0.001, 0.003):
        for r2 in (0.001, 0.003):
            m1, m2 = (RHO * 4 / 3 * math.pi * r**3 for r in (r1, r2))
            kn = 2 * 1e8 * r1 * r2 / (r1 + r2)
            steps += [2 / math.sqrt(kn * (1 / m1 + 1 / m2)), 2 / math.sqrt(0.25 * kn * 3.5 * (1 / m1 + 1 / m2))]
    assert res.dt_isolated == pytest.approx(min(steps), rel=1e-14)


def test_frictionless_and_dashpot_only_tangential():
    res = critical_step(parse_scene(f'integrator = "velocity-verlet"\n{SPHERE}[contact]\nmodel = "linear"\n'
                                    f'kn = {KN!r}\nks = 0.0\ncn = 0.0\ncs = 0.3\n'))
    (p,) = res.pairs
    assert p.shear.regime == "dashpot only"
    assert p.shear.dt == pytest.approx(2 / (0.3 * 7 / M), rel=1e-14)  # velocity Verlet: dt = 2/(c A)
    assert p.normal.dt == pytest.approx(2 / math.sqrt(KN * 2 / M), rel=1e-14)


@pytest.mark.parametrize("text,key,reason", [
    (f'integrator = "velocity-verlet"\ncoordination_max = -3\n{SPHERE}[contact]\nmodel = "linear"\nkn = 1.0\nks = 1.0\n',
     "coordination_max", "positive whole number"),
    ('integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradii = [0.001, 0.002]\nfractions = [0.5, 0.6]\n'
     'density = 1000.0\n[contact]\nmodel = "linear"\nkn = 1.0\nks = 1.0\n', "particle[1].fractions", "must sum to 1"),
    (f'integrator = "velocity-verlet"\n{SPHERE}[contact]\nmodel = "linear"\nkn = 1.0\nks = 1.0\n[[wall]]\nks = 1.0\n',
     "wall[1].kn", "missing"),
    (f'integrator = "velocity-verlet"\n{SPHERE}[contact]\nmodel = "linear"\nkn = 1.0\nks = 1.0\n[[wall]]\nkn = 1.0\n'
     'ks = 1.0\nparticles = [4]\n', "wall[1].particles", "no particle table 4"),
    (f'integrator = "forward-euler"\ncoordination_max = 6\n{SPHERE}[contact]\nmodel = "linear"\nkn = 1.0\nks = 1.0\n'
     'damping_ratio = 0.5\n', "coordination_max", "no packing bound"),
])
def test_bad_input_is_one_line(tmp_path, capsys, text, key, reason):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    rc = main(["step", str(path)])
    out, err = capsys.readouterr()
    assert rc == 2 and out == ""
    assert len(err.splitlines()) == 1 and err.startswith(f"{path}:{key}: "), err
    assert reason in err and "Traceback" not in err


@pytest.mark.parametrize("convention,wall_mass", [("lammps", 1.0), ("liggghts", 1.0), ("mercurydpm", 1.0), ("yade", 0.5),
                                                  ("pfc", 1.0)])
def test_wall_damping_uses_each_codes_wall_mass(convention, wall_mass):
    """LAMMPS fix wall/gran and LIGGGHTS use the particle's mass; YADE's ViscElMat replaces the wall's zero
    mass by the particle's, so its reduced mass is m/2."""
    wall = f"[[wall]]\nkn = {KN!r}\nks = {KS!r}\ndamping_ratio = 0.3\n"
    s = _scene(f'damping_ratio = 0.3\ndamping_convention = "{convention}"', walls=wall)
    w = next(p for p in critical_step(s).pairs if p.contact.wall is not None)
    assert w.contact.cn == pytest.approx(2 * 0.3 * math.sqrt(KN * wall_mass * M), rel=1e-14)
    assert w.normal.A == pytest.approx(1 / M, rel=1e-15)


def test_review_findings(tmp_path, capsys):
    """A dashpot without spring gives valid JSON (zeta_mode null); a huge coordination_max is one line; the shear
    zeta of a convention that derives c_s from c_n is not labelled 'as given'."""
    import json

    text = (f'integrator = "velocity-verlet"\n{SPHERE}[contact]\nmodel = "linear"\nkn = {KN!r}\nks = 0.0\n'
            'restitution = 0.5\n')
    path = tmp_path / "dashpot.toml"
    path.write_text(text)
    assert main(["step", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["pairs"][0]["shear"]["zeta_mode"] is None and doc["pairs"][0]["shear"]["regime"] == "dashpot only"
    path.write_text("coordination_max = 100000000000000000000\n" + text)
    assert main(["step", str(path)]) == 2
    assert capsys.readouterr().err.startswith(f"{path}:coordination_max: ")
    s = _scene('restitution = 0.5\ndamping_convention = "liggghts"')
    res = critical_step(s)
    assert res.translation.governing_direction.direction == "shear" and "as given" not in res.bound
