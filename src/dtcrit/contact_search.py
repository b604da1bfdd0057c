"""Admissible contacts of two convex particles and the suprema behind ``dtcrit.a_bound``.

Peng et al. (2020), Section 3, keep only the diagonal of the coefficient matrix ``A`` of the
contact force in three tip-to-tip configurations and state (Eq 26) that
``A_max = a1^2/Ixx1 + a2^2/Ixx2 + 1/m1 + 1/m2`` bounds it.  For an arbitrary contact

    A = (1/m1 + 1/m2) 1 + T1 + T2,   T_i = Q_i [p_i]x^T I_i^-1 [p_i]x Q_i^T,

where ``p_i`` is the contact point in particle ``i``'s local frame and ``Q_i`` its orientation
(body -> global).  This module provides

* :func:`arm_term_supremum`: bounds on ``S = sup over the body of lambda_max([p]x^T I^-1 [p]x)``.
  ``lambda_max`` of that matrix is a maximum of convex quadratics in ``p`` (``v^T T v =
  |I^-1/2 (p x v)|^2``), hence convex in ``p``: over a convex body its supremum sits at extreme
  points.  Polyhedra: exact maximum over the vertices.  Isotropic inertia: ``max_arm^2 / I``
  exactly.  Smooth bodies: outer approximation by support half-spaces (every polytope
  ``{x : n.x <= h(n)}`` contains the body, so the maximum over its vertices is an upper bound),
  refined where the bound is largest until it meets the best value found on the surface.
* :func:`contact_frames` / :func:`random_contacts`: admissible contacts (the two outward normals
  opposite, particle 2 free to spin about the normal), for sampling.
* :func:`search_supremum`: random sampling plus local maximisation of ``lambda_max(A)`` over
  admissible contacts (the searched supremum the derivation record compares with).
* :func:`mirror_contact`: for two identical particles, the admissible contact (particle 2 is
  particle 1 turned by a half-turn about an axis normal to the contact normal and to the top
  eigenvector) at which ``lambda_max(A) = 2/m + 2 S`` is attained.

No SymPy: NumPy, SciPy and the generated kernels only.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._generated import contact as _k

# Cutting-plane controls for smooth bodies (the returned upper bound is valid whatever they are).
SUP_RTOL = 1e-7
"""Stop refining when the upper bound is within this relative distance of the best surface value."""
SUP_MAX_HALFSPACES = 12000
SUP_MAX_ITERATIONS = 80
_SUPPORT_SLACK = 1e-12  # relative inflation of h(n): rounding in the support point never cuts the body


# ============================================================================================
# Small linear algebra (vectorised over a leading axis)
# ============================================================================================
def skew(v: np.ndarray) -> np.ndarray:
    """``[v]x`` for each row of ``v`` (shape (..., 3) -> (..., 3, 3))."""
    v = np.asarray(v, dtype=float)
    z = np.zeros(v.shape[:-1])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([np.stack([z, -w, y], -1), np.stack([w, z, -x], -1), np.stack([-y, x, z], -1)], -2)


def arm_terms_local(points: np.ndarray, inertia) -> np.ndarray:
    """``[p]x^T I^-1 [p]x`` (generated kernel ``arm_term``) for each row of ``points`` (local frame)."""
    p = np.atleast_2d(np.asarray(points, dtype=float))
    ixx, iyy, izz = (float(i) for i in inertia)
    txx, tyy, tzz, txy, txz, tyz = (np.broadcast_to(np.asarray(t, float), p.shape[:1])
                                    for t in _k.arm_term(p[:, 0], p[:, 1], p[:, 2], ixx, iyy, izz))
    return np.stack([np.stack([txx, txy, txz], -1), np.stack([txy, tyy, tyz], -1),
                     np.stack([txz, tyz, tzz], -1)], -2)


def largest_eigenvalue(sym: np.ndarray) -> np.ndarray:
    """Largest eigenvalue of each symmetric 3x3 matrix in ``sym`` (..., 3, 3)."""
    return np.linalg.eigvalsh(sym)[..., -1]


def arm_lambda(points: np.ndarray, inertia) -> np.ndarray:
    """``lambda_max([p]x^T I^-1 [p]x)`` for each row of ``points``."""
    return largest_eigenvalue(arm_terms_local(points, inertia))


def rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Proper rotations (body -> global style, ``Q a = b``) taking unit rows ``a`` to unit rows ``b``."""
    a, b = np.atleast_2d(a).astype(float), np.atleast_2d(b).astype(float)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    b = b / np.linalg.norm(b, axis=1, keepdims=True)
    axis = np.cross(a, b)
    s = np.linalg.norm(axis, axis=1)
    c = np.einsum("ij,ij->i", a, b)
    # antiparallel: half-turn about any axis normal to a
    helper = np.eye(3)[np.argmin(np.abs(a), axis=1)]
    perp = np.cross(a, helper)
    perp /= np.linalg.norm(perp, axis=1, keepdims=True)
    use_perp = s < 1e-12
    k = np.where(use_perp[:, None], perp, axis / np.where(s > 0, s, 1.0)[:, None])
    angle = np.where(use_perp, np.where(c > 0, 0.0, math.pi), np.arctan2(s, c))
    return axis_angle(k, angle)


def axis_angle(axis: np.ndarray, angle) -> np.ndarray:
    """Rodrigues: rotation matrices (active, ``v -> Q v``) about unit ``axis`` rows by ``angle``."""
    k = np.atleast_2d(axis).astype(float)
    k = k / np.linalg.norm(k, axis=1, keepdims=True)
    th = np.broadcast_to(np.asarray(angle, float), k.shape[:1])
    K = skew(k)
    s, c = np.sin(th)[:, None, None], np.cos(th)[:, None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def random_rotations(rng: np.random.Generator, n: int) -> np.ndarray:
    """Uniformly distributed rotations (normalised Gaussian quaternions, Eq 7 kernel, transposed to body->global)."""
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    R = np.stack([np.asarray(e, float) for e in _k.rotation_matrix(q[:, 0], q[:, 1], q[:, 2], q[:, 3])], -1)
    return R.reshape(n, 3, 3).transpose(0, 2, 1)


def unit_vectors(rng: np.random.Generator, n: int) -> np.ndarray:
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def fibonacci_sphere(n: int) -> np.ndarray:
    """``n`` nearly uniform unit vectors (deterministic)."""
    i = np.arange(n) + 0.5
    polar = np.arccos(1.0 - 2.0 * i / n)
    azim = math.pi * (1.0 + math.sqrt(5.0)) * i
    return np.column_stack([np.cos(azim) * np.sin(polar), np.sin(azim) * np.sin(polar), np.cos(polar)])


# ============================================================================================
# Per-particle supremum S = sup lambda_max([p]x^T I^-1 [p]x) over the body
# ============================================================================================
@dataclass(frozen=True)
class ArmSupremum:
    """Bounds on ``S`` for one shape: ``lower <= S <= upper`` [1/kg].

    ``point`` is a surface point (local frame) where ``lower`` is attained, ``normal`` an outward
    unit normal there (in the normal cone at a vertex: ``support(normal) == point``), and
    ``method`` says how the bounds were obtained (``"vertices"``, ``"isotropic"`` or
    ``"support cutting planes"``).
    """

    upper: float
    lower: float
    point: tuple[float, float, float]
    normal: tuple[float, float, float]
    method: str
    halfspaces: int = 0

    @property
    def relative_gap(self) -> float:
        return self.upper / self.lower - 1.0


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
    )


_CACHE: dict[tuple, ArmSupremum] = {}
_CACHE_SIZE = 512


def arm_term_supremum(shape) -> ArmSupremum:
    """Bounds on ``sup over the body of lambda_max([p]x^T I^-1 [p]x)`` (cached per shape geometry)."""
    key = _shape_key(shape)
    hit = _CACHE.get(key)
    if hit is None:
        hit = _arm_term_supremum(shape)
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = hit
    return hit


def _arm_term_supremum(shape) -> ArmSupremum:
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
        d, p = _farthest_support_point(shape)
        return ArmSupremum(crude, min(crude, float(arm_lambda(p[None, :], inertia)[0])), tuple(p), tuple(d), "isotropic")
    return _cutting_planes(shape, inertia, crude)


def _vertex_normal(shape, vertex: np.ndarray) -> tuple[float, float, float]:
    """A unit direction whose support point is ``vertex`` (in its normal cone): the vertex's own
    direction when that works, else the sampled vertex normal (mean of the adjacent face normals)."""
    d = vertex / np.linalg.norm(vertex)
    if np.allclose(shape.support(d), vertex, rtol=0, atol=1e-12 * np.linalg.norm(vertex)):
        return tuple(d)
    pts, nrm = shape.surface_points(1)  # the vertices come first, with their mean face normals
    return tuple(nrm[int(np.argmin(np.linalg.norm(pts - vertex, axis=1)))])


def _farthest_support_point(shape) -> tuple[np.ndarray, np.ndarray]:
    """Direction and support point of largest norm (a surface point at distance ~ ``max_arm``):
    dense directions, then a few rounds of local random refinement."""
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


def _support_planes(shape, normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    pts = np.asarray(shape.support(normals), dtype=float)
    h = np.einsum("ij,ij->i", normals, pts)
    return pts, h + _SUPPORT_SLACK * np.linalg.norm(pts, axis=1)


def _cut_directions(shape, outside: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Directions ``n`` with (ideally) ``n.v > h(n)`` for points ``v`` outside the body: gradient ascent
    of the violation ``n.v - h(n)`` (concave in ``n``; its supergradient is ``v - support(n)``) on
    the sphere from each row of ``start``, keeping only improving steps."""
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


def _cutting_planes(shape, inertia: np.ndarray, crude: float) -> ArmSupremum:
    normals = np.vstack([fibonacci_sphere(240), np.eye(3), -np.eye(3)])
    pts, h = _support_planes(shape, normals)
    lam = arm_lambda(pts, inertia)
    best = int(np.argmax(lam))
    lower, point, normal = float(lam[best]), pts[best], normals[best]
    upper = crude
    for _ in range(SUP_MAX_ITERATIONS):
        from scipy.spatial import HalfspaceIntersection, QhullError  # lazy: keeps start-up short

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
        p_new, h_new = _support_planes(shape, n_new)
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


# ============================================================================================
# Admissible contacts
# ============================================================================================
@dataclass
class Contacts:
    """A batch of contacts (arrays with a leading axis of length N).

    ``p1, p2``: contact points in the local frames; ``n1``: outward normal of particle 1 (local);
    ``Q1, Q2``: orientations (body -> global, so the paper's ``R_i = Q_i^T``, Eq 5);
    ``r1, r2``: contact arms ``x_c - x_i`` in global components (Eqs 1-2); ``normal``: global
    outward normal of particle 1 (particle 2's is its negative).
    """

    p1: np.ndarray
    p2: np.ndarray
    Q1: np.ndarray
    Q2: np.ndarray
    r1: np.ndarray
    r2: np.ndarray
    normal: np.ndarray

    def coefficient_matrices(self, shape1, shape2) -> np.ndarray:
        """``A`` (global frame) for each contact."""
        T1 = self.Q1 @ arm_terms_local(self.p1, shape1.inertia) @ self.Q1.transpose(0, 2, 1)
        T2 = self.Q2 @ arm_terms_local(self.p2, shape2.inertia) @ self.Q2.transpose(0, 2, 1)
        return (1.0 / shape1.mass + 1.0 / shape2.mass) * np.eye(3) + T1 + T2

    def largest_eigenvalues(self, shape1, shape2) -> np.ndarray:
        return largest_eigenvalue(self.coefficient_matrices(shape1, shape2))


def contact_frames(p1, n1, p2, n2, spin, Q1=None) -> Contacts:
    """Place particle 2 against particle 1: its outward normal ``n2`` (local) is turned onto minus
    the global normal ``Q1 n1`` and then spun by ``spin`` [rad] about that normal."""
    p1, n1, p2, n2 = (np.atleast_2d(np.asarray(x, float)) for x in (p1, n1, p2, n2))
    N = max(x.shape[0] for x in (p1, n1, p2, n2))
    p1, n1, p2, n2 = (np.broadcast_to(x, (N, 3)) for x in (p1, n1, p2, n2))
    Q1 = np.broadcast_to(np.eye(3), (N, 3, 3)) if Q1 is None else np.broadcast_to(np.asarray(Q1, float), (N, 3, 3))
    normal = np.einsum("nij,nj->ni", Q1, n1 / np.linalg.norm(n1, axis=1, keepdims=True))
    align = rotation_between(n2, -normal)
    Q2 = axis_angle(normal, np.broadcast_to(np.asarray(spin, float), (N,))) @ align
    r1 = np.einsum("nij,nj->ni", Q1, p1)
    r2 = np.einsum("nij,nj->ni", Q2, p2)
    return Contacts(np.array(p1), np.array(p2), np.array(Q1), Q2, r1, r2, normal)


def _support_samples(shape, rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Support points of random directions with those directions as normals (for a polyhedron: its
    vertices, with normals spread over their normal cones)."""
    d = unit_vectors(rng, n)
    return np.asarray(shape.support(d), float), d


def surface_samples(shape, rng: np.random.Generator, n: int, n_surface: int = 400) -> tuple[np.ndarray, np.ndarray]:
    """``n`` surface points and outward normals (local frame): half support points of random
    directions (every vertex with normals spread over its cone for polyhedra), half drawn from
    ``shape.surface_points`` (faces, edges and smooth regions with their normals)."""
    k = n // 2
    p_a, n_a = _support_samples(shape, rng, k)
    pts, nrm = shape.surface_points(n_surface)
    idx = rng.integers(0, pts.shape[0], size=n - k)
    return np.vstack([p_a, pts[idx]]), np.vstack([n_a, nrm[idx]])


def random_contacts(shape1, shape2, n: int, seed: int = 0) -> Contacts:
    """``n`` random admissible contacts: random surface points and normals on both particles, a
    random orientation of particle 1 and a random spin of particle 2 about the common normal."""
    rng = np.random.default_rng(seed)
    p1, n1 = surface_samples(shape1, rng, n)
    p2, n2 = surface_samples(shape2, rng, n)
    spin = rng.uniform(0.0, 2.0 * math.pi, size=n)
    return contact_frames(p1, n1, p2, n2, spin, random_rotations(rng, n))


# ============================================================================================
# Searched supremum of lambda_max(A) over admissible contacts
# ============================================================================================
def _direction(angles: np.ndarray) -> np.ndarray:
    t, f = angles[..., 0], angles[..., 1]
    return np.stack([np.cos(f) * np.sin(t), np.sin(f) * np.sin(t), np.cos(t)], -1)


@dataclass(frozen=True)
class SearchResult:
    """Largest ``lambda_max(A)`` found [1/kg] and the contact that gives it (one-element batch)."""

    value: float
    contact: Contacts
    evaluations: int


def search_supremum(shape1, shape2, n_random: int = 4000, n_starts: int = 8, iterations: int = 200,
                    seed: int = 0) -> SearchResult:
    """Maximise ``lambda_max(A)`` over admissible contacts.

    Random admissible contacts (:func:`random_contacts`) first; then, from the ``n_starts`` best of
    them, a vectorised (1+16) evolution strategy with step-size adaptation over the parameters
    (polar angles of particle 1's normal, of particle 2's normal, spin about the common normal),
    the contact points being the support points of the normals: by convexity of ``lambda_max`` in
    the contact points, at fixed normals the maximum over the touching faces is at their vertices.
    """
    rng = np.random.default_rng(seed)
    batch = random_contacts(shape1, shape2, n_random, seed)
    lam = batch.largest_eigenvalues(shape1, shape2)
    evaluations = n_random

    def build(x):
        n1, n2 = _direction(x[:, 0:2]), _direction(x[:, 2:4])
        return contact_frames(shape1.support(n1), n1, shape2.support(n2), n2, x[:, 4])

    def value(x):
        return build(x).largest_eigenvalues(shape1, shape2)

    order = np.argsort(-lam)[:n_starts]
    n1 = np.einsum("nji,nj->ni", batch.Q1[order], batch.normal[order])  # local normal of particle 1
    n2 = -np.einsum("nji,nj->ni", batch.Q2[order], batch.normal[order])
    rel = batch.Q1[order].transpose(0, 2, 1) @ batch.Q2[order] @ rotation_between(n2, -n1).transpose(0, 2, 1)
    u = np.cross(n1, np.eye(3)[np.argmin(np.abs(n1), axis=1)])
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    ru = np.einsum("nij,nj->ni", rel, u)
    spin = np.arctan2(np.einsum("ni,ni->n", np.cross(u, ru), n1), np.einsum("ni,ni->n", u, ru))
    x = np.column_stack([np.arccos(np.clip(n1[:, 2], -1, 1)), np.arctan2(n1[:, 1], n1[:, 0]),
                         np.arccos(np.clip(n2[:, 2], -1, 1)), np.arctan2(n2[:, 1], n2[:, 0]), spin])
    fx = value(x)
    evaluations += x.shape[0]
    sigma = np.full(x.shape[0], 0.05)
    children = 16
    for _ in range(iterations):
        trial = x[:, None, :] + sigma[:, None, None] * rng.normal(size=(x.shape[0], children, 5))
        ft = value(trial.reshape(-1, 5)).reshape(x.shape[0], children)
        evaluations += ft.size
        j = np.argmax(ft, axis=1)
        better = ft[np.arange(x.shape[0]), j] > fx
        x[better] = trial[better, j[better]]
        fx[better] = ft[better, j[better]]
        sigma = np.clip(np.where(better, sigma * 1.5, sigma * 0.6), 1e-9, 1.0)
    k = int(np.argmax(fx))
    i = int(np.argmax(lam))
    if lam[i] >= fx[k]:
        one = Contacts(*(np.asarray(getattr(batch, f))[i : i + 1] for f in ("p1", "p2", "Q1", "Q2", "r1", "r2", "normal")))
        return SearchResult(float(lam[i]), one, evaluations)
    return SearchResult(float(fx[k]), build(x[k : k + 1]), evaluations)


def mirror_contact(shape, point, normal) -> Contacts:
    """Two copies of ``shape`` touching at the same local ``point`` with outward ``normal`` (local,
    in the normal cone at ``point``), particle 2 turned by a half-turn about the axis normal to
    both the contact normal and the top eigenvector ``v`` of ``[p]x^T I^-1 [p]x``: then particle
    2's top eigenvector is ``-v`` and ``lambda_max(A) = 2/m + 2 lambda_max(T(p))``."""
    p = np.asarray(point, float)
    nrm = np.asarray(normal, float) / np.linalg.norm(normal)
    _, vecs = np.linalg.eigh(arm_terms_local(p[None, :], shape.inertia)[0])
    v = vecs[:, -1]
    axis = np.cross(nrm, v)
    if np.linalg.norm(axis) < 1e-12:  # v along the normal: any axis normal to it
        axis = np.cross(nrm, np.eye(3)[int(np.argmin(np.abs(nrm)))])
    Q2 = axis_angle(axis[None, :], math.pi)
    r1 = p[None, :]
    r2 = np.einsum("nij,j->ni", Q2, p)
    return Contacts(r1.copy(), p[None, :].copy(), np.eye(3)[None], Q2, r1, r2, nrm[None, :])
