"""The damped critical step of a packing by the spectral radius of its amplification operator.

The route for what the lagged and centred closed forms do not cover: the amplification operator of the
integrator applied matrix-free (``amplification_operator``), its spectral radius (``spectral_radius``,
dense below ``DENSE_STATES`` states, ARPACK above), the growth a statically unstable packing allows
(``physical_growth``) and the bisection on the step (``critical_by_spectral_radius``).
"""
from __future__ import annotations

import math
import numpy as np
import scipy.sparse.linalg as spla
from dtcrit.errors import InputError, NotConvergedError
from dtcrit.integrators.schemes import INTEGRATORS


CENTRED = ("leapfrog-centred",)
"""Schemes whose damping term is centred (a linear solve per step): their step is ``2/omega_max``."""


def amplification_operator(k, c, integrator: str, h: float) -> spla.LinearOperator:
    """One step of ``integrator``'s update rule on the mass-scaled packing ``y'' = -K~ y - C~ y'``.

    Built from the scheme's own ``step`` (``dtcrit.integrators.schemes``), so its spectrum is exactly
    the scheme's amplification.

    Parameters
    ----------
    k : scipy.sparse matrix or LinearOperator
        ``K~`` [1/s^2].
    c : scipy.sparse matrix or LinearOperator
        ``C~`` [1/s].
    integrator : str
        Integrator name (not ``leapfrog-centred``, whose step is ``2/omega_max``).
    h : float
        Time step [s].

    Returns
    -------
    scipy.sparse.linalg.LinearOperator
        The map on the stacked state (two or three blocks of ``n``).
    """
    scheme = INTEGRATORS[integrator]
    if integrator in CENTRED:
        raise InputError("integrator", "leapfrog-centred needs a linear solve per step; its step is 2/omega_max")
    n, parts = k.shape[0], len(scheme.state)

    class _Force:
        dv = None

        def __call__(self, x, v):
            return -(k @ x) - (c @ v)

    force = _Force()

    def matvec(s):
        s = np.asarray(s).reshape(-1)
        out = scheme.step([s[p * n:(p + 1) * n] for p in range(parts)], h, force)
        return np.concatenate(out)

    return spla.LinearOperator((parts * n, parts * n), matvec=matvec, dtype=float)


STATIC_INSTABILITY = 1e-9
"""A lowest eigenvalue of ``K~`` below ``-STATIC_INSTABILITY * lambda_max`` is a physically growing mode
(above it: rounding of the rigid-body modes at zero).  The spectral-radius route then refuses: the
growth of the exact motion cannot be told apart from the scheme's, mode by mode, from the spectral radius
alone (an allowance ``exp(h g)`` on the whole spectrum would admit a stiff mode growing by as much)."""

DENSE_STATES = 600
FALLBACK_STATES = 2400
"""Up to ``DENSE_STATES`` states the amplification operator's spectrum is computed densely (LAPACK
``geev``); above, by ARPACK's "largest magnitude" iteration, which near the critical step meets many
eigenvalues crowding the unit circle (the rigid modes sit at ``+1``) and can stop unconverged: up to
``FALLBACK_STATES`` the dense solve then answers (seconds at 2400 states), above it the failure
propagates to ``critical_by_spectral_radius``, which reports its bracket."""


def spectral_radius(k, c, integrator: str, h: float) -> float:
    """Largest ``|lambda|`` of the amplification operator at step ``h``.

    Dense ``geev`` up to ``DENSE_STATES`` states, else ARPACK ``eigs`` (``which="LM"``), falling back
    to dense up to ``FALLBACK_STATES`` when ARPACK does not converge.

    Parameters
    ----------
    k : scipy.sparse matrix or LinearOperator
        ``K~`` [1/s^2].
    c : scipy.sparse matrix or LinearOperator
        ``C~`` [1/s].
    integrator : str
        Integrator name.
    h : float
        Time step [s].

    Returns
    -------
    float
        Spectral radius (dimensionless; ``<= 1`` up to rounding means stable).
    """
    op = amplification_operator(k, c, integrator, h)
    size = op.shape[0]
    if size > DENSE_STATES:
        v0 = np.random.default_rng(20170601).standard_normal(size)
        try:
            w = spla.eigs(op, k=1, which="LM", v0=v0, tol=1e-10, return_eigenvectors=False)
            return float(np.max(np.abs(w)))
        except spla.ArpackNoConvergence:
            if size > FALLBACK_STATES:
                raise
    dense = op @ np.eye(size)
    return float(np.max(np.abs(np.linalg.eigvals(dense))))


def physical_growth(k) -> float:
    """Fastest exponential growth rate of the exact motion, ``sqrt(max(-lambda_min(K~), 0))``.

    For ``y'' = -K~ y - C~ y'`` with ``C~`` positive semi-definite a real root ``s`` of
    ``s^2 + c s + k = 0`` (Rayleigh quotients ``c >= 0``, ``k >= lambda_min``) is at most ``sqrt(-k)``.
    Compressive pre-loads can make ``K~`` indefinite (a statically unstable packing): that growth is
    physics, not the integrator's instability, and ``damped_critical_dt`` refuses it on the
    spectral-radius route.

    Parameters
    ----------
    k : scipy.sparse matrix or LinearOperator
        ``K~`` [1/s^2].

    Returns
    -------
    float
        Growth rate [1/s] (0 when ``K~`` is positive semi-definite).
    """
    n = k.shape[0]
    if n <= FALLBACK_STATES:
        dense = k.toarray() if hasattr(k, "toarray") else k @ np.eye(n)
        lowest = float(np.linalg.eigvalsh(0.5 * (dense + dense.T))[0])
    else:
        try:
            lowest = float(spla.eigsh(k, k=1, which="SA", tol=1e-8, return_eigenvectors=False,
                                      v0=np.random.default_rng(20170601).standard_normal(n))[0])
        except spla.ArpackNoConvergence:
            raise NotConvergedError("lambda_min(K~) [1/s^2]", -math.inf, math.inf, "ARPACK eigsh",
                                    "the lowest eigenvalue of the pre-loaded stiffness (its physical growth)") from None
    return math.sqrt(max(-lowest, 0.0))


def critical_by_spectral_radius(k, c, integrator: str, h_hi: float, *, rtol: float = 1e-7,
                                slack: float = 1e-6) -> tuple[float, int]:
    """Largest step with spectral radius ``<= 1 + slack``, by doubling then bisection.

    Searched from ``h_hi`` (doubled while stable; a statically unstable packing is refused before,
    ``STATIC_INSTABILITY``).  The slack covers rounding: undamped modes of a stable step sit on the
    unit circle, and the rigid-body modes of a packing are Jordan blocks at ``+1``, which rounding
    spreads by about ``sqrt(eps)``; a mode growing by less than ``1e-6`` a step is taken as stable.

    Parameters
    ----------
    k : scipy.sparse matrix or LinearOperator
        ``K~`` [1/s^2].
    c : scipy.sparse matrix or LinearOperator
        ``C~`` [1/s].
    integrator : str
        Integrator name.
    h_hi : float
        Starting upper step [s] (the undamped ``2/omega_max``).
    rtol : float
        Relative width at which the bisection stops.
    slack : float
        Allowed growth of the spectral radius above 1.

    Returns
    -------
    h : float
        Largest stable step found [s] (``inf`` if stable beyond ``1e6 h_hi``).
    solves : int
        Spectral-radius evaluations spent.

    Raises
    ------
    NotConvergedError
        On an ARPACK failure, with the bracket ``[lo, hi]`` reached so far.
    """
    solves = 0
    lo, hi = 0.0, h_hi  # lo: the largest step known stable; hi: unstable once the doubling is over
    doubling = True

    def stable(h: float) -> bool:
        try:
            return spectral_radius(k, c, integrator, h) <= 1.0 + slack
        except spla.ArpackNoConvergence:
            raise NotConvergedError("dt_crit [s]", lo, math.inf if doubling else hi, "ARPACK eigs (spectral radius)",
                                    f"at dt = {h:.6g} s after {solves} bisection steps") from None

    while stable(hi):
        solves += 1
        lo, hi = hi, 2.0 * hi
        if hi > 1e6 * h_hi:
            return math.inf, solves
    doubling = False
    lo = 0.0  # the bisection searches all of [0, hi] (as it always has)
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        solves += 1
        if stable(mid):
            lo = mid
        else:
            hi = mid
    return lo, solves


__all__ = ["CENTRED", "DENSE_STATES", "FALLBACK_STATES", "STATIC_INSTABILITY", "amplification_operator",
           "critical_by_spectral_radius", "physical_growth", "spectral_radius"]
