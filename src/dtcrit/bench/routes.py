"""Every route the toolkit has to the critical step, as a callable over arrays of (k, c, A).

A route maps ``(integrator, k, c, A)`` (float arrays of equal shape; ``k`` [N/m], ``c`` [N s/m],
``A`` [1/kg]) to the critical step ``dt`` [s] as a float64 array.  It may raise
``dtcrit.errors.InputError`` (a refusal) or return NaN/inf where it fails.

=============================  =========  =================================================
route                          family     what it computes
=============================  =========  =================================================
closed-form-numpy              dtcrit     generated closed form, vectorised
                                          (``dtcrit.integrators.stability.critical_dt_array``)
closed-form-fused              dtcrit     the same closed forms, fused and in place
                                          (``dtcrit.bench.fused``)
closed-form-c                  dtcrit     the careful step emitted as C (``dtcrit codegen``'s),
                                          compiled, via ctypes (``dtcrit.bench.c_kernel``)
closed-form-scalar             dtcrit     ``dtcrit.critical_dt`` scene by scene (validates
                                          its input and refuses what it cannot represent)
eigenvalues-closed+bisection   direct     generated closed-form eigenvalues
                                          (``dtcrit._generated.eigenvalues``) + bisection
paper-cardano+bisection        paper      the paper's Cardano eigenvalues, Eqs. (42)-(43),
                                          in complex float64 + bisection (paper-eq40 only)
eigvals+bisection              direct     batched ``numpy.linalg.eigvals`` of the matrix built
                                          from the update rule + bisection
mpmath-eig-15/30/50            mpmath     ``mpmath.eig`` at 15, 30, 50 digits + bisection
=============================  =========  =================================================

The direct routes need no closed form: they search ``tau = omega dt`` for the largest step with
spectral radius <= 1 (``dtcrit.bench.bisection``; NaN when even tau = 4 tests stable).  The float64 ones work in scaled units
(``dtcrit.integrators.stability.scaled_rates``: exact power-of-two scaling, so ``k A`` is never formed);
the mpmath ones take the exact float inputs and never overflow.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import mpmath as mp
import numpy as np

from dtcrit.bench.amplification import spectral_radius_eigvals, spectral_radius_mp
from dtcrit.bench.bisection import bisect_tau, bisect_tau_mp
from dtcrit.integrators.schemes import NAMES
from dtcrit.integrators.stability import critical_dt, critical_dt_array, scaled_rates

EPS = float(np.finfo(float).eps)
RHO_TOL_FLOAT = 4 * EPS  # "stable" is rho <= 1 + 4 eps in float64

# Tiers: which scenes a route is run and timed on (the slow routes on a sample of the batch).
FULL, EIG_SAMPLE, MP_SAMPLE = "full", "eig-sample", "mp-sample"


@dataclass(frozen=True)
class Route:
    """One way of computing the critical step that the bench times and checks.

    Parameters
    ----------
    name : str
        Name of the route.
    family : str
        ``"dtcrit"``, ``"paper"``, ``"direct"`` or ``"mpmath"``.
    summary : str
        What the route does, in words.
    evaluate : callable
        ``evaluate(integrator, k, c, A)`` returns the steps [s].
    tier : str
        Which sample size the route is timed on.
    integrators : tuple of str
        The schemes it applies to.
    held_to_4_ulp : bool
        dtcrit's own closed-form routes: within 4 ulp or refuse.
    """

    name: str
    family: str  # dtcrit | paper | direct | mpmath
    summary: str
    evaluate: Callable[[str, np.ndarray, np.ndarray, np.ndarray], np.ndarray]
    tier: str = FULL
    integrators: tuple[str, ...] = NAMES
    held_to_4_ulp: bool = False  # dtcrit's own closed-form routes: within 4 ulp or refuse

    def applies_to(self, integrator: str) -> bool:
        """Whether the route computes the step of ``integrator``.

        Parameters
        ----------
        integrator : str
            Name of the scheme.

        Returns
        -------
        bool
            True when it is one of ``integrators``.
        """
        return integrator in self.integrators


def _arrays(k, c, A):
    return tuple(np.atleast_1d(np.asarray(v, dtype=float)) for v in (k, c, A))


# --- closed forms ------------------------------------------------------------------------------

def closed_form_numpy(integrator, k, c, A):
    """Generated closed form, vectorised: ``dtcrit.integrators.stability.critical_dt_array``.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s].
    """
    return np.asarray(critical_dt_array(integrator, *_arrays(k, c, A)), dtype=float)


def closed_form_scalar(integrator, k, c, A):
    """``dtcrit.critical_dt`` one scene at a time (raises InputError on what it refuses).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s].
    """
    k, c, A = _arrays(k, c, A)
    return np.array([critical_dt(integrator, *x).dt for x in zip(k.tolist(), c.tolist(), A.tolist())])


def closed_form_fused(integrator, k, c, A):
    """The fused closed form (``dtcrit.bench.fused.critical_dt_fused``) over arrays.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s].
    """
    from dtcrit.bench.fused import critical_dt_fused

    return critical_dt_fused(integrator, *_arrays(k, c, A))


def closed_form_c(integrator, k, c, A):
    """The emitted careful C step over arrays; a step outside float64 (inf, or 0 for a stable
    contact) is refused as by the other dtcrit routes.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s].
    """
    from dtcrit.bench.c_kernel import critical_dt_c
    from dtcrit.integrators.stability import refuse_unrepresentable

    k, c, A = _arrays(k, c, A)
    return refuse_unrepresentable(integrator, critical_dt_c(integrator, k, c, A), k, c, A)


# --- direct float64 routes: eigenvalues + bisection ---------------------------------------------

def _scaled_search(integrator, k, c, A, radius, tol):
    """The step dt from the bisection on ``radius(integrator, tau, zeta)``, in scaled units.

    Elements whose damping ratio is not a finite float64 number are returned as NaN.
    """
    k, c, A = _arrays(k, c, A)
    with np.errstate(all="ignore"):
        w, g, s = scaled_rates(k, c, A)
        zeta = g / w
    out = np.full(k.shape, np.nan)
    ok = np.isfinite(zeta)
    if np.any(ok):
        z = zeta[ok]

        def stable(tau):
            with np.errstate(all="ignore"):
                return radius(integrator, tau, z) <= 1.0 + tol

        lo, _ = bisect_tau(stable, z.size)
        with np.errstate(all="ignore"):
            out[ok] = np.ldexp(lo / w[ok], -s[ok])
    return out


def _radius_eigvals(integrator, tau, zeta):
    return spectral_radius_eigvals(integrator, tau, zeta)


def eigvals_bisection(integrator, k, c, A):
    """Batched ``numpy.linalg.eigvals`` of the update-rule matrix + bisection on rho <= 1 + 4 eps.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s].
    """
    return _scaled_search(integrator, k, c, A, _radius_eigvals, RHO_TOL_FLOAT)


def _radius_closed_eigenvalues(integrator, tau, zeta):
    from dtcrit._generated import eigenvalues as ev

    return ev.spectral_radius(integrator, tau, zeta)


def closed_eigenvalues_bisection(integrator, k, c, A):
    """Generated closed-form eigenvalues (``dtcrit._generated.eigenvalues``) + bisection.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s].
    """
    return _scaled_search(integrator, k, c, A, _radius_closed_eigenvalues, RHO_TOL_FLOAT)


def _radius_cardano(integrator, tau, zeta):
    from dtcrit._generated import eigenvalues as ev

    lam = ev.eigenvalues_cardano_paper_eq40(tau, zeta)
    return np.max(np.abs(lam), axis=0)  # NaN where D = 0 propagates: counted unstable


def paper_cardano_bisection(integrator, k, c, A):
    """The paper's route: Eqs. (42)-(43) in complex float64, then the boundary search.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : array_like
        Stiffness [N/m].
    c : array_like
        Viscous coefficient [N s/m].
    A : array_like
        Inverse inertia of the mode [1/kg].

    Returns
    -------
    numpy.ndarray
        The critical steps [s].
    """
    if integrator != "paper-eq40":
        raise ValueError("the paper's Cardano eigenvalues (Eqs. 42-43) belong to the paper-eq40 scheme only")
    return _scaled_search(integrator, k, c, A, _radius_cardano, RHO_TOL_FLOAT)


# --- mpmath eigenvalues at fixed precision + bisection -------------------------------------------

def mp_eig_dt(integrator: str, k: float, c: float, A: float, dps: int) -> float:
    """Critical step by ``mpmath.eig`` at ``dps`` digits and bisection on rho <= 1 + tol.

    zeta and omega come from the exact float inputs at ``dps`` digits (no overflow: mpmath has
    an unbounded exponent).  The bisection (``bisect_tau_mp``) brackets tau* by its binary exponent
    first, so tau* below float64's range is found as well, then halves the bracket 64 times;
    dt = tau/omega is rounded once to float64.  tol = 4 * 10**-dps.  NaN when tau = 4 tests
    stable (no bracket).

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    k : float
        Stiffness [N/m].
    c : float
        Viscous coefficient [N s/m].
    A : float
        Inverse inertia of the mode [1/kg].
    dps : int
        Decimal digits.

    Returns
    -------
    float
        The critical step [s].
    """
    with mp.workdps(dps):
        kk, cc, AA = mp.mpf(k), mp.mpf(c), mp.mpf(A)
        w = mp.sqrt(kk * AA)
        zeta = cc * AA / (2 * w)
        tol = 4 * mp.mpf(10) ** (-dps)

        def stable(t) -> bool:
            return spectral_radius_mp(integrator, t, zeta) <= 1 + tol

        lo, _ = bisect_tau_mp(stable)
        return float(lo / w)


def _mp_route(dps: int):
    def evaluate(integrator, k, c, A):
        k, c, A = _arrays(k, c, A)
        return np.array([mp_eig_dt(integrator, *x, dps=dps) for x in zip(k.tolist(), c.tolist(), A.tolist())])

    evaluate.__doc__ = f"mpmath.eig at {dps} digits + bisection (one scene at a time)."
    return evaluate


ROUTES: tuple[Route, ...] = (
    Route("closed-form-numpy", "dtcrit", "generated closed form, NumPy vectorised (critical_dt_array)",
          closed_form_numpy, held_to_4_ulp=True),
    Route("closed-form-fused", "dtcrit", "the closed forms fused in place, chunked (dtcrit.bench.fused)",
          closed_form_fused, held_to_4_ulp=True),
    Route("closed-form-c", "dtcrit", "the closed forms emitted as C, compiled, called via ctypes",
          closed_form_c, held_to_4_ulp=True),
    Route("closed-form-scalar", "dtcrit", "dtcrit.critical_dt scene by scene (validates, refuses)",
          closed_form_scalar, tier=EIG_SAMPLE, held_to_4_ulp=True),
    Route("eigenvalues-closed+bisection", "direct", "generated closed-form eigenvalues + bisection",
          closed_eigenvalues_bisection, tier=EIG_SAMPLE),
    Route("paper-cardano+bisection", "paper", "the paper's Cardano roots, Eqs. (42)-(43), float64 + bisection",
          paper_cardano_bisection, tier=EIG_SAMPLE, integrators=("paper-eq40",)),
    Route("eigvals+bisection", "direct", "batched numpy.linalg.eigvals + bisection on the spectral radius",
          eigvals_bisection, tier=EIG_SAMPLE),
    Route("mpmath-eig-15", "mpmath", "mpmath.eig at 15 digits + bisection", _mp_route(15), tier=MP_SAMPLE),
    Route("mpmath-eig-30", "mpmath", "mpmath.eig at 30 digits + bisection", _mp_route(30), tier=MP_SAMPLE),
    Route("mpmath-eig-50", "mpmath", "mpmath.eig at 50 digits + bisection", _mp_route(50), tier=MP_SAMPLE),
)

ROUTES_BY_NAME = {r.name: r for r in ROUTES}


def floor_kernel(k, A, out=None):
    """The trivial memory-bound kernel over the same arrays, 2/sqrt(k A), in place (section 4).

    Parameters
    ----------
    k : numpy.ndarray
        Stiffness [N/m].
    A : numpy.ndarray
        Inverse inertia [1/kg].
    out : numpy.ndarray, optional
        Output buffer (a new array when omitted).

    Returns
    -------
    numpy.ndarray
        ``out``.
    """
    out = np.multiply(k, A, out=out)
    np.sqrt(out, out=out)
    np.divide(2.0, out, out=out)
    return out
