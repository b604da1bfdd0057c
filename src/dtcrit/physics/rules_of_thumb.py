"""The time-step estimates DEM codes use, to set beside the verified critical step.

Each is one estimate from the codes' sources or documentation (YADE, woo, PFC, LIGGGHTS, EDEM,
MercuryDPM, MFiX, LAMMPS).  They are *comparisons*, not stability bounds.  Functions take floats or
NumPy arrays.  Notation: ``m* = m_1 m_2/(m_1 + m_2)``, ``R* = R_1 R_2/(R_1 + R_2)``,
``G = E/(2 (1 + nu))``.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from dtcrit.physics.contact_laws import shear_modulus

__all__ = [
    "rayleigh_time",
    "hertz_contact_time",
    "collision_time",
    "damped_collision_time",
    "diagonal_stiffness_step",
    "yade_gsts_step",
    "YADE_GSTS_CONSTANT",
    "YADE_GSTS_SAFETY",
    "RAYLEIGH_FRACTIONS",
    "COLLISION_TIME_DIVISOR",
    "HERTZ_TIME_CONSTANT",
    "HERTZ_FRACTIONS",
]

RAYLEIGH_FRACTIONS = (0.10, 0.20, 0.40)
"""Fractions of the Rayleigh time used by codes (EDEM: 20 % for coordination >= 4, up to 40 % below;
'normal range' 10-40 %)."""
COLLISION_TIME_DIVISOR = 50.0
"""MercuryDPM drivers, MFiX-DEM and the LAMMPS granular examples take dt = t_c / 50."""
HERTZ_TIME_CONSTANT = 2.87
"""Hertz contact duration t = 2.87 (m*^2 / (R* E*^2 v))^(1/5), as LIGGGHTS' ``check/timestep/gran``
prints it (the exact constant is 2.868...)."""
HERTZ_FRACTIONS = (0.10, 0.20)
"""Fractions of the Hertz contact duration codes step with: LIGGGHTS' ``fix check/timestep/gran N f_R f_H``
warns when dt exceeds the fraction ``f_H`` of it given in the input script, 0.1 or 0.2 in its examples."""
YADE_GSTS_CONSTANT = 1.41044
"""YADE GlobalStiffnessTimeStepper's factor in front of sqrt(min(m/K_ii, I/K_rot_ii)) (GlobalStiffnessTimeStepper.cpp);
its comment calls it sqrt(2), but 1.41044 / sqrt(2) = 0.99733: the step it sets is 0.27 % below sqrt(2) x ..."""
YADE_GSTS_SAFETY = 0.8
"""Its default ``timestepSafetyCoefficient`` (GlobalStiffnessTimeStepper.hpp)."""


def rayleigh_time(radius: Any, density: Any, youngs_modulus: Any, poisson_ratio: Any) -> Any:
    """Rayleigh-wave time ``T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766)``, ``G = E/(2 (1 + nu))``.

    Li et al. (2005), as EDEM and LIGGGHTS use it.  The linear fit in ``nu`` of the Rayleigh-wave
    speed ratio ``c_R/c_S`` is within about 0.3 % of the exact root for ``0 <= nu < 0.5``.

    Parameters
    ----------
    radius : float or numpy.ndarray
        Particle radius [m].
    density : float or numpy.ndarray
        Particle density [kg/m^3].
    youngs_modulus : float or numpy.ndarray
        Young's modulus [Pa].
    poisson_ratio : float or numpy.ndarray
        Poisson's ratio.

    Returns
    -------
    float or numpy.ndarray
        ``T_R`` [s].
    """
    shear = shear_modulus(youngs_modulus, poisson_ratio)
    out = np.pi * radius * np.sqrt(density / shear) / (0.1631 * poisson_ratio + 0.8766)
    return float(out) if np.ndim(out) == 0 else out


def hertz_contact_time(m_star: float, r_star: float, e_star: float, velocity: float) -> float:
    """Hertz contact duration ``t = 2.87 (m*^2/(R* E*^2 v))^(1/5)`` (LIGGGHTS, EDEM).

    Parameters
    ----------
    m_star : float
        Effective mass [kg].
    r_star : float
        Effective radius [m].
    e_star : float
        Effective modulus [Pa].
    velocity : float
        Impact speed [m/s].

    Returns
    -------
    float
        The duration [s], evaluated in logarithms (no overflow).
    """
    log_t = 0.2 * (2.0 * math.log(m_star) - math.log(r_star) - 2.0 * math.log(e_star) - math.log(velocity))
    return HERTZ_TIME_CONSTANT * math.exp(log_t)


def collision_time(m_star: Any, k: Any) -> Any:
    """Undamped collision time of a linear spring, ``t_c = pi sqrt(m*/k)`` (LAMMPS granular docs).

    Parameters
    ----------
    m_star : float or numpy.ndarray
        Effective mass [kg].
    k : float or numpy.ndarray
        Spring [N/m] (zero gives infinity).

    Returns
    -------
    float or numpy.ndarray
        ``t_c`` [s].
    """
    with np.errstate(divide="ignore"):
        return np.pi * np.sqrt(m_star / k)


def damped_collision_time(k: float, c: float, m_star: float) -> float | None:
    """Collision time of a linear spring-dashpot, ``t_c = pi/sqrt(k/m* - (c/(2 m*))^2)`` (MercuryDPM).

    Written as ``pi/(omega_0 sqrt((1 - zeta)(1 + zeta)))`` with ``zeta = c/(2 sqrt(k m*))`` to avoid
    cancellation.

    Parameters
    ----------
    k : float
        Normal spring [N/m].
    c : float
        Normal dashpot on the relative velocity [N s/m].
    m_star : float
        Effective mass [kg].

    Returns
    -------
    float or None
        ``t_c`` [s]; None when not underdamped (``zeta >= 1``).
    """
    omega0 = math.sqrt(k) / math.sqrt(m_star)
    zeta = c / (2.0 * math.sqrt(k) * math.sqrt(m_star))
    if zeta >= 1.0:
        return None
    return math.pi / (omega0 * math.sqrt((1.0 - zeta) * (1.0 + zeta)))


def diagonal_stiffness_step(mass: float, inertia: float, k_translation: float, k_rotation: float) -> float:
    """Per-body diagonal-stiffness estimate ``sqrt(2) sqrt(min(m/K_ii, I/K_rot_ii))``.

    YADE's GlobalStiffnessTimeStepper (before its factor 1.41044/sqrt(2) and safety 0.8), woo's
    DynDt and PFC sum the stiffnesses of a body's contacts into diagonal terms.

    Parameters
    ----------
    mass : float
        Body mass [kg].
    inertia : float
        Its smallest principal moment [kg m^2].
    k_translation : float
        Summed translational stiffness ``K_ii`` [N/m].
    k_rotation : float
        Summed rotational stiffness ``K_rot_ii`` [N m/rad] (zero: no rotational term).

    Returns
    -------
    float
        The step [s].
    """
    rotation = inertia / k_rotation if k_rotation > 0 else math.inf
    return math.sqrt(2.0) * math.sqrt(min(mass / k_translation, rotation))


def yade_gsts_step(diagonal_step: float, safety: float = 1.0) -> float:
    """YADE GlobalStiffnessTimeStepper's step from the ``sqrt(2)`` diagonal estimate.

    ``1.41044 sqrt(min(M/K)) x safety`` = ``diagonal_step x 1.41044/sqrt(2) x safety``
    (``GlobalStiffnessTimeStepper.cpp``; default ``timestepSafetyCoefficient`` 0.8).  It is the step YADE
    sets only where ``diagonal_step`` sums the stiffnesses as YADE does; the step it sets on any
    scene, clumps included, is ``dtcrit.packing.bounds.yade_stepper.yade_stepper``.

    Parameters
    ----------
    diagonal_step : float
        ``sqrt(2) sqrt(min(M/K))`` [s] (:func:`diagonal_stiffness_step`).
    safety : float
        ``timestepSafetyCoefficient``; 1 for the unscaled step.

    Returns
    -------
    float
        The step YADE sets [s].
    """
    return YADE_GSTS_CONSTANT * safety / math.sqrt(2.0) * diagonal_step
