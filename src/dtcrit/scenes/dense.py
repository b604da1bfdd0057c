"""A rigorous critical step for *any* packing of a scene's particles with at most ``z`` contacts each
(``coordination_max``): the two-particle step is an upper bound on a packing's step, unsafe in
dense packings (Otsubo et al. 2017); this is a lower bound that holds for every arrangement.

Proof (the full text is in ``derivations/records/dense_bound.md``).  With ``M`` the mass matrix
(translations and rotations), the packing's ``K = sum_c K_c`` and ``C = sum_c C_c`` over contacts,
each element positive semi-definite.

0. *Spheres.*  For sphere-only scenes without walls (at most ``SPHERE_BOUND_MAX_SPECIES`` sizes) the
   sharper bound of :mod:`dtcrit.scenes.dense_spheres` (``derivations/proofs/dense_packing_bound.md``)
   is used where it is smaller: it also uses that the contact normals of a sphere are at least the
   law-of-cosines angle apart (60 degrees for equal spheres without overlap; ``overlap_max`` of the
   scene, default 0.05 of ``R_i + R_j``, widens the cones) and how many such normals fit (Tammes).
   It bounds the largest eigenvalue of any assembly of such contact elements, so it serves for the
   springs (``lambda_K``) and for the dashpots (``lambda_C``) alike.
1. *Block bound.*  A contact between particles i and j couples only their blocks, and for a
   positive semi-definite ``[[P, Q], [Q^T, R]]`` we have ``<= 2 diag(P, R)``; a wall contact touches
   one block only.  So ``M^-1/2 K M^-1/2 <= blockdiag_i(sum_(c at i) w_c D_ic)`` with ``w_c = 2``
   (particle-particle) or ``1`` (wall), ``D_ic`` the contact's own block of particle i, and
   ``lambda_max(D_ic) = lambda_max(K_c^1/2 A_ic K_c^1/2)`` with ``A_ic = 1/m_i + [p]x^T I_i^-1 [p]x``
   the particle's part of the coefficient matrix.  For a sphere (arm R along n) that is
   ``max(kn/m_i, ks (1/m_i + R_i^2/I_i))``; for another shape at most ``max(kn, ks)(1/m_i + S_i)``
   (arm supremum ``S_i``); with rotational springs see :func:`_rotational_block`.  With at most ``z`` contacts per particle,
   ``lambda_K <= max_i z max_c w_c lambda_max(D_ic)``, and likewise ``lambda_C`` with ``cn, cs``.
2. *Damping.*  Each scheme evaluates the force once per step, at fixed scalar combinations of its
   stored state, so eliminating the state from an eigenvector of the whole packing's update gives
   ``P(z) u = 0`` with ``P(z) = M p(z) + h C q(z) + h^2 K r(z)``, ``p, q, r`` scalar polynomials (the
   one-mode characteristic polynomial's coefficients).  Then ``u* P(z) u = m p + h c q + h^2 k r = 0``
   with ``(m, c, k) = (u*Mu, u*Cu, u*Ku)``: every eigenvalue of the packing is an eigenvalue of one
   mode with ``c/m <= lambda_C`` and ``k/m <= lambda_K``.  Where that mode's stable set in
   ``(h c/m, h^2 k/m)`` is closed downwards (``DENSE_SCHEMES``: ``k~ + 2 c~ <= 4`` for symplectic
   Euler, leapfrog and velocity Verlet, ``k~ + 4 c~ <= 4`` for velocity Verlet with a predicted
   velocity, ``k~ <= 4`` for centred damping), the one-mode step at ``(lambda_C, lambda_K)`` is stable
   for the whole packing, damped or not, proportional or not.  Forward Euler and the paper's Eq. (40)
   scheme are unstable undamped (their stable sets are not closed downwards): ``dt_dense`` is
   ``None`` for them, with the reason.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.integrators.stability import mode_dt

SPHERE_BOUND_MAX_SPECIES = 6
"""The sphere bound enumerates species (0.1-0.5 s each); wider size distributions use the block bound."""
DENSE_SCHEMES = ("symplectic-euler", "leapfrog", "leapfrog-centred", "velocity-verlet", "velocity-verlet-predicted")


def dense_reason(integrator: str) -> str | None:
    """None when the packing bound applies to ``integrator`` (a ``DENSE_SCHEMES`` entry, or a user-written
    scheme whose update is the same map as one of them for matrix K and C), else why it does not.

    Parameters
    ----------
    integrator : str
        Name of the scheme.

    Returns
    -------
    str or None
        None, or the reason in words.
    """
    from dtcrit.integrators.schemes import USER_INTEGRATORS

    if integrator in DENSE_SCHEMES:
        return None
    if integrator in USER_INTEGRATORS:
        from dtcrit.integrators.user_rules import same_update_as

        if same_update_as(USER_INTEGRATORS[integrator], DENSE_SCHEMES) is not None:
            return None
        return (f"the user-written '{integrator}' is not the same update as any of {', '.join(DENSE_SCHEMES)}, "
                "the schemes whose one-mode stable set is proven closed downwards")
    return f"'{integrator}' is unstable undamped, so its one-mode stable set is not closed downwards"
FACTOR_COORDINATIONS = (4, 6, 12)


@dataclass(frozen=True)
class DenseStep:
    """The step that holds for every packing with at most ``coordination`` contacts per particle.

    Parameters
    ----------
    coordination : int
        Largest number of contacts of a particle.
    dt : float or None
        The step [s] (None when the bound does not apply).
    lambda_k : float
        Bound on lambda_max(M^-1/2 K M^-1/2) [1/s^2].
    lambda_c : float
        Bound on lambda_max(M^-1/2 C M^-1/2) [1/s].
    particle : str
        Where the bound is attained: ``"particle i (radius r) against j"``.
    reason : str
        Which bound gives the step, in words.
    """

    coordination: int
    dt: float | None
    lambda_k: float  # bound on lambda_max(M^-1/2 K M^-1/2) [1/s^2]
    lambda_c: float  # bound on lambda_max(M^-1/2 C M^-1/2) [1/s]
    particle: str  # where the bound is attained: "particle i (radius r) against j"
    reason: str


def _block(kind: str, shape, k_n: float, k_s: float) -> float:
    """lambda_max(K_c^1/2 A_ic K_c^1/2) of one contact's block of a particle (step 1 above)."""
    if kind == "sphere":
        return max(k_n / shape.mass, k_s * (1.0 / shape.mass + shape.max_arm**2 / shape.inertia[0]))
    from dtcrit.bodies.arm_supremum import arm_term_supremum

    return max(k_n, k_s) * (1.0 / shape.mass + arm_term_supremum(shape).upper)


def _rotational_block(kind: str, shape, k_n: float, k_s: float, k_r: float, k_tw: float, wall: bool) -> float:
    """The block of step 1 with rotational springs: a sphere's own block of the element is the element of
    that sphere against a fixed wall (normal, shear-rolling 2x2, twisting: exact); another shape's is at
    most ``max(k_n, k_s)(1/m + S) + max(k_r, k_tw)/I_min`` (``lambda_max`` of a PSD block matrix is at most
    the sum of its diagonal blocks' ``lambda_max``).
    """
    if kind != "sphere":
        from dtcrit.bodies.arm_supremum import arm_term_supremum

        return max(k_n, k_s) * (1.0 / shape.mass + arm_term_supremum(shape).upper) + max(k_r, k_tw) / min(shape.inertia)
    from dtcrit._generated import rotational_modes as gen

    a_ss, a_sr, a_rr, a_tw, _ = (float(x) for x in gen.wall_shear_rolling_block(shape.mass, shape.inertia[0], shape.max_arm))
    block = np.array([[k_s * a_ss, math.sqrt(k_s * k_r) * a_sr], [math.sqrt(k_s * k_r) * a_sr, k_r * a_rr]])
    return max(k_n / shape.mass, float(np.linalg.eigvalsh(block)[-1]), k_tw * a_tw)


def block_terms(scene, steps) -> list[tuple[float, float, str]]:
    """``(w lambda_K, w lambda_C, where)`` of every contact a particle can have, from the pair steps.

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The parsed scene.
    steps : sequence of dtcrit.scenes.pair_modes.PairStep
        The isolated-contact steps of the scene's pairs.

    Returns
    -------
    list of tuple
        One ``(lambda_K, lambda_C, where)`` per contact end.
    """
    out = []
    for s in steps:
        pc = s.contact
        sides = [(pc.i, pc.radius_i, pc.j, pc.radius_j)]
        if pc.wall is None and (pc.i, pc.radius_i) != (pc.j, pc.radius_j):
            sides.append((pc.j, pc.radius_j, pc.i, pc.radius_i))
        for i, r, j, r_other in sides:
            part = scene.particle(i)
            shape = part.shape_at(r)
            w = 1.0 if pc.wall is not None else 2.0
            size = "" if r is None else f" (radius {r:g})"
            other = pc.wall if pc.wall is not None else f"particle {j}" + ("" if r_other is None else f" (radius {r_other:g})")
            if pc.rotational:
                terms = (w * _rotational_block(part.kind, shape, pc.kn, pc.ks, pc.kr, pc.ktw, pc.wall is not None),
                         w * _rotational_block(part.kind, shape, pc.cn, pc.cs, pc.cr, pc.ctw, pc.wall is not None))
            else:
                terms = (w * _block(part.kind, shape, pc.kn, pc.ks), w * _block(part.kind, shape, pc.cn, pc.cs))
            out.append(terms + (f"particle {i}{size} against {other}",))
    return out


def sphere_bound(scene, steps, z: int, rtol: float = 2e-3, n_theta: int = 96) -> tuple[float, float] | None:
    """``(lambda_K, lambda_C)`` from the geometric sphere-packing bound (:mod:`dtcrit.scenes.dense_spheres`),
    or None where it does not apply (other shapes, walls, more than ``SPHERE_BOUND_MAX_SPECIES`` sizes).
    ``rtol``, ``n_theta``: the branch-and-bound tolerance and sphere grid (tightness and time, never validity).

    Parameters
    ----------
    scene : dtcrit.scenes.model.Scene
        The parsed scene.
    steps : sequence of dtcrit.scenes.pair_modes.PairStep
        The isolated-contact steps of the scene's pairs.
    z : int
        Largest number of contacts of a particle.
    rtol : float
        Branch-and-bound stopping tolerance.
    n_theta : int
        Resolution of the sphere grid.

    Returns
    -------
    tuple of float or None
        ``(lambda_K [1/s^2], lambda_C [1/s])``, or None.
    """
    if scene.walls or any(p.kind != "sphere" for p in scene.particles) or any(s.contact.rotational for s in steps):
        return None  # the geometric bound covers normal and shear springs only
    if sum(len(part.radii) for part in scene.particles) > SPHERE_BOUND_MAX_SPECIES:
        return None
    species = [(part.shape_at(r).mass, r, part.shape_at(r).inertia[0]) for part in scene.particles for r in part.radii]
    from dtcrit.scenes.dense_spheres import dense_omega2_bound

    m, r, inertia = (list(v) for v in zip(*species))
    bounds = []
    for a, b in ((max(s.contact.kn for s in steps), max(s.contact.ks for s in steps)),
                 (max(s.contact.cn for s in steps), max(s.contact.cs for s in steps))):
        scale = max(a, b)  # the bound is linear in the springs jointly: solve at max 1 (no overflow near 1e308)
        with np.errstate(all="ignore"):  # wide cones (large overlap_max) divide by a zero cap; the bound stays valid
            bounds.append(0.0 if scale == 0 else
                          scale * dense_omega2_bound(a / scale, b / scale, m, r, inertia, z, overlap=scene.overlap_max,
                                                     rtol=rtol, n_theta=n_theta).omega2)
    return bounds[0], bounds[1]


def dense_step(integrator: str, terms: list[tuple[float, float, str]], z: int,
               spheres: tuple[float, float] | None = None, overlap: float | None = None) -> DenseStep:
    """The step that holds for every packing with at most ``z`` contacts per particle: the block bound,
    or the smaller geometric sphere bound ``spheres = (lambda_K, lambda_C)`` where it applies.

    Parameters
    ----------
    integrator : str
        Name of the scheme.
    terms : list of tuple
        ``(lambda_K, lambda_C, where)`` per contact end (``block_terms``).
    z : int
        Largest number of contacts of a particle.
    spheres : tuple of float, optional
        The geometric sphere bound ``(lambda_K, lambda_C)``.
    overlap : float, optional
        Largest overlap as a fraction of ``R_i + R_j`` (reported).

    Returns
    -------
    DenseStep
        The step and the bound that gives it.
    """
    lam_k = z * max(t[0] for t in terms)
    lam_c = z * max(t[1] for t in terms)
    where = max(terms, key=lambda t: t[0])[2]
    how = f"block bound, worst at {where}"
    if spheres is not None and (spheres[0] < lam_k or spheres[1] < lam_c):
        lam_k, lam_c = min(lam_k, spheres[0]), min(lam_c, spheres[1])
        how = (f"sphere-packing bound: contact normals at least the law-of-cosines angle apart, overlaps at most "
               f"{overlap:g} of R_i + R_j")
    why = dense_reason(integrator)
    if why is not None:
        return DenseStep(z, None, lam_k, lam_c, where, f"no packing bound for '{integrator}': {why}")
    r = mode_dt(integrator, lam_k, lam_c, 1.0)
    dt = r.dt if math.isfinite(r.dt) else None
    reason = (f"any packing with at most {z} contacts per particle: lambda_max(M^-1 K) <= {lam_k:.6g} 1/s^2, "
              f"lambda_max(M^-1 C) <= {lam_c:.6g} 1/s ({how})")
    return DenseStep(z, dt, lam_k, lam_c, where, reason)
