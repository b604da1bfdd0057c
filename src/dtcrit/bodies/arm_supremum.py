"""Per-particle supremum ``S = sup over the body of lambda_max([p]x^T I^-1 [p]x)`` (run time; no SymPy).

Peng et al. (2020), Section 3: the coefficient matrix of the contact force is
``A = (1/m1 + 1/m2) 1 + T1 + T2`` with ``T_i = Q_i [p_i]x^T I_i^-1 [p_i]x Q_i^T`` (``p_i`` the contact
point in particle ``i``'s principal frame), so ``lambda_max(A) <= 1/m1 + 1/m2 + S1 + S2``
(:func:`dtcrit.a_bound`).  ``lambda_max(T(p)) = max_{|v|=1} |I^-1/2 (p x v)|^2`` is a maximum of
convex quadratics in ``p``, hence convex: over a convex body its supremum sits at extreme points.
Routes, chosen per shape by :func:`arm_term_supremum`:

* ``"vertices"`` (boxes, polyhedra): the exact maximum over the corners.
* ``"isotropic"`` (sphere, any body with equal moments): ``max_arm^2 / I`` exactly.
* ``"ellipsoid closed form"``: ``max_{i != j} d_i^2 / I_j`` (generated kernel
  ``ellipsoid_arm_supremum``; proof in ``derivations/records/sec2_3_kinematics.md``).
* ``"octant cones"`` (superquadrics): branch and bound over cones of directions in the first
  octant (:mod:`dtcrit.bodies.arm_cones`), NumPy only.
* ``"clump"`` (multi-sphere bodies, not convex): ``r_max^2 / I_min`` (:mod:`dtcrit.bodies.clump`).
* ``"support cutting planes"`` (any other smooth convex body with a support function): outer
  polytopes from support half-spaces, vertices by SciPy's Qhull, refined until the bound meets
  the best surface value.  Also the independent cross-check of the two routes above in the tests.

Every route returns a valid upper bound ``upper`` and an attained value ``lower`` (at a surface
point, with an outward normal there, for :func:`dtcrit.bodies.contact_search.mirror_contact`).
"""
from __future__ import annotations

import numpy as np

from dtcrit._generated import contact as _k
from dtcrit.bodies.checks import _vec3
from dtcrit.bodies.arm_terms import (
    SUP_MAX_HALFSPACES,
    SUP_MAX_ITERATIONS,
    SUP_RTOL,
    SUPPORT_SLACK,
    ArmSupremum,
    arm_lambda,
    fibonacci_sphere,
)


def _shape_key(shape) -> tuple:
    verts = getattr(shape, "vertices", None)
    extra = tuple(float(getattr(shape, name)) for name in ("eps1", "eps2") if hasattr(shape, name))
    return (
        getattr(shape, "kind", type(shape).__name__),
        tuple(float(x) for x in shape.inertia),
        tuple(float(x) for x in shape.half_lengths),
        float(shape.max_arm),
        extra,
        None if verts is None else np.asarray(verts, float).tobytes(),
        None if getattr(shape, "kind", "") != "clump" else shape.spheres.tobytes(),
    )


_CACHE: dict[tuple, ArmSupremum] = {}
_CACHE_SIZE = 512


def arm_term_supremum(shape) -> ArmSupremum:
    """Bounds on ``sup over the body of lambda_max([p]x^T I^-1 [p]x)`` (cached per shape geometry).

    Parameters
    ----------
    shape : object
        A ``dtcrit.bodies`` shape.

    Returns
    -------
    ArmSupremum
        Lower and upper bounds on ``S`` [1/kg], with the method used.
    """
    key = _shape_key(shape)
    hit = _CACHE.get(key)
    if hit is None:
        hit = _arm_term_supremum(shape)
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = hit
    return hit


def _is_ellipsoid(shape) -> bool:
    kind = getattr(shape, "kind", "")
    if kind in ("sphere", "ellipsoid"):
        return True
    return kind == "superquadric" and float(shape.eps1) == 1.0 and float(shape.eps2) == 1.0


def _arm_term_supremum(shape) -> ArmSupremum:
    if getattr(shape, "kind", "") == "clump":  # not convex: the generic bound (dtcrit.bodies.clump)
        return shape.arm_term_bound()
    inertia = np.array(shape.inertia, dtype=float)
    verts = getattr(shape, "vertices", None)
    if verts is not None:
        V = np.asarray(verts, dtype=float)
        lam = arm_lambda(V, inertia)
        i = int(np.argmax(lam))
        return ArmSupremum(float(lam[i]), float(lam[i]), tuple(V[i]), _vertex_normal(shape, V[i]), "vertices")
    w = 1.0 / inertia
    arm = float(shape.max_arm)
    crude = arm * arm * float(np.max(w))  # lambda_max(T(p)) <= |p|^2 max(1/I)
    if float(np.max(w)) == float(np.min(w)):
        d, p = _sphere_tip(shape) if getattr(shape, "kind", "") == "sphere" else _farthest_support_point(shape)
        return ArmSupremum(crude, min(crude, float(arm_lambda(p[None, :], inertia)[0])), tuple(p), tuple(d), "isotropic")
    if _is_ellipsoid(shape):
        return ellipsoid_supremum(shape.half_lengths, inertia)
    if getattr(shape, "kind", "") == "superquadric":
        from dtcrit.bodies.arm_cones import octant_cone_supremum

        return octant_cone_supremum(shape, inertia, crude, SUP_RTOL)
    return cutting_plane_supremum(shape, inertia, crude)


def ellipsoid_supremum(semi_axes, inertia) -> ArmSupremum:
    """``S = max_{i != j} d_i^2 / I_j`` for an ellipsoid whose semi-axes ``d`` lie along its principal
    axes (generated kernel ``ellipsoid_arm_supremum``), attained at the tip ``d_i e_i``.

    Evaluated on ``d / max(d)`` and ``I / max(d) / max(d)`` (``S`` is invariant under that
    scaling), so neither ``d^2`` nor ``max(d)^2`` can overflow or underflow.

    Parameters
    ----------
    semi_axes : array_like
        Semi-axes ``(a, b, c)`` along the principal axes [m].
    inertia : array_like
        Principal moments [kg m^2].

    Returns
    -------
    ArmSupremum
        ``S`` (equal lower and upper bounds) and the tip where it is attained.
    """
    d = np.array([float(x) for x in semi_axes])
    inertia = np.asarray(inertia, dtype=float)
    scale = float(np.max(d))
    ds, Is = d / scale, inertia / scale / scale
    value = float(_k.ellipsoid_arm_supremum(*ds, *Is))
    tip_values = [(ds[i] / Is[j]) * ds[i] for i in range(3) for j in range(3) if i != j]
    i = [i for i in range(3) for j in range(3) if i != j][int(np.argmax(tip_values))]
    point = np.zeros(3)
    point[i] = d[i]
    normal = np.zeros(3)
    normal[i] = 1.0
    return ArmSupremum(value, value, _floats(point), _floats(normal), "ellipsoid closed form")


def _floats(v) -> tuple[float, float, float]:
    return _vec3(v)


def _vertex_normal(shape, vertex: np.ndarray) -> tuple[float, float, float]:
    """A unit direction whose support point is ``vertex`` (in its normal cone): the vertex's own
    direction when that works, else the sampled vertex normal (mean of the adjacent face normals).
    """
    d = vertex / np.linalg.norm(vertex)
    if np.allclose(shape.support(d), vertex, rtol=0, atol=1e-12 * np.linalg.norm(vertex)):
        return tuple(d)
    pts, nrm = shape.surface_points(1)  # the vertices come first, with their mean face normals
    return tuple(nrm[int(np.argmin(np.linalg.norm(pts - vertex, axis=1)))])


def _sphere_tip(shape) -> tuple[np.ndarray, np.ndarray]:
    """A sphere's farthest support point is any: the one along ``z`` (no search, and no import of
    ``numpy.random`` at start).
    """
    d = np.array([0.0, 0.0, 1.0])
    return d, np.asarray(shape.support(d), float)


def _farthest_support_point(shape) -> tuple[np.ndarray, np.ndarray]:
    """Direction and support point of largest norm (a surface point at distance ~ ``max_arm``):
    dense directions, then a few rounds of local random refinement.
    """
    rng = np.random.default_rng(0)
    d = fibonacci_sphere(2000)
    r = np.linalg.norm(shape.support(d), axis=1)
    best = d[int(np.argmax(r))]
    best_r = float(np.max(r))
    sigma = 0.05
    for _ in range(60):
        trial = best + sigma * rng.normal(size=(32, 3))
        trial /= np.linalg.norm(trial, axis=1, keepdims=True)
        rt = np.linalg.norm(shape.support(trial), axis=1)
        k = int(np.argmax(rt))
        if rt[k] > best_r:
            best, best_r, sigma = trial[k], float(rt[k]), sigma * 1.5
        else:
            sigma *= 0.6
    return best, np.asarray(shape.support(best), float)


# ============================================================================================
# General smooth convex bodies: support cutting planes (Qhull)
# ============================================================================================
def support_planes(shape, normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Support points of unit ``normals`` and offsets ``h(n)`` inflated by ``SUPPORT_SLACK |p|``:
    every half-space ``n.x <= h`` contains the body despite rounding.

    Parameters
    ----------
    shape : object
        A convex shape with a ``support`` function.
    normals : numpy.ndarray
        Unit directions, shape (N, 3).

    Returns
    -------
    tuple of numpy.ndarray
        The support points (N, 3) and the inflated offsets (N,).
    """
    pts = np.asarray(shape.support(normals), dtype=float)
    h = np.einsum("ij,ij->i", normals, pts)
    return pts, h + SUPPORT_SLACK * np.linalg.norm(pts, axis=1)


def _cut_directions(shape, outside: np.ndarray, start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directions ``n`` with (ideally) ``n.v > h(n)`` for points ``v`` outside the body: gradient ascent
    of the violation ``n.v - h(n)`` (concave in ``n``; its supergradient is ``v - support(n)``) on
    the sphere from each row of ``start``, keeping only improving steps.
    """
    scale = np.linalg.norm(outside, axis=1, keepdims=True)
    n = start / np.linalg.norm(start, axis=1, keepdims=True)

    def violation(nn):
        return np.einsum("ij,ij->i", nn, outside) - np.einsum("ij,ij->i", nn, shape.support(nn))

    g = violation(n)
    step = np.full(n.shape[0], 0.5)
    for _ in range(20):
        trial = n + step[:, None] * (outside - shape.support(n)) / scale
        trial /= np.linalg.norm(trial, axis=1, keepdims=True)
        gt = violation(trial)
        better = gt > g
        n = np.where(better[:, None], trial, n)
        g = np.where(better, gt, g)
        step = np.where(better, step * 1.5, step * 0.3)
    return n, g


def cutting_plane_supremum(shape, inertia, crude: float | None = None) -> ArmSupremum:
    """Bounds on ``S`` for any convex body with a ``support`` function, by outer polytopes.

    Every polytope ``{x : n.x <= h(n)}`` contains the body, so the largest value at its vertices
    (SciPy's ``HalfspaceIntersection``) bounds ``S`` from above; half-spaces are added where a
    vertex exceeds the best surface value until the two meet within ``SUP_RTOL`` (or the budget
    ``SUP_MAX_HALFSPACES`` / ``SUP_MAX_ITERATIONS`` is spent; the bound stays valid).

    Parameters
    ----------
    shape : object
        A convex shape with a ``support`` function.
    inertia : array_like
        Principal moments [kg m^2].
    crude : float, optional
        A known upper bound [1/kg] that caps the result; ``max_arm^2 max(1/I)`` when omitted.

    Returns
    -------
    ArmSupremum
        Lower and upper bounds on ``S`` [1/kg].
    """
    from scipy.spatial import HalfspaceIntersection, QhullError  # lazy: heavy import, general route only

    inertia = np.asarray(inertia, dtype=float)
    if crude is None:
        crude = float(shape.max_arm) ** 2 / float(np.min(inertia))
    normals = np.vstack([fibonacci_sphere(240), np.eye(3), -np.eye(3)])
    pts, h = support_planes(shape, normals)
    lam = arm_lambda(pts, inertia)
    best = int(np.argmax(lam))
    lower, point, normal = float(lam[best]), pts[best], normals[best]
    upper = crude
    for _ in range(SUP_MAX_ITERATIONS):
        try:
            hs = HalfspaceIntersection(np.column_stack([normals, -h]), np.zeros(3))
        except QhullError:  # pragma: no cover - degenerate input; keep the bound found so far
            break
        corners = hs.intersections
        fc = arm_lambda(corners, inertia)
        upper = min(upper, float(np.max(fc)))
        if upper <= lower * (1.0 + SUP_RTOL) or normals.shape[0] >= SUP_MAX_HALFSPACES:
            break
        bad_idx = np.flatnonzero(fc > lower * (1.0 + SUP_RTOL))
        room = SUP_MAX_HALFSPACES - normals.shape[0]
        if bad_idx.size > room:
            bad_idx = bad_idx[np.argsort(-fc[bad_idx])[:room]]
        bad = corners[bad_idx]
        # two starts per corner: the mean normal of the half-spaces meeting there (refines the
        # sampled normals where the polytope is too coarse) and the corner's own direction
        mean_normal = np.array([normals[list(hs.dual_facets[i])].sum(axis=0) for i in bad_idx])
        n_a, g_a = _cut_directions(shape, bad, mean_normal)
        n_b, g_b = _cut_directions(shape, bad, bad)
        n_new = np.where((g_a >= g_b)[:, None], n_a, n_b)
        p_new, h_new = support_planes(shape, n_new)
        keep = np.einsum("ij,ij->i", n_new, bad) > h_new
        if not np.any(keep):
            break
        normals = np.vstack([normals, n_new[keep]])
        h = np.concatenate([h, h_new[keep]])
        lam_new = arm_lambda(p_new, inertia)
        j = int(np.argmax(lam_new))
        if lam_new[j] > lower:
            lower, point, normal = float(lam_new[j]), p_new[j], n_new[j]
    return ArmSupremum(upper, lower, tuple(point), tuple(normal), "support cutting planes", normals.shape[0])
