"""Box and convex, centrally symmetric polyhedron (Peng et al. 2020, Section 3: convex, centrally
symmetric particles with a principal local frame).
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from dtcrit._generated import mass_properties as _mp
from dtcrit.bodies.base import _Shape
from dtcrit.bodies.checks import SYMMETRY_RTOL, _axes, _direction, _fmt, _kernel, _positive, _readonly
from dtcrit.bodies.hull import HULL_RTOL, HullError, convex_hull_3d, nearest_neighbours
from dtcrit.bodies.polyhedral_frame import _principal_axes, _tetra_decomposition
from dtcrit.bodies.polyhedral_surface import _PolyhedralSurface
from dtcrit.errors import InputError


class _PolyhedralShape(_Shape):
    __slots__ = ("_surface",)
    _surface: _PolyhedralSurface

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



class Box(_PolyhedralShape):
    """Uniform rectangular box with half-lengths a >= b >= c: I_xx = m (b^2 + c^2)/3, etc.

    Parameters
    ----------
    a, b, c : float
        Half-lengths [m], a >= b >= c.
    density : float, optional
        Density [kg/m^3] (give exactly one of ``density`` and ``mass``).
    mass : float, optional
        Mass [kg].

    Examples
    --------
    >>> from dtcrit import Box
    >>> b = Box(1.0, 0.5, 0.25, mass=2.0)   # half-lengths [m]
    >>> round(b.max_arm, 6), [round(i, 6) for i in b.inertia]
    (1.145644, [0.208333, 0.708333, 0.833333])
    """

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
        """Largest half-length [m]."""
        return self._abc[0]

    @property
    def b(self) -> float:
        """Middle half-length [m]."""
        return self._abc[1]

    @property
    def c(self) -> float:
        """Smallest half-length [m]."""
        return self._abc[2]

    def _label(self) -> str:
        a, b, c = self._abc
        return f"Box(a={_fmt(a)}, b={_fmt(b)}, c={_fmt(c)})"


class ConvexPolyhedron(_PolyhedralShape):
    """Uniform convex, centrally symmetric polyhedron given by its vertices (any frame, any origin).

    Construction:

    1. The hull of the points is taken with :func:`dtcrit.bodies.hull.convex_hull_3d` (after shifting to
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

    Parameters
    ----------
    vertices : array_like
        Points, (N, 3) [m].
    density : float, optional
        Density [kg/m^3] (give exactly one of ``density`` and ``mass``).
    mass : float, optional
        Mass [kg].
    rtol : float
        Relative tolerance of the convexity and symmetry checks.

    Examples
    --------
    >>> from dtcrit import ConvexPolyhedron
    >>> corners = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    >>> cube = ConvexPolyhedron(corners, density=1.0)   # the hull of the corners
    >>> round(cube.volume, 12), round(cube.max_arm ** 2, 12)
    (8.0, 3.0)
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
