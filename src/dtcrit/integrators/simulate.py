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
    log_early: np.ndarray  # log of the max state norm over the first quarter of the run
    log_late: np.ndarray  # log of the max state norm over the last quarter of the run
    n_steps: int

    @property
    def growth(self) -> np.ndarray:
        """Late amplitude over early amplitude (inf when it exceeds float64's range)."""
        with np.errstate(over="ignore"):
            return np.exp(self.log_late - self.log_early)


def run(integrator: str, tau, zeta, n_steps: int, x0: float = 1.0, v0: float = 0.0) -> Trajectory:
    """Iterate the update rule ``n_steps`` times for arrays of (tau, zeta) at once.

    The initial acceleration of three-variable schemes is consistent with (x0, v0).  The state
    norm is the Euclidean norm of all state variables; it is renormalised every step block so
    that a growing run never overflows (the growth factors are accumulated in log form).
    """
    integ = lookup(integrator)
    tau = np.asarray(tau, dtype=float)
    zeta = np.asarray(zeta, dtype=float)
    tau, zeta = np.broadcast_arrays(tau, zeta)
    force = LinearForce(1.0, 2.0 * zeta)
    x = np.full(tau.shape, x0)
    v = np.full(tau.shape, v0)
    state = (x, v) if len(integ.state) == 2 else (x, v, force(x, v))
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
    """True where the late amplitude exceeds ``factor`` times the early amplitude."""
    return run(integrator, tau, zeta, n_steps).growth > factor
