"""Contact laws of two spheres: effective quantities and the linear(ised) spring stiffnesses.

Every function takes floats or NumPy arrays (one entry per contact) and returns the same kind.
Notation: ``R* = R_1 R_2/(R_1 + R_2)``, ``m* = m_1 m_2/(m_1 + m_2)``,
``E* = [(1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2]^-1``, ``G = E/(2 (1 + nu))``,
``G* = [(2 - nu_1)/G_1 + (2 - nu_2)/G_2]^-1`` (Johnson, *Contact Mechanics*, 1985, Eqs. (4.22), (7.13)).
"""
from __future__ import annotations

import math
from typing import Any

__all__ = [
    "reduced",
    "shear_modulus",
    "effective_youngs_modulus",
    "effective_shear_modulus",
    "same_material_moduli",
    "hertz_normal_stiffness",
    "mindlin_tangent_stiffness",
    "hertz_max_overlap",
    "lammps_hertz_tangent_stiffness",
    "yade_normal_stiffness",
    "liggghts_hooke_stiffness",
]


def reduced(x: Any, y: Any) -> Any:
    """The series combination ``x y/(x + y)``: effective mass ``m*`` or effective radius ``R*``.

    Parameters
    ----------
    x, y : float or numpy.ndarray
        The two masses [kg] or radii [m] (positive).

    Returns
    -------
    float or numpy.ndarray
        ``x y/(x + y)``, in the units of ``x``.
    """
    return x * y / (x + y)


def shear_modulus(youngs: Any, poisson: Any) -> Any:
    """Shear modulus of an isotropic material, ``G = E/(2 (1 + nu))``.

    Parameters
    ----------
    youngs : float or numpy.ndarray
        Young's modulus ``E`` [Pa].
    poisson : float or numpy.ndarray
        Poisson's ratio ``nu``.

    Returns
    -------
    float or numpy.ndarray
        ``G`` [Pa].
    """
    return youngs / (2.0 * (1.0 + poisson))


def effective_youngs_modulus(e1: Any, nu1: Any, e2: Any, nu2: Any) -> Any:
    """Hertz's effective modulus of two materials, ``E* = [(1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2]^-1``.

    Parameters
    ----------
    e1, e2 : float or numpy.ndarray
        Young's moduli of the two bodies [Pa].
    nu1, nu2 : float or numpy.ndarray
        Their Poisson's ratios.

    Returns
    -------
    float or numpy.ndarray
        ``E*`` [Pa] (Johnson 1985, Eq. (4.22)).
    """
    return 1.0 / ((1.0 - nu1**2) / e1 + (1.0 - nu2**2) / e2)


def effective_shear_modulus(e1: Any, nu1: Any, e2: Any, nu2: Any) -> Any:
    """Mindlin's effective shear modulus of two materials, ``G* = [(2 - nu_1)/G_1 + (2 - nu_2)/G_2]^-1``.

    Parameters
    ----------
    e1, e2 : float or numpy.ndarray
        Young's moduli of the two bodies [Pa].
    nu1, nu2 : float or numpy.ndarray
        Their Poisson's ratios.

    Returns
    -------
    float or numpy.ndarray
        ``G*`` [Pa], with ``G = E/(2 (1 + nu))`` (Johnson 1985, Eq. (7.13)).
    """
    return 1.0 / ((2.0 - nu1) / shear_modulus(e1, nu1) + (2.0 - nu2) / shear_modulus(e2, nu2))


def same_material_moduli(youngs: Any, poisson: Any) -> tuple[Any, Any]:
    """``(E*, G*)`` of two bodies of one material: ``E/(2 (1 - nu^2))`` and ``G/(2 (2 - nu))``.

    Evaluated by the two-material formulas, so that a packing's contact and a scene's pair of one
    material give the same bits.

    Parameters
    ----------
    youngs : float or numpy.ndarray
        Young's modulus ``E`` [Pa].
    poisson : float or numpy.ndarray
        Poisson's ratio ``nu``.

    Returns
    -------
    tuple
        ``(E*, G*)`` [Pa].
    """
    return (effective_youngs_modulus(youngs, poisson, youngs, poisson),
            effective_shear_modulus(youngs, poisson, youngs, poisson))


def hertz_normal_stiffness(e_star: Any, contact_radius: Any) -> Any:
    """Hertz tangent normal stiffness ``k_n = dF/d(delta) = 2 E* a``, ``a = sqrt(R* delta)``.

    From ``F = 4/3 E* sqrt(R*) delta^(3/2)`` (Johnson 1985, Eq. (4.23)).

    Parameters
    ----------
    e_star : float or numpy.ndarray
        Effective modulus ``E*`` [Pa].
    contact_radius : float or numpy.ndarray
        Contact radius ``a = sqrt(R* delta)`` [m].

    Returns
    -------
    float or numpy.ndarray
        ``k_n`` [N/m].
    """
    return 2.0 * e_star * contact_radius


def mindlin_tangent_stiffness(g_star: Any, contact_radius: Any) -> Any:
    """Mindlin's no-slip tangential stiffness ``k_s = 8 G* a``, ``a = sqrt(R* delta)``.

    Parameters
    ----------
    g_star : float or numpy.ndarray
        Effective shear modulus ``G*`` [Pa].
    contact_radius : float or numpy.ndarray
        Contact radius ``a = sqrt(R* delta)`` [m].

    Returns
    -------
    float or numpy.ndarray
        ``k_s`` [N/m] (Mindlin 1949; EDEM Hertz-Mindlin, LAMMPS ``tangential mindlin NULL``).
    """
    return 8.0 * g_star * contact_radius


def lammps_hertz_tangent_stiffness(kn: Any, contact_radius: Any) -> Any:
    """Tangent normal stiffness of LAMMPS's Hertz force ``F = K_n a delta``: ``3/2 K_n a``.

    ``pair_style gran/hertz/history`` and ``pair_style granular ... hertz`` (LAMMPS docs
    ``pair_gran``, ``pair_granular``).

    Parameters
    ----------
    kn : float or numpy.ndarray
        LAMMPS's coefficient ``K_n`` [N/m^2].
    contact_radius : float or numpy.ndarray
        ``a = sqrt(R* delta)`` [m].

    Returns
    -------
    float or numpy.ndarray
        ``k_n`` [N/m].
    """
    return 1.5 * kn * contact_radius


def hertz_max_overlap(m_star: float, e_star: float, r_star: float, velocity: float) -> float:
    """Largest overlap of a Hertz impact at relative normal speed ``velocity``.

    Energy balance ``1/2 m* v^2 = (8/15) E* sqrt(R*) delta^(5/2)`` for ``F = (4/3) E* sqrt(R*) delta^(3/2)``:
    ``delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5)``, evaluated in logarithms (no overflow).

    Parameters
    ----------
    m_star : float
        Effective mass [kg].
    e_star : float
        Effective modulus [Pa].
    r_star : float
        Effective radius [m].
    velocity : float
        Relative normal speed at impact [m/s].

    Returns
    -------
    float
        ``delta_max`` [m].
    """
    log_d = 0.4 * (math.log(15.0 / 16.0) + math.log(m_star) + 2.0 * math.log(velocity) - math.log(e_star)
                   - 0.5 * math.log(r_star))
    return math.exp(log_d)


def yade_normal_stiffness(e1_r1: float, e2_r2: float) -> float:
    """YADE's linear normal stiffness ``k_n = 2 E_1 R_1 E_2 R_2/(E_1 R_1 + E_2 R_2)``.

    ``Ip2_FrictMat_FrictMat_FrictPhys`` (``2 E R_1 R_2/(R_1 + R_2)`` for one material), written
    ``2/(1/(E_1 R_1) + 1/(E_2 R_2))`` so that it does not overflow.

    Parameters
    ----------
    e1_r1, e2_r2 : float
        Young's modulus times radius of each body [N/m].

    Returns
    -------
    float
        ``k_n`` [N/m].
    """
    x, y = e1_r1, e2_r2
    return 2.0 * (x / (1.0 + x / y) if x <= y else y / (1.0 + y / x))


def liggghts_hooke_stiffness(y_star: Any, r_star: Any, m_star: Any, velocity: Any) -> Any:
    """LIGGGHTS ``model hooke`` spring: Hertz's secant stiffness at the overlap of an impact at ``velocity``.

    ``k_n = 16/15 sqrt(R*) Y* (15 m* v^2/(16 sqrt(R*) Y*))^(1/5)`` with ``v`` the
    ``characteristicVelocity`` (LIGGGHTS-PUBLIC ``src/normal_model_hooke.h``); the force is ``k_n delta``.

    Parameters
    ----------
    y_star : float or numpy.ndarray
        Effective modulus ``Y*`` [Pa] (``effective_youngs_modulus``).
    r_star : float or numpy.ndarray
        Effective radius ``R*`` [m].
    m_star : float or numpy.ndarray
        Effective mass ``m*`` [kg].
    velocity : float or numpy.ndarray
        The characteristic velocity [m/s].

    Returns
    -------
    float or numpy.ndarray
        ``k_n`` [N/m].
    """
    sqrt_r = r_star**0.5
    return 16.0 / 15.0 * sqrt_r * y_star * (15.0 * m_star * velocity * velocity / (16.0 * sqrt_r * y_star)) ** 0.2
