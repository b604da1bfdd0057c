"""The schemes DEM codes ship (Chrono DEM-Engine / Kratos extended Taylor, MFiX Adams-Bashforth 2)
against direct computation, and the code-name map of ``dtcrit.integrators.engines``."""
import math

import mpmath as mp
import pytest
import sympy as sp

from dtcrit.errors import InputError
from dtcrit.integrators.engines import ENGINES, resolve_integrator
from dtcrit.integrators.schemes import INTEGRATORS
from dtcrit.integrators.simulate import run
from dtcrit.integrators.stability import check_integrator, critical_dt
from dtcrit.symbolic.integrators import amplification_matrix, tau, zeta

from support.amplification import spectral_radius_mp

NEW = ("extended-taylor", "adams-bashforth-2")
ZETAS = (0.01, 0.05, 0.3, 0.5, 1.0, 3.0, 30.0)


def test_extended_taylor_determinant_exceeds_one_undamped():
    """det G = 1 - 2 zeta tau + tau^2/2: undamped 1 + (omega h)^2/2 > 1, so |lambda| > 1 for every h."""
    G = amplification_matrix("extended-taylor", dimensionless=True)
    assert sp.expand(G.det() - (1 - 2 * zeta * tau + tau**2 / 2)) == 0
    for name in NEW:
        assert critical_dt(name, 1e10, 0.0, 7.0).dt == 0.0
        for t in (1e-6, 1e-3, 0.1, 1.0, 3.0):
            assert spectral_radius_mp(name, t, 0) > 1


def _exact_tau(name, z):
    """Independent closed forms: extended Taylor min(4 zeta, 1/zeta); AB2 the cubic root below sqrt(3)/6."""
    with mp.workdps(50):
        z = mp.mpf(z)
        if name == "extended-taylor":
            return min(4 * z, 1 / z)
        if z >= mp.sqrt(3) / 6:
            return 1 / (2 * z)
        return mp.findroot(lambda t: t**3 - 2 * z * t**2 - 8 * z * z * t - 8 * z, 2 * mp.cbrt(z) + 4 * z)


@pytest.mark.parametrize("name", NEW)
@pytest.mark.parametrize("z", ZETAS)
def test_spectral_radius_at_50_digits_brackets_the_boundary(name, z):
    t = _exact_tau(name, z)
    got = critical_dt(name, 1.0, 2.0 * z, 1.0).dt
    assert abs(got - float(t)) <= 4 * math.ulp(float(t))
    with mp.workdps(50):
        assert spectral_radius_mp(name, t * mp.mpf("0.99"), z) <= 1
        assert spectral_radius_mp(name, t * mp.mpf("1.01"), z) > 1
        assert abs(spectral_radius_mp(name, t, z) - 1) < mp.mpf(10) ** -30


@pytest.mark.parametrize("name", NEW)
@pytest.mark.parametrize("z", ZETAS[1:])  # zeta = 0.01: rho(1.01 tau*) - 1 ~ 4e-6 needs millions of steps
def test_time_stepping_bounded_at_099_growing_at_101(name, z):
    t = critical_dt(name, 1.0, 2.0 * z, 1.0).dt
    rho = float(spectral_radius_mp(name, 1.01 * t, z))
    n = int(min(400_000, max(4_000, 8 * math.log(10) / math.log(rho))))
    assert run(name, 1.01 * t, z, n).growth > 100, (name, z, n)
    assert run(name, 0.99 * t, z, n).growth <= 1.5


def test_ab2_switch_point():
    """The cubic and 1/(2 zeta) meet at zeta = sqrt(3)/6, tau = sqrt(3)."""
    z = math.sqrt(3) / 6
    assert critical_dt("adams-bashforth-2", 1.0, 2 * z, 1.0).dt == pytest.approx(math.sqrt(3), rel=1e-15)


def test_code_names_resolve_to_schemes():
    assert check_integrator("chrono") == "extended-taylor"
    assert check_integrator("MFiX-AB2") == "adams-bashforth-2"
    assert check_integrator("yade") == "leapfrog"
    assert resolve_integrator("leapfrog") == ("leapfrog", "")
    key, note = resolve_integrator("kratos-taylor")
    assert key == "extended-taylor" and "taylor_scheme.cpp" in note
    assert all(scheme in INTEGRATORS for scheme, _v, _s in ENGINES.values())
    assert critical_dt("chrono", 1e10, 1e3, 7.0).dt == critical_dt("extended-taylor", 1e10, 1e3, 7.0).dt


@pytest.mark.parametrize("name", ["edem", "EDEM", "rocky"])
def test_ambiguous_code_names_are_refused_in_one_line(name):
    with pytest.raises(InputError) as e:
        check_integrator(name)
    assert e.value.key == "integrator" and "ambiguous" in str(e.value) and "\n" not in str(e.value)
