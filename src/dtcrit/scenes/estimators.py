"""The time-step estimates DEM codes use, to print side by side with the verified critical step.

Each function implements one estimate from the project's reference notes on how DEM codes choose
their step (``dem-codes-time-step.md``: YADE, woo, PFC, LIGGGHTS, EDEM, MercuryDPM, MFiX, Kratos).  They are *comparisons*, not stability bounds: ``dtcrit step`` flags each one
that exceeds the verified critical step of the scene as unsafe.

Notation: m* = m1 m2/(m1 + m2), R* = R1 R2/(R1 + R2), E* = [(1 - nu1^2)/E1 + (1 - nu2^2)/E2]^-1,
G = E / (2 (1 + nu)).  No SymPy here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "Estimate",
    "rayleigh_time",
    "hertz_contact_time",
    "damped_collision_time",
    "diagonal_stiffness_step",
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
"""MercuryDPM drivers and MFiX-DEM take dt = t_c / 50."""
HERTZ_TIME_CONSTANT = 2.87
"""Hertz contact duration t = 2.87 (m*^2 / (R* E*^2 v))^(1/5), as LIGGGHTS' ``check/timestep/gran``
prints it (the exact constant is 2.868..., see tests/test_step_estimators.py)."""
HERTZ_FRACTIONS = (0.10, 0.20)
"""Fractions of the Hertz contact duration codes step with: LIGGGHTS' ``fix check/timestep/gran N f_R f_H``
warns when dt exceeds the fraction ``f_H`` of it given in the input script, 0.1 or 0.2 in its examples."""


@dataclass(frozen=True)
class Estimate:
    """One labelled estimate: ``dt`` in seconds, or ``None`` with ``note`` saying why it does not apply."""

    key: str
    label: str
    dt: float | None
    note: str = ""


def rayleigh_time(radius: float, density: float, youngs_modulus: float, poisson_ratio: float) -> float:
    """Rayleigh-wave time T_R = pi R sqrt(rho / G) / (0.1631 nu + 0.8766) [s], G = E / (2 (1 + nu)).

    The linear fit in nu of the Rayleigh-wave speed ratio c_R / c_S is within about 0.3 % of the
    exact root for 0 <= nu < 0.5 (checked against the Rayleigh equation in the tests).
    """
    shear = youngs_modulus / (2.0 * (1.0 + poisson_ratio))
    return math.pi * radius * math.sqrt(density / shear) / (0.1631 * poisson_ratio + 0.8766)


def hertz_contact_time(m_star: float, r_star: float, e_star: float, velocity: float) -> float:
    """Hertz contact duration t = 2.87 (m*^2 / (R* E*^2 v))^(1/5) [s] (LIGGGHTS, EDEM)."""
    log_t = 0.2 * (2.0 * math.log(m_star) - math.log(r_star) - 2.0 * math.log(e_star) - math.log(velocity))
    return HERTZ_TIME_CONSTANT * math.exp(log_t)


def damped_collision_time(k: float, c: float, m_star: float) -> float | None:
    """Collision time of a linear spring-dashpot, t_c = pi / sqrt(k/m* - (c/(2 m*))^2) [s] (MercuryDPM).

    ``m*`` is the reduced mass m1 m2/(m1 + m2) (the convention of MercuryDPM with c the dashpot on
    the relative velocity).  Written as pi / (omega0 sqrt((1 - zeta)(1 + zeta))) with
    zeta = c / (2 sqrt(k m*)) to avoid cancellation; ``None`` when not underdamped (zeta >= 1).
    """
    omega0 = math.sqrt(k) / math.sqrt(m_star)
    zeta = c / (2.0 * math.sqrt(k) * math.sqrt(m_star))
    if zeta >= 1.0:
        return None
    return math.pi / (omega0 * math.sqrt((1.0 - zeta) * (1.0 + zeta)))


def diagonal_stiffness_step(mass: float, inertia: float, k_translation: float, k_rotation: float) -> float:
    """Per-body diagonal-stiffness estimate sqrt(2) sqrt(min(m / K_ii, I / K_rot_ii)) [s].

    YADE's GlobalStiffnessTimeStepper (before its safety factor 0.8), woo's DynDt and PFC sum the
    stiffnesses of a body's contacts into diagonal translational terms K_ii [N/m] and rotational
    terms K_rot_ii [N m/rad]; for one contact K_ii is the contact stiffness and K_rot_ii is the
    stiffness times the squared lever arm.  ``inertia`` is the body's smallest principal moment.
    """
    rotation = inertia / k_rotation if k_rotation > 0 else math.inf  # no tangential spring: no rotational stiffness
    return math.sqrt(2.0) * math.sqrt(min(mass / k_translation, rotation))


YADE_GSTS_CONSTANT = 1.41044
"""YADE GlobalStiffnessTimeStepper's factor in front of sqrt(min(m/K_ii, I/K_rot_ii)) (GlobalStiffnessTimeStepper.cpp);
its comment calls it sqrt(2), but 1.41044 / sqrt(2) = 0.99733: the step it sets is 0.27 % below sqrt(2) x ..."""
YADE_GSTS_SAFETY = 0.8
"""Its default ``timestepSafetyCoefficient`` (GlobalStiffnessTimeStepper.hpp)."""
