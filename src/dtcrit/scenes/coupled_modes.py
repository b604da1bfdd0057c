"""The exact critical step of a small coupled contact block ``e'' = -A (K e + C e')`` (run time).

Used for the shear-rolling block of a sphere contact whose rolling spring does not separate from the
shear spring (``R_1/I_1 != R_2/I_2``, or a sphere on a wall: :mod:`dtcrit.symbolic.rotational_modes`):
``A = [[a_ss, a_sr], [a_sr, a_rr]]`` positive definite, ``K = diag(k_s, k_r)``, ``C = diag(c_s, c_r)``.
With ``A = L L^T`` and ``e = L y`` the block is ``y'' = -K~ y - C~ y'`` with the symmetric
``K~ = L^T K L``, ``C~ = L^T C L`` (the same eigenvalues as ``A K`` and ``A C``).  Then:

* undamped, or ``c_s k_r = c_r k_s`` (``C = alpha K``, proportional): the block separates into its two
  modes ``omega_i^2`` (eigenvalues of ``K^1/2 A K^1/2``) with modal dashpots ``alpha omega_i^2``, each solved
  exactly by :func:`dtcrit.integrators.stability.mode_dt`;
* otherwise, for the lagged schemes (``leapfrog``, ``symplectic-euler``, ``velocity-verlet``): the root of
  ``lambda_max(2 h C~ + h^2 K~) = 4``, exact (the proof is in :mod:`dtcrit.packing.solvers.damped_step`); for
  ``leapfrog-centred``: ``2/sqrt(lambda_max(K~))``; for the other schemes: bisection on the spectral
  radius of the scheme's own amplification matrix (:mod:`dtcrit.integrators.schemes`) to ``BISECT_RTOL``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.integrators.schemes import INTEGRATORS, MatrixForce, lookup
from dtcrit.integrators.stability import mode_dt

LAGGED = ("leapfrog", "symplectic-euler", "velocity-verlet")
CENTRED = ("leapfrog-centred",)
BISECT_RTOL = 1e-12
GROWTH_SLACK = 1e-10
"""|lambda| <= 1 + GROWTH_SLACK counts as stable in the bisection (undamped modes sit on the circle)."""


@dataclass(frozen=True)
class BlockStep:
    """The critical step of a coupled block and how it was found.

    Parameters
    ----------
    dt : float
        The exact critical step [s].
    omega2 : float
        The block's largest ``omega^2`` (eigenvalue of ``K~``) [1/s^2].
    zeta_mode : float
        The damping ratio ``v^T C~ v/(2 omega)`` of its top undamped mode.
    route : str
        Which route of the module docstring gave ``dt``.
    """

    dt: float
    omega2: float  # the block's largest omega^2 (eigenvalue of K~) [1/s^2]
    zeta_mode: float  # the damping ratio v^T C~ v/(2 omega) of its top undamped mode
    route: str


def scaled_block(a_ss: float, a_sr: float, a_rr: float, a_det: float, k: tuple[float, float], c: tuple[float, float]):
    """The symmetric ``(K~, C~) = (L^T K L, L^T C L)`` of the block, ``A = L L^T`` (module docstring).

    Parameters
    ----------
    a_ss : float
        Shear-shear entry of the inverse-inertia matrix ``A`` [1/kg].
    a_sr : float
        Shear-rolling entry of ``A`` [1/(kg m)].
    a_rr : float
        Rolling-rolling entry of ``A`` [1/(kg m^2)].
    a_det : float
        ``a_ss a_rr - a_sr^2``, given without cancellation.
    k : tuple of float
        ``(k_s, k_r)``: shear [N/m] and rolling [N m/rad] springs.
    c : tuple of float
        ``(c_s, c_r)``: shear [N s/m] and rolling [N m s/rad] dashpots.

    Returns
    -------
    tuple of numpy.ndarray
        ``(K~, C~)``, each 2 x 2 and symmetric [1/s^2, 1/s].
    """
    l11 = math.sqrt(a_ss)
    L = np.array([[l11, 0.0], [a_sr / l11, math.sqrt(a_det / a_ss)]])
    K = L.T @ np.diag(k) @ L
    C = L.T @ np.diag(c) @ L
    return 0.5 * (K + K.T), 0.5 * (C + C.T)


def _symmetric(a_ss: float, a_sr: float, a_rr: float, k: tuple[float, float]) -> np.ndarray:
    """``K^1/2 A K^1/2``: the same eigenvalues as ``A K``, its largest to rounding of its norm."""
    off = math.sqrt(k[0]) * math.sqrt(k[1]) * a_sr
    return np.array([[k[0] * a_ss, off], [off, k[1] * a_rr]])


def _spectral_radius(integrator: str, K: np.ndarray, C: np.ndarray, h: float) -> float:
    scheme = lookup(integrator)  # a built-in or user-written scheme
    n, parts = K.shape[0], len(scheme.state)
    force = MatrixForce(K, C)
    cols = []
    for j in range(parts * n):
        s = np.zeros(parts * n)
        s[j] = 1.0
        out = scheme.step([s[p * n:(p + 1) * n] for p in range(parts)], h, force)
        cols.append(np.concatenate(out))
    return float(np.max(np.abs(np.linalg.eigvals(np.column_stack(cols)))))


def _bisect(integrator: str, K: np.ndarray, C: np.ndarray, h_hi: float) -> float:
    stable = lambda h: _spectral_radius(integrator, K, C, h) <= 1.0 + GROWTH_SLACK  # noqa: E731
    hi = h_hi
    for _ in range(200):
        if not stable(hi):
            break
        hi *= 2.0
    else:
        return math.inf
    lo = hi * 1e-9
    if not stable(lo):
        return 0.0
    while hi - lo > BISECT_RTOL * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo


def block_step(integrator: str, a_ss: float, a_sr: float, a_rr: float, a_det: float, k: tuple[float, float],
               c: tuple[float, float]) -> BlockStep:
    """The exact critical step of the coupled block ``e'' = -A (K e + C e')`` (module docstring).

    Parameters
    ----------
    integrator : str
        Integrator name (built-in or user-written scheme).
    a_ss : float
        Shear-shear entry of the inverse-inertia matrix ``A`` [1/kg].
    a_sr : float
        Shear-rolling entry of ``A`` [1/(kg m)].
    a_rr : float
        Rolling-rolling entry of ``A`` [1/(kg m^2)].
    a_det : float
        ``a_ss a_rr - a_sr^2``, given without cancellation.
    k : tuple of float
        ``(k_s, k_r)``: shear [N/m] and rolling [N m/rad] springs.
    c : tuple of float
        ``(c_s, c_r)``: shear [N s/m] and rolling [N m s/rad] dashpots.

    Returns
    -------
    BlockStep
        Step [s], largest ``omega^2`` [1/s^2], top mode's damping ratio and the route.
    """
    K, C = scaled_block(a_ss, a_sr, a_rr, a_det, k, c)
    proportional = c[0] * k[1] == c[1] * k[0] and (k[0] > 0 or c[0] == 0) and (k[1] > 0 or c[1] == 0)
    if proportional:  # C = alpha K (undamped: alpha = 0): modes of K^1/2 A K^1/2, modal dashpots alpha omega^2
        alpha = c[0] / k[0] if k[0] > 0 else (c[1] / k[1] if k[1] > 0 else 0.0)
        w = np.linalg.eigvalsh(_symmetric(a_ss, a_sr, a_rr, k))
        dts = [mode_dt(integrator, max(float(x), 0.0), alpha * max(float(x), 0.0), 1.0).dt for x in w]
        omega2 = float(w[-1])
        zeta = alpha * math.sqrt(omega2) / 2.0
        return BlockStep(min(dts), omega2, zeta, "modes separate (C proportional to K): exact per mode")
    w, v = np.linalg.eigh(K)
    omega2 = float(w[-1])
    top = v[:, -1]
    zeta = float(top @ C @ top) / (2.0 * math.sqrt(omega2)) if omega2 > 0 else math.inf
    if integrator in CENTRED:
        return BlockStep(2.0 / math.sqrt(omega2) if omega2 > 0 else math.inf, omega2, zeta,
                         "centred damping: 2/sqrt(lambda_max(K~))")
    lam_c = float(np.linalg.eigvalsh(C)[-1])
    if integrator in LAGGED:
        g = lambda h: float(np.linalg.eigvalsh(2.0 * h * C + h * h * K)[-1]) - 4.0  # noqa: E731
        hi = 2.0 / math.sqrt(omega2) if omega2 > 0 else 2.0 / lam_c
        while g(hi) < 0:
            hi *= 2.0
        from scipy.optimize import brentq  # SciPy only when a damped coupled mode needs the root (start-up)

        dt = brentq(g, 0.0, hi, xtol=1e-300, rtol=4.0 * np.finfo(float).eps, maxiter=200)
        return BlockStep(dt, omega2, zeta, "root of lambda_max(2 h C~ + h^2 K~) = 4 (exact for the lagged schemes)")
    h0 = 2.0 / math.sqrt(omega2) if omega2 > 0 else 2.0 / lam_c
    dt = _bisect(integrator, K, C, h0)
    if integrator not in INTEGRATORS:  # a user-written scheme: confirmed by stepping its rules on the block
        from dtcrit.integrators.user_confirm import confirm_step

        confirm_step(integrator, dt, K, C)
    return BlockStep(dt, omega2, zeta, f"bisection on the amplification matrix's spectral radius (rtol {BISECT_RTOL:g})")
