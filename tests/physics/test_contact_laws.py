"""The shared contact laws (``dtcrit.physics.contact_laws``) against closed forms evaluated in mpmath,
and the scene and packing stacks giving the same numbers for the same contact."""
import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, seed, settings
from hypothesis import strategies as st

from dtcrit.packing.conventions.granular_style import parse_granular
from dtcrit.packing.conventions.pair_styles import parse_pair_style
from dtcrit.packing.model import Contacts, HertzMindlinLaw, Packing
from dtcrit.physics import contact_laws as cl
from dtcrit.scenes.laws import resolve_pair
from dtcrit.scenes.scene import parse_scene

E, NU, RHO, R, V = 6.3e10, 0.22, 2500.0, 1e-3, 1.0


def _mp_moduli(e1, nu1, e2, nu2):
    """Johnson (1985), Eqs. (4.22) and (7.13), in 40 digits."""
    with mp.workdps(40):
        e1, nu1, e2, nu2 = map(mp.mpf, (e1, nu1, e2, nu2))
        g1, g2 = e1 / (2 * (1 + nu1)), e2 / (2 * (1 + nu2))
        return (1 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2), 1 / ((2 - nu1) / g1 + (2 - nu2) / g2))


@seed(25)
@settings(max_examples=60, deadline=None)
@given(st.floats(1e6, 1e12), st.floats(-0.9, 0.49), st.floats(1e6, 1e12), st.floats(-0.9, 0.49))
def test_effective_moduli_match_johnson(e1, nu1, e2, nu2):
    e_star, g_star = _mp_moduli(e1, nu1, e2, nu2)
    assert cl.effective_youngs_modulus(e1, nu1, e2, nu2) == pytest.approx(float(e_star), rel=1e-14)
    assert cl.effective_shear_modulus(e1, nu1, e2, nu2) == pytest.approx(float(g_star), rel=1e-14)


@pytest.mark.parametrize("nu", [-0.5, 0.0, 0.22, 0.3, 0.49])
def test_same_material_closed_form_is_the_two_material_formula(nu):
    e_star, g_star = _mp_moduli(E, nu, E, nu)
    got = cl.same_material_moduli(E, nu)
    assert got[0] == pytest.approx(float(e_star), rel=1e-15)
    assert got[1] == pytest.approx(float(g_star), rel=1e-15)


def test_hertz_stiffness_is_the_derivative_of_hertz_force():
    """k_n = dF/d(delta) of F = 4/3 E* sqrt(R*) delta^(3/2), differentiated by mpmath."""
    e_star, r_star, delta = 3.4e10, 5e-4, 2e-7
    with mp.workdps(40):
        dfd = mp.diff(lambda d: mp.mpf(4) / 3 * e_star * mp.sqrt(r_star) * d ** mp.mpf(1.5), delta)
    a = np.sqrt(r_star * delta)
    assert cl.hertz_normal_stiffness(e_star, a) == pytest.approx(float(dfd), rel=1e-14)
    # LAMMPS's F = K_n a delta: its tangent 3/2 K_n a
    with mp.workdps(40):
        dfl = mp.diff(lambda d: 7e9 * mp.sqrt(r_star * d) * d, delta)
    assert cl.lammps_hertz_tangent_stiffness(7e9, a) == pytest.approx(float(dfl), rel=1e-14)


def test_hertz_max_overlap_stores_the_impact_energy():
    """The Hertz work to delta_max, (8/15) E* sqrt(R*) delta^(5/2), integrated by mpmath, is 1/2 m* v^2."""
    m_star, e_star, r_star, v = 2.6e-6, 3.4e10, 5e-4, 1.7
    d = cl.hertz_max_overlap(m_star, e_star, r_star, v)
    with mp.workdps(30):
        work = mp.quad(lambda x: mp.mpf(4) / 3 * e_star * mp.sqrt(r_star) * x ** mp.mpf(1.5), [0, d])
    assert float(work) == pytest.approx(0.5 * m_star * v * v, rel=1e-13)


def test_yade_normal_stiffness_literal():
    """Ip2_FrictMat_FrictMat_FrictPhys: 2 E1 R1 E2 R2 / (E1 R1 + E2 R2); one material: 2 E R1 R2/(R1 + R2)."""
    assert cl.yade_normal_stiffness(1e9 * 1e-3, 1e9 * 3e-3) == pytest.approx(2 * 1e9 * 1e-3 * 3e-3 / 4e-3, rel=1e-15)
    assert cl.yade_normal_stiffness(1e308, 1e308) == pytest.approx(1e308, rel=1e-15)  # no overflow


def test_reduced_on_arrays_and_scalars():
    x, y = np.array([1.0, 2.0, 3.0]), np.array([1.0, 6.0, 1.5])
    assert np.array_equal(cl.reduced(x, y), np.array([0.5, 1.5, 1.0]))
    assert cl.reduced(2.0, 2.0) == 1.0


def _scene_pair():
    s = parse_scene(f"""
integrator = "velocity-verlet"
[[particle]]
shape = "sphere"
radius = {R}
density = {RHO}
youngs_modulus = {E}
poisson_ratio = {NU}
[contact]
model = "hertz"
velocity = {V}
""")
    return resolve_pair(s, 1, 1)


def _packing_contact(delta: float):
    packing = Packing.spheres([[0.0, 0.0, 0.0], [2 * R - delta, 0.0, 0.0]], R, density=RHO)
    n = np.array([[1.0, 0.0, 0.0]])
    contacts = Contacts(np.array([0]), np.array([1]), n, R * n, -R * n, np.array([delta]),
                        np.zeros((1, 3), dtype=np.int64), np.array([R / 2]))
    return packing, contacts


def test_scene_and_packing_give_the_same_hertz_mindlin_stiffness():
    """The same two spheres at the same overlap: the scene's pair, the packing's Hertz-Mindlin law and
    LAMMPS's ``granular hertz/material ... mindlin NULL`` give identical k_n and k_s."""
    pc = _scene_pair()
    packing, contacts = _packing_contact(pc.delta_max)
    kn, ks = HertzMindlinLaw(E, NU).stiffness(contacts)
    assert kn[0] == pc.kn and ks[0] == pc.ks
    style = parse_granular(f"hertz/material {E} 0 {NU} tangential mindlin NULL 0 0.5".split())
    terms = style.terms(packing, contacts)
    assert terms.kn[0] == pc.kn and terms.ks[0] == pc.ks
    # and against the closed form in 40 digits
    e_star, g_star = _mp_moduli(E, NU, E, NU)
    with mp.workdps(40):
        a = mp.sqrt(mp.mpf(R) / 2 * mp.mpf(pc.delta_max))
        assert pc.kn == pytest.approx(float(2 * e_star * a), rel=1e-14)
        assert pc.ks == pytest.approx(float(8 * g_star * a), rel=1e-14)


def test_lammps_gran_hertz_and_granular_hertz_agree():
    """``gran/hertz/history Kn`` and ``granular hertz Kn``: the same force K_n a delta, the same tangent."""
    packing, contacts = _packing_contact(3e-6)
    gran = parse_pair_style("gran/hertz/history 1e9 NULL 0 NULL 0.5 0").terms(packing, contacts)
    granular = parse_granular("hertz 1e9 0 tangential linear_history 1 0 0.5".split()).terms(packing, contacts)
    assert gran.kn[0] == granular.kn[0]
    assert gran.kn[0] == pytest.approx(1.5e9 * np.sqrt(R / 2 * 3e-6), rel=1e-15)
