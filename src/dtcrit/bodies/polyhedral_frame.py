"""Exact moments of a convex polyhedron (tetrahedral decomposition with the generated kernel) and the
choice of its principal frame with the paper's ordering (Peng et al. 2020, Section 3, assumption 3).
"""
from __future__ import annotations

import math

import numpy as np

from dtcrit._generated import mass_properties as _mp
from dtcrit.bodies.checks import _DEGENERATE_RTOL, ORDER_RTOL
from dtcrit.bodies.hull import HullError, convex_hull_2d, nearest_neighbours
from dtcrit.bodies.polyhedral_surface import _plane_basis
from dtcrit.numerics.distinct import distinct


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
    for ang in distinct(np.round(angles, 14)):
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
    assert best is not None  # the first face normal always sets it
    return best
