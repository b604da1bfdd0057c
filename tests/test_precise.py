"""dtcrit.integrators.precise evaluates the *derived* closed forms: symbolic identities, and ulps where it matters.

The careful forms (forward Euler's error-free residual, the Eq. (40) cubic's identity) are checked
against the closed forms produced by dtcrit.symbolic, and numerically against 50-digit references
at the inputs that defeat a naive evaluation (zeta -> 1 for forward Euler; rates beyond float64).
"""
import mpmath as mp
import numpy as np
import pytest
import sympy as sp

from dtcrit.integrators import precise
from dtcrit.integrators.stability import critical_dt_array
from dtcrit.symbolic.closed_forms import closed_pieces, dt_crit_mp
from dtcrit.symbolic.integrators import tau, zeta

k, A, z = sp.symbols("k A z", positive=True)


def _dt(tau_expr, c):
    """dt = tau(zeta)/omega with omega = sqrt(k A), zeta = c A/(2 omega)."""
    w = sp.sqrt(k * A)
    return tau_expr.subs(zeta, c * A / (2 * w)) / w


def test_forward_euler_forms_are_the_derived_pieces():
    under, over = closed_pieces("forward-euler")
    c_under = 2 * z * sp.sqrt(k / A)  # zeta = z
    assert sp.simplify(_dt(under.tau_expr, c_under) - c_under / k) == 0  # dt = c/k for zeta <= 1
    zz = 1 + z  # zeta > 1
    c_over = 2 * zz * sp.sqrt(k / A)
    residual = c_over**2 * A - 4 * k  # R = c^2 A - 4k
    careful = 4 / (c_over * A + sp.sqrt(A * residual))
    assert sp.simplify(_dt(over.tau_expr, c_over) - careful) == 0


def test_paper_eq40_identity_follows_from_the_derived_cubic():
    (piece,) = closed_pieces("paper-eq40")
    g = tau**3 + sum(coef * tau ** (2 - i) for i, coef in enumerate(piece.cubic))
    assert sp.expand(g - (tau * (tau - 2 * zeta) ** 2 + 2 * (tau - zeta))) == 0
    # g(tau) = 0  <=>  tau = zeta / (1 + (tau - 2 zeta)^2 / 2)
    assert sp.expand(2 * (zeta - tau * (1 + (tau - 2 * zeta) ** 2 / 2)) + g) == 0


@pytest.mark.parametrize("dz", [1e-16, 1e-12, 1e-8, 1e-4, -1e-8, -1e-4])
def test_forward_euler_near_critical_damping_within_4_ulp(dz):
    for k_, A_ in ((1.0, 1.0), (3.3e7, 2.9e-3), (1e-200, 1e150)):
        with mp.workdps(40):
            c_ = float(2 * (1 + mp.mpf(dz)) * mp.sqrt(mp.mpf(k_) / mp.mpf(A_)))
        ref = dt_crit_mp("forward-euler", k_, c_, A_)
        got = float(critical_dt_array("forward-euler", k_, c_, A_))
        assert abs(mp.mpf(got) - ref) / np.spacing(float(ref)) <= 4, (dz, k_, A_)


def test_scaling_by_the_larger_rate_keeps_huge_damping_ratios():
    # zeta ~ 1e305: gamma/omega beyond float64 if scaled by omega alone
    k_, c_, A_ = 1e-300, 1e300, 1e-10
    for name in ("velocity-verlet", "forward-euler", "paper-eq40"):
        ref = dt_crit_mp(name, k_, c_, A_)
        got = float(critical_dt_array(name, k_, c_, A_))
        assert abs(mp.mpf(got) - ref) / np.spacing(float(ref)) <= 4, name
    assert precise.scaled_closed_form("velocity-verlet", k_, c_, A_) > 0
