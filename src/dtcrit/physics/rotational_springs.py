"""Rolling and twisting springs and dashpots of a sphere contact, as the DEM codes define them.

Every function takes floats or NumPy arrays (one entry per contact).  ``R* = R_1 R_2/(R_1 + R_2)``;
stiffnesses in N m/rad, dashpots in N m s/rad.
"""
from __future__ import annotations

import math
from typing import Any

__all__ = [
    "sds_rolling",
    "marshall_twisting",
    "epsd_rolling_stiffness",
    "epsd_rolling_dashpot",
    "epsd2_rolling_stiffness",
    "yade_rotational_stiffness",
]


def sds_rolling(k_roll: Any, gamma_roll: Any, r_star: Any) -> tuple[Any, Any]:
    """LAMMPS ``pair_style granular`` ``rolling sds k_roll gamma_roll mu`` as ``(k_r, c_r)``.

    The pseudo-force ``k_roll xi`` on ``v_roll = -R* (w_i - w_j) x n`` with torque ``R* n x F``
    gives ``k_r = k_roll R*^2`` and ``c_r = gamma_roll R*^2`` (LAMMPS ``pair_granular`` docs,
    ``granular_model`` ``RollingSDS``).

    Parameters
    ----------
    k_roll : float or numpy.ndarray
        Rolling pseudo-spring [N/m].
    gamma_roll : float or numpy.ndarray
        Rolling pseudo-dashpot [N s/m].
    r_star : float or numpy.ndarray
        Effective radius ``R*`` [m].

    Returns
    -------
    tuple
        ``(k_r, c_r)`` [N m/rad, N m s/rad].
    """
    return k_roll * r_star**2, gamma_roll * r_star**2


def marshall_twisting(k_t: Any, c_t: Any, contact_radius: Any) -> tuple[Any, Any]:
    """LAMMPS ``twisting marshall``: ``k_tw = k_t a^2/2`` and ``c_tw = c_t a^2/2``.

    Marshall (2009): the twisting spring and dashpot from the tangential ones over the contact
    area of radius ``a`` (LAMMPS ``pair_granular`` docs).

    Parameters
    ----------
    k_t : float or numpy.ndarray
        Tangential spring [N/m].
    c_t : float or numpy.ndarray
        Tangential dashpot [N s/m].
    contact_radius : float or numpy.ndarray
        Contact radius ``a`` [m] (Hertz: ``sqrt(R* delta)``).

    Returns
    -------
    tuple
        ``(k_tw, c_tw)`` [N m/rad, N m s/rad].
    """
    return 0.5 * k_t * contact_radius**2, 0.5 * c_t * contact_radius**2


def epsd_rolling_stiffness(factor: Any, kn: Any, mu_r: Any, r_star: Any) -> Any:
    """LIGGGHTS EPSD rolling spring ``k_r = f k_n mu_r^2 R*^2``.

    ``f = 2.25`` for ``rolling_model epsd`` (``rolling_model_epsd.h``), ``coeffRollStiffness`` for
    ``epsd3`` (``rolling_model_epsd3.h``).

    Parameters
    ----------
    factor : float or numpy.ndarray
        The stiffness factor ``f``.
    kn : float or numpy.ndarray
        Normal spring [N/m].
    mu_r : float or numpy.ndarray
        Rolling friction coefficient (``coeffRollFrict``).
    r_star : float or numpy.ndarray
        Effective radius [m].

    Returns
    -------
    float or numpy.ndarray
        ``k_r`` [N m/rad].
    """
    return factor * kn * mu_r**2 * r_star * r_star


def epsd_rolling_dashpot(eta_r: float, k_r: float, m1: float, r1: float, m2: float, r2: float) -> float:
    """LIGGGHTS EPSD rolling dashpot ``c_r = eta_r 2 sqrt(I_r k_r)``, ``I_r = 1.4 m_1 R_1^2 m_2 R_2^2/(m_1 R_1^2 + m_2 R_2^2)``.

    Parameters
    ----------
    eta_r : float
        Rolling viscous damping coefficient (``coeffRollVisc``).
    k_r : float
        Rolling spring [N m/rad].
    m1, m2 : float
        Masses of the two spheres [kg].
    r1, r2 : float
        Their radii [m].

    Returns
    -------
    float
        ``c_r`` [N m s/rad] (``rolling_model_epsd.h``).
    """
    i1, i2 = m1 * r1 * r1, m2 * r2 * r2
    i_r = 1.4 * (i1 / (1.0 + i1 / i2) if i1 <= i2 else i2 / (1.0 + i2 / i1))
    return eta_r * 2.0 * math.sqrt(i_r * k_r)


def epsd2_rolling_stiffness(k_t: Any, r_star: Any) -> Any:
    """LIGGGHTS/Aspherix ``rolling_model epsd2``: ``k_r = k_t R*^2`` (``rolling_model_epsd2.h``).

    Parameters
    ----------
    k_t : float or numpy.ndarray
        Tangential spring [N/m].
    r_star : float or numpy.ndarray
        Effective radius [m].

    Returns
    -------
    float or numpy.ndarray
        ``k_r`` [N m/rad].
    """
    return k_t * r_star * r_star


def yade_rotational_stiffness(alpha: Any, k_s: Any, r1: Any, r2: Any) -> Any:
    """YADE ``Ip2_CohFrictMat_CohFrictMat_CohFrictPhys``: ``k = alpha k_s R_1 R_2`` (rolling or twisting).

    Parameters
    ----------
    alpha : float or numpy.ndarray
        ``alphaKr`` or ``alphaKtw`` (harmonic mean of the two materials').
    k_s : float or numpy.ndarray
        Shear spring [N/m].
    r1, r2 : float or numpy.ndarray
        Radii [m].

    Returns
    -------
    float or numpy.ndarray
        The rolling or twisting spring [N m/rad] (``CohesiveFrictionalContactLaw.cpp``).
    """
    return alpha * k_s * r1 * r2
