"""Mass properties of a union of spheres (a clump), overlaps counted once (run time; NumPy only).

For a uniform density ``rho`` the union ``U`` of balls ``B_k = (c_k, r_k)`` has mass ``rho V(U)``, centre
``int_U x dV / V`` and second moments ``S = int_U x x^T dV``; the inertia tensor about the centre is
``I = rho (tr(S_c) 1 - S_c)`` with ``S_c = S - V x_c x_c^T``.

* **Closed form** (no point of the union in three or more balls; checked conservatively: no three
  pairwise-overlapping balls): inclusion-exclusion ``U = sum B_k - sum_(k<l) (B_k cap B_l)``, each
  lens the union of two spherical caps on either side of the radical plane at
  ``a_k = (d^2 + r_k^2 - r_l^2)/(2 d)`` from ``c_k`` (a ball inside another is removed whole).  A cap of
  ``B(0, r)`` beyond the plane ``z = a`` is a stack of discs of radius ``rho(z)^2 = (r - z)(r + z)``:
  ``V = pi int rho^2``, ``int z dV = pi int z rho^2``, ``int z^2 dV = pi int z^2 rho^2`` and
  ``int (x^2 + y^2) dV = (pi/2) int rho^4`` over ``z in [a, r]``, polynomials of degree <= 4 in ``z``
  integrated exactly by 3-point Gauss-Legendre on ``[a, r]`` (no cancellation for thin caps).
* **Quadrature** (otherwise): each point is assigned to the first ball containing it,
  ``U = disjoint union of B_k minus (B_1 cup ... cup B_(k-1))``; along a ray from ``c_k`` in direction ``u``
  the part of ``B_k`` outside the earlier balls is ``[0, r_k]`` minus intervals (the roots of a
  quadratic), so the radial integrals of ``s^2, s^3, s^4`` are exact and only the directions are
  sampled: Gauss-Legendre in ``cos theta`` times the trapezoid rule in ``phi``.  The estimate at
  ``n`` and ``2n`` directions per axis gives the stated error (:attr:`MassProperties.quadrature_error`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dtcrit.errors import InputError

GAUSS3 = (np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)]), np.array([5.0, 8.0, 5.0]) / 9.0)
QUADRATURE_NODES = 96  # Gauss-Legendre nodes in cos(theta); twice as many in phi


@dataclass(frozen=True)
class MassProperties:
    """Volume, centre and second moments of a union of balls.

    Parameters
    ----------
    volume : float
        Volume [m^3].
    centre : numpy.ndarray
        Centre of volume in the given frame [m].
    second_moment : numpy.ndarray
        ``int x x^T dV`` about the centre [m^5].
    method : str
        ``"closed form"`` or ``"quadrature"``.
    quadrature_error : float
        Relative change from half resolution (quadrature only).
    """

    volume: float  # [m^3]
    centre: np.ndarray  # centre of volume in the given frame [m]
    second_moment: np.ndarray  # int x x^T dV about the centre [m^5]
    method: str  # "closed form" | "quadrature"
    quadrature_error: float = 0.0  # relative change from half resolution (quadrature only)

    def inertia_tensor(self, density: float) -> np.ndarray:
        """The inertia tensor ``rho (tr(S) 1 - S)`` about the centre.

        Parameters
        ----------
        density : float
            Density [kg/m^3].

        Returns
        -------
        numpy.ndarray
            The 3x3 tensor [kg m^2].
        """
        s = self.second_moment
        return density * (np.trace(s) * np.eye(3) - s)


def _cap_integrals(r: float, a: float) -> tuple[float, float, float, float]:
    """``(V, int z, int z^2, int (x^2 + y^2))`` of the cap ``z >= a`` of ``B(0, r)``, ``-r <= a <= r``."""
    h = r - a
    x, w = GAUSS3
    z = a + 0.5 * h * (x + 1.0)
    rho2 = (r - z) * (r + z)
    w = 0.5 * h * w
    return (math.pi * float(w @ rho2), math.pi * float(w @ (z * rho2)), math.pi * float(w @ (z * z * rho2)),
            0.5 * math.pi * float(w @ (rho2 * rho2)))


def _axial_moments(c: np.ndarray, axis: np.ndarray, ints) -> tuple[float, np.ndarray, np.ndarray]:
    """Volume, first and second moments (about the origin) of a solid of revolution about ``axis``
    through ``c`` with axial integrals ``ints`` measured from ``c``.
    """
    v, mz, mzz, mrr = ints
    first = v * c + mz * axis
    local = mzz * np.outer(axis, axis) + 0.5 * mrr * (np.eye(3) - np.outer(axis, axis))
    second = local + np.outer(c, axis) * mz + np.outer(axis, c) * mz + v * np.outer(c, c)
    return v, first, second


def _ball(c, r):
    return _axial_moments(np.asarray(c, float), np.array([0.0, 0.0, 1.0]), _cap_integrals(r, -r))


def _lens(c1, r1, c2, r2):
    """Moments of ``B_1 cap B_2`` (zero when disjoint)."""
    c1, c2 = np.asarray(c1, float), np.asarray(c2, float)
    d = float(np.linalg.norm(c2 - c1))
    if d >= r1 + r2:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    if d <= abs(r1 - r2):
        return _ball(c1, r1) if r1 <= r2 else _ball(c2, r2)
    axis = (c2 - c1) / d
    a1 = (d * d + (r1 - r2) * (r1 + r2)) / (2.0 * d)
    v1, f1, s1 = _axial_moments(c1, axis, _cap_integrals(r1, a1))
    v2, f2, s2 = _axial_moments(c2, -axis, _cap_integrals(r2, d - a1))
    return v1 + v2, f1 + f2, s1 + s2


def _overlaps(centres: np.ndarray, radii: np.ndarray) -> np.ndarray:
    d = np.linalg.norm(centres[:, None, :] - centres[None, :, :], axis=-1)
    o = d < radii[:, None] + radii[None, :]
    np.fill_diagonal(o, False)
    return o


def needs_quadrature(centres, radii) -> bool:
    """Whether three balls overlap pairwise (their triple intersection may be non-empty).

    Parameters
    ----------
    centres : array_like
        Ball centres, shape (N, 3) [m].
    radii : array_like
        Ball radii, shape (N,) [m].

    Returns
    -------
    bool
        True when the closed form (pairwise lenses) may be wrong and the quadrature is needed.
    """
    o = _overlaps(np.asarray(centres, float), np.asarray(radii, float))
    n = len(radii)
    return any(o[i, j] and o[i, k] and o[j, k] for i in range(n) for j in range(i + 1, n) for k in range(j + 1, n))


def _finish(v: float, first: np.ndarray, second: np.ndarray, method: str, err: float = 0.0) -> MassProperties:
    centre = first / v
    return MassProperties(v, centre, second - v * np.outer(centre, centre), method, err)


def closed_form(centres, radii) -> MassProperties:
    """Mass properties by inclusion-exclusion over balls and pairwise lenses (no triple overlaps).

    Parameters
    ----------
    centres : array_like
        Ball centres, shape (N, 3) [m].
    radii : array_like
        Ball radii, shape (N,) [m].

    Returns
    -------
    MassProperties
        The exact volume, centre and second moments.
    """
    centres, radii = np.asarray(centres, float), np.asarray(radii, float)
    v, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    for c, r in zip(centres, radii):
        dv, df, ds = _ball(c, r)
        v, first, second = v + dv, first + df, second + ds
    n = len(radii)
    for i in range(n):
        for j in range(i + 1, n):
            dv, df, ds = _lens(centres[i], radii[i], centres[j], radii[j])
            v, first, second = v - dv, first - df, second - ds
    return _finish(v, first, second, "closed form (inclusion-exclusion with lens caps)")


def _directions(n: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    phi = (np.arange(2 * n) + 0.5) * (math.pi / n)
    st = np.sqrt((1.0 - x) * (1.0 + x))
    u = np.stack([np.outer(st, np.cos(phi)), np.outer(st, np.sin(phi)), np.outer(x, np.ones_like(phi))], -1).reshape(-1, 3)
    weights = np.outer(w, np.full(2 * n, math.pi / n)).reshape(-1)
    return u, weights


def _ray_moments(centres, radii, n: int) -> tuple[float, np.ndarray, np.ndarray]:
    u, wts = _directions(n)
    v, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    for k, (c, r) in enumerate(zip(centres, radii)):
        lo = np.zeros(len(u))[:, None]
        hi = np.full(len(u), r)[:, None]
        keep = [(lo, hi)]  # intervals [s0, s1] along each ray, as (N, m) arrays
        for j in range(k):
            e = centres[j] - c
            b = u @ e
            disc = b * b - (float(e @ e) - radii[j] ** 2)
            ok = disc > 0
            root = np.sqrt(np.where(ok, disc, 0.0))
            t0, t1 = np.where(ok, b - root, 0.0), np.where(ok, b + root, 0.0)
            new = []
            for s0, s1 in keep:  # subtract [t0, t1] from each interval
                left_hi = np.minimum(s1, t0[:, None])
                right_lo = np.maximum(s0, t1[:, None])
                new += [(s0, np.maximum(left_hi, s0)), (np.minimum(right_lo, s1), s1)]
            keep = new
        zero = np.zeros_like(lo)  # 0 + x == x: the sums below add in the same order as from 0
        m2 = sum(((s1**3 - s0**3) / 3.0 for s0, s1 in keep), zero)[:, 0]
        m3 = sum(((s1**4 - s0**4) / 4.0 for s0, s1 in keep), zero)[:, 0]
        m4 = sum(((s1**5 - s0**5) / 5.0 for s0, s1 in keep), zero)[:, 0]
        dv = float(wts @ m2)
        df = (wts * m3) @ u
        ds = np.einsum("n,ni,nj->ij", wts * m4, u, u)
        v += dv
        first += dv * c + df
        second += ds + np.outer(c, df) + np.outer(df, c) + dv * np.outer(c, c)
    return v, first, second


def quadrature(centres, radii, n: int = QUADRATURE_NODES) -> MassProperties:
    """Mass properties by quadrature over the union, with the change from half resolution as error.

    Parameters
    ----------
    centres : array_like
        Ball centres, shape (N, 3) [m].
    radii : array_like
        Ball radii, shape (N,) [m].
    n : int
        Quadrature resolution.

    Returns
    -------
    MassProperties
        The approximate volume, centre and second moments.
    """
    centres, radii = np.asarray(centres, float), np.asarray(radii, float)
    coarse = _finish(*_ray_moments(centres, radii, n // 2), "")
    fine = _ray_moments(centres, radii, n)
    props = _finish(*fine, "")
    scale = float(np.abs(props.second_moment).max())
    err = max(abs(coarse.volume / props.volume - 1.0), float(np.abs(coarse.second_moment - props.second_moment).max()) / scale)
    return MassProperties(props.volume, props.centre, props.second_moment,
                          f"quadrature over rays ({n} x {2 * n} directions per member)", err)


def union_mass_properties(centres, radii) -> MassProperties:
    """The union's volume, centre and second moments (module docstring); refuses an empty union.

    Parameters
    ----------
    centres : array_like
        Ball centres, shape (N, 3) [m].
    radii : array_like
        Ball radii, shape (N,) [m].

    Returns
    -------
    MassProperties
        Closed form when no three balls overlap pairwise, else quadrature.
    """
    centres, radii = np.asarray(centres, float), np.asarray(radii, float)
    if len(radii) == 0:
        raise InputError("spheres", "a clump needs at least one sphere")
    if needs_quadrature(centres, radii):
        return quadrature(centres, radii)
    return closed_form(centres, radii)
