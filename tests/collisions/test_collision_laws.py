"""The collision laws against the formulas read in each code's source, written out by hand here."""
import math

import numpy as np
import pytest

from dtcrit.errors import InputError
from dtcrit.physics.collision_laws import CLIPPING, DAMPING_MODELS, collision_law

M, K, E, R = 2.0e-3, 3.0e4, 7.0e7, 1.5e-3
LN = math.log


def beta(e):
    return -LN(e) / math.sqrt(LN(e) ** 2 + math.pi**2)


def alpha(e):  # LAMMPS gran_sub_mod_damping.cpp, Marshall 2009 Eq. 53 (literal coefficients)
    return (1.2728 - 4.2783 * e + 11.087 * e**2 - 22.348 * e**3 + 27.467 * e**4 - 18.022 * e**5 + 4.8218 * e**6)


def thornton(en):
    """YADE's betan from en, Thornton et al. (2013) eqs. B6-B7 with Table 2's h1..h10 (literals)."""
    h = [-6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18, 6276.757, -1489.915]
    alphan = sum(hk * en ** (k + 1) for k, hk in enumerate(h))
    return math.sqrt(1.0 / (1.0 - (1.0 + en) ** 2 * math.exp(alphan)) - 1.0)


@pytest.mark.parametrize("d, v", [(1e-5, 0.3), (4e-6, -0.7), (2.5e-4, 1.9)])
def test_hertz_laws_match_the_sources(d, v):
    kh = 4.0 / 3.0 * E * math.sqrt(R)
    fe = kh * d**1.5
    sn = 2.0 * E * math.sqrt(R * d)  # LIGGGHTS Sn = 2 Yeff sqrt(reff deltan)
    e = 0.6
    expect = {
        "liggghts": fe + 2.0 * math.sqrt(5.0 / 6.0) * beta(e) * math.sqrt(sn * M) * v,
        "lammps-tsuji": fe + math.sqrt(2.0) * alpha(e) * math.sqrt(M * fe / d) * v,
        "lammps-coeff-restitution": fe + math.sqrt(1.5) * 1.82574185835055380345 * beta(e) * math.sqrt(M * fe / d) * v,
        # YADE (pkg/dem/HertzMindlin.cpp): betan by Thornton (2013) B6-B7; cn = 2 betan sqrt(mbar kn),
        # kn = 3/2 kno sqrt(uN), kno = 4/3 E sqrt(R); the total normal force clipped at zero
        "yade-mindlin": max(fe + 2 * thornton(e) * math.sqrt(M * 1.5 * kh * math.sqrt(d)) * v, 0.0),
        "none": fe,
    }
    for damping, want in expect.items():
        law = collision_law("hertz", damping, m_eff=M, E_eff=E, R_eff=R, restitution=e)
        assert law.force(d, v) == pytest.approx(want, rel=1e-12), damping
    visc = collision_law("hertz", "lammps-viscoelastic", m_eff=M, E_eff=E, R_eff=R, coefficient=50.0)
    assert visc.force(d, v) == pytest.approx(fe + 50.0 * M * math.sqrt(R * d) * v, rel=1e-12)
    mv = collision_law("hertz", "lammps-mass-velocity", m_eff=M, E_eff=E, R_eff=R, coefficient=80.0)
    assert mv.force(d, v) == pytest.approx(fe + 80.0 * M * v, rel=1e-12)
    merc = collision_law("hertz", "mercurydpm", m_eff=M, E_eff=E, R_eff=R, coefficient=0.4)
    assert merc.force(d, v) == pytest.approx(fe + 0.4 * math.sqrt(M * 4 / 3 * E * math.sqrt(R * d)) * v, rel=1e-12)


def test_hooke_laws_and_the_tsuji_versions():
    d, v, e = 2e-5, 0.4, 0.7
    zeta = beta(e)
    assert collision_law("hooke", "liggghts", m_eff=M, k=K, restitution=e).force(d, v) == pytest.approx(
        K * d + math.sqrt(4 * M * K / (1 + (math.pi / LN(e)) ** 2)) * v, rel=1e-12)  # LIGGGHTS hooke gamman
    new = collision_law("hooke", "lammps-tsuji", m_eff=M, k=K, restitution=e)
    old = collision_law("hooke", "lammps-tsuji", m_eff=M, k=K, restitution=e, tsuji_version="2021")
    assert new.force(d, v) - K * d == pytest.approx(math.sqrt(2) * (old.force(d, v) - K * d), rel=1e-12)
    assert old.force(d, v) == pytest.approx(K * d + alpha(e) * math.sqrt(M * K) * v, rel=1e-12)
    assert collision_law("hooke", "lammps-coeff-restitution", m_eff=M, k=K, restitution=e).force(d, v) == pytest.approx(
        K * d + 2 * zeta * math.sqrt(M * K) * v, rel=1e-12)


def test_no_force_out_of_contact_and_clipping_as_the_codes_do():
    law = collision_law("hertz", "liggghts", m_eff=M, E_eff=E, R_eff=R, restitution=0.3)
    d = np.array([-1e-6, 0.0, 1e-8, 1e-6])
    f = law.force(d, -5.0 * np.ones(4))
    assert f[0] == 0.0 and f[2] < 0  # LIGGGHTS default: the dashpot may pull
    yade = collision_law("hertz", "yade-mindlin", m_eff=M, E_eff=E, R_eff=R, restitution=0.3)
    assert np.all(yade.force(d, -5.0 * np.ones(4)) >= 0.0) and yade.clip
    assert collision_law("hertz", "liggghts", m_eff=M, E_eff=E, R_eff=R, restitution=0.3, clip=True).clip
    assert not DAMPING_MODELS["lammps-tsuji"].clips and not DAMPING_MODELS["mercurydpm"].clips
    assert set(CLIPPING) >= {"LAMMPS pair granular", "LIGGGHTS", "YADE Law2_ScGeom_MindlinPhys_Mindlin", "MercuryDPM"}


@pytest.mark.parametrize("kwargs, key", [
    ({"normal": "hertz", "damping": "liggghts", "cohesion": "jkr"}, "cohesion"),
    ({"normal": "hertz", "damping": "liggghts", "cohesion": "dmt"}, "cohesion"),
    ({"normal": "hooke", "damping": "yade-mindlin"}, "damping"),
    ({"normal": "hertz", "damping": "edem-magic"}, "damping"),
    ({"normal": "linear", "damping": "none"}, "normal"),
    ({"normal": "hertz", "damping": "liggghts", "restitution": 1.5}, "restitution"),
    ({"normal": "hertz", "damping": "lammps-viscoelastic"}, "coefficient"),
])
def test_bad_input_is_refused_in_one_line(kwargs, key):
    base = {"m_eff": M, "k": K, "E_eff": E, "R_eff": R, "restitution": 0.5}
    base.update(kwargs)
    normal, damping = base.pop("normal"), base.pop("damping")
    with pytest.raises(InputError) as err:
        collision_law(normal, damping, **base)
    assert err.value.location.key == key and "\n" not in str(err.value)


def test_mindlin_tangential_sticks_then_slides_as_lammps_writes_it():
    from dtcrit.physics.collision_laws import mindlin_tangential
    a, k, damp, mu, fn, dt = 2e-5, 8 * 1.5e9, 0.02, 0.3, 4.0, 1e-7
    f, xi = mindlin_tangential(1e-9, 0.01, dt, a, k, damp, mu, fn)  # stick: F = -k a (xi + v dt) - damp v
    assert f == pytest.approx(-k * a * (1e-9 + 0.01 * dt) - damp * 0.01, rel=1e-12) and abs(f) < mu * fn
    assert xi == pytest.approx(1e-9 + 0.01 * dt, rel=1e-12)
    f, xi = mindlin_tangential(1e-5, 0.01, dt, a, k, damp, mu, fn)  # slide: Coulomb limit, xi reset
    assert f == pytest.approx(-mu * fn, rel=1e-12)
    assert -k * a * xi - damp * 0.01 == pytest.approx(-mu * fn, rel=1e-12)
