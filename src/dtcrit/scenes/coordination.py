"""The largest number of contacts a particle of a scene can have, from the shapes and sizes alone.

``dtcrit step`` headlines the step proven for *any* packing of the scene's particles; the dense bounds of
:mod:`dtcrit.scenes.dense` need a coordination cap ``z``, and without ``coordination_max`` this module
supplies one that every packing obeys.  The packing assumption is the one of the sphere-packing bound
(``overlap_max`` = ``eps``, ``derivations/proofs/dense_packing_bound.md``, H4): the particles shrunk by
the factor ``1 - eps`` about their centres do not overlap (for spheres: ``d_jk >= (1 - eps)(R_j + R_k)``),
and a contact has ``d_ij <= (1 + tau)(r_i + r_j)`` with ``r`` the largest centre-to-surface distance.

* **Spheres** (Lemma 5 of the proof): two contact normals of sphere i are at least the law-of-cosines
  angle ``theta_i`` apart, so at most ``max_code_size(theta_i)`` neighbours fit (Fejes Toth's bound,
  sharpened by the solved Tammes problems: 12 for equal spheres without overlap, 13 with 5 % overlap).
  ``cos theta_i`` is bounded above over the neighbour sizes: exactly over every pair of sizes for up to
  ``EXACT_SPECIES`` radii, else over log-spaced bins of the radii by interval arithmetic (every term of
  ``(x^2 + y^2 - L^2)/(2 x y)`` taken at its worst end), which is never smaller.
* **Other shapes** (a volume count): the shrunken neighbours of particle i are disjoint, each of volume at
  least ``(1 - eps)^3 V_min``, and lie in the ball of radius ``(1 + tau)(r_i + r_max) + (1 - eps) r_max``
  about i's centre, outside i's own shrunken body: ``z_i <= (4/3 pi rho^3 - (1 - eps)^3 V_i)/((1 - eps)^3 V_min)``.
  A clump's volume is taken as its largest member sphere's (a lower bound).
* **Walls**: a convex particle touches a plane at most once, so each wall a type touches adds one.

NumPy only.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.numerics.distinct import distinct
from dtcrit.scenes.dense_cells import max_code_size, min_contact_angle_cos

CONTACT_TOLERANCE = 1e-9  # tau: how far beyond touching a contact may be (as in dense_spheres)
EXACT_SPECIES = 64
"""Up to this many distinct sphere radii the contact angle is bounded over every pair of neighbour sizes
(``EXACT_SPECIES^3`` evaluations); wider distributions are binned."""
BINS = 48
ROUND = 1e-12  # relative inflation of the interval bound on cos(theta): covers rounding


@dataclass(frozen=True)
class Coordination:
    """``z``: the largest number of contacts any particle of the scene can have; ``where``: which particle
    attains it; ``how``: the argument, in words (printed with the headline).

    Parameters
    ----------
    z : int
        The largest coordination.
    where : str
        The particle that attains it.
    how : str
        The argument, in words.
    """

    z: int
    where: str
    how: str


def _cos_bound_binned(lo: np.ndarray, hi: np.ndarray, overlap: float) -> np.ndarray:
    """Per bin i: an upper bound on cos(angle between two contact normals) of a sphere with radius in
    ``[lo_i, hi_i]`` against neighbours with radii in any bins (interval form of Lemma 5).
    """
    q, s_hi = 1.0 - overlap, 1.0 + CONTACT_TOLERANCE
    ri_lo, ri_hi = lo[:, None, None], hi[:, None, None]
    rj_lo, rj_hi = lo[None, :, None], hi[None, :, None]
    rk_lo, rk_hi = lo[None, None, :], hi[None, None, :]
    big_l = q * (rj_lo + rk_lo)
    best = np.full(lo.shape, -1.0)
    for sx in (q, s_hi):
        for sy in (q, s_hi):
            x_lo, x_hi = sx * (ri_lo + rj_lo), sx * (ri_hi + rj_hi)
            y_lo, y_hi = sy * (ri_lo + rk_lo), sy * (ri_hi + rk_hi)
            num = x_hi * x_hi + y_hi * y_hi - big_l * big_l
            c = np.where(num >= 0, num / (2.0 * x_lo * y_lo), num / (2.0 * x_hi * y_hi))
            best = np.maximum(best, c.max(axis=(1, 2)))
    return np.minimum(best + ROUND * np.abs(best) + ROUND, 1.0)


def sphere_cos_bounds(radii, overlap: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(lo, hi, cos_max)``: groups of radii ``[lo, hi]`` (single radii up to ``EXACT_SPECIES``, else bins)
    and for each an upper bound on the cosine of the smallest angle between two contact normals.

    Parameters
    ----------
    radii : array_like
        Sphere radii of the scene [m].
    overlap : float
        Largest overlap as a fraction of ``R_i + R_j``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(lo, hi, cos_max)`` per group.
    """
    r = distinct(np.asarray(radii, float))
    if len(r) <= EXACT_SPECIES:
        c = min_contact_angle_cos(r[:, None, None], r[None, :, None], r[None, None, :], overlap, CONTACT_TOLERANCE)
        return r, r, c.max(axis=(1, 2))
    edges = np.exp(np.linspace(math.log(r[0]), math.log(r[-1]), BINS + 1))
    idx = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, BINS - 1)
    used = distinct(idx)
    lo = np.array([r[idx == b].min() for b in used])
    hi = np.array([r[idx == b].max() for b in used])
    return lo, hi, _cos_bound_binned(lo, hi, overlap)


def sphere_volume_count(lo: np.ndarray, hi: np.ndarray, r_min: float, r_max: float, overlap: float) -> np.ndarray:
    """Volume count for a sphere of radius in ``[lo, hi]`` (the other-shapes argument of the module
    docstring with balls): its neighbours shrunk by ``1 - eps`` are disjoint balls of radius at least
    ``(1 - eps) r_min`` inside the ball of radius ``(1 + tau)(hi + r_max) + (1 - eps) r_max``, outside its
    own shrunken ball.  Finite for every size ratio, where the angle argument may bound nothing.

    Parameters
    ----------
    lo, hi : numpy.ndarray
        Radius groups [m].
    r_min, r_max : float
        Smallest and largest radius of the scene [m].
    overlap : float
        Largest overlap as a fraction of ``R_i + R_j``.

    Returns
    -------
    numpy.ndarray
        The count per group.
    """
    q = 1.0 - overlap
    rho = (1.0 + CONTACT_TOLERANCE) * (hi + r_max) + q * r_max
    return np.floor((rho**3 - (q * lo) ** 3) / (q * r_min) ** 3 * (1.0 + 1e-12))


def sphere_coordination(radii, overlap: float) -> tuple[int, float]:
    """The largest number of sphere neighbours a sphere with one of ``radii`` can have (the smaller of
    the contact-angle and the volume count), and the radius (lower end of its group) where it is attained.

    Parameters
    ----------
    radii : array_like
        Sphere radii of the scene [m].
    overlap : float
        Largest overlap as a fraction of ``R_i + R_j``.

    Returns
    -------
    tuple
        ``(z, radius)``.
    """
    lo, hi, cos_max = sphere_cos_bounds(radii, overlap)
    r = np.asarray(radii, float)
    volume = sphere_volume_count(lo, hi, float(r.min()), float(r.max()), overlap)
    counts = [min(max_code_size(math.acos(float(c))), float(v)) for c, v in zip(cos_max, volume)]
    k = int(np.argmax(counts))
    return int(counts[k]), float(lo[k])


def _volume_lower(part, shape) -> float:
    if part.kind == "clump":
        return 4.0 / 3.0 * math.pi * float(max(s[3] for s in part.dimensions["spheres"])) ** 3
    return float(shape.volume)


def _body_coordination(shapes: list, overlap: float) -> tuple[int, int]:
    """Volume count for particles of any shape: ``(z, index of the shape attaining it)``."""
    q = 1.0 - overlap
    r_max = max(float(s.max_arm) for _, s in shapes)
    v_min = min(_volume_lower(p, s) for p, s in shapes) * q**3
    best, where = 0, 0
    for n, (p, s) in enumerate(shapes):
        rho = (1.0 + CONTACT_TOLERANCE) * (float(s.max_arm) + r_max) + q * r_max
        z = int(math.floor((4.0 / 3.0 * math.pi * rho**3 - q**3 * _volume_lower(p, s)) / v_min * (1.0 + 1e-12)))
        if z > best:
            best, where = z, n
    return best, where


def scene_coordination(scene) -> Coordination:
    """The largest coordination the scene's shapes and sizes allow (see the module docstring).

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The parsed scene.

    Returns
    -------
    Coordination
        The bound, where it is attained and why.
    """
    overlap = scene.overlap_max
    walls = {p.number: sum(1 for w in scene.walls if p.number in w.particles) for p in scene.particles}
    if all(p.kind == "sphere" for p in scene.particles):
        radii = [r for p in scene.particles for r in p.radii]
        z, at = sphere_coordination(radii, overlap)
        n_walls = max(walls.values())
        how = (f"spheres: contact normals at least the law-of-cosines angle apart (overlaps at most {overlap:g} of "
               f"R_i + R_j), at most {z} neighbours (Fejes Toth, Tammes) for a sphere of radius {at:g}"
               + (f", plus {n_walls} wall{'s' if n_walls > 1 else ''}" if n_walls else ""))
        return Coordination(z + n_walls, f"radius {at:g}", how)
    shapes = [(p, p.shape_at(r)) for p in scene.particles for r in (p.radii or (None,))]
    z, k = _body_coordination(shapes, overlap)
    part = shapes[k][0]
    n_walls = max(walls.values())
    how = (f"volume count: particles shrunk by {1 - overlap:g} about their centres are disjoint and a neighbour lies "
           f"within r_i + r_max, so at most {z} neighbours of particle {part.number}"
           + (f", plus {n_walls} wall{'s' if n_walls > 1 else ''}" if n_walls else ""))
    return Coordination(z + n_walls, f"particle {part.number}", how)
