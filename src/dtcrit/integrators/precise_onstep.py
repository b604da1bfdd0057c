"""Careful evaluation of the exact steps of the on-step-force schemes DEM codes ship (runtime; no SymPy).

Both schemes evaluate the force, dashpot included, at (x_n, v_n); their boundaries are derived in
``dtcrit.symbolic`` (``derivations/records/sec4_stability.md``) and emitted as
``dtcrit._generated.critical_steps.dt_<name>``.  Evaluated here from the mantissas and exponents of
k, c, A (never forming k A or c A in float64), with omega = sqrt(k A), gamma = c A / 2,
zeta = gamma / omega:

* ``extended-taylor`` (Chrono DEM-Engine, Kratos Taylor): omega dt = min(4 zeta, 1/zeta), i.e.
  ``dt = min(2 c / k, 2 / (c A))`` -- two divisions, no root, no cancellation; 0 when c = 0;
* ``adams-bashforth-2`` (MFiX): for zeta >= sqrt(3)/6 ``dt = 1 / (c A)``; below it tau* is the root
  of tau^3 - 2 zeta tau^2 - 8 zeta^2 tau - 8 zeta = tau (tau - 4 zeta)(tau + 2 zeta) - 8 zeta, so
  ``dt = (4 c / k) / ((tau* - 4 zeta)(tau* + 2 zeta))``: the lead 4c/k straight from the inputs and
  the computed root (the generated cubic solver) only in the denominator, where tau* - 4 zeta is
  at least (sqrt(3)/3) tau* (no cancellation).

``tests/integrators/test_integrators_engines.py`` checks both against the 50-digit boundary and in ulps.
"""
from __future__ import annotations

import numpy as np

from dtcrit.numerics.cubic import cubic_positive_root
from dtcrit.numerics.scaling import frexp_parts, scaled_root

SCHEMES = ("extended-taylor", "adams-bashforth-2")
_AB2_SWITCH = np.sqrt(3.0) / 6.0
_AB2_TINY = 2.0**-94


def extended_taylor(k, c, A) -> np.ndarray:
    """Critical step dt = min(2c/k, 2/(cA)) of the extended Taylor scheme (0 when c = 0).

    Parameters
    ----------
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical step [s] of ``extended-taylor``, elementwise.
    """
    mk, ek, mc, ec, mA, eA = frexp_parts(k, c, A)
    with np.errstate(all="ignore"):
        spring = np.ldexp(2.0 * mc / mk, ec - ek)
        dashpot = np.ldexp(2.0 / (mc * mA), -(ec + eA))
        return np.where(mc > 0, np.minimum(spring, dashpot), 0.0)


def adams_bashforth_2(k, c, A) -> np.ndarray:
    """Critical step of Adams-Bashforth 2: 1/(cA) for zeta >= sqrt(3)/6, else (4c/k)/((tau - 4 zeta)(tau + 2 zeta)).

    Parameters
    ----------
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical step [s] of ``adams-bashforth-2``, elementwise.
    """
    mk, ek, mc, ec, mA, eA = frexp_parts(k, c, A)
    w, s = scaled_root(mk, ek, mA, eA)  # omega = w 2^s
    with np.errstate(all="ignore"):
        z = np.ldexp(mc * mA * 0.5, np.clip(ec + eA - s, -1100, 1100)) / w
        dashpot = np.ldexp(1.0 / (mc * mA), -(ec + eA))
        zs = np.where(z < _AB2_SWITCH, z, 0.25)
        t = cubic_positive_root(-2.0 * zs, -8.0 * zs * zs, -8.0 * zs, False)
        lead = np.ldexp(4.0 * mc / mk, ec - ek)
        cubic = lead / ((t - 4.0 * zs) * (t + 2.0 * zs))
        out = np.where(z < _AB2_SWITCH, cubic, dashpot)
        # tiny zeta (down to zeta underflowing): the leading order of the same cubic, tau^3 = 8 zeta, i.e.
        # dt = (4 c / (k^2 A))^(1/3), from the mantissas and a whole multiple of 3 in the exponent;
        # below zeta = 2^-94 the neglected terms are under 2^-64 relative (symbolic.careful_forms'
        # small-zeta branch, checked in tests/symbolic/test_kernels_careful_forms.py)
        big_e = ec - 2 * ek - eA
        q = np.floor_divide(big_e, 3)
        small = np.ldexp(np.cbrt(np.ldexp(4.0 * mc / (mk * mk * mA), big_e - 3 * q)), q)
        out = np.where(z <= _AB2_TINY, small, out)
        return np.where(mc > 0, out, 0.0)


CAREFUL = {"extended-taylor": extended_taylor, "adams-bashforth-2": adams_bashforth_2}


def steps(integrator: str, k, c, A) -> np.ndarray:
    """The careful exact step of one of ``SCHEMES`` for arrays of k, c, A.

    Parameters
    ----------
    integrator : str
        One of ``SCHEMES``.
    k, c, A : float or array_like
        Stiffness [N/m], viscous damping coefficient [N s/m] and inverse inertia coefficient [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical step [s], elementwise.
    """
    return CAREFUL[integrator](k, c, A)
