"""Sphere, ellipsoid and convex superquadric: closed-form mass properties emitted by
``dtcrit.symbolic.mass_properties`` into ``dtcrit._generated.mass_properties``; the sphere and the
ellipsoid are superquadrics with ``eps1 = eps2 = 1``.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from dtcrit._generated import mass_properties as _mp
from dtcrit.bodies.base import _Shape
from dtcrit.bodies.checks import _axes, _direction, _exponent, _fmt, _kernel, _positive
from dtcrit.bodies.superquadric_surface import (
    _superquadric_normals,
    _superquadric_radial_projection,
    _superquadric_support,
    _superquadric_surface_points,
    superquadric_max_arm,
)


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
        (:func:`_superquadric_radial_projection`); shape (N, 3), local frame.
        """
        d = np.atleast_2d(np.asarray(directions, dtype=float))
        return _superquadric_radial_projection(d, self._axes_arr, self._e1, self._e2)

    def outward_normals(self, points: np.ndarray) -> np.ndarray:
        """Outward unit normals (normalised gradient of the inside-outside function) at the surface
        ``points`` (rows, local frame; :func:`_superquadric_normals`).
        """
        p = np.atleast_2d(np.asarray(points, dtype=float))
        return _superquadric_normals(p, self._axes_arr, self._e1, self._e2)


class Sphere(_SuperquadricFamily):
    """Uniform solid sphere of radius ``radius``: I = 2/5 m R^2 about every centroidal axis.

    Parameters
    ----------
    radius : float
        Radius [m].
    density : float, optional
        Density [kg/m^3] (give exactly one of ``density`` and ``mass``).
    mass : float, optional
        Mass [kg].

    Examples
    --------
    >>> from dtcrit import Sphere
    >>> s = Sphere(0.5, density=2500.0)
    >>> round(s.mass, 6), s.max_arm
    (1308.996939, 0.5)
    """

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
        """Radius [m]."""
        return self._radius

    @property
    def equivalent_radius(self) -> float:
        """Radius of the sphere of equal volume: the radius itself [m]."""
        return self._radius

    def _label(self) -> str:
        return f"Sphere(radius={_fmt(self._radius)})"


class Ellipsoid(_SuperquadricFamily):
    """Uniform solid ellipsoid (x/a)^2 + (y/b)^2 + (z/c)^2 <= 1 with a >= b >= c.

    I_xx = m (b^2 + c^2)/5, I_yy = m (a^2 + c^2)/5, I_zz = m (a^2 + b^2)/5; V = 4/3 pi a b c
    (Peng et al. 2020, Section 6.4).  ``max_arm = a``.

    Parameters
    ----------
    a, b, c : float
        Semi-axes [m], a >= b >= c.
    density : float, optional
        Density [kg/m^3] (give exactly one of ``density`` and ``mass``).
    mass : float, optional
        Mass [kg].

    Examples
    --------
    >>> from dtcrit import Ellipsoid
    >>> e = Ellipsoid(3.0, 2.0, 1.0, density=1000.0)   # semi-axes [m], Peng et al. 2020, Section 6
    >>> round(e.mass, 3), e.max_arm
    (25132.741, 3.0)
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

    Parameters
    ----------
    a, b, c : float
        Semi-axes [m], a >= b >= c.
    eps1, eps2 : float
        Shape exponents (north-south and east-west).
    density : float, optional
        Density [kg/m^3] (give exactly one of ``density`` and ``mass``).
    mass : float, optional
        Mass [kg].

    Examples
    --------
    >>> from dtcrit import Superquadric, Ellipsoid
    >>> q = Superquadric(3.0, 2.0, 1.0, 1.0, 1.0, density=1000.0)   # eps1 = eps2 = 1: the ellipsoid
    >>> round(q.mass / Ellipsoid(3.0, 2.0, 1.0, density=1000.0).mass, 12)
    1.0
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
        """North-south shape exponent."""
        return self._e1

    @property
    def eps2(self) -> float:
        """East-west shape exponent."""
        return self._e2

    def _label(self) -> str:
        a, b, c = self._axes_arr
        return f"Superquadric(a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)}, eps1={_fmt(self._e1)}, eps2={_fmt(self._e2)})"
