"""The bound ``Phi_s`` of one sphere species (``derivations/proofs/dense_packing_bound.md``, Lemmas 6-9).

``_phi_bound`` bounds ``sup lambda_max(sum_e Q_e)`` over every arrangement of at most ``z`` contact
normals pairwise at least ``2 psi`` apart by branch and bound over cells of the sphere
(:mod:`dtcrit.scenes.dense_cells`); :func:`dtcrit.scenes.dense_spheres.dense_omega2_bound` takes the
largest over the species.  NumPy only.
"""
from __future__ import annotations
import math
import numpy as np
from dtcrit.scenes.dense_cells import SAFETY, _SphereCells, _cells, _variants, end_matrix


# ----------------------------------------------------------------------------- the kernel F_v (Lemmas 6-7)

def _f_coefficients(v, pars, psi):
    """For reduced test vectors ``v`` (nv, 3) -- ``x = v1 e1``, ``y = v2 e1 + v3 e2`` (Lemma 4) -- the
    cap-inverted kernel ``F_v(m) = kappa + 2 g'.m + m^T H' m`` (Lemma 6) as (nv,) kappa, (nv, 3) g',
    (nv, 3, 3) traceless H'.
    """
    alpha, beta, gamma, gr, gw = pars[:5]
    c = math.cos(psi)
    lam1, lam2 = 0.5 * (1.0 + c), 0.5 * c * (1.0 + c)
    v1, v2, v3 = v[:, 0], v[:, 1], v[:, 2]
    nv = len(v)
    x = np.zeros((nv, 3))
    x[:, 0] = v1
    y = np.zeros((nv, 3))
    y[:, 0], y[:, 1] = v2, v3
    c0 = beta * v1 * v1 + (gamma + gr) * (v2 * v2 + v3 * v3)
    h = (alpha - beta) * x[:, :, None] * x[:, None, :] + (gw - gamma - gr) * y[:, :, None] * y[:, None, :]
    g = np.zeros((nv, 3))
    g[:, 2] = math.sqrt(beta * gamma) * v1 * v3  # g = -sqrt(beta gamma) (y x x), y x x = -v1 v3 e3
    tr = np.trace(h, axis1=1, axis2=2) / 3.0
    h0 = h - tr[:, None, None] * np.eye(3)
    return c0 + tr, g / lam1, h0 / lam2


def _coefficient_vector(kappa, gp, hp):
    """Coefficients of F in the basis of ``_SphereCells.moments``."""
    return np.stack([kappa, 2 * gp[:, 0], 2 * gp[:, 1], 2 * gp[:, 2], hp[:, 0, 0], hp[:, 1, 1], hp[:, 2, 2],
                     2 * hp[:, 0, 1], 2 * hp[:, 0, 2], 2 * hp[:, 1, 2]], 1)


def _cell_bounds(coef, gp, hp, cells: _SphereCells):
    """Per cell: centre value, exact integral and rigorous upper / lower bounds of the quadratic
    ``F = kappa + 2 g'.m + m^T H' m`` (Lemma 8: second-order Taylor with the radial/tangential split).
    """
    f_c = coef @ cells.basis_at_centre.T  # (nv, K) values at the centres
    integral = coef @ cells.moments.T  # (nv, K) exact integrals over the cells
    cen = cells.centre
    grad = 2.0 * gp[:, None, :] + 2.0 * np.einsum("vij,kj->vki", hp, cen)  # R^3 gradient at the centres
    rad = np.einsum("vki,ki->vk", grad, cen)
    tang = np.sqrt(np.clip(np.einsum("vki,vki->vk", grad, grad) - rad * rad, 0.0, None))
    ev = np.linalg.eigvalsh(hp)
    r = cells.radius[None, :]
    upper = f_c + tang * r + (0.5 * np.abs(rad) + np.maximum(ev[:, -1:], 0.0)) * r * r
    lower = f_c - tang * r - (0.5 * np.abs(rad) + np.maximum(-ev[:, :1], 0.0)) * r * r
    return f_c, integral, upper, lower


def _bathtub_upper(v, pars, psi, z_eff, cells: _SphereCells):
    """Rigorous upper bound on ``B(v) = (1/|C|) sup_{|S| <= z_eff |C|} int_S max_arm F_v`` (Lemmas 7-8) per row of v."""
    cap = 2.0 * math.pi * (1.0 - math.cos(psi))
    area_total = z_eff * cap
    kernels = []
    for q in _variants(pars):
        kappa, gp, hp = _f_coefficients(v, q, psi)
        kernels.append((kappa, gp, hp, _coefficient_vector(kappa, gp, hp)))
    f_c, integral, upper, lower = _cell_bounds(kernels[0][3], kernels[0][1], kernels[0][2], cells)
    if len(kernels) == 2:  # max(F0, F1): bounds of the max; integral via F1 + (F0 - F1)^+ and F0 + (F1 - F0)^+
        k0, k1 = kernels
        f_c1, int1, up1, lo1 = _cell_bounds(k1[3], k1[1], k1[2], cells)
        _, _, up_d, _ = _cell_bounds(k0[3] - k1[3], k0[1] - k1[1], k0[2] - k1[2], cells)
        _, _, up_e, _ = _cell_bounds(k1[3] - k0[3], k1[1] - k0[1], k1[2] - k0[2], cells)
        a = cells.area[None, :]
        integral = np.minimum(int1 + np.clip(up_d, 0.0, None) * a, integral + np.clip(up_e, 0.0, None) * a)
        f_c, upper, lower = np.maximum(f_c, f_c1), np.maximum(upper, up1), np.maximum(lower, lo1)
    a = cells.area[None, :]
    # threshold guess: the level whose superlevel set (by centre values) has area area_total
    order = np.argsort(-f_c, axis=1)
    cum = np.cumsum(np.take_along_axis(np.broadcast_to(a, f_c.shape), order, 1), axis=1)
    idx = np.minimum((cum < area_total).sum(axis=1), f_c.shape[1] - 1)
    t0 = np.maximum(np.take_along_axis(f_c, order, 1)[np.arange(len(v)), idx], 0.0)
    spread = np.maximum(np.abs(t0), 1e-300)
    best = np.full(len(v), np.inf)
    for rel in (-2e-2, -5e-3, -1e-3, 0.0, 1e-3, 5e-3, 2e-2):
        t = np.maximum(t0 + rel * spread, 0.0)[:, None]  # any t >= 0 gives a valid bound (Lemma 7)
        first = np.clip(upper - t, 0.0, None) * a
        second = integral - t * a + np.clip(t - lower, 0.0, None) * a
        total = t[:, 0] * area_total + np.minimum(first, second).sum(axis=1)
        best = np.minimum(best, total)
    scale = np.abs(integral).sum(axis=1) + np.abs(t0) * area_total
    return (best + SAFETY * scale) / cap * (1.0 + SAFETY)


def _kernel_min_eig(pars, psi) -> float:
    """``min over arms of lambda_min`` of the 6 x 6 matrix of ``v -> F_v(m)`` (any m; Lemma 9's sigma)."""
    return min(_kernel_min_eig_one(q, psi) for q in _variants(pars))


def _kernel_min_eig_one(pars, psi) -> float:
    c = math.cos(psi)
    lam1, lam2 = 0.5 * (1.0 + c), 0.5 * c * (1.0 + c)
    m = np.array([0.0, 0.0, 1.0])
    # v^T Qhat v = F_v(m) = (cap inversion of f_v) at m; f_v(n) = v^T Q(n) v, so build it from the
    # harmonic decomposition of Q(n) in n: Qhat(m) = Q0 + Q1(m)/lam1 + Q2(m)/lam2 with Q(n) = Q0 + Q1(n) + Q2(n).
    # Average of Q over the sphere (degree 0), odd part (degree 1), remainder (degree 2):
    e = np.eye(3)
    q_plus = end_matrix(m, pars)
    q_minus = end_matrix(-m, pars)
    q1 = 0.5 * (q_plus - q_minus)  # the linear (odd) part at m
    # sphere average of Q: exact from the six axis directions (Q is quadratic in n, a 3-design suffices)
    q0 = sum(end_matrix(s * e[k], pars) for k in range(3) for s in (1.0, -1.0)) / 6.0
    q2 = 0.5 * (q_plus + q_minus) - q0
    qhat = q0 + q1 / lam1 + q2 / lam2
    return float(np.linalg.eigvalsh(qhat)[0])


# ----------------------------------------------------------------------------- branch and bound (Lemma 9)

def _phi_bound(z_eff: int, psi: float, pars, rtol: float = 2e-3, n_theta: int = 96, max_evals: int = 20000):
    """Rigorous upper bound on ``sup_{v in S^2} B(v)`` over the closed octant (Lemma 4) by Lemma 9.

    Returns ``(upper, best_vertex_value, evaluations)``.
    """
    cells = _cells(n_theta)
    sigma = z_eff * max(0.0, -_kernel_min_eig(pars, psi))
    cache: dict[tuple, float] = {}

    def key(p):
        return tuple(np.round(p, 13))

    def evaluate(points):
        todo = [p for p in points if key(p) not in cache]
        uniq = {}
        for p in todo:
            uniq.setdefault(key(p), p)
        todo = list(uniq.values())
        for s in range(0, len(todo), 48):
            chunk = np.array(todo[s:s + 48])
            vals = _bathtub_upper(chunk, pars, psi, z_eff, cells)
            for p, b in zip(chunk, vals):
                cache[key(p)] = float(b)
        return [cache[key(p)] for p in points]

    def normal(p):
        return p / np.linalg.norm(p)

    def tri_bound(tri, vals):
        a, b, c = tri
        nrm = np.cross(b - a, c - a)
        nn = np.linalg.norm(nrm)
        dist = abs(float(np.dot(nrm, a))) / nn if nn > 0 else 1.0
        s2 = 1.0 / (dist * dist) * (1.0 + 1e-12)
        return s2 * max(vals) + sigma * (s2 - 1.0)

    # initial triangulation of the octant: 4-way subdivision, three levels
    e = np.eye(3)
    tris = [(e[0], e[1], e[2])]
    for _ in range(3):
        nxt = []
        for a, b, c in tris:
            ab, bc, ca = normal(a + b), normal(b + c), normal(c + a)
            nxt += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        tris = nxt
    live = []
    for t in tris:
        vals = evaluate(list(t))
        live.append((tri_bound(t, vals), t))
    pruned_max = 0.0
    while True:
        best_vertex = max(cache.values())
        top = max(ub for ub, _ in live)
        if top <= best_vertex * (1.0 + rtol) or len(cache) > max_evals:
            break
        keep, split = [], []
        for ub, t in live:
            if ub <= best_vertex * (1.0 + rtol):
                pruned_max = max(pruned_max, ub)
            elif ub >= top - 0.5 * (top - best_vertex * (1.0 + rtol)) or len(live) < 400:
                split.append(t)
            else:
                keep.append((ub, t))
        new = []
        for a, b, c in split:
            ab, bc, ca = normal(a + b), normal(b + c), normal(c + a)
            new += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        evaluate([p for t in new for p in t])
        live = keep + [(tri_bound(t, [cache[key(p)] for p in t]), t) for t in new]
    upper = max(pruned_max, max(ub for ub, _ in live))
    return upper, max(cache.values()), len(cache)


# ----------------------------------------------------------------------------- species and weights (Lemma 2)
