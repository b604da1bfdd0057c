"""Hertz-Mindlin ``[[wall]]`` tables (``model = "hertz"``): the wall contact's tangent springs at its
overlap, checked against a direct eigen-solve of the sphere on an immovable plane with the springs
written here from Johnson's formulas (``R* = R``, ``m* = m``), and the keys a Hertz wall refuses.
"""
from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from dtcrit import critical_step, parse_scene
from dtcrit.errors import InputError

R, RHO, E, NU = 0.005, 2500.0, 7e10, 0.25
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO
INERTIA = 0.4 * MASS * R**2
BASE = (f'integrator = "velocity-verlet"\n[[particle]]\nshape = "sphere"\nradius = {R!r}\ndensity = {RHO!r}\n'
        f'youngs_modulus = {E!r}\npoisson_ratio = {NU!r}\n[contact]\nmodel = "linear"\nkn = 1.0\nks = 1.0\n')


def _springs(delta: float, e_w: float = E, nu_w: float = NU) -> tuple[float, float]:
    e_star = 1.0 / ((1 - NU**2) / E + (1 - nu_w**2) / e_w)
    g, g_w = E / (2 * (1 + NU)), e_w / (2 * (1 + nu_w))
    g_star = 1.0 / ((2 - NU) / g + (2 - nu_w) / g_w)
    a = math.sqrt(R * delta)
    return 2 * e_star * a, 8 * g_star * a


def _wall_step(kn: float, ks: float) -> float:
    """2/omega_max of a sphere on a fixed plane: dofs (z, x, theta_y); slip x + R theta_y."""
    K = np.array([[kn, 0, 0], [0, ks, ks * R], [0, ks * R, ks * R**2]])
    m = np.array([MASS, MASS, INERTIA])
    return 2.0 / math.sqrt(np.linalg.eigvalsh(K / np.sqrt(np.outer(m, m))).max())


def _wall_pair(text: str):
    res = critical_step(parse_scene(text))
    return next(p for p in res.pairs if p.contact.wall is not None)


def test_hertz_wall_at_a_given_overlap():
    """``overlap``: k_n = 2 E* sqrt(R delta), k_s = 8 G* sqrt(R delta), the wall of the particle's material."""
    delta = 2e-6
    w = _wall_pair(BASE + f'[[wall]]\nmodel = "hertz"\noverlap = {delta!r}\n')
    kn, ks = _springs(delta)
    assert (w.contact.kn, w.contact.ks) == (pytest.approx(kn, rel=1e-13), pytest.approx(ks, rel=1e-13))
    assert w.contact.m_star == MASS
    assert w.dt_translation == pytest.approx(_wall_step(kn, ks), rel=1e-10)


def test_hertz_wall_of_another_material_at_an_impact():
    """``velocity``: the largest overlap of an impact on the wall.

    From the energy balance m v^2/2 = 8/15 E* sqrt(R) delta^(5/2), solved with mpmath.
    """
    v, e_w, nu_w = 2.0, 2.1e11, 0.3
    w = _wall_pair(BASE + f'[[wall]]\nmodel = "hertz"\nvelocity = {v!r}\nyoungs_modulus = {e_w!r}\npoisson_ratio = {nu_w!r}\n')
    e_star = 1 / (mp.mpf(1 - NU**2) / E + mp.mpf(1 - nu_w**2) / e_w)
    delta = float(mp.findroot(lambda d: mp.mpf(8) / 15 * e_star * mp.sqrt(R) * d ** 2.5 - mp.mpf(MASS) * v**2 / 2, 1e-5))
    kn, ks = _springs(delta, e_w, nu_w)
    assert (w.contact.kn, w.contact.ks) == (pytest.approx(kn, rel=1e-9), pytest.approx(ks, rel=1e-9))


@pytest.mark.parametrize("extra, key", [
    ("kn = 1e5\n", "wall[1].kn"),
    ("overlap = 1e-6\nvelocity = 1.0\n", "wall[1].overlap"),
    ("", "wall[1].overlap"),
    ("overlap = 0.01\n", "wall[1].overlap"),
    ("poisson_ratio = 0.5\noverlap = 1e-6\n", "wall[1].poisson_ratio"),
])
def test_hertz_wall_refusals(extra, key):
    """Stiffness given to a Hertz wall, both overlap and speed, neither, an overlap past R, nu = 0.5."""
    with pytest.raises(InputError) as exc:
        critical_step(parse_scene(BASE + f'[[wall]]\nmodel = "hertz"\n{extra}'))
    assert exc.value.key == key


def test_linear_wall_refuses_hertz_keys():
    """``overlap`` on a linear wall is named, not ignored."""
    with pytest.raises(InputError) as exc:
        parse_scene(BASE + "[[wall]]\nkn = 1e5\nks = 1e4\noverlap = 1e-6\n")
    assert exc.value.key == "wall[1].overlap"
