"""Geometry behind the sphere-packing bound of :mod:`dtcrit.scenes.dense_spheres` (proof in
``derivations/proofs/dense_packing_bound.md``): the smallest angle between two contact normals of a sphere
(law of cosines, Lemma 5), how many such normals fit (Fejes Toth; the solved Tammes problems), the
6 x 6 matrix of one contact end (Lemma 3), and a partition of the unit sphere into cells with exact
polynomial moments and rigorous circumradii (Lemma 8).  NumPy only.
"""
from __future__ import annotations
import math
import numpy as np


SAFETY = 1e-9  # relative inflation of every computed upper bound: covers floating-point rounding


# ----------------------------------------------------------------------------- geometry (Lemma 5)

def min_contact_angle_cos(r_i, r_j, r_k, overlap=0.0, contact_tolerance=1e-9):
    """Upper bound on cos(angle between the normals of two contacts of sphere i with spheres j, k).

    Lemma 5: with ``d_ij <= (1+tau)(R_i+R_j)``, ``d_ij >= (1-eps)(R_i+R_j)`` (same for k) and
    ``d_jk >= (1-eps)(R_j+R_k)``, ``cos(angle) <= max over the four corners (x, y) of
    (x^2 + y^2 - L^2) / (2 x y)``, ``L = (1-eps)(R_j+R_k)``.  Broadcasts.

    Parameters
    ----------
    r_i, r_j, r_k : array_like
        Radii of the centre sphere and its two neighbours [m].
    overlap : float
        Largest overlap ``eps`` as a fraction of the sum of radii.
    contact_tolerance : float
        How far beyond touching a contact may be, ``tau``.

    Returns
    -------
    numpy.ndarray
        The bound on the cosine, broadcast shape.
    """
    r_i, r_j, r_k = np.broadcast_arrays(*(np.asarray(v, float) for v in (r_i, r_j, r_k)))
    lo, hi = 1.0 - overlap, 1.0 + contact_tolerance
    big_l = lo * (r_j + r_k)
    best = np.full(r_i.shape, -np.inf)
    for sx in (lo, hi):
        for sy in (lo, hi):
            x = sx * (r_i + r_j)
            y = sy * (r_i + r_k)
            best = np.maximum(best, (x * x + y * y - big_l * big_l) / (2.0 * x * y))
    return np.clip(best, -1.0, 1.0)


# ----------------------------------------------------------------------------- the end matrix (Lemma 3)

def _cross(n):
    n = np.asarray(n, float)
    return np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])


def end_matrix(n, pars):
    """The 6 x 6 matrix ``Q(n)`` of one contact end (Lemma 3), mass-scaled DOFs ``v = (x, y)``.

    ``v^T Q v = alpha (n.x)^2 + |sqrt(beta) P x - sqrt(gamma) n x y|^2 + gamma_r |P y|^2 + gamma_w (n.y)^2``
    with ``P = 1 - n n^T`` and ``pars = (alpha, beta, gamma, gamma_r, gamma_w)``.

    Parameters
    ----------
    n : array_like
        Unit contact normal (3,).
    pars : sequence of float
        ``(alpha, beta, gamma, gamma_r, gamma_w)``.

    Returns
    -------
    numpy.ndarray
        ``Q(n)``, shape (6, 6).
    """
    alpha, beta, gamma, gr, gw = pars[:5]
    n = np.asarray(n, float)
    nn = np.outer(n, n)
    p = np.eye(3) - nn
    t = np.hstack([math.sqrt(beta) * p, -math.sqrt(gamma) * _cross(n)])
    q = t.T @ t
    q[:3, :3] += alpha * nn
    q[3:, 3:] += gr * p + gw * nn
    return q


def _variants(pars):
    """The end parameters at the two extreme arms: full radius, and ``t0 R`` when ``t0 = pars[5] < 1``
    (Remark 3 of dense_packing_bound.md: the end form is convex in the arm, so the two extremes dominate).
    """
    alpha, beta, gamma, gr, gw = (float(t) for t in pars[:5])
    t0 = float(pars[5]) if len(pars) > 5 else 1.0
    out = [(alpha, beta, gamma, gr, gw)]
    if t0 < 1.0:
        out.append((alpha, beta, gamma * t0 * t0, gr, gw))
    return out


def _trivial(pars) -> float:
    """``max over arms of lambda_max(Q(n))`` (the same for every n by rotation invariance)."""
    return max(float(np.linalg.eigvalsh(end_matrix([0.0, 0.0, 1.0], q))[-1]) for q in _variants(pars))


# ----------------------------------------------------------------------------- sphere cells (Lemma 8)

class _SphereCells:
    """A partition of the unit sphere into (theta, phi) cells with exact polynomial moments,
    centres and rigorous circumradii (chordal distance from the centre to any point of the cell).
    """

    def __init__(self, n_theta: int = 96):
        edges = np.linspace(0.0, math.pi, n_theta + 1)
        rows = []
        for b in range(n_theta):
            t0, t1 = edges[b], edges[b + 1]
            tc = 0.5 * (t0 + t1)
            n_phi = max(3, int(math.ceil(2.0 * n_theta * math.sin(tc))))
            ph = np.linspace(0.0, 2.0 * math.pi, n_phi + 1)
            rows.append((np.full(n_phi, t0), np.full(n_phi, t1), ph[:-1], ph[1:]))
        t0, t1, p0, p1 = (np.concatenate(c) for c in zip(*rows))
        tc, pc = 0.5 * (t0 + t1), 0.5 * (p0 + p1)
        self.centre = np.stack([np.sin(tc) * np.cos(pc), np.sin(tc) * np.sin(pc), np.cos(tc)], 1)
        # path along the parallel of the centre, then along the meridian (a geodesic is shorter, a chord shorter still)
        self.radius = 0.5 * (t1 - t0) + np.sin(tc) * 0.5 * (p1 - p0)
        u0, u1 = np.cos(t1), np.cos(t0)  # u = cos(theta), u0 < u1

        def prim(f):
            return f(u1) - f(u0)

        s = lambda u: np.sqrt(np.clip(1.0 - u * u, 0.0, None))  # noqa: E731
        s0 = u1 - u0
        s1 = prim(lambda u: 0.5 * (u * s(u) + np.arcsin(np.clip(u, -1.0, 1.0))))
        s2 = prim(lambda u: u - u**3 / 3.0)
        uu1 = prim(lambda u: 0.5 * u * u)
        uu2 = prim(lambda u: u**3 / 3.0)
        us = prim(lambda u: -s(u) ** 3 / 3.0)
        dphi = p1 - p0
        c1 = np.sin(p1) - np.sin(p0)
        sn1 = np.cos(p0) - np.cos(p1)
        d2 = (np.sin(2 * p1) - np.sin(2 * p0)) / 4.0
        cc, ss = 0.5 * dphi + d2, 0.5 * dphi - d2
        cs = 0.5 * (np.sin(p1) ** 2 - np.sin(p0) ** 2)
        # moments of the basis 1, m1, m2, m3, m1^2, m2^2, m3^2, m1 m2, m1 m3, m2 m3 (dA = du dphi)
        self.moments = np.stack([s0 * dphi, s1 * c1, s1 * sn1, uu1 * dphi, s2 * cc, s2 * ss, uu2 * dphi,
                                 s2 * cs, us * c1, us * sn1], 1)
        self.area = self.moments[:, 0]
        c = self.centre
        self.basis_at_centre = np.stack([np.ones(len(c)), c[:, 0], c[:, 1], c[:, 2], c[:, 0] ** 2, c[:, 1] ** 2,
                                         c[:, 2] ** 2, c[:, 0] * c[:, 1], c[:, 0] * c[:, 2], c[:, 1] * c[:, 2]], 1)


_CELLS: dict[int, _SphereCells] = {}


def _cells(n_theta: int) -> _SphereCells:
    if n_theta not in _CELLS:
        _CELLS[n_theta] = _SphereCells(n_theta)
    return _CELLS[n_theta]


TAMMES_13_DEG = 57.1367031  # Musin & Tarasov 2012: 13 points on S^2 have minimal angle <= 57.1367031 deg
TAMMES_14_DEG = 55.6705700  # Musin & Tarasov 2015: 14 points on S^2 have minimal angle <= 55.6705700 deg


def max_code_size(theta: float) -> float:
    """Largest number of points of S^2 that can be pairwise at least ``theta`` [rad] apart, bounded
    above (Lemma 5b): Fejes Toth's inequality ``sin^2(theta/2) <= 1 - 1/(4 sin^2(pi N/(6(N-2))))``
    for every N >= 3 points, sharpened to 12 (13) when theta exceeds the Tammes angle of 13 (14)
    points (Musin & Tarasov 2012, 2015) with a margin of 1e-6 deg.  ``math.inf`` when ``theta <= 0``
    (no angle between the normals: the angle argument bounds nothing).

    Parameters
    ----------
    theta : float
        Smallest angle between two points [rad].

    Returns
    -------
    float
        The bound on the number of points.
    """
    if theta <= 0:
        return math.inf
    deg = math.degrees(theta)
    if deg > TAMMES_13_DEG + 1e-6:
        return 12
    s2 = math.sin(0.5 * theta) ** 2 * (1.0 - 1e-12)

    def impossible(n: int) -> bool:  # n + 1 points violate the inequality (monotone in n)
        # 1 - 1/(4 sin^2 w) at w = pi/6 + a, written without cancellation: delta/(1 + delta) with
        # delta = 4 sin^2 w - 1 = 4 sin(a) sin(pi/3 + a), a = pi/(3(n - 1))
        a = math.pi / (3.0 * (n - 1))
        delta = 4.0 * math.sin(a) * math.sin(math.pi / 3.0 + a)
        return s2 > delta / (1.0 + delta)

    lo, hi = 2, 3  # impossible(lo) is false (n >= 3 always fits), find hi with impossible(hi)
    while not impossible(hi):
        lo, hi = hi, 2 * hi
    while hi - lo > 1:  # smallest n with impossible(n), by bisection (O(log n) evaluations)
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if impossible(mid) else (mid, hi)
    n = hi
    if deg > TAMMES_14_DEG + 1e-6:
        n = min(n, 13)
    return n


def _species_geometry(r, z, overlap, contact_tolerance):
    """Per species: half the smallest admissible angle between two of its contact normals (Lemma 5)
    and the effective contact cap ``z_eff = min(z, max_code_size(theta))`` (Lemma 5b).
    """
    s = len(r)
    psi = np.empty(s)
    z_eff = np.empty(s, dtype=int)
    for a in range(s):
        cmax = float(min_contact_angle_cos(r[a], r[:, None], r[None, :], overlap, contact_tolerance).max())
        theta = math.acos(cmax)
        psi[a] = 0.5 * theta
        z_eff[a] = min(int(z[a]), max_code_size(theta))
    return psi, z_eff
