"""Particle shapes: mass, volume, principal inertia and surface geometry in the local frame.

Peng, Burns & Hanley (2020), Section 3, restrict the critical-time-step analysis to convex,
centrally symmetric particles whose local frame is principal (assumption 2), with semi-axes
``a >= b >= c`` and principal moments ``I_zz >= I_yy >= I_xx`` (assumption 3).  This module gives
those inputs for

* :class:`Sphere`, :class:`Ellipsoid`, :class:`Superquadric` (convex range) and :class:`Box`
  (half-lengths): closed forms emitted by ``dtcrit.symbolic.mass_properties`` into
  ``dtcrit._generated.mass_properties``;
* :class:`ConvexPolyhedron`: convex hull of a centrally symmetric vertex set (:mod:`dtcrit.hull`),
  exact moments by tetrahedral decomposition (generated tetrahedron kernel), rotated into its
  principal frame.

Every shape is immutable and exposes ``kind``, ``mass``, ``volume``, ``density``, ``inertia``
(principal moments ``(I_xx, I_yy, I_zz)`` about the centre, local frame), ``half_lengths``
(``(a, b, c)`` of the local axis-aligned bounding box), ``max_arm`` (largest centre-to-surface
distance), ``equivalent_radius``, ``vertices``, ``surface_points(n)``, ``support(direction)``,
``satisfies_paper_assumptions`` and ``assumption_issues``.  When assumption 3 fails at
construction an :class:`AssumptionWarning` names the shape and what fails; the axes of ellipsoids,
superquadrics and boxes are never reordered (a < b or b < c is refused as bad input), and a
polyhedron's principal frame is chosen to meet the assumption where its inertia allows (see
:class:`ConvexPolyhedron`), otherwise flagged.

Superquadric convention (Barr 1981; Jaklic et al. 2000)::

    (|x/a|^(2/eps2) + |y/b|^(2/eps2))^(eps2/eps1) + |z/c|^(2/eps1) <= 1,

accepted for ``SUPERQUADRIC_EPS_MIN <= eps1, eps2 <= 2`` (2 is the convex limit; below 0.01 the
body is within 0.6 % of a box, use :class:`Box`).  The sphere and the ellipsoid share the
superquadric surface routines with ``eps1 = eps2 = 1``.

No SymPy and no SciPy here: only NumPy, the generated kernels and :mod:`dtcrit.hull` (importing
``scipy.spatial`` would cost more start-up time than ``dtcrit step`` needs for a whole scene).
"""
from __future__ import annotations

import math
import numbers
import warnings
from typing import Any

import numpy as np

from ._generated import mass_properties as _mp
from .errors import InputError
from .hull import HULL_RTOL, HullError, connected_components, convex_hull_2d, convex_hull_3d, nearest_neighbours

__all__ = [
    "AssumptionWarning",
    "Sphere",
    "Ellipsoid",
    "Superquadric",
    "Box",
    "ConvexPolyhedron",
    "shape_from_spec",
    "superquadric_max_arm",
    "SUPERQUADRIC_EPS_MIN",
    "SUPERQUADRIC_EPS_MAX",
    "SYMMETRY_RTOL",
    "ORDER_RTOL",
]

SUPERQUADRIC_EPS_MIN = 0.01
"""Smallest accepted superquadric exponent: at eps = 0.01 the corner on the body diagonal lies at
3^(-eps/2) = 0.9945 of the box corner, and the inside-outside exponent 2/eps = 200 is as large as
double precision tolerates for points up to ~35 half-lengths away."""
SUPERQUADRIC_EPS_MAX = 2.0
"""Largest exponent for which the superquadric is convex (eps = 2 gives flat faces)."""
SYMMETRY_RTOL = 1e-6
"""Default tolerance of the central-symmetry and convexity checks of :class:`ConvexPolyhedron`,
relative to the largest distance of a vertex from the vertex mean."""
ORDER_RTOL = 1e-9
"""Relative slack of the assumption check ``a >= b >= c``, ``I_zz >= I_yy >= I_xx``: equal values
(a sphere, a prolate spheroid) pass despite rounding."""

_PLANE_RTOL = 1e-8  # facets whose unit normals and offsets differ by less are one planar face
_DEGENERATE_RTOL = 1e-9  # second moments this close (relative) share a principal subspace


class AssumptionWarning(UserWarning):
    """A shape breaks Peng et al. (2020) Section 3 assumption 3 (a >= b >= c, I_zz >= I_yy >= I_xx)."""


# ============================================================================================
# Input checks
# ============================================================================================
def _real(key: str, value: Any) -> float:
    if isinstance(value, (bool, np.bool_)):
        raise InputError(key, f"must be a real number (got {value!r})")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if not isinstance(value, numbers.Real):
        raise InputError(key, f"must be a real number (got {value!r})")
    return float(value)


def _positive(key: str, value: Any) -> float:
    x = _real(key, value)
    if not math.isfinite(x):
        raise InputError(key, f"must be finite (got {x})")
    if x <= 0.0:
        raise InputError(key, f"must be positive (got {x})")
    return x


def _axes(a: Any, b: Any, c: Any) -> tuple[float, float, float]:
    a, b, c = _positive("a", a), _positive("b", b), _positive("c", c)
    if a < b:
        raise InputError("b", f"a >= b >= c required (got a={a:g}, b={b:g})")
    if b < c:
        raise InputError("c", f"a >= b >= c required (got b={b:g}, c={c:g})")
    return a, b, c


def _exponent(key: str, value: Any) -> float:
    e = _real(key, value)
    if not math.isfinite(e):
        raise InputError(key, f"must be finite (got {e})")
    if not SUPERQUADRIC_EPS_MIN <= e <= SUPERQUADRIC_EPS_MAX:
        raise InputError(
            key,
            f"must lie in [{SUPERQUADRIC_EPS_MIN:g}, {SUPERQUADRIC_EPS_MAX:g}] (convex superquadrics; "
            f"eps > 2 is non-convex, eps < {SUPERQUADRIC_EPS_MIN:g} is a box to 0.6 %) (got {e:g})",
        )
    return e


def _mass_and_density(volume: float, density: Any, mass: Any, size_key: str) -> tuple[float, float]:
    if not (math.isfinite(volume) and volume > 0.0):
        raise InputError(size_key, f"dimensions give a volume of {volume!r}, outside double precision")
    if density is not None and mass is not None:
        raise InputError("density", "give exactly one of density= or mass= (got both)")
    if density is None and mass is None:
        raise InputError("density", "give exactly one of density= or mass= (got neither)")
    if density is not None:
        rho = _positive("density", density)
        m = rho * volume
        if not (math.isfinite(m) and m > 0.0):
            raise InputError("density", f"density * volume = {m!r} is not a positive finite mass")
        return m, rho
    m = _positive("mass", mass)
    rho = m / volume
    if not (math.isfinite(rho) and rho > 0.0):
        raise InputError("mass", f"mass / volume = {rho!r} is not a positive finite density")
    return m, rho


def _direction(direction: Any) -> np.ndarray:
    try:
        d = np.asarray(direction, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError("direction", f"must be a 3-vector of real numbers ({exc})") from None
    if d.shape[-1:] != (3,) or d.ndim > 2:
        raise InputError("direction", f"must have shape (3,) or (N, 3) (got {d.shape})")
    if not np.all(np.isfinite(d)):
        raise InputError("direction", "must be finite")
    if np.any(np.max(np.abs(d), axis=-1) == 0.0):
        raise InputError("direction", "must be non-zero")
    return d


def _count(n: Any) -> int:
    if isinstance(n, (bool, np.bool_)) or not isinstance(n, numbers.Integral):
        raise InputError("n", f"must be an integer (got {n!r})")
    if n < 1:
        raise InputError("n", f"must be at least 1 (got {n})")
    if n > 1_000_000:
        raise InputError("n", f"must be at most 1000000 (got {n})")
    return int(n)


def _kernel(fn, *args):
    """Call a generated kernel in NumPy float64 so that overflow gives inf (checked by the caller)."""
    with np.errstate(over="ignore", under="ignore"):
        out = fn(*(np.float64(x) for x in args))
    return tuple(float(x) for x in out) if isinstance(out, tuple) else float(out)


def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _unit_rows(v: np.ndarray) -> np.ndarray:
    scale = np.max(np.abs(v), axis=1, keepdims=True)
    v = v / np.where(scale > 0, scale, 1.0)
    return v / np.linalg.norm(v, axis=1, keepdims=True)


# ============================================================================================
# Base class
# ============================================================================================
class _Shape:
    """Common, immutable part of every shape (values fixed in ``_finish``)."""

    kind: str = ""
    __slots__ = ("_mass", "_volume", "_density", "_inertia", "_half_lengths", "_max_arm", "_issues", "_samples", "_frozen")

    def __setattr__(self, name: str, value: Any) -> None:
        if getattr(self, "_frozen", False):
            raise AttributeError(f"{type(self).__name__} is immutable")
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"{type(self).__name__} is immutable")

    def _finish(self, volume, density, mass, inertia_per_mass, half_lengths, max_arm, size_key) -> None:
        m, rho = _mass_and_density(float(volume), density, mass, size_key)
        inertia = tuple(float(m * i) for i in inertia_per_mass)
        if not all(math.isfinite(i) and i > 0.0 for i in inertia):
            raise InputError(size_key, f"principal moments {inertia} are outside double precision")
        self._volume = float(volume)
        self._mass = m
        self._density = rho
        self._inertia = inertia
        self._half_lengths = tuple(float(h) for h in half_lengths)
        self._max_arm = float(max_arm)
        self._issues = _assumption_issues(self._label(), self._half_lengths, inertia)
        self._samples = {}  # n -> (points, normals), filled by surface_points
        self._frozen = True
        if self._issues:
            warnings.warn(
                "; ".join(self._issues) + " (Peng et al. 2020, Section 3, assumption 3)",
                AssumptionWarning,
                stacklevel=3,
            )

    def _label(self) -> str:  # pragma: no cover - overridden
        return type(self).__name__

    def __repr__(self) -> str:
        return f"{self._label()[:-1]}, mass={_fmt(self._mass)})"

    # ----- public read-only properties ------------------------------------------------------
    @property
    def mass(self) -> float:
        """Mass [kg]."""
        return self._mass

    @property
    def volume(self) -> float:
        """Volume [m^3]."""
        return self._volume

    @property
    def density(self) -> float:
        """Uniform density [kg/m^3]."""
        return self._density

    @property
    def inertia(self) -> tuple[float, float, float]:
        """Principal moments ``(I_xx, I_yy, I_zz)`` about the centre in the local frame [kg m^2]."""
        return self._inertia

    @property
    def half_lengths(self) -> tuple[float, float, float]:
        """Half-lengths ``(a, b, c)`` of the local axis-aligned bounding box [m]."""
        return self._half_lengths

    @property
    def max_arm(self) -> float:
        """Largest distance from the centre to the surface [m]."""
        return self._max_arm

    @property
    def equivalent_radius(self) -> float:
        """Radius of the sphere of equal volume, (3 V / (4 pi))^(1/3) [m]."""
        return float(np.cbrt(3.0 / (4.0 * math.pi)) * np.cbrt(self._volume))

    @property
    def vertices(self) -> np.ndarray | None:
        """Corners ``(N, 3)`` in the local frame for boxes and polyhedra, ``None`` otherwise."""
        return None

    @property
    def satisfies_paper_assumptions(self) -> bool:
        """Whether a >= b >= c and I_zz >= I_yy >= I_xx hold (Peng et al. 2020, Section 3, assumption 3)."""
        return not self._issues

    @property
    def assumption_issues(self) -> tuple[str, ...]:
        """What fails of Peng et al. (2020) Section 3 assumption 3, one sentence each (empty if none)."""
        return self._issues

    def surface_points(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """About ``n`` surface points roughly uniform in area and their outward unit normals.

        Returns ``(points, normals)``, two ``(N, 3)`` arrays in the local frame; deterministic
        (computed once per ``n`` and cached; each call returns fresh copies).  The sampling is
        described by each shape's ``_sample``.
        """
        n = _count(n)
        if n not in self._samples:
            if len(self._samples) >= 16:
                self._samples.pop(next(iter(self._samples)))
            self._samples[n] = self._sample(n)
        points, normals = self._samples[n]
        return points.copy(), normals.copy()

    def _sample(self, n: int) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - overridden
        raise NotImplementedError

    def support(self, direction: Any) -> np.ndarray:
        """The surface point farthest along ``direction`` (local frame); ``(3,)`` or ``(N, 3)``."""
        raise NotImplementedError


def _assumption_issues(label: str, half: tuple[float, float, float], inertia: tuple[float, float, float]) -> tuple[str, ...]:
    """Peng et al. (2020) Section 3 assumption 3, checked with relative slack ``ORDER_RTOL``."""
    a, b, c = half
    ixx, iyy, izz = inertia
    issues = []
    if a < b * (1 - ORDER_RTOL) or b < c * (1 - ORDER_RTOL):
        issues.append(f"{label}: half-lengths violate a >= b >= c (a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)})")
    if izz < iyy * (1 - ORDER_RTOL) or iyy < ixx * (1 - ORDER_RTOL):
        issues.append(
            f"{label}: principal moments violate I_zz >= I_yy >= I_xx "
            f"(I_xx={_fmt(ixx)}, I_yy={_fmt(iyy)}, I_zz={_fmt(izz)})"
        )
    return tuple(issues)


# ============================================================================================
# Superquadric-family geometry (sphere, ellipsoid and superquadric)
# ============================================================================================
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
    """
    return _superellipse_max_radius(_superellipse_max_radius(a, b, eps2), c, eps1)


def _superquadric_ray_hits(axes: np.ndarray, e1: float, e2: float, delta: float):
    """Surface points hit by rays parallel to each axis through a square grid of spacing ``delta``.

    Along a ray the inside-outside equation has a closed-form root, e.g. for rays along z
    ``|z/c|^(2/eps1) = 1 - (|x/a|^(2/eps2) + |y/b|^(2/eps2))^(eps2/eps1)``.  Near a surface point with
    unit normal n the family along the axis of largest |n_k| >= 1/sqrt(3) leaves gaps of at most
    sqrt(3) delta, so the union covers the surface with no parametrisation distortion.

    Returns ``(points, dominant_area)``: all hits, and for each hit the area it stands for if its
    ray family is the one of largest |n_k| there (``delta^2 / |n_k|``), else 0; the sum estimates
    the surface area.
    """
    p1, p2 = 2.0 / e1, 2.0 / e2
    out, area = [], []
    for k in range(3):
        i, j = [m for m in range(3) if m != k]
        gi = np.arange(-math.floor(axes[i] / delta), math.floor(axes[i] / delta) + 1) * delta
        gj = np.arange(-math.floor(axes[j] / delta), math.floor(axes[j] / delta) + 1) * delta
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
        chosen, pts, h = best
        chosen = pts[chosen]
        near_tip = nearest_neighbours(chosen, tips)[0] < 0.5 * h
        points = np.concatenate([tips, chosen[~near_tip]])
    else:
        points = tips
    return points, _superquadric_normals(points, axes, e1, e2)


class _SuperquadricFamily(_Shape):
    """Shared surface geometry of sphere, ellipsoid and superquadric (half-axes and exponents)."""

    __slots__ = ("_axes_arr", "_e1", "_e2")

    def _set_geometry(self, a: float, b: float, c: float, e1: float, e2: float) -> None:
        arr = np.array([a, b, c], dtype=float)
        arr.flags.writeable = False
        self._axes_arr, self._e1, self._e2 = arr, e1, e2

    @property
    def a(self) -> float:
        """Semi-axis along local x [m]."""
        return float(self._axes_arr[0])

    @property
    def b(self) -> float:
        """Semi-axis along local y [m]."""
        return float(self._axes_arr[1])

    @property
    def c(self) -> float:
        """Semi-axis along local z [m]."""
        return float(self._axes_arr[2])

    def _sample(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """About ``n`` surface points (never fewer than the six axis tips ``(+-a,0,0), ...``).

        Candidates (where rays parallel to the axes through a grid of spacing h/4 meet the surface)
        are thinned to one per cube of side h, h tuned to the count (within ~10 % of ``n`` unless the
        body is thinner than h); points and outward unit normals (gradient of the
        inside-outside function) in the local frame.  Deterministic.
        """
        return _superquadric_surface_points(n, self._axes_arr, self._e1, self._e2)

    def support(self, direction: Any) -> np.ndarray:
        """Farthest surface point along ``direction`` (Hoelder equality case, exact)."""
        d = _direction(direction)
        out = _superquadric_support(self._axes_arr, self._e1, self._e2, np.atleast_2d(d))
        return out[0] if d.ndim == 1 else out

    def radial_surface_points(self, directions: np.ndarray) -> np.ndarray:
        """Where the rays from the centre along the (non-zero) rows of ``directions`` leave the body
        (:func:`_superquadric_radial_projection`); shape (N, 3), local frame."""
        d = np.atleast_2d(np.asarray(directions, dtype=float))
        return _superquadric_radial_projection(d, self._axes_arr, self._e1, self._e2)

    def outward_normals(self, points: np.ndarray) -> np.ndarray:
        """Outward unit normals (normalised gradient of the inside-outside function) at the surface
        ``points`` (rows, local frame; :func:`_superquadric_normals`)."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        return _superquadric_normals(p, self._axes_arr, self._e1, self._e2)


class Sphere(_SuperquadricFamily):
    """Uniform solid sphere of radius ``radius``: I = 2/5 m R^2 about every centroidal axis."""

    kind = "sphere"
    __slots__ = ("_radius",)

    def __init__(self, radius: float, *, density: float | None = None, mass: float | None = None):
        r = _positive("radius", radius)
        self._radius = r
        self._set_geometry(r, r, r, 1.0, 1.0)
        i = _kernel(_mp.sphere_inertia_per_mass, r)
        self._finish(_kernel(_mp.sphere_volume, r), density, mass, (i, i, i), (r, r, r), r, "radius")

    @property
    def radius(self) -> float:
        return self._radius

    @property
    def equivalent_radius(self) -> float:
        return self._radius

    def _label(self) -> str:
        return f"Sphere(radius={_fmt(self._radius)})"


class Ellipsoid(_SuperquadricFamily):
    """Uniform solid ellipsoid (x/a)^2 + (y/b)^2 + (z/c)^2 <= 1 with a >= b >= c.

    I_xx = m (b^2 + c^2)/5, I_yy = m (a^2 + c^2)/5, I_zz = m (a^2 + b^2)/5; V = 4/3 pi a b c
    (Peng et al. 2020, Section 6.4).  ``max_arm = a``.
    """

    kind = "ellipsoid"
    __slots__ = ()

    def __init__(self, a: float, b: float, c: float, *, density: float | None = None, mass: float | None = None):
        a, b, c = _axes(a, b, c)
        self._set_geometry(a, b, c, 1.0, 1.0)
        self._finish(_kernel(_mp.ellipsoid_volume, a, b, c), density, mass, _kernel(_mp.ellipsoid_inertia_per_mass, a, b, c), (a, b, c), a, "a")

    def _label(self) -> str:
        a, b, c = self._axes_arr
        return f"Ellipsoid(a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)})"


class Superquadric(_SuperquadricFamily):
    """Uniform convex superquadric (Barr/Jaklic convention, module docstring) with a >= b >= c.

    Accepts ``SUPERQUADRIC_EPS_MIN <= eps1, eps2 <= 2``.  Volume and moments are Beta-function
    products (``dtcrit.symbolic.mass_properties``); ``max_arm`` from
    :func:`superquadric_max_arm`.  a >= b >= c does not guarantee I_zz >= I_yy when b is close to c
    and eps1 < eps2 (box-like profile, diamond cross-section): that case is flagged.
    """

    kind = "superquadric"
    __slots__ = ()

    def __init__(self, a: float, b: float, c: float, eps1: float, eps2: float, *,
                 density: float | None = None, mass: float | None = None):
        a, b, c = _axes(a, b, c)
        e1, e2 = _exponent("eps1", eps1), _exponent("eps2", eps2)
        self._set_geometry(a, b, c, e1, e2)
        self._finish(
            _kernel(_mp.superquadric_volume, a, b, c, e1, e2),
            density,
            mass,
            _kernel(_mp.superquadric_inertia_per_mass, a, b, c, e1, e2),
            (a, b, c),
            superquadric_max_arm(a, b, c, e1, e2),
            "a",
        )

    @property
    def eps1(self) -> float:
        return self._e1

    @property
    def eps2(self) -> float:
        return self._e2

    def _label(self) -> str:
        a, b, c = self._axes_arr
        return f"Superquadric(a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}, eps1={_fmt(self._e1)}, eps2={_fmt(self._e2)})"


# ============================================================================================
# Polyhedral geometry (box and convex polyhedron), all in the local frame
# ============================================================================================
class _PolyhedralSurface:
    """Faces (merged coplanar hull facets), edges and vertex normals of a convex polytope.

    Every point of ``vertices`` must be a corner of the hull.  ``faces`` (corner indices, counter-
    clockwise seen from outside) and their outward unit ``normals`` may be given (a hull already
    taken); otherwise :func:`dtcrit.hull.convex_hull_3d` finds them.  Neighbouring faces whose unit
    normals and offsets differ by less than ``_PLANE_RTOL`` (offsets relative to the largest
    vertex distance) are merged into one face.
    """

    def __init__(self, vertices: np.ndarray, faces: tuple[np.ndarray, ...] | None = None,
                 normals: np.ndarray | None = None):
        self.vertices = vertices
        scale = float(np.max(np.linalg.norm(vertices, axis=1)))
        if faces is None:
            hull = convex_hull_3d(vertices)
            faces, normals = hull.faces, hull.equations[:, :3]
        lens = np.array([len(poly) for poly in faces])
        owner0 = np.repeat(np.arange(len(faces)), lens)
        flat = np.concatenate(faces)
        offsets = -np.bincount(owner0, weights=np.einsum("ij,ij->i", vertices[flat], normals[owner0])) / lens
        nxt = flat[_ring_successor(lens)]
        newell = np.zeros((len(faces), 3))  # twice the vector area of each face
        np.add.at(newell, owner0, np.cross(vertices[flat], vertices[nxt]))
        self.area = float(0.5 * np.sum(np.linalg.norm(newell, axis=1)))
        # merge neighbouring faces of one plane: connected components of the "same plane" graph
        across = {(a, b): f for a, b, f in zip(flat.tolist(), nxt.tolist(), owner0.tolist())}
        pairs = [(f, across[(b, a)]) for (a, b), f in across.items() if (b, a) in across]
        pairs = np.array(pairs, dtype=int).reshape(-1, 2)
        f, g = pairs[:, 0], pairs[:, 1]
        same = (np.max(np.abs(normals[f] - normals[g]), axis=1) < _PLANE_RTOL) & (np.abs(offsets[f] - offsets[g]) < _PLANE_RTOL * scale)
        comp = connected_components(len(faces), f[same], g[same])  # label: the first face of each
        is_first = comp == np.arange(len(faces))
        label = (np.cumsum(is_first) - 1)[comp]  # merged faces numbered by their first face
        nface = int(np.count_nonzero(is_first))
        self.face_normals = np.empty((nface, 3))
        self.face_normals[label] = normals
        self.face_normals = _unit_rows(self.face_normals)
        # corners of each face counter-clockwise: by angle about their mean in the basis of
        # _plane_basis(normal), from -pi (ties in ascending vertex order)
        pairs, _ = _distinct_pairs(np.column_stack([label[owner0], flat]))
        face_of, idx = pairs[:, 0], pairs[:, 1]
        count = np.bincount(face_of, minlength=nface)
        centre = np.zeros((nface, 3))
        np.add.at(centre, face_of, vertices[idx])
        rel = vertices[idx] - (centre / count[:, None])[face_of]
        u, v = _plane_basis_rows(self.face_normals)
        ang = np.arctan2(np.einsum("ij,ij->i", rel, v[face_of]), np.einsum("ij,ij->i", rel, u[face_of]))
        order = np.lexsort((ang, face_of))
        self.faces: list[np.ndarray] = np.split(idx[order], np.cumsum(count)[:-1])
        sizes = np.array([len(poly) for poly in self.faces])
        starts = np.concatenate(self.faces)
        ends = starts[_ring_successor(sizes)]
        owner = np.repeat(np.arange(nface), sizes)
        keys = np.sort(np.column_stack([starts, ends]), axis=1)
        self.edges, inverse = _distinct_pairs(keys)
        esum = np.zeros((self.edges.shape[0], 3))
        np.add.at(esum, inverse.ravel(), self.face_normals[owner])
        self.edge_normals = _unit_rows(esum)
        vsum = np.zeros_like(vertices)
        np.add.at(vsum, starts, self.face_normals[owner])
        self.vertex_normals = _unit_rows(vsum)
        self.edge_length = float(np.sum(np.linalg.norm(vertices[self.edges[:, 1]] - vertices[self.edges[:, 0]], axis=1)))
        # per face: longest edge and centroid (fan of triangles from the vertex mean)
        counts = np.bincount(owner, minlength=nface)
        self.face_max_edge = np.zeros(nface)
        np.maximum.at(self.face_max_edge, owner, np.linalg.norm(vertices[ends] - vertices[starts], axis=1))
        ref = np.zeros((nface, 3))
        np.add.at(ref, owner, vertices[starts])
        ref /= counts[:, None]
        fan = np.einsum("ij,ij->i", np.cross(vertices[starts] - ref[owner], vertices[ends] - ref[owner]), self.face_normals[owner])
        cen = np.zeros((nface, 3))
        np.add.at(cen, owner, fan[:, None] * (ref[owner] + vertices[starts] + vertices[ends]) / 3.0)
        total = np.bincount(owner, weights=fan, minlength=nface)
        self.face_centroids = np.where(total[:, None] > 0, cen / np.where(total > 0, total, 1.0)[:, None], ref)

    def transformed(self, rotation: np.ndarray, scale: float) -> "_PolyhedralSurface":
        """The same polytope rotated (rows of ``rotation`` are the new axes) and scaled."""
        out = object.__new__(_PolyhedralSurface)
        out.vertices = _readonly(scale * self.vertices @ rotation.T)
        out.faces, out.edges = self.faces, self.edges
        out.face_normals = self.face_normals @ rotation.T
        out.edge_normals = self.edge_normals @ rotation.T
        out.vertex_normals = self.vertex_normals @ rotation.T
        out.area, out.edge_length = self.area * scale**2, self.edge_length * scale
        out.face_max_edge = self.face_max_edge * scale
        out.face_centroids = scale * self.face_centroids @ rotation.T
        return out

    def sample(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """All vertices, edge points and face points at a common spacing h, ``n`` points in total.

        h solves ``area/h^2 + edge_length/h + vertices = n``; every face gets at least its
        centroid.  Normals: face normal on faces, mean of the two face normals on edges, mean of
        the adjacent face normals at vertices.
        """
        nv = self.vertices.shape[0]
        room = n - nv
        inv_h = 0.0 if room <= 0 else (-self.edge_length + math.sqrt(self.edge_length**2 + 4 * self.area * room)) / (2 * self.area)
        pts, nrm = [self.vertices], [self.vertex_normals]
        if inv_h > 0:
            p0, p1 = self.vertices[self.edges[:, 0]], self.vertices[self.edges[:, 1]]
            k = np.rint(np.linalg.norm(p1 - p0, axis=1) * inv_h).astype(int)  # segments per edge
            e = np.repeat(np.arange(self.edges.shape[0]), np.maximum(k - 1, 0))
            if e.size:
                j = np.arange(e.size) - np.repeat(np.cumsum(np.maximum(k - 1, 0)) - np.maximum(k - 1, 0), np.maximum(k - 1, 0)) + 1
                t = (j / k[e])[:, None]
                pts.append(p0[e] + t * (p1[e] - p0[e]))
                nrm.append(self.edge_normals[e])
        h = math.inf if inv_h == 0 else 1.0 / inv_h
        # faces smaller than the spacing (every edge shorter than h) get their centroid only
        small = self.face_max_edge < h
        for g in np.flatnonzero(~small):
            fp = _face_grid(self.vertices[self.faces[g]], self.face_normals[g], h)
            pts.append(fp)
            nrm.append(np.repeat(self.face_normals[g : g + 1], fp.shape[0], axis=0))
        pts.append(self.face_centroids[small])
        nrm.append(self.face_normals[small])
        return np.concatenate(pts), np.concatenate(nrm)

    def support(self, d: np.ndarray) -> np.ndarray:
        """Farthest point along each row of ``d``: the mean of the maximising vertices (ties within 1e-12)."""
        proj = d @ self.vertices.T
        best = np.max(proj, axis=1, keepdims=True)
        scale = np.linalg.norm(d, axis=1, keepdims=True) * float(np.max(np.linalg.norm(self.vertices, axis=1)))
        ties = proj >= best - 1e-12 * scale
        return (ties @ self.vertices) / np.sum(ties, axis=1, keepdims=True)


def _distinct(a: np.ndarray) -> np.ndarray:
    """Sorted distinct values (``np.unique`` without its import of ``numpy.ma``, ~30 ms)."""
    s = np.sort(a)
    return s[np.concatenate([[True], s[1:] != s[:-1]])] if s.size else s


def _distinct_pairs(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distinct rows of a non-negative ``(K, 2)`` int array, lexicographic, and each row's position."""
    code = keys[:, 0] * (int(keys.max()) + 1) + keys[:, 1]
    order = np.argsort(code, kind="stable")
    new = np.concatenate([[True], code[order][1:] != code[order][:-1]])
    inverse = np.empty(code.size, dtype=int)
    inverse[order] = np.cumsum(new) - 1
    return keys[order[new]], inverse


def _ring_successor(sizes: np.ndarray) -> np.ndarray:
    """For rings of ``sizes`` laid end to end, the position of each entry's successor in its ring."""
    nxt = np.arange(1, int(np.sum(sizes)) + 1)
    ends = np.cumsum(sizes)
    nxt[ends - 1] = ends - sizes
    return nxt


def _plane_basis_rows(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_plane_basis` of each row of ``normals``."""
    helper = np.eye(3)[np.argmin(np.abs(normals), axis=1)]
    u = np.cross(normals, helper)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return u, np.cross(normals, u)


def _plane_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors spanning the plane normal to ``normal`` (deterministic)."""
    u, v = _plane_basis_rows(np.asarray(normal, dtype=float)[None, :])
    return u[0], v[0]


def _face_grid(poly: np.ndarray, normal: np.ndarray, h: float) -> np.ndarray:
    """Points of a grid of about h x h cells inside a convex planar polygon (cell centres).

    The grid is aligned with the polygon's longest edge and its cells divide the bounding
    rectangle evenly (so a rectangular face of sides W x H gets round(W/h) x round(H/h) points,
    half a cell from its edges); centres closer than a quarter cell to an edge are dropped.  A face
    too small for any cell contributes its centroid.
    """
    centre = _polygon_centroid(poly, normal)
    if not math.isfinite(h):
        return centre[None, :]
    edges = np.roll(poly, -1, axis=0) - poly
    longest = edges[int(np.argmax(np.linalg.norm(edges, axis=1)))]
    u = longest / np.linalg.norm(longest)
    v = np.cross(normal, u)
    rel = poly - centre
    pu, pv = rel @ u, rel @ v
    ku = max(1, int(round(np.ptp(pu) / h)))
    kv = max(1, int(round(np.ptp(pv) / h)))
    if ku * kv > 4_000_000:
        raise InputError("n", "too many surface points requested")
    step_u, step_v = np.ptp(pu) / ku, np.ptp(pv) / kv
    gu, gv = np.meshgrid(pu.min() + (np.arange(ku) + 0.5) * step_u, pv.min() + (np.arange(kv) + 0.5) * step_v, indexing="ij")
    grid = np.column_stack([gu.ravel(), gv.ravel()])
    # inward edge normals in the (u, v) plane: the polygon runs counter-clockwise about +normal
    ring = np.column_stack([pu, pv])
    e2 = np.roll(ring, -1, axis=0) - ring
    inward = np.column_stack([-e2[:, 1], e2[:, 0]]) / np.linalg.norm(e2, axis=1)[:, None]
    signed = grid @ inward.T - np.einsum("ek,ek->e", ring, inward)[None, :]
    inside = np.min(signed, axis=1) >= 0.25 * min(step_u, step_v)
    if not np.any(inside):
        return centre[None, :]
    g = grid[inside]
    return centre + g[:, :1] * u + g[:, 1:] * v


def _polygon_centroid(poly: np.ndarray, normal: np.ndarray) -> np.ndarray:
    ref = poly.mean(axis=0)
    a = np.cross(poly - ref, np.roll(poly, -1, axis=0) - ref) @ normal
    c = (poly + np.roll(poly, -1, axis=0) + ref) / 3.0
    total = np.sum(a)
    return ref if total <= 0 else (a[:, None] * c).sum(axis=0) / total


class _PolyhedralShape(_Shape):
    __slots__ = ("_surface",)

    @property
    def vertices(self) -> np.ndarray:
        """Corners ``(N, 3)`` in the local (principal) frame (read-only array)."""
        return self._surface.vertices

    def _sample(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """All vertices, then edge points, then face points at a common spacing; about ``n`` in total.

        Never fewer than the vertices plus one point per face.  Normals: the face normal on faces,
        the mean of the two adjacent face normals on edges and the mean of the adjacent face
        normals at vertices (unit length).  Deterministic.
        """
        return self._surface.sample(n)

    def support(self, direction: Any) -> np.ndarray:
        """Farthest vertex along ``direction`` (mean of tied vertices: a face or edge centre)."""
        d = _direction(direction)
        out = self._surface.support(np.atleast_2d(d))
        return out[0] if d.ndim == 1 else out


def _readonly(x: np.ndarray) -> np.ndarray:
    x = np.ascontiguousarray(x, dtype=float)
    x.flags.writeable = False
    return x


class Box(_PolyhedralShape):
    """Uniform rectangular box with half-lengths a >= b >= c: I_xx = m (b^2 + c^2)/3, etc."""

    kind = "box"
    __slots__ = ("_abc",)

    def __init__(self, a: float, b: float, c: float, *, density: float | None = None, mass: float | None = None):
        a, b, c = _axes(a, b, c)
        self._abc = (a, b, c)
        signs = np.array([[sx, sy, sz] for sx in (1, -1) for sy in (1, -1) for sz in (1, -1)], float)
        self._surface = _PolyhedralSurface(_readonly(signs * np.array([a, b, c])))
        self._finish(
            _kernel(_mp.box_volume, a, b, c), density, mass, _kernel(_mp.box_inertia_per_mass, a, b, c), (a, b, c),
            math.hypot(a, b, c), "a",
        )

    @property
    def a(self) -> float:
        return self._abc[0]

    @property
    def b(self) -> float:
        return self._abc[1]

    @property
    def c(self) -> float:
        return self._abc[2]

    def _label(self) -> str:
        a, b, c = self._abc
        return f"Box(a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)})"


# ============================================================================================
# Convex, centrally symmetric polyhedron
# ============================================================================================
def _tetra_decomposition(points: np.ndarray, simplices: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Volume, centroid and second-moment tensor ``int r r^T dV`` about the origin (exact).

    The hull is the union of the tetrahedra (origin, facet triangle ``simplices``) when the origin
    is inside; each contributes the generated ``tetrahedron_moments`` taken with the sign of its
    orientation.
    """
    tri = points[simplices]  # (F, 3, 3): facet, vertex, coordinate
    args = [tri[:, v, k] for v in range(3) for k in range(3)]
    vol, mx, my, mz, sxx, syy, szz, sxy, sxz, syz = (np.asarray(x, float) for x in _mp.tetrahedron_moments(*args))
    sign = np.sign(vol)
    volume = float(np.sum(sign * vol))
    first = np.array([np.sum(sign * mx), np.sum(sign * my), np.sum(sign * mz)])
    xy, xz, yz = np.sum(sign * sxy), np.sum(sign * sxz), np.sum(sign * syz)
    second = np.array(
        [[np.sum(sign * sxx), xy, xz], [xy, np.sum(sign * syy), yz], [xz, yz, np.sum(sign * szz)]]
    )
    return volume, first / volume, second


def _min_area_rectangle(points2: np.ndarray) -> tuple[float, float]:
    """Angle and area of the smallest bounding rectangle of 2-D points (one side on a hull edge)."""
    try:
        ring = points2[convex_hull_2d(points2)]
    except HullError:
        return 0.0, 0.0
    edges = np.roll(ring, -1, axis=0) - ring
    angles = np.arctan2(edges[:, 1], edges[:, 0]) % (np.pi / 2)
    best_angle, best_area = 0.0, math.inf
    for ang in _distinct(np.round(angles, 14)):
        c, s = math.cos(ang), math.sin(ang)
        pu = points2 @ np.array([c, s])
        pv = points2 @ np.array([-s, c])
        area = float(np.ptp(pu) * np.ptp(pv))
        if area < best_area * (1 - 1e-9):
            best_angle, best_area = float(ang), area
    return best_angle, best_area


def _resolve_plane(points: np.ndarray, e1: np.ndarray, e2: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Orthonormal basis of span(e1, e2) whose bounding rectangle of ``points`` has least area."""
    ang, area = _min_area_rectangle(np.column_stack([points @ e1, points @ e2]))
    c, s = math.cos(ang), math.sin(ang)
    return c * e1 + s * e2, -s * e1 + c * e2, area


def _principal_axes(points: np.ndarray, second: np.ndarray, face_normals: np.ndarray, rtol: float) -> np.ndarray:
    """Rows: local x, y, z axes (input coordinates) of a principal frame with the paper's ordering.

    * The input axes are kept when they are principal (off-diagonal second moments below 1e-9 of
      the trace) and are mirror planes of the vertex set (each reflection x -> -x, y -> -y,
      z -> -z maps every vertex within ``rtol`` of a vertex): the usual axis-aligned input such as
      an octahedron with vertices on the axes.  Otherwise the eigenvectors of the second-moment
      tensor are used.
    * Axes are ordered by decreasing second moment int x^2 dV, i.e. increasing principal moment
      (I_xx <= I_yy <= I_zz).
    * Any orthonormal basis of a degenerate eigenspace is principal: a 2-D degenerate pair of
      eigenvectors is replaced by the basis with the smallest bounding rectangle, and a fully
      degenerate (isotropic) tensor by the smallest bounding box with one axis along a face
      normal (a rotated cube gets its own axes back).  Axes of equal moment are then ordered by
      decreasing half-length.
    * Paper convention where possible: if a 2-D degenerate pair (also of kept input axes) then
      breaks a >= b >= c against the third axis, the pair is rotated in its plane to the basis of
      least bounding area that satisfies it, when one exists (e.g. a square double pyramid whose
      apexes are nearer than its base corners gets its x axis through a base corner).
    * Signs: each axis points so that its largest component is positive; det = +1.
    """
    trace = float(np.trace(second))
    off = max(abs(second[0, 1]), abs(second[0, 2]), abs(second[1, 2]))
    from_input = off <= 1e-9 * trace and _mirror_symmetric(points, rtol)
    if from_input:
        moments, axes = np.diag(second).copy(), np.eye(3)
    else:
        moments, vecs = np.linalg.eigh(second)
        axes = vecs.T.copy()
    order = sorted(range(3), key=lambda k: -moments[k])
    groups: list[list[int]] = [[order[0]]]
    for k in order[1:]:
        if moments[groups[-1][-1]] - moments[k] <= _DEGENERATE_RTOL * moments[order[0]]:
            groups[-1].append(k)
        else:
            groups.append([k])
    rows: list[np.ndarray] = []
    for gi, group in enumerate(groups):
        basis = [axes[k] for k in group]
        if not from_input and len(group) == 3:
            basis = _least_box_basis(points, face_normals)
        elif len(group) == 2:
            if not from_input:
                basis = list(_resolve_plane(points, basis[0], basis[1])[:2])
            basis = _by_half_length(points, basis)
            other = float(np.max(np.abs(points @ axes[groups[1 - gi][0]])))
            if gi == 0:  # local x, y in the plane, local z fixed: need b >= c
                ok = _half(points, basis[1]) >= other * (1 - ORDER_RTOL)
                bounds = dict(at_least=other)
            else:  # local x fixed, local y, z in the plane: need a >= b
                ok = _half(points, basis[0]) <= other * (1 + ORDER_RTOL)
                bounds = dict(at_most=other)
            if not ok:
                better = _plane_basis_within(points, basis[0], basis[1], **bounds)
                basis = better if better is not None else basis
        rows += _by_half_length(points, basis)
    frame = np.array(rows)
    for k in range(3):
        if frame[k, int(np.argmax(np.abs(frame[k])))] < 0:
            frame[k] = -frame[k]
    if np.linalg.det(frame) < 0:
        frame[2] = -frame[2]
    return frame


def _half(points: np.ndarray, axis: np.ndarray) -> float:
    return float(np.max(np.abs(points @ axis)))


def _by_half_length(points: np.ndarray, basis: list[np.ndarray]) -> list[np.ndarray]:
    """Axes of equal moment ordered by decreasing half-length (stable for ties within 1e-9)."""
    half = [_half(points, e) for e in basis]
    top = max(half)
    return [basis[i] for i in sorted(range(len(basis)), key=lambda i: -round(half[i] / top * 1e9))]


def _plane_basis_within(points: np.ndarray, e1: np.ndarray, e2: np.ndarray, *, at_least: float | None = None,
                        at_most: float | None = None) -> list[np.ndarray] | None:
    """A basis of span(e1, e2) whose two half-lengths are >= ``at_least`` (or <= ``at_most``).

    Candidate angles, in this order of preference: the edges of the projected hull (least-rectangle
    candidates), the directions of its vertices (an axis through a corner), then every quarter
    degree; within the first family that has feasible members, the least bounding area wins.
    ``None`` if no candidate is feasible.
    """
    p2 = np.column_stack([points @ e1, points @ e2])
    try:
        ring = p2[convex_hull_2d(p2)]
    except HullError:
        ring = p2
    edges = np.roll(ring, -1, axis=0) - ring
    families = (
        np.arctan2(edges[:, 1], edges[:, 0]) % (np.pi / 2),
        np.arctan2(ring[:, 1], ring[:, 0]) % (np.pi / 2),
        np.arange(360) * (np.pi / 720),
    )
    for angles in families:  # first family with a feasible member wins
        best, best_area = None, math.inf
        for ang in angles:
            c, s = math.cos(ang), math.sin(ang)
            hu = float(np.max(np.abs(p2 @ np.array([c, s]))))
            hv = float(np.max(np.abs(p2 @ np.array([-s, c]))))
            if at_least is not None and min(hu, hv) < at_least * (1 - ORDER_RTOL):
                continue
            if at_most is not None and max(hu, hv) > at_most * (1 + ORDER_RTOL):
                continue
            if hu * hv < best_area * (1 - 1e-9):
                best, best_area = [c * e1 + s * e2, -s * e1 + c * e2], hu * hv
        if best is not None:
            return best
    return None


def _mirror_symmetric(points: np.ndarray, rtol: float) -> bool:
    """Whether reflection in each coordinate plane maps every point within ``rtol`` of a point."""
    for k in range(3):
        mirrored = points.copy()
        mirrored[:, k] = -mirrored[:, k]
        if np.max(nearest_neighbours(mirrored, points)[0]) > rtol:
            return False
    return True


def _least_box_basis(points: np.ndarray, face_normals: np.ndarray) -> list[np.ndarray]:
    """Orthonormal basis with the least bounding-box volume among those with an axis along a face normal."""
    best, best_volume = None, math.inf
    seen: list[np.ndarray] = []
    for nrm in face_normals:
        if any(abs(float(nrm @ s)) > 1 - 1e-9 for s in seen):
            continue
        seen.append(nrm)
        e1, e2 = _plane_basis(nrm)
        u, v, area = _resolve_plane(points, e1, e2)
        volume = area * float(np.ptp(points @ nrm))
        if volume < best_volume * (1 - 1e-9):
            best, best_volume = [u, v, nrm.copy()], volume
    return best


class ConvexPolyhedron(_PolyhedralShape):
    """Uniform convex, centrally symmetric polyhedron given by its vertices (any frame, any origin).

    Construction:

    1. The hull of the points is taken with :func:`dtcrit.hull.convex_hull_3d` (after shifting to
       the vertex mean and scaling by the largest distance, so the checks are scale-free; points
       within ``min(rtol, 1e-10)`` (not below 1e-13, rounding) of a face plane lie on it, points
       that close to each other are one).
       Refused (``InputError`` key ``"vertices"``): fewer than 4 non-coplanar points; a point
       strictly inside the hull (farther than ``rtol`` inside every face: the set is not convex);
       a hull that is not centrally symmetric about its centroid (some ``-v`` farther than
       ``rtol`` from every vertex).  Points on the hull surface that are not corners are dropped.
    2. Volume, centroid and inertia tensor: exact tetrahedral decomposition (generated kernel).
    3. The frame is rotated to principal axes ordered so that I_xx <= I_yy <= I_zz (see
       :func:`_principal_axes`): input axes are kept when already principal and mirror planes;
       within equal moments the axes go by decreasing half-length, and a degenerate pair is
       turned in its plane to meet a >= b >= c when some basis does.  ``rotation`` (det +1) maps
       input to local coordinates: ``local = rotation @ (input - centroid)``.
       Tolerances ``rtol`` (default ``SYMMETRY_RTOL`` = 1e-6) are relative to the largest distance
       of a point from the vertex mean.
    4. If the half-lengths of the local bounding box then fail a >= b >= c (possible: the axis of
       least inertia need not be the longest), ``assumption_issues`` says so and an
       :class:`AssumptionWarning` is emitted; nothing is hidden.
    """

    kind = "polyhedron"
    __slots__ = ("_rotation", "_centroid", "_dropped")

    def __init__(self, vertices: Any, *, density: float | None = None, mass: float | None = None,
                 rtol: float = SYMMETRY_RTOL):
        rtol = _positive("rtol", rtol)
        try:
            pts = np.array(vertices, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InputError("vertices", f"must be an (N, 3) array of real numbers ({exc})") from None
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise InputError("vertices", f"must be an (N, 3) array (got shape {pts.shape})")
        if not np.all(np.isfinite(pts)):
            raise InputError("vertices", "must be finite (got NaN or inf)")
        if pts.shape[0] < 4:
            raise InputError("vertices", f"need at least 4 non-coplanar points (got {pts.shape[0]})")
        mean = pts.mean(axis=0)
        scale = float(np.max(np.linalg.norm(pts - mean, axis=1)))
        if not (math.isfinite(scale) and scale > 0.0):
            raise InputError("vertices", "all points coincide")
        q = (pts - mean) / scale
        try:
            hull = convex_hull_3d(q, rtol=max(min(rtol, HULL_RTOL), 1e-13))
        except HullError:
            raise InputError("vertices", "need at least 4 non-coplanar points (the points are coplanar or degenerate)") from None
        if hull.volume < 1e-12:
            raise InputError("vertices", f"the hull is (nearly) flat: volume {hull.volume:.3g} of the unit-scaled set")
        corner = np.zeros(q.shape[0], dtype=bool)
        corner[hull.vertices] = True
        depth = -np.max(q @ hull.equations[:, :3].T + hull.equations[:, 3], axis=1)
        inside = np.flatnonzero(~corner & (depth > rtol))
        if inside.size:
            i = int(inside[np.argmax(depth[inside])])
            raise InputError(
                "vertices",
                f"not convex: point {i} {pts[i].tolist()} lies strictly inside the convex hull "
                f"({depth[i] * scale:.3g} inside the nearest face)",
            )
        self._dropped = int(np.count_nonzero(~corner))
        hv = q[hull.vertices]  # ascending input order
        position = np.full(q.shape[0], -1)
        position[hull.vertices] = np.arange(hull.vertices.size)  # input index -> row of hv
        ref = hv.mean(axis=0)
        volume, centroid, second0 = _tetra_decomposition(hv - ref, position[hull.simplices])
        rel = hv - ref - centroid
        mirror_gap, _ = nearest_neighbours(-rel, rel)
        worst = int(np.argmax(mirror_gap))
        if mirror_gap[worst] > rtol:
            raise InputError(
                "vertices",
                f"not centrally symmetric about the centroid: the mirror image of vertex "
                f"{(rel[worst] * scale + mean + (ref + centroid) * scale).tolist()} is {mirror_gap[worst] * scale:.3g} "
                f"from the nearest vertex (tolerance rtol={rtol:g} x {scale:.3g})",
            )
        second = second0 - volume * np.outer(centroid, centroid)  # parallel-axis shift to the centroid
        second = 0.5 * (second + second.T)
        surface0 = _PolyhedralSurface(rel, tuple(position[f] for f in hull.faces), hull.equations[:, :3])
        frame = _principal_axes(rel, second, surface0.face_normals, rtol)
        local = rel @ frame.T
        # moments per unit volume in the principal frame (unit-scaled), then physical units
        diag = np.diag(frame @ second @ frame.T) / volume
        per_mass = (scale**2 * (diag[1] + diag[2]), scale**2 * (diag[0] + diag[2]), scale**2 * (diag[0] + diag[1]))
        half = tuple(float(scale * np.max(np.abs(local[:, k]))) for k in range(3))
        arm = float(scale * np.max(np.linalg.norm(local, axis=1)))
        self._rotation = _readonly(frame)
        self._centroid = _readonly(mean + scale * (ref + centroid))
        self._surface = surface0.transformed(frame, scale)
        self._finish(volume * scale**3, density, mass, per_mass, half, arm, "vertices")

    @property
    def rotation(self) -> np.ndarray:
        """3x3 rotation (det +1): ``local = rotation @ (input - centroid)``."""
        return self._rotation

    @property
    def centroid(self) -> np.ndarray:
        """Centroid of the solid in the input frame."""
        return self._centroid

    @property
    def dropped_points(self) -> int:
        """How many input points were not corners (on the hull surface, or duplicates) and were dropped."""
        return self._dropped

    def _label(self) -> str:
        a, b, c = self._half_lengths if hasattr(self, "_half_lengths") else (0, 0, 0)
        return f"ConvexPolyhedron({self._surface.vertices.shape[0]} vertices, half-lengths {_fmt(a)}, {_fmt(b)}, {_fmt(c)})"


# ============================================================================================
# Factory
# ============================================================================================
_KINDS = {
    "sphere": (Sphere, ("radius",)),
    "ellipsoid": (Ellipsoid, ("a", "b", "c")),
    "superquadric": (Superquadric, ("a", "b", "c", "eps1", "eps2")),
    "box": (Box, ("a", "b", "c")),
    "polyhedron": (ConvexPolyhedron, ("vertices",)),
}
_OPTIONAL = {"density", "mass"}


def shape_from_spec(kind: str, **params: Any) -> _Shape:
    """Build a shape from a kind name and keyword parameters (scene files).

    ``kind`` is one of ``sphere, ellipsoid, superquadric, box, polyhedron``; parameters are the
    constructor arguments by name plus exactly one of ``density`` / ``mass`` (and ``rtol`` for
    polyhedra).  Unknown or missing parameters raise ``InputError`` naming them.
    """
    if not isinstance(kind, str) or kind.lower() not in _KINDS:
        raise InputError("kind", f"must be one of {', '.join(_KINDS)} (got {kind!r})")
    cls, required = _KINDS[kind.lower()]
    allowed = set(required) | _OPTIONAL | ({"rtol"} if cls is ConvexPolyhedron else set())
    for key in params:
        if key not in allowed:
            raise InputError(key, f"unknown parameter for a {kind.lower()} (expected {', '.join(sorted(allowed))})")
    for key in required:
        if key not in params:
            raise InputError(key, f"missing (a {kind.lower()} needs {', '.join(required)})")
    positional = [params.pop(key) for key in required]
    return cls(*positional, **params)
