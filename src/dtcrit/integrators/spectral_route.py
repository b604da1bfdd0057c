"""The critical step of a scheme without an emitted closed form (a user-written one): the first
step at which the spectral radius of its amplification matrix exceeds 1 (runtime; no SymPy).

In scaled units (omega = sqrt(k A) = 1, zeta = c A / (2 omega), tau = omega dt) the amplification
matrix of the update rule (``dtcrit.integrators.amplification.matrix_mp``) is evaluated at 50
digits; tau is scanned on a geometric grid from 1e-12 to 1e4 (10 points a decade) for the first
unstable point (rho > 1 + 1e-30), then bisected to 1e-20 relative.  Stability is taken from 0
upwards, as ``dtcrit.symbolic.boundary.tau_crit_mp`` does: 0 when even tau = 1e-12 is unstable.
``tests/integrators/test_user_rules.py`` checks it against the exact boundary roots of the built-in schemes.
"""
from __future__ import annotations

import math

import mpmath as mp

from dtcrit.errors import InputError
from dtcrit.integrators.amplification import spectral_radius_mp

DPS = 50
_TOL = mp.mpf(10) ** -30


def _unstable(integrator, t, z) -> bool:
    if z is None:  # a dashpot without spring: K = 0, C = 1, the step is t = c A dt
        return _dashpot_radius(integrator, t) > 1 + _TOL
    return spectral_radius_mp(integrator, t, z, dps=DPS) > 1 + _TOL


def _dashpot_radius(integrator, t):
    from dtcrit.integrators.schemes import LinearForce, lookup

    integ = lookup(integrator)
    d = len(integ.state)
    G = mp.matrix(d, d)
    for j in range(d):
        column = integ.step(tuple(mp.mpf(1) if i == j else mp.mpf(0) for i in range(d)), t, LinearForce(mp.mpf(0), mp.mpf(1)))
        for i in range(d):
            G[i, j] = column[i]
    return max(abs(v) for v in mp.eig(G, left=False, right=False))


def tau_crit(integrator, zeta) -> float:
    """tau* (float) of ``integrator`` at damping ratio ``zeta`` (0: no stable step; inf: none found up to 1e4).

    ``zeta = None``: a dashpot without spring (K = 0, C = 1): the critical ``c A dt``.

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or user-written scheme.
    zeta : float, str or None
        Damping ratio ``c A / (2 omega)`` (read exactly by mpmath), or None for a dashpot without spring.

    Returns
    -------
    float
        The critical dimensionless step ``omega dt`` (``c A dt`` when ``zeta`` is None).
    """
    with mp.workdps(DPS):
        z = None if zeta is None else mp.mpf(zeta)
        grid = [mp.mpf(10) ** (mp.mpf(e) / 10) for e in range(-120, 41)]
        lo = mp.mpf(0)
        for t in grid:
            if _unstable(integrator, t, z):
                hi = t
                break
            lo = t
        else:
            return math.inf
        if lo == 0:
            return 0.0
        while hi - lo > mp.mpf(10) ** -20 * hi:
            mid = (lo + hi) / 2
            if _unstable(integrator, mid, z):
                hi = mid
            else:
                lo = mid
        return float(lo)


def critical_dt_spectral(integrator, k, c, A) -> float:
    """dt* [s] for one contact mode (k > 0, c >= 0, A > 0) from the spectral radius.

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or user-written scheme.
    k : float
        Contact stiffness [N/m].
    c : float
        Viscous damping [N s/m].
    A : float
        Inverse inertia coefficient [1/kg].

    Returns
    -------
    float
        The critical step [s], confirmed by stepping the rules (``user_confirm.confirm_step``).
    """
    with mp.workdps(DPS):
        w = mp.sqrt(mp.mpf(k) * mp.mpf(A))
        if w == 0:
            raise InputError("k", "the spectral route needs k A > 0")
        z = mp.mpf(c) * mp.mpf(A) / (2 * w)
        t = tau_crit(integrator, z)
        dt = float(mp.mpf(t) / w) if math.isfinite(t) else math.inf
    if math.isinf(dt) and math.isfinite(t):
        raise InputError("k", "the critical step lies beyond the float64 range; rescale the units and retry")
    from dtcrit.integrators.user_confirm import confirm_step

    confirm_step(integrator, dt, float(k) * float(A), float(c) * float(A))  # stepping the rules, physical units
    return dt


def dashpot_dt_spectral(integrator, c, A) -> float:
    """dt* [s] of a dashpot without spring (``xddot = -c A xdot``, c > 0, A > 0): by dimensional
    consistency the amplification matrix depends on ``c A dt`` only (the critical value is scanned
    as ``tau`` above), confirmed by stepping the rules in physical units like every other mode.

    Parameters
    ----------
    integrator : str or Integrator
        A built-in or user-written scheme.
    c : float
        Viscous damping [N s/m].
    A : float
        Inverse inertia coefficient [1/kg].

    Returns
    -------
    float
        The critical step [s] (inf when every step is stable).
    """
    with mp.workdps(DPS):
        rate = mp.mpf(c) * mp.mpf(A)
        t = tau_crit(integrator, None)
        dt = float(mp.mpf(t) / rate) if math.isfinite(t) else math.inf
    from dtcrit.integrators.user_confirm import confirm_step

    confirm_step(integrator, dt, 0.0, float(c) * float(A))
    return dt
