"""A Hertz-Mindlin ``[[wall]]`` (``model = "hertz"``): its tangent springs with one particle.

A plane has infinite radius and the wall infinite mass, so ``R* = R`` and ``m* = m`` of the sphere;
``E*``, ``G*`` combine the particle's material with the wall's (default: the same material).  The
contact is linearised at the overlap given (``overlap``), or at the largest overlap of an impact at
``velocity`` (default: ``[contact] velocity``), by the tangent stiffness
(:func:`dtcrit.physics.walls.hertz_wall_stiffness`), as Hertz pairs are (:mod:`dtcrit.scenes.laws`).
"""
from __future__ import annotations

import math

from dtcrit.errors import InputError
from dtcrit.physics import contact_laws as cl
from dtcrit.physics.walls import hertz_wall_stiffness

__all__ = ["hertz_wall_springs"]


def _material(wall, particle) -> tuple[float, float, float, float]:
    key = f"wall[{wall.number}]."
    e, nu = particle.youngs_modulus, particle.poisson_ratio
    if e is None or nu is None:
        raise InputError(key + "model", f"a Hertz wall needs particle {particle.number}'s youngs_modulus and "
                                        "poisson_ratio (in [[particle]] or [contact])")
    e_w = wall.youngs_modulus if wall.youngs_modulus is not None else e
    nu_w = wall.poisson_ratio if wall.poisson_ratio is not None else nu
    return e, nu, e_w, nu_w


def hertz_wall_springs(scene, wall, particle, radius: float | None, mass: float) -> tuple[float, float]:
    """``(k_n, k_s)`` [N/m] of a Hertz wall with one particle (module docstring).

    Parameters
    ----------
    scene : Scene
        The parsed scene (its ``[contact] velocity`` is the default impact speed).
    wall : Wall
        The Hertz wall.
    particle : ParticleType
        The particle type touching it (its material).
    radius : float or None
        The sphere's radius [m]; None for another shape (refused: a Hertz wall needs a sphere).
    mass : float
        The particle's mass [kg].

    Returns
    -------
    tuple of float
        The tangent normal and tangential stiffness.

    Raises
    ------
    InputError
        No material, no overlap or speed, a non-sphere, or a stiffness outside double precision.
    """
    key = f"wall[{wall.number}]."
    if radius is None:
        raise InputError(key + "model", f"a Hertz wall needs spheres (particle {particle.number} is not one)")
    e, nu, e_w, nu_w = _material(wall, particle)
    delta = wall.overlap
    if delta is None:
        velocity = wall.velocity if wall.velocity is not None else getattr(scene.contact, "velocity", None)
        if velocity is None:
            raise InputError(key + "overlap", "a Hertz wall is linearised at its overlap: give overlap [m] or velocity [m/s]")
        delta = cl.hertz_max_overlap(mass, cl.effective_youngs_modulus(e, nu, e_w, nu_w), radius, velocity)
    if not delta < radius:
        raise InputError(key + "overlap", f"the overlap {delta:g} m reaches the sphere's radius {radius:g} m")
    kn, ks = (float(k) for k in hertz_wall_stiffness(e, nu, radius, delta, e_w, nu_w))
    if not (math.isfinite(kn) and kn > 0 and math.isfinite(ks) and ks > 0):
        raise InputError(key + "youngs_modulus", f"the Hertz tangent stiffness ({kn!r}, {ks!r}) is outside double precision")
    return kn, ks
