"""Surface geometry of the superquadric family (sphere, ellipsoid, convex superquadric).

Convention (Barr 1981; Jaklic et al. 2000)::

    (|x/a|^(2/eps2) + |y/b|^(2/eps2))^(eps2/eps1) + |z/c|^(2/eps1) <= 1.

Support points (Hoelder's equality case), radial projection onto the surface, outward normals,
the largest centre-to-surface distance, and deterministic surface samples.
"""
from __future__ import annotations

import math

import numpy as np


def _holder_maximiser(g: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray]:
    """Maximise ``g . x`` over the unit l_p ball (p >= 1), row-wise.

    Hoelder's equality case: ``x_i = sign(g_i) (|g_i| / ||g||_q)^(q-1)`` with ``1/p + 1/q = 1`` and
    maximum ``||g||_q``.  Computed with ratios to the largest ``|g_i|`` so nothing overflows; for
    p = 1 (q = inf) ties share the weight equally.
    """
    absg = np.abs(g)
    big = np.max(absg, axis=1, keepdims=True)
    safe = np.where(big > 0, big, 1.0)
    r = absg / safe
    if p == 1.0:
        top = (r == 1.0) & (big > 0)
        x = np.sign(g) * top / np.maximum(np.sum(top, axis=1, keepdims=True), 1)
        return x, big[:, 0]
    q = p / (p - 1.0)
    with np.errstate(under="ignore"):
        ratio = np.sum(r**q, axis=1, keepdims=True) ** (1.0 / q)  # ||g||_q / max|g_i|, in [1, 2]
        ratio = np.where(big > 0, ratio, 1.0)
        x = np.sign(g) * (r / ratio) ** (q - 1.0)
    x = np.where(big > 0, x, 0.0)
    return x, (big * ratio)[:, 0]


def _superquadric_support(axes: np.ndarray, e1: float, e2: float, d: np.ndarray) -> np.ndarray:
    """Support point of the superquadric along each row of ``d``.

    In scaled coordinates (u, v, w) = (x/a, y/b, z/c) the body is the unit ball of the nested norm
    ``|| (||(u, v)||_{2/eps2}, w) ||_{2/eps1}``; maximising the linear form ``(a d_x, b d_y, c d_z)``
    is Hoelder's equality case applied twice (inner in the x-y plane, outer with the z part).
    """
    g = d * axes
    inner, inner_norm = _holder_maximiser(g[:, :2], 2.0 / e2)
    outer, _ = _holder_maximiser(np.column_stack([inner_norm, g[:, 2]]), 2.0 / e1)
    uvw = np.column_stack([outer[:, :1] * inner, outer[:, 1]])
    return uvw * axes


def _log_abs(x: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore"):
        return np.log(np.abs(x))


def _superquadric_radial_projection(p: np.ndarray, axes: np.ndarray, e1: float, e2: float) -> np.ndarray:
    """Scale each (non-zero) point along its ray onto the surface: ``p F(p)^(-eps1/2)``.

    F (the inside-outside function) is homogeneous: ``F(t p) = t^(2/eps1) F(p)``.  It is evaluated
    in logarithms (``logaddexp``) so that exponents up to 2/eps = 200 neither overflow nor underflow.
    """
    lx, ly, lz = (_log_abs(p[:, k] / axes[k]) for k in range(3))
    log_g = np.logaddexp(2.0 / e2 * lx, 2.0 / e2 * ly)
    log_f = np.logaddexp(e2 / e1 * log_g, 2.0 / e1 * lz)
    return p * np.exp(-0.5 * e1 * log_f)[:, None]


def _superquadric_normals(q: np.ndarray, axes: np.ndarray, e1: float, e2: float) -> np.ndarray:
    """Outward unit normals (normalised gradient of F) at surface points ``q``.

    ``grad F ~ (G^(e2/e1-1) u^(2/e2-1)/a, G^(e2/e1-1) v^(2/e2-1)/b, w^(2/e1-1)/c)`` with signs, where
    u = |x/a|, v = |y/b|, w = |z/c| and G = u^(2/e2) + v^(2/e2).  Components are formed in logarithms
    and scaled by the largest; a component whose coordinate is zero is zero (at edges of eps = 2
    bodies this gives the mean of the two face normals).
    """
    lu, lv, lw = (_log_abs(q[:, k] / axes[k]) for k in range(3))
    log_g = np.logaddexp(2.0 / e2 * lu, 2.0 / e2 * lv)
    with np.errstate(invalid="ignore"):
        cx = (e2 / e1 - 1.0) * log_g + (2.0 / e2 - 1.0) * lu - math.log(axes[0])
        cy = (e2 / e1 - 1.0) * log_g + (2.0 / e2 - 1.0) * lv - math.log(axes[1])
        cz = (2.0 / e1 - 1.0) * lw - math.log(axes[2])
    comps = np.column_stack([cx, cy, cz])
    comps = np.where(q == 0.0, -np.inf, comps)
    top = np.max(comps, axis=1, keepdims=True)
    n = np.sign(q) * np.exp(comps - top)
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def _superellipse_max_radius(p: float, q: float, e: float) -> float:
    """``max over theta of sqrt(p^2 cos^(2e) theta + q^2 sin^(2e) theta)`` on [0, pi/2].

    With u = cos^2 theta the squared radius ``p^2 u^e + q^2 (1-u)^e`` is convex in u for e >= 1
    (maximum max(p, q) at an end) and concave for e < 1, where the stationary point gives
    ``(p^(2k) + q^(2k))^(1/(2k))`` with k = 1/(1 - e)  (an l_{2k} norm; -> sqrt(p^2 + q^2) as e -> 0).
    """
    hi, lo = max(p, q), min(p, q)
    if e >= 1.0:
        return hi
    k2 = 2.0 / (1.0 - e)
    return hi * (1.0 + (lo / hi) ** k2) ** (1.0 / k2)


def superquadric_max_arm(a: float, b: float, c: float, eps1: float, eps2: float) -> float:
    """Largest centre-to-surface distance of the superquadric.

    On the surface (a C^e1(eta) C^e2(w), b C^e1(eta) S^e2(w), c S^e1(eta)) the squared distance is
    ``C^(2 e1)(eta) R2(w) + c^2 S^(2 e1)(eta)`` with ``R2 = a^2 C^(2 e2) + b^2 S^(2 e2)``; the maximum over w
    does not depend on eta, so the 2-D search is two nested 1-D maxima
    (:func:`_superellipse_max_radius`).

    Parameters
    ----------
    a, b, c : float
        Semi-axes [m].
    eps1, eps2 : float
        Shape exponents.

    Returns
    -------
    float
        The largest distance [m].
    """
    return _superellipse_max_radius(_superellipse_max_radius(a, b, eps2), c, eps1)


def _half_offset_grid(half_length: float, delta: float) -> np.ndarray:
    """``(k + 1/2) delta`` for every integer ``k`` with ``|(k + 1/2) delta| <= half_length``
    (symmetric about 0, which it never contains).
    """
    m = math.floor(half_length / delta - 0.5)
    return (np.arange(-m - 1, m + 1) + 0.5) * delta


def _superquadric_ray_hits(axes: np.ndarray, e1: float, e2: float, delta: float):
    """Surface points hit by rays parallel to each axis through a square grid of spacing ``delta``.

    Along a ray the inside-outside equation has a closed-form root, e.g. for rays along z
    ``|z/c|^(2/eps1) = 1 - (|x/a|^(2/eps2) + |y/b|^(2/eps2))^(eps2/eps1)``.  Near a surface point with
    unit normal n the family along the axis of largest |n_k| >= 1/sqrt(3) leaves gaps of at most
    sqrt(3) delta, so the union covers the surface with no parametrisation distortion.

    The grid is offset by half a spacing (:func:`_half_offset_grid`): with ``delta = h/4`` a grid
    through the origin would put half the hits exactly on the faces of the thinning cubes
    (:func:`_voxel_thin`), where the last bit of ``p/h`` decides the cube and with it the count, so
    the samples would change with the processor's SIMD loops.

    Returns ``(points, dominant_area)``: all hits, and for each hit the area it stands for if its
    ray family is the one of largest |n_k| there (``delta^2 / |n_k|``), else 0; the sum estimates
    the surface area.
    """
    p1, p2 = 2.0 / e1, 2.0 / e2
    out, area = [], []
    for k in range(3):
        i, j = [m for m in range(3) if m != k]
        gi = _half_offset_grid(axes[i], delta)
        gj = _half_offset_grid(axes[j], delta)
        ui, uj = np.meshgrid(np.abs(gi) / axes[i], np.abs(gj) / axes[j], indexing="ij")
        si, sj = np.meshgrid(gi, gj, indexing="ij")
        ui, uj, si, sj = ui.ravel(), uj.ravel(), si.ravel(), sj.ravel()
        with np.errstate(under="ignore", invalid="ignore"):
            if k == 2:  # (x, y) given
                root = 1.0 - (ui**p2 + uj**p2) ** (e2 / e1)
                uk = np.where(root >= 0, np.abs(root) ** (1.0 / p1), np.nan)
            else:  # x or y along the ray; the other in-plane coordinate and z given
                root = np.where(uj <= 1.0, (1.0 - uj**p1) ** (e1 / e2), np.nan) - ui**p2
                uk = np.where(root >= 0, np.abs(root) ** (1.0 / p2), np.nan)
        ok = np.isfinite(uk)
        for sign in (1.0, -1.0):
            pt = np.empty((int(ok.sum()), 3))
            pt[:, i], pt[:, j], pt[:, k] = si[ok], sj[ok], sign * uk[ok] * axes[k]
            pt = _superquadric_radial_projection(pt, axes, e1, e2)
            nrm = _superquadric_normals(pt, axes, e1, e2)
            dominant = np.argmax(np.abs(nrm), axis=1) == k
            out.append(pt)
            area.append(np.where(dominant, delta**2 / np.maximum(np.abs(nrm[:, k]), 1e-300), 0.0))
    return np.concatenate(out), np.concatenate(area)


def _voxel_thin(points: np.ndarray, h: float) -> np.ndarray:
    """Indices of one point per occupied cube of side ``h`` (the one nearest the cube centre).

    Cubes are centred on the lattice h Z^3, so the selection is symmetric about the origin up to
    ties; the order is lexicographic in the cube index (deterministic).
    """
    cell = np.floor(points / h + 0.5)
    dist = np.linalg.norm(points / h - cell, axis=1)
    order = np.lexsort((dist, cell[:, 2], cell[:, 1], cell[:, 0]))
    sorted_cells = cell[order]
    first = np.ones(order.size, dtype=bool)
    first[1:] = np.any(sorted_cells[1:] != sorted_cells[:-1], axis=1)
    return order[first]


def _superquadric_surface_points(n: int, axes: np.ndarray, e1: float, e2: float):
    """About ``n`` points (at least the six axis tips) spread roughly uniformly in area.

    Dense candidates (:func:`_superquadric_ray_hits`) are thinned to one per cube of side h, with
    h chosen from the estimated area so that the count is close to ``n``.
    """
    tips = np.zeros((6, 3))
    tips[[0, 2, 4], [0, 1, 2]] = axes
    tips[[1, 3, 5], [0, 1, 2]] = -axes
    target = n - tips.shape[0]
    if target > 0:
        a, b, c = axes
        coarse = math.sqrt(4.0 * (a * b + b * c + c * a) / 2.0e4)  # about 2e4 rays in all
        _, coarse_area = _superquadric_ray_hits(axes, e1, e2, coarse)
        area = float(np.sum(coarse_area))
        h = math.sqrt(1.5 * area / target)
        delta = h / 4.0
        pts, _ = _superquadric_ray_hits(axes, e1, e2, delta)
        lo, hi = 0.0, math.inf  # bracket of the cube side: count(lo) > target > count(hi)
        best = None
        for _ in range(24):
            if delta > h / 3.0:  # keep the hits at least three times denser than the cubes
                delta = h / 4.0
                pts, _ = _superquadric_ray_hits(axes, e1, e2, delta)
            chosen = _voxel_thin(pts, h)
            if best is None or abs(chosen.size - target) < abs(best[0].size - target):
                best = (chosen, pts, h)
            if abs(chosen.size - target) <= 0.02 * target + 1:
                break
            if chosen.size > target:
                lo = h
            else:
                hi = h
            h = math.sqrt(lo * hi) if 0 < lo and hi < math.inf else h * math.sqrt(chosen.size / target)
        assert best is not None  # set on the first pass
        chosen, pts, h = best
        chosen = pts[chosen]
        from dtcrit.bodies.hull import nearest_neighbours  # imported only when a sample is thinned

        near_tip = nearest_neighbours(chosen, tips)[0] < 0.5 * h
        points = np.concatenate([tips, chosen[~near_tip]])
    else:
        points = tips
    return points, _superquadric_normals(points, axes, e1, e2)
