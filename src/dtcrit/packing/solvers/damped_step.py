"""The exact critical step of a packing with per-contact dashpots (any, non-proportional, damping).

The packing obeys ``M x'' + C x' + K x = 0`` with ``C`` the assembled contact dashpots
(``dtcrit.packing.operators.assembly.damping_matrix``).  When ``C`` is not diagonalised by the undamped modes the
modal route (``dtcrit.packing.solvers.integrator_step``: top undamped mode, its modal damping ratio) is only an
approximation; with strong dashpots another mode governs.  This module gives the exact answer.

**Lagged-damping central difference** (``leapfrog``; ``symplectic-euler`` and ``velocity-verlet`` have
the same amplification polynomial: LAMMPS's ``fix nve/sphere`` with its dashpots on the half-step
velocity, YADE's leapfrog with the lagged velocity).  Eliminating the velocities, ``x_n = lambda^n x``
solves ``P(lambda) x = 0`` with

    P(lambda) = (lambda - 1)^2 M + h (lambda - 1) C + h^2 lambda K.

For an eigenpair, ``x^H P(lambda) x = 0`` is the scalar polynomial with the Rayleigh quotients
``m = x^H M x > 0``, ``c = x^H C x >= 0``, ``k = x^H K x >= 0``, whose roots lie in the closed unit disk
iff ``4m - 2hc - h^2 k >= 0`` (Jury conditions of ``lambda^2 - (2 - hc/m - h^2 k/m) lambda + 1 - hc/m``).
Hence every eigenvalue satisfies ``|lambda| <= 1`` while ``4M - 2hC - h^2 K`` is positive definite, and
at the first ``h`` where it turns singular its null vector ``x`` gives ``P(-1) x = 0``: ``lambda = -1``
is an eigenvalue.  The critical step is therefore exactly the root of

    g(h) = lambda_max(2h C~ + h^2 K~) - 4,   C~ = M^(-1/2) C M^(-1/2),  K~ = M^(-1/2) K M^(-1/2),

a convex increasing function of ``h`` (a maximum of convex Rayleigh quotients ``2hc + h^2 k``), solved
by Newton's method from the undamped step ``2/omega_max`` downwards (monotone for a convex increasing
function) with ``g'(h) = v^T (2 C~ + 2h K~) v`` (Hellmann-Feynman).  With ``C = 0`` it is ``2/omega_max``;
for one contact it is the closed form ``2/(omega (zeta + sqrt(zeta^2 + 1)))``.

``leapfrog-centred`` (damping on the mean of the half-step velocities):
``P(lambda) = (lambda - 1)^2 M + (h/2)(lambda^2 - 1) C + h^2 lambda K`` and the same argument gives the
condition ``4M - h^2 K > 0``: ``2/omega_max`` whatever the dashpots.

Every other scheme is solved by ``spectral_radius`` (the largest ``|lambda|`` of its amplification
operator, ARPACK, built from the scheme's own update rule ``dtcrit.integrators.schemes``) and bisection.

``dt_lower`` is a rigorous lower bound: ``lambda_max(2h C~ + h^2 K~) <= 2h beta + h^2 alpha`` with
``alpha``, ``beta`` upper bounds of ``lambda_max(K~)``, ``lambda_max(C~)`` (block-diagonal and Gershgorin
bounds of ``dtcrit.packing.bounds.estimates``, the smaller; both need positive semi-definite elements, so
``alpha`` is taken for the springs with the tensile pre-loads only: the compressive pre-load terms are
negative semi-definite and can only lower ``lambda_max(K~)``), so ``h = 4/(beta + sqrt(beta^2 + 4 alpha))``
is stable.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse.linalg as spla

from dtcrit.errors import InputError, NotConvergedError
from dtcrit.integrators.schemes import INTEGRATORS

from dtcrit.packing.operators.assembly import damping_matrix, mass_diagonal, scale_symmetric, stiffness_matrix
from dtcrit.packing.solvers.largest_mode import largest_mode
from dtcrit.packing.bounds.estimates import block_diagonal, gershgorin
from dtcrit.packing.model import Contacts, Packing
from dtcrit.packing.operators.matrix_free import CombinedOperator, damping_operator, stiffness_operator
from dtcrit.packing.solvers.spectral_step import CENTRED, STATIC_INSTABILITY, critical_by_spectral_radius, physical_growth


LAGGED = ("leapfrog", "symplectic-euler", "velocity-verlet")
UNCONDITIONALLY_UNSTABLE = ("forward-euler",)
"""Schemes with no stable step on an undamped oscillator: without dashpots they are refused (asked of
the spectral-radius bisection, it was an ill-posed search that ARPACK could not converge on)."""
NEWTON_RTOL = 1e-10


@dataclass(frozen=True)
class DampedStep:
    """Critical step of the packing with its contact dashpots (module docstring).

    Parameters
    ----------
    dt : float
        Critical step [s] of the integrator.
    dt_lower : float
        Rigorous lower bound [s], ``4/(beta + sqrt(beta^2 + 4 alpha))`` (0 on the spectral route).
    dt_undamped : float
        Undamped step ``2/omega_max`` [s].
    method : str
        Route taken (closed condition, Newton root, or spectral-radius bisection).
    vector : numpy.ndarray or None
        Governing mode in mass-scaled coordinates, the null vector of ``4M - 2hC - h^2 K`` at ``dt``
        (``None`` for the spectral route).
    solves : int
        Number of eigen-solves spent.
    """

    dt: float
    dt_lower: float
    dt_undamped: float
    method: str
    vector: np.ndarray | None
    solves: int


def use_operator(packing: Packing, route: str = "auto") -> bool:
    """Whether ``route`` means the matrix-free operators for this packing.

    Parameters
    ----------
    packing : Packing
        The packing (its DOF count decides ``"auto"``).
    route : str
        ``"auto"`` (``dtcrit.packing.report``'s measured ``OPERATOR_DOFS`` / ``NUMPY_OPERATOR_DOFS``
        threshold), ``"assembled"`` or ``"matrix-free"``.

    Returns
    -------
    bool
        True for matrix-free.

    Raises
    ------
    InputError
        For an unknown ``route``.
    """
    import dtcrit.packing.operators.matrix_free_kernels as operator_kernels
    from dtcrit.packing.report import NUMPY_OPERATOR_DOFS, OPERATOR_DOFS

    if route == "auto":
        return packing.dofs > (OPERATOR_DOFS if operator_kernels.available() else NUMPY_OPERATOR_DOFS)
    if route not in ("assembled", "matrix-free"):
        raise InputError("route", f"unknown route {route!r}; choose one of auto, assembled, matrix-free")
    return route == "matrix-free"


def scaled_matrices(packing: Packing, contacts: Contacts, route: str = "assembled"):
    """Mass-scaled stiffness and damping ``K~ = M^(-1/2) K M^(-1/2)``, ``C~ = M^(-1/2) C M^(-1/2)``.

    Parameters
    ----------
    packing : Packing
        Particles (masses and inertias give ``M``).
    contacts : Contacts
        Contact springs [N/m, N m/rad] and dashpots [N s/m, N m s/rad].
    route : str
        ``"assembled"`` (sparse matrices), ``"matrix-free"`` (``dtcrit.packing.operators.matrix_free``
        operators) or ``"auto"`` (see ``use_operator``).

    Returns
    -------
    tuple
        ``(K~, C~)`` [1/s^2, 1/s], sparse matrices or linear operators.
    """
    d = mass_diagonal(packing)
    if use_operator(packing, route):
        return (stiffness_operator(packing, contacts, mass_diag=d), damping_operator(packing, contacts, mass_diag=d))
    k = scale_symmetric(stiffness_matrix(packing, contacts), d, inplace=True)
    c = scale_symmetric(damping_matrix(packing, contacts), d, inplace=True, key="damping")
    return k, c


def _upper_bound(a, d_ones) -> float:
    block, rows = block_diagonal(a).omega2, gershgorin(a, d_ones).omega2
    assert block is not None and rows is not None  # both are built from omega^2 (Estimate.from_omega2)
    return min(block, rows)


def lagged_lower_bound(k, c) -> float:
    """Rigorous lower bound on the lagged central difference's critical step (module docstring).

    ``h = 4/(beta + sqrt(beta^2 + 4 alpha))`` with ``alpha``, ``beta`` the smaller of the
    block-diagonal and Gershgorin upper bounds of ``lambda_max(K~)`` and ``lambda_max(C~)``.

    Parameters
    ----------
    k : scipy.sparse matrix or LinearOperator
        ``K~`` [1/s^2]; must be positive semi-definite element by element (springs only, no
        compressive pre-load term).
    c : scipy.sparse matrix or LinearOperator
        ``C~`` [1/s].

    Returns
    -------
    float
        Stable step [s] (``inf`` without stiffness).
    """
    ones = np.ones(k.shape[0])
    alpha = _upper_bound(k, ones)
    zero = c.is_zero if hasattr(c, "is_zero") else c.nnz == 0
    beta = _upper_bound(c, ones) if not zero else 0.0
    if alpha <= 0:
        return math.inf
    return 4.0 / (beta + math.sqrt(beta * beta + 4.0 * alpha))


def _lagged_root(k, c, omega2: float, method: str):
    """Newton's method on ``g(h)`` from ``h = 2/omega_max`` (module docstring)."""
    h = 2.0 / math.sqrt(omega2)
    operator = isinstance(k, spla.LinearOperator)
    if not operator:
        k, c = k.tocsr(), c.tocsr()
    solves, v = 0, None
    for _ in range(60):
        a = CombinedOperator(c, 2.0 * h, k, h * h) if operator else (2.0 * h) * c + (h * h) * k
        try:
            top = largest_mode(a, method)
        except NotConvergedError as exc:  # Newton descends from above: h is still an upper bound
            raise NotConvergedError("dt_crit [s]", 0.0, h, exc.solver,
                                    f"{exc.reason}, Newton step {solves + 1}") from None
        solves += 1
        v = top.vector
        slope = float(v @ (2.0 * (c @ v) + 2.0 * h * (k @ v)))
        g = top.value - 4.0
        if slope <= 0:
            break
        step = g / slope
        h_new = h - step
        if abs(step) <= NEWTON_RTOL * h:
            h = h_new
            break
        h = h_new
    return h, v, solves


def damped_critical_dt(packing: Packing, contacts: Contacts, integrator: str = "velocity-verlet", *,
                       method: str = "auto", route: str = "auto") -> DampedStep:
    """Exact critical step of ``integrator`` on the packing with its contact dashpots.

    Lagged schemes: Newton root of ``lambda_max(2h C~ + h^2 K~) = 4``; ``leapfrog-centred`` and
    undamped lagged schemes: ``2/omega_max``; every other scheme: bisection on the spectral radius of
    its amplification operator (module docstring).

    Parameters
    ----------
    packing : Packing
        Particles.
    contacts : Contacts
        Contact springs, dashpots and optional normal pre-loads ``force_n`` [N].
    integrator : str
        Integrator name of ``dtcrit.integrators.schemes``.
    method : str
        Eigen-solver of ``largest_mode``.
    route : str
        ``"auto"``, ``"assembled"`` or ``"matrix-free"`` ``K~``, ``C~`` (see ``scaled_matrices``).

    Returns
    -------
    DampedStep
        Step, lower bound, undamped step, route, governing mode and solve count.

    Raises
    ------
    InputError
        Unknown integrator, no stiffness, forward Euler without dashpots, or a statically unstable
        pre-loaded packing on the spectral route.
    NotConvergedError
        When an eigen-solve stops early (with the bracket reached).
    """
    if integrator not in INTEGRATORS:
        raise InputError("integrator", f"unknown integrator {integrator!r}")
    k, c = scaled_matrices(packing, contacts, route)
    try:
        top = largest_mode(k, method)
    except NotConvergedError as exc:  # the lagged and centred steps are at most 2/omega_max (docstring)
        family = integrator in LAGGED or integrator in CENTRED
        upper = 2.0 / math.sqrt(exc.lower) if exc.lower > 0 and family else math.inf
        raise NotConvergedError("dt_crit [s]", 0.0, upper, exc.solver, f"{exc.reason}, undamped omega_max") from None
    if top.value <= 0:
        raise InputError("contacts", "the packing has no stiffness: no vibrating mode")
    dt_undamped = 2.0 / math.sqrt(top.value)

    def bound(c_part) -> float:
        # a compressive pre-load term is negative semi-definite: the springs with only the tensile
        # pre-loads (positive semi-definite elements) bound the packing from above
        if contacts.force_n is None or not np.any(contacts.force_n > 0):
            return lagged_lower_bound(k, c_part)
        tensile = replace(contacts, force_n=np.minimum(contacts.force_n, 0.0))
        return lagged_lower_bound(scaled_matrices(packing, tensile, route)[0], c_part)

    if integrator in CENTRED or (integrator in LAGGED and not contacts.damped):
        undamped_c = c.multiply(0.0) if not isinstance(c, spla.LinearOperator) else damping_operator(
            packing, replace(contacts, cn=None, cs=None, cr=None, ctw=None))
        return DampedStep(dt_undamped, min(bound(undamped_c), dt_undamped), dt_undamped,
                          "2/omega_max (4M - h^2 K > 0)", top.vector, 1)
    if integrator in LAGGED:
        try:
            h, v, solves = _lagged_root(k, c, top.value, method)
        except NotConvergedError as exc:
            raise NotConvergedError(exc.quantity, min(bound(c), exc.upper), exc.upper, exc.solver, exc.reason) from None
        return DampedStep(h, min(bound(c), h), dt_undamped, "root of lambda_max(2h C~ + h^2 K~) = 4", v, solves + 1)
    if integrator in UNCONDITIONALLY_UNSTABLE and not contacts.damped:
        raise InputError("integrator", f"{integrator!r} has no stable step on a packing without dashpots "
                                       "(|lambda|^2 = 1 + h^2 omega^2 > 1 for every mode and step)")
    if contacts.force_n is not None and np.any(contacts.force_n > 0):
        growth = physical_growth(k)
        if growth**2 > STATIC_INSTABILITY * top.value:
            raise InputError("stiffness", f"the compressive pre-loads make the packing statically unstable "
                                          f"(lambda_min(M^-1 K) = {-growth**2:.4g} 1/s^2 < 0): its motion grows "
                                          f"whatever the step, and the critical step of {integrator!r} is not defined there")
    h, solves = critical_by_spectral_radius(k, c, integrator, dt_undamped)
    return DampedStep(h, 0.0, dt_undamped, "bisection on the amplification operator's spectral radius",
                      None, solves + 1)


__all__ = ["CENTRED", "LAGGED", "DampedStep", "damped_critical_dt", "lagged_lower_bound", "scaled_matrices",
           "use_operator"]
