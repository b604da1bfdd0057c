"""Branch and bound over cones of directions for ``S = sup lambda_max([p]x^T I^-1 [p]x)`` on a superquadric.

NumPy only (no Qhull), so ``dtcrit step`` stays quick for superquadric scenes.  Three facts make it
an upper bound, not an estimate:

1. ``f(p) = lambda_max([p]x^T W [p]x)`` with ``W = I^-1`` diagonal is convex in ``p`` (a maximum of
   convex quadratics) and unchanged by the coordinate reflections ``R`` (``[R p]x = det(R) R [p]x R``
   and ``R W R = W``).  A superquadric is symmetric under the same reflections, so the supremum over
   the body is the supremum over its part in the first octant.
2. The first octant of directions is the union of the cones over the squares ``(u, v) in [0, 1]^2``
   of the three cube faces ``x = 1``, ``y = 1``, ``z = 1``; a square's cone is exactly the polyhedral
   cone spanned by its four corner rays.  The part of the body inside a cone lies in the polytope

       cone  and  n_k . x <= h(n_k)  (k = 1..4)  and  x <= a, y <= b, z <= c,

   with ``n_k`` the outward normal where the corner ray ``k`` meets the surface and ``h`` the
   support function (a supporting half-space for any unit ``n``; offsets inflated by
   ``SUPPORT_SLACK``).
3. A convex function's maximum over a polytope is at a vertex; the vertices are the feasible
   intersections of three of the eleven planes (all 165 triples are tried).

The largest vertex value over the cones bounds ``S``; the values at the corner surface points
are attained.  Cones whose bound exceeds the best attained value by more than ``rtol`` are split
in four until none remains (or ``MAX_CELLS`` / ``MAX_LEVELS`` is reached: the bound stays
valid, only looser).  Near a smooth maximiser the tangent planes make each cone's excess
second order in its size, so few levels are needed.
"""
from __future__ import annotations

import itertools

import numpy as np

from dtcrit.bodies.arm_terms import SUPPORT_SLACK, ArmSupremum, arm_lambda
from dtcrit.bodies.checks import _vec3

START_SPLITS = 4
"""Each cube face starts as START_SPLITS x START_SPLITS squares."""
MAX_LEVELS = 30
MAX_CELLS = 20000
"""Largest number of cones refined at once; beyond it the search stops with the bound it has."""
FEASIBILITY_RTOL = 1e-10
"""A triple intersection within this distance (relative to the body's size) of the polytope counts
as one of its vertices: including near-vertices can only raise the bound."""

_TRIPLES = np.array(list(itertools.combinations(range(11), 3)))
_PAIRS = np.array(list(itertools.combinations(range(11), 2)))
_PAIR_INDEX = {(int(i), int(j)): k for k, (i, j) in enumerate(_PAIRS)}
_JK, _IK, _IJ = (np.array([_PAIR_INDEX[(int(t[a]), int(t[b]))] for t in _TRIPLES]) for a, b in ((1, 2), (0, 2), (0, 1)))
"""Per triple ``(i, j, k)``, the rows of ``n_j x n_k``, ``n_i x n_k`` and ``n_i x n_j`` among the 55 pairs."""


def _corner_directions(face: np.ndarray, u0, u1, v0, v1) -> np.ndarray:
    """(N, 4, 3) corner rays, in cyclic order, of the squares ``[u0, u1] x [v0, v1]`` on cube face
    ``face`` (the coordinate equal to 1); ``u`` and ``v`` are the other two coordinates in order.
    """
    n = face.shape[0]
    D = np.empty((n, 4, 3))
    uu = np.stack([u0, u1, u1, u0], axis=1)
    vv = np.stack([v0, v0, v1, v1], axis=1)
    for k in range(3):
        i, j = [m for m in range(3) if m != k]
        sel = face == k
        D[sel, :, k] = 1.0
        D[sel, :, i] = uu[sel]
        D[sel, :, j] = vv[sel]
    return D


def _cell_planes(shape, D: np.ndarray, P: np.ndarray, Nrm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Planes ``n . x <= h`` (unit ``n``) of each cone's polytope: 4 cone sides, 4 supporting
    half-spaces at the corner surface points, 3 faces of the bounding box; shapes (N, 11, 3), (N, 11).
    """
    n_cells = D.shape[0]
    centre = D.sum(axis=1)
    side = np.cross(D, np.roll(D, -1, axis=1))
    side /= np.linalg.norm(side, axis=2, keepdims=True)
    inward = np.einsum("nkj,nj->nk", side, centre) > 0
    side = np.where(inward[..., None], -side, side)  # n . x <= 0 on the cone
    flat = Nrm.reshape(-1, 3)
    support = np.asarray(shape.support(flat), float)
    h = np.einsum("ij,ij->i", flat, support) + SUPPORT_SLACK * np.linalg.norm(support, axis=1)
    box_n = np.broadcast_to(np.eye(3), (n_cells, 3, 3))
    box_h = np.broadcast_to(np.asarray(shape.half_lengths, float) * (1.0 + SUPPORT_SLACK), (n_cells, 3))
    normals = np.concatenate([side, Nrm, box_n], axis=1)
    offsets = np.concatenate([np.zeros((n_cells, 4)), h.reshape(n_cells, 4), box_h], axis=1)
    return normals, offsets


def _cell_bounds(normals: np.ndarray, offsets: np.ndarray, inertia, scale: float, chunk: int = 1024) -> np.ndarray:
    """Largest ``lambda_max(T)`` over the vertices of each polytope (``inf`` if none is found)."""
    return np.concatenate([_chunk_bounds(normals[i : i + chunk], offsets[i : i + chunk], inertia, scale)
                           for i in range(0, normals.shape[0], chunk)])


def _chunk_bounds(normals: np.ndarray, offsets: np.ndarray, inertia, scale: float) -> np.ndarray:
    """Cramer's rule for every triple, from the 55 pair cross products of each polytope's planes.

    ``n_k x n_i`` is taken as ``-(n_i x n_k)``, which is the same number: IEEE products commute and
    ``a - b = -(b - a)`` exactly.  Planes, pairs and triples run along the first axis, cells along
    the second, so that each gather copies whole rows.
    """
    planes = np.ascontiguousarray(normals.transpose(1, 0, 2))  # (11, N, 3)
    levels = np.ascontiguousarray(offsets.T)  # (11, N)
    pair_cross = np.cross(planes[_PAIRS[:, 0]], planes[_PAIRS[:, 1]])  # (55, N, 3)
    c23, c31, c12 = pair_cross[_JK], -pair_cross[_IK], pair_cross[_IJ]  # (165, N, 3)
    h1, h2, h3 = (levels[_TRIPLES[:, k], :, None] for k in range(3))
    det = np.einsum("tnj,tnj->tn", planes[_TRIPLES[:, 0]], c23)
    ok = np.abs(det) > 1e-14
    x = ((h1 * c23 + h2 * c31 + h3 * c12) / np.where(ok, det, 1.0)[..., None]).transpose(1, 0, 2)  # (N, 165, 3)
    slack = np.matmul(x, normals.transpose(0, 2, 1)) - offsets[:, None, :]  # (N, 165, 11)
    ok = ok.T & np.all(slack <= FEASIBILITY_RTOL * scale, axis=2)
    values = np.full(ok.shape, -np.inf)
    if np.any(ok):
        values[ok] = arm_lambda(x[ok], inertia)
    bound = np.max(values, axis=1)
    return np.where(np.isfinite(bound), bound, np.inf)


def octant_cone_supremum(shape, inertia, crude: float, rtol: float) -> ArmSupremum:
    """Bounds on ``S`` for a superquadric-family ``shape`` (it provides ``support``,
    ``radial_surface_points``, ``outward_normals``, ``half_lengths`` and ``max_arm``; module
    docstring); ``crude = max_arm^2 max(1/I)`` caps the bound.

    Parameters
    ----------
    shape : object
        A sphere, ellipsoid or superquadric of ``dtcrit.bodies.smooth``.
    inertia : array_like
        Principal moments ``(I_xx, I_yy, I_zz)`` [kg m^2].
    crude : float
        The crude bound ``max_arm^2 max(1/I)`` [1/kg].
    rtol : float
        Relative gap at which the refinement stops.

    Returns
    -------
    ArmSupremum
        Lower and upper bounds on ``S`` [1/kg].
    """
    inertia = np.asarray(inertia, dtype=float)
    scale = float(shape.max_arm)
    grid = np.arange(START_SPLITS) / START_SPLITS
    u0, v0 = (g.ravel() for g in np.meshgrid(grid, grid, indexing="ij"))
    face = np.repeat(np.arange(3), u0.size)
    u0, v0 = np.tile(u0, 3), np.tile(v0, 3)
    width = np.full(face.size, 1.0 / START_SPLITS)
    lower, point, normal = -np.inf, None, None
    settled = -np.inf  # largest bound among the cones set aside
    cells = 0
    bounds = np.array([np.inf])
    for _ in range(MAX_LEVELS):
        D = _corner_directions(face, u0, u0 + width, v0, v0 + width)
        P = shape.radial_surface_points(D.reshape(-1, 3))
        Nrm = shape.outward_normals(P)
        lam = arm_lambda(P, inertia)
        j = int(np.argmax(lam))
        if lam[j] > lower:
            lower, point, normal = float(lam[j]), P[j], Nrm[j]
        normals, offsets = _cell_planes(shape, D, P.reshape(-1, 4, 3), Nrm.reshape(-1, 4, 3))
        bounds = _cell_bounds(normals, offsets, inertia, scale)
        cells += face.size
        open_ = bounds > lower * (1.0 + rtol)
        if np.any(~open_):
            settled = max(settled, float(np.max(bounds[~open_])))
        if not np.any(open_) or 4 * np.count_nonzero(open_) > MAX_CELLS:
            break
        face, u0, v0, width = (np.repeat(x[open_], 4) for x in (face, u0, v0, width))
        width = width / 2.0
        quarter = np.tile(np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float), (face.size // 4, 1))
        u0 = u0 + quarter[:, 0] * width
        v0 = v0 + quarter[:, 1] * width
    still_open = bounds[bounds > lower * (1.0 + rtol)]
    upper = max(settled, float(np.max(still_open)) if still_open.size else -np.inf, lower)
    upper = min(upper, crude)
    assert point is not None and normal is not None  # the first cell always gives a lower bound
    return ArmSupremum(upper, min(lower, upper), _vec3(point), _vec3(normal),
                        "octant cones", cells)
