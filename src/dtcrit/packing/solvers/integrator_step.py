"""Damped / integrator-specific critical step of the highest mode, via ``dtcrit.integrators.stability``.

The packing's highest mode is treated as the 1-DOF system ``x'' = -omega^2 x - 2 zeta omega x'``
(``k = omega_max^2``, ``c = 2 zeta omega_max``, ``A = 1`` in ``dtcrit.integrators.stability.critical_dt``).  That
is exact when the damping matrix is diagonalised by the undamped modes (classical or Rayleigh
damping, e.g. contact dashpots proportional to the springs, ``C = beta K``, giving
``zeta = beta omega_max / 2`` in the top mode) and ``zeta`` is the top mode's damping ratio; with
non-proportional contact dashpots the modes couple and it is an approximation.
"""
from __future__ import annotations

import math
from types import ModuleType

from dtcrit.errors import InputError

# undamped critical step 2/omega when the stability engine is not importable
_CENTRAL_DIFFERENCE_FAMILY = ("paper-eq40", "symplectic-euler", "leapfrog", "leapfrog-centred",
                              "velocity-verlet", "velocity-verlet-predicted")
DEFAULT_INTEGRATOR = "velocity-verlet"


def integrator_dt(omega: float, integrator: str = DEFAULT_INTEGRATOR, damping_ratio: float = 0.0) -> tuple[float, str]:
    """Critical step of ``integrator`` for the highest mode treated as a damped 1-DOF oscillator.

    Solves ``x'' = -omega^2 x - 2 zeta omega x'`` with ``dtcrit.integrators.stability.critical_dt``
    (``k = omega^2``, ``c = 2 zeta omega``, mass 1; module docstring).  Without that module, the
    undamped central-difference family falls back to ``2/omega``.

    Parameters
    ----------
    omega : float
        Highest angular eigenfrequency ``omega_max`` [rad/s].
    integrator : str
        Integrator name of ``dtcrit.integrators.schemes`` (e.g. ``"velocity-verlet"``).
    damping_ratio : float
        Modal damping ratio ``zeta >= 0`` of the top mode (dimensionless).

    Returns
    -------
    dt : float
        Critical step [s] (``inf`` when ``omega <= 0``; 0 for undamped forward Euler).
    how : str
        The formula or reason reported by the stability engine.
    """
    if not math.isfinite(damping_ratio) or damping_ratio < 0:
        raise InputError("damping_ratio", f"must be a finite number >= 0, got {damping_ratio}")
    if omega <= 0:
        return math.inf, "no vibrating mode"
    stability: ModuleType | None
    try:
        from dtcrit.integrators import stability
    except ImportError:
        stability = None
    if stability is not None and hasattr(stability, "critical_dt"):
        result = stability.critical_dt(integrator, omega * omega, 2.0 * damping_ratio * omega, 1.0)
        return float(result.dt), str(getattr(result, "formula", "") or getattr(result, "reason", ""))
    if damping_ratio == 0 and integrator in _CENTRAL_DIFFERENCE_FAMILY:
        return 2.0 / omega, "2/omega (undamped; dtcrit.integrators.stability not available)"
    if damping_ratio == 0 and integrator == "forward-euler":
        return 0.0, "forward Euler is unstable for every step on an undamped oscillator"
    raise InputError("integrator", f"{integrator!r} with damping needs dtcrit.integrators.stability, which is not available")
