"""Rolling and twisting springs (``dtcrit.physics.rotational_springs``): the LAMMPS and LIGGGHTS
definitions as literals, and the scene and packing stacks agreeing on the same contact."""
import math

import numpy as np
import pytest

from dtcrit.packing.conventions.granular_style import parse_granular
from dtcrit.packing.model import Contacts, Packing
from dtcrit.physics import rotational_springs as rs
from dtcrit.scenes.rotational import RotationalLaw, resolve_rotational


def test_sds_rolling_literal():
    """LAMMPS ``rolling sds k gamma mu``: torque R* n x (k R* theta) -> k_r = k R*^2; c_r = gamma R*^2."""
    assert rs.sds_rolling(4.0, 2.0, 0.5) == (1.0, 0.5)
    k, c = rs.sds_rolling(np.array([4.0, 8.0]), 2.0, np.array([0.5, 0.25]))
    assert np.array_equal(k, [1.0, 0.5]) and np.array_equal(c, [0.5, 0.125])


def test_marshall_twisting_literal():
    """LAMMPS ``twisting marshall``: k_tw = k_t a^2/2, c_tw = eta_t a^2/2."""
    assert rs.marshall_twisting(8.0, 4.0, 0.5) == (1.0, 0.5)


def test_epsd_literals():
    """LIGGGHTS rolling_model_epsd.h: k_r = 2.25 k_n mu_r^2 R*^2, c_r = eta 2 sqrt(I_r k_r), I_r = 1.4 of
    the series combination of m R^2."""
    assert rs.epsd_rolling_stiffness(2.25, 1e4, 0.2, 1e-3) == pytest.approx(2.25 * 1e4 * 0.04 * 1e-6, rel=1e-15)
    i_r = 1.4 * (2.0 * 1.0) * (3.0 * 4.0) / (2.0 + 12.0)
    assert rs.epsd_rolling_dashpot(0.3, 5.0, 2.0, 1.0, 3.0, 2.0) == pytest.approx(0.3 * 2 * math.sqrt(i_r * 5.0), rel=1e-15)
    assert rs.epsd2_rolling_stiffness(3.0, 0.5) == 0.75
    assert rs.yade_rotational_stiffness(0.5, 4.0, 1.0, 2.0) == 4.0


def test_scene_and_packing_give_the_same_rotational_springs():
    """``rolling sds`` and ``twisting marshall`` of one sphere pair, through the scene's law and LAMMPS's
    granular style, are the same numbers."""
    r, delta, kt, eta, k_roll, g_roll = 1e-3, 2e-6, 3e4, 0.7, 5e3, 2.0
    packing = Packing.spheres([[0.0, 0.0, 0.0], [2 * r - delta, 0.0, 0.0]], r, density=2500.0)
    n = np.array([[1.0, 0.0, 0.0]])
    contacts = Contacts(np.array([0]), np.array([1]), n, r * n, -r * n, np.array([delta]),
                        np.zeros((1, 3), dtype=np.int64), np.array([r / 2]))
    style = parse_granular(f"hooke 1e5 {eta} tangential linear_history {kt} 1 0.5 damping velocity "
                           f"rolling sds {k_roll} {g_roll} 0.3 twisting marshall".split())
    t = style.terms(packing, contacts)
    a = math.sqrt(r / 2 * delta)
    law = RotationalLaw(rolling_model="sds", twisting_model="marshall",
                        params=(("k_roll", k_roll), ("gamma_roll", g_roll), ("contact_radius", a)))
    m = float(packing.masses[0])
    kr, ktw, cr, ctw = resolve_rotational(law, 1e5, kt, float(t.cs[0]), r, r, m, m, None, "1-1")
    assert (kr, cr) == (t.kr[0], t.cr[0])
    assert (ktw, ctw) == (t.ktw[0], t.ctw[0])
    assert kr == pytest.approx(k_roll * (r / 2) ** 2, rel=1e-15) and ktw == pytest.approx(kt * a * a / 2, rel=1e-15)
