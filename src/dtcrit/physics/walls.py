"""A sphere on a fixed wall as each engine codes it: effective radius, material constants and arms.

The wall is rigid and immobile (infinite mass): the effective mass of the contact is the particle's
own ``m``.  The springs themselves are those of the engine's pair law (``dtcrit.physics.contact_laws``:
a Hertz wall is linearised at its overlap by the tangent stiffness, as Hertz pairs are); what a wall
changes is collected here.

**LAMMPS** ``fix wall/gran`` (``src/GRANULAR/fix_wall_gran.cpp``, LAMMPS 29 Sep 2021):

* ``meff = rmass[i]`` (the rigid body's mass for a particle of ``fix rigid``);
* the slip velocity ``v_t - (d x omega) R / r`` and the torque ``-R (n x f_s)`` use the full radius
  ``R`` (``hooke``, ``hooke_history``, ``hertz_history`` and ``granular``): the arm is ``R``;
* the Hertz factor ``polyhertz = sqrt(delta R_eff)`` with ``R_eff = R`` on a plane (``rwall = 0``)
  and ``R_eff = R rwall/(rwall + R)`` on ``zcylinder``, where LAMMPS sets ``rwall = -2 r_c`` for a
  sphere inside the cylinder and ``+2 r_c`` outside (:func:`lammps_wall_effective_radius`);
* ``granular`` with a material normal model stores ``4/3 E/(2 (1 - nu))`` as its Hertz coefficient
  (:func:`lammps_wall_material_coefficient`; ``pair granular`` mixes ``E/(2 (1 - nu^2))``) and, for
  ``mindlin`` with ``kt NULL``, ``E/4 (2 - nu)(1 + nu)`` before the factor ``a = sqrt(R_eff delta)``
  (:func:`lammps_wall_mindlin_coefficient`).

**YADE** (``pkg/dem/Ig2_Facet_Sphere_ScGeom.cpp``, YADE 2023.02): ``Ig2_Wall_Sphere_ScGeom`` puts the
contact point on the wall plane (the sphere's centre projected on it: force arm ``R - delta``) with
``refR1 = R`` (``1e8 R`` when ``Hertzian``), ``refR2 = R`` and passes its ``noRatch`` to
``ScGeom::precompute``: with it the slip velocity is ``alpha`` times that of the point at ``R/alpha``,
``alpha = (refR1 + refR2)/(refR1 + refR2 - delta)`` (``ScGeom::getIncidentVel``).
``Ig2_Facet_Sphere_ScGeom`` puts the point at ``R - delta/2`` and never uses the ratcheting
correction.  :func:`yade_wall_arm` gives the symmetric equivalent of the two sides, as for YADE's
sphere pairs (``dtcrit.packing.readers.yade_clumps``).
"""
from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["lammps_wall_effective_radius", "lammps_zcylinder_rwall", "lammps_wall_material_coefficient",
           "lammps_wall_mindlin_coefficient", "yade_wall_arm", "hertz_wall_stiffness"]


def lammps_zcylinder_rwall(inside: Any, cylinder_radius: float) -> Any:
    """The wall "radius" LAMMPS gives a ``zcylinder`` contact: ``-2 r_c`` inside, ``+2 r_c`` outside.

    Parameters
    ----------
    inside : bool or numpy.ndarray
        Whether the sphere's centre lies inside the cylinder.
    cylinder_radius : float
        ``r_c`` [m] of ``fix wall/gran ... zcylinder r_c``.

    Returns
    -------
    float or numpy.ndarray
        ``rwall`` [m] (``fix_wall_gran.cpp``, ``post_force``).
    """
    return np.where(inside, -2.0 * cylinder_radius, 2.0 * cylinder_radius)


def lammps_wall_effective_radius(radius: Any, rwall: Any = 0.0) -> Any:
    """``R_eff`` of a LAMMPS wall contact: ``R`` on a plane, ``R rwall/(rwall + R)`` on a curved wall.

    Parameters
    ----------
    radius : float or numpy.ndarray
        The sphere's radius ``R`` [m].
    rwall : float or numpy.ndarray
        LAMMPS's ``rwall`` [m]: 0 for a plane, :func:`lammps_zcylinder_rwall` for ``zcylinder``.

    Returns
    -------
    float or numpy.ndarray
        ``R_eff`` [m] (``polyhertz = sqrt(delta R_eff)`` in ``hertz_history``, ``Reff`` in ``granular``).

    Examples
    --------
    >>> float(lammps_wall_effective_radius(1.0)), float(lammps_wall_effective_radius(1.0, -4.0))
    (1.0, 1.3333333333333333)
    """
    radius = np.asarray(radius, dtype=float)
    rwall = np.broadcast_to(np.asarray(rwall, dtype=float), radius.shape)
    flat = rwall == 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        curved = radius * rwall / (rwall + radius)
    return np.where(flat, radius, curved)


def lammps_wall_material_coefficient(youngs: float, poisson: float) -> float:
    """The Hertz coefficient ``fix wall/gran granular hertz/material`` stores: ``4/3 E/(2 (1 - nu))``.

    The force is this times ``a delta``, ``a = sqrt(R_eff delta)``; its tangent stiffness ``3/2`` of it
    times ``a`` (``fix_wall_gran.cpp``, constructor: ``normal_coeffs[0] = Emod/(2*(1-poiss))*FOURTHIRDS``).

    Parameters
    ----------
    youngs : float
        ``E`` [Pa].
    poisson : float
        ``nu``.

    Returns
    -------
    float
        The coefficient [Pa].
    """
    return 4.0 / 3.0 * youngs / (2.0 * (1.0 - poisson))


def lammps_wall_mindlin_coefficient(youngs: float, poisson: float) -> float:
    """The tangential coefficient of ``fix wall/gran granular ... tangential mindlin NULL``:
    ``E/4 (2 - nu)(1 + nu)``, multiplied by ``a = sqrt(R_eff delta)`` at each step.

    Parameters
    ----------
    youngs : float
        ``E`` [Pa].
    poisson : float
        ``nu``.

    Returns
    -------
    float
        The coefficient [Pa] (``fix_wall_gran.cpp``: ``tangential_coeffs[0] = Emod/4*(2-poiss)*(1+poiss)``).
    """
    return youngs / 4.0 * (2.0 - poisson) * (1.0 + poisson)


def yade_wall_arm(radius: Any, delta: Any, ref1: Any, ref2: Any, force_side: Any, ratchet: Any) -> tuple[Any, Any]:
    """The symmetric arm and shear factor of a YADE sphere-wall or sphere-facet contact.

    YADE applies the force at ``force_side`` from the sphere's centre and, with the ratcheting
    correction, takes the slip velocity as ``alpha`` times that of the point at ``R/alpha``,
    ``alpha = (ref1 + ref2)/(ref1 + ref2 - delta)``; without it, at the contact point.  The
    linearised shear element ``alpha k_s B_force^T (1 - n n^T) B_velocity`` is replaced by its
    symmetric equivalent: arm ``sqrt(force_side x velocity_side)``, stiffness ``alpha k_s``.

    Parameters
    ----------
    radius : float or numpy.ndarray
        The sphere's radius ``R`` [m].
    delta : float or numpy.ndarray
        The penetration depth [m].
    ref1, ref2 : float or numpy.ndarray
        ``geom.refR1``, ``geom.refR2`` [m].
    force_side : float or numpy.ndarray
        Distance [m] from the sphere's centre to the contact point (``R - delta`` on a Wall,
        ``R - delta/2`` on a Facet).
    ratchet : bool or numpy.ndarray
        Whether the ratcheting correction is on (``Ig2_Wall_Sphere_ScGeom.noRatch``; never for facets).

    Returns
    -------
    tuple
        ``(arm [m], alpha)``.
    """
    ratchet = np.asarray(ratchet, dtype=bool)
    alpha = np.where(ratchet, (ref1 + ref2) / (ref1 + ref2 - delta), 1.0)
    velocity_side = np.where(ratchet, radius / alpha, force_side)
    return np.sqrt(force_side * velocity_side), alpha


def hertz_wall_stiffness(youngs: float, poisson: float, radius: Any, delta: Any,
                         wall_youngs: float | None = None, wall_poisson: float | None = None) -> tuple[Any, Any]:
    """Tangent Hertz-Mindlin stiffness of a sphere on a flat wall at overlap ``delta``.

    A plane has infinite radius, so ``R* = R`` and ``a = sqrt(R delta)``; ``k_n = 2 E* a``,
    ``k_s = 8 G* a`` (:func:`dtcrit.physics.contact_laws.hertz_normal_stiffness`,
    :func:`dtcrit.physics.contact_laws.mindlin_tangent_stiffness`) with ``E*``, ``G*`` of the
    sphere's and the wall's materials (default: the wall of the sphere's material).

    Parameters
    ----------
    youngs, poisson : float
        The sphere's ``E`` [Pa] and ``nu``.
    radius : float or numpy.ndarray
        The sphere's radius [m].
    delta : float or numpy.ndarray
        The overlap with the wall [m].
    wall_youngs, wall_poisson : float or None
        The wall's ``E`` [Pa] and ``nu`` (default: the sphere's).

    Returns
    -------
    tuple
        ``(k_n, k_s)`` [N/m].

    Examples
    --------
    >>> kn, ks = hertz_wall_stiffness(1e9, 0.25, 1e-3, 1e-6)
    >>> round(float(kn) / (2 * 1e9 / (2 * (1 - 0.25**2)) * (1e-9) ** 0.5), 12)
    1.0
    """
    from dtcrit.physics.contact_laws import (effective_shear_modulus, effective_youngs_modulus, hertz_normal_stiffness,
                                             mindlin_tangent_stiffness)

    e_w = youngs if wall_youngs is None else wall_youngs
    nu_w = poisson if wall_poisson is None else wall_poisson
    a = np.sqrt(np.asarray(radius, dtype=float) * np.maximum(np.asarray(delta, dtype=float), 0.0))
    e_star = effective_youngs_modulus(youngs, poisson, e_w, nu_w)
    g_star = effective_shear_modulus(youngs, poisson, e_w, nu_w)
    return hertz_normal_stiffness(e_star, a), mindlin_tangent_stiffness(g_star, a)
