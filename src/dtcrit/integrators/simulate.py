"""Time-step the contact ODE with an integrator's own update rule: the direct check of a bound.

The linear contact system ``xddot = -K x - C v`` (Peng et al. 2020, Eq. (30)) is stepped in scaled
units (``omega = 1``, so ``K = 1``, ``C = 2 zeta`` and the step is ``tau = omega dt``); the scaling
keeps stiff and extreme inputs (k A up to float64's limits) representable.  The update rule is the
one in ``dtcrit.integrators.schemes`` -- the same description the symbolic layer differentiates -- but here
it is simply iterated, with no matrix, polynomial or closed form involved.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dtcrit.integrators.schemes import LinearForce, lookup


@dataclass(frozen=True)
class Trajectory:
    """Early and late amplitude of a batch of time-stepped runs.

    Parameters
    ----------
    log_early : numpy.ndarray
        Log of the largest state norm over the first quarter of the run.
    log_late : numpy.ndarray
        Log of the largest state norm over the last quarter of the run.
    n_steps : int
        Number of steps taken.
    """

    log_early: np.ndarray  # log of the max state norm over the first quarter of the run
    log_late: np.ndarray  # log of the max state norm over the last quarter of the run
    n_steps: int

    @property
    def growth(self) -> np.ndarray:
        """Late amplitude over early amplitude (inf when it exceeds float64's range)."""
        with np.errstate(over="ignore"):
            return np.exp(self.log_late - self.log_early)


def run(integrator: str, tau, zeta, n_steps: int, x0: float = 1.0, v0: float = 0.0) -> Trajectory:
    """Iterate the update rule ``n_steps`` times for arrays of (tau, zeta) at once (``x'' = -x - 2 zeta x'``).

    The initial acceleration of three-variable schemes is consistent with (x0, v0).  The state
    norm is the Euclidean norm of all state variables; it is renormalised every step block so
    that a growing run never overflows (the growth factors are accumulated in log form).

    Parameters
    ----------
    integrator : str
        The scheme key (``dtcrit.integrators.schemes``).
    tau : float or array_like
        Dimensionless step ``omega dt``.
    zeta : float or array_like
        Damping ratio ``c A / (2 omega)``; broadcast against ``tau``.
    n_steps : int
        Number of steps.
    x0 : float
        Initial position (scaled).
    v0 : float
        Initial velocity (scaled).

    Returns
    -------
    Trajectory
        The logs of the early and late amplitudes, shape ``broadcast(tau, zeta).shape``.
    """
    integ = lookup(integrator)
    tau = np.asarray(tau, dtype=float)
    zeta = np.asarray(zeta, dtype=float)
    tau, zeta = np.broadcast_arrays(tau, zeta)
    force = LinearForce(1.0, 2.0 * zeta)
    x = np.full(tau.shape, x0)
    v = np.full(tau.shape, v0)
    state: tuple = (x, v) if len(integ.state) == 2 else (x, v, force(x, v))
    quarter = max(1, n_steps // 4)
    log_scale = np.zeros(tau.shape)
    early = np.full(tau.shape, -np.inf)
    late = np.full(tau.shape, -np.inf)
    block = 64
    with np.errstate(all="ignore"):
        for i in range(n_steps):
            state = integ.step(state, tau, force)
            if i % block == block - 1 or i < quarter or i >= n_steps - quarter:
                norm = np.sqrt(sum(s * s for s in state))
                if i < quarter:
                    early = np.maximum(early, np.log(norm) + log_scale)
                if i >= n_steps - quarter:
                    late = np.maximum(late, np.log(norm) + log_scale)
                if i % block == block - 1:
                    scale = np.where(norm > 0, norm, 1.0)
                    state = tuple(s / scale for s in state)
                    log_scale = log_scale + np.log(scale)
    return Trajectory(early, late, n_steps)


def is_growing(integrator: str, tau, zeta, n_steps: int, factor: float = 100.0) -> np.ndarray:
    """True where the late amplitude of :func:`run` exceeds ``factor`` times the early amplitude.

    Parameters
    ----------
    integrator : str
        The scheme key (``dtcrit.integrators.schemes``).
    tau : float or array_like
        Dimensionless step ``omega dt``.
    zeta : float or array_like
        Damping ratio ``c A / (2 omega)``; broadcast against ``tau``.
    n_steps : int
        Number of steps.
    factor : float
        Growth (late over early amplitude) that counts as unstable.

    Returns
    -------
    numpy.ndarray of bool
        Per (tau, zeta): whether the run grows.
    """
    return run(integrator, tau, zeta, n_steps).growth > factor
