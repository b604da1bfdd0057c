"""The SymPy derivations in dtcrit.symbolic.mass_properties, checked symbolically and at 50 digits."""
from __future__ import annotations

import mpmath as mp
import pytest
import sympy as sp

from dtcrit.symbolic import mass_properties as mpr


@pytest.mark.parametrize("alpha,beta", [("1/3", "7/2"), ("1/200", "3/2"), ("5", "51/100"), ("9/4", "9/4")])
def test_euler_beta_lemma_at_fifty_digits(alpha, beta):
    """The SymPy-derived lemma against mpmath's Beta function and (mild cases) its quadrature."""
    mp.mp.dps = 60
    al, be = sp.Rational(alpha), sp.Rational(beta)
    value = mp.mpf(str(sp.N(mpr.euler_beta_integral().subs({mpr._alpha: al, mpr._beta: be}), 55)))
    ma, mb = mp.mpf(al.p) / al.q, mp.mpf(be.p) / be.q
    assert abs(value / mp.beta(ma, mb) - 1) < mp.mpf("1e-50")
    if ma >= 1 and mb >= 1:
        direct = mp.quad(lambda t: t ** (ma - 1) * (1 - t) ** (mb - 1), [0, 1])
        assert abs(value / direct - 1) < mp.mpf("1e-50")


def test_superquadric_reduces_to_the_ellipsoid_at_eps_one():
    sq, ell = mpr.superquadric_moments(), mpr.ellipsoid_moments()
    for key in ("volume", "xx", "yy", "zz"):
        assert sp.simplify(sp.gammasimp(sq[key].subs({mpr.eps1: 1, mpr.eps2: 1})) - ell[key]) == 0


def test_superquadric_reduces_to_the_octahedron_at_eps_two():
    """|x/a| + |y/b| + |z/c| <= 1: 8 copies of a simplex, integrated directly by SymPy."""
    x, y, z = sp.symbols("x y z", nonnegative=True)
    a, b, c = mpr.a, mpr.b, mpr.c

    def octant(f):
        return 8 * sp.integrate(f, (z, 0, c * (1 - x / a - y / b)), (y, 0, b * (1 - x / a)), (x, 0, a))

    direct = {"volume": octant(1), "xx": octant(x**2), "yy": octant(y**2), "zz": octant(z**2)}
    sq = mpr.superquadric_moments()
    for key, value in direct.items():
        assert sp.simplify(sp.gammasimp(sq[key].subs({mpr.eps1: 2, mpr.eps2: 2})) - value) == 0


def test_box_and_sphere_moments():
    box, sph = mpr.box_moments(), mpr.sphere_moments()
    assert box["volume"] == 8 * mpr.a * mpr.b * mpr.c
    assert sp.simplify(box["xx"] - box["volume"] * mpr.a**2 / 3) == 0
    assert sp.simplify(mpr.inertia_per_mass(sph)[0] - sp.Rational(2, 5) * mpr.radius**2) == 0
    assert sp.simplify(mpr.inertia_per_mass(mpr.ellipsoid_moments())[0] - (mpr.b**2 + mpr.c**2) / 5) == 0


def test_tetrahedron_moments_against_cartesian_integration():
    """Vertices 0, (2,0,0), (0,3,0), (0,0,5) with the opposite orientation giving the opposite sign."""
    x, y, z = sp.symbols("x y z", nonnegative=True)
    lim = [(z, 0, 5 * (1 - x / 2 - y / 3)), (y, 0, 3 * (1 - x / 2)), (x, 0, 2)]
    direct = [sp.integrate(f, *lim) for f in (1, x, y, z, x**2, y**2, z**2, x * y, x * z, y * z)]
    tet = mpr.tetrahedron_moments()
    keys = ("volume", "x", "y", "z", "xx", "yy", "zz", "xy", "xz", "yz")
    subs = dict(zip(mpr.TETRA_VERTICES, (2, 0, 0, 0, 3, 0, 0, 0, 5)))
    flipped = dict(zip(mpr.TETRA_VERTICES, (0, 3, 0, 2, 0, 0, 0, 0, 5)))
    for key, value in zip(keys, direct):
        assert tet[key].subs(subs) == value
        assert tet[key].subs(flipped) == -value
