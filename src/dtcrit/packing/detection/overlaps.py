"""Contact detection for packings: spheres by overlap (``scipy.spatial.cKDTree``), convex shapes by
penetration depth from their support functions.

Spheres ``i`` and ``j`` touch when their centre distance ``d <= (R_i + R_j) (1 + tolerance)``.
Periodic axes use the minimum image when the box is wider than twice the contact range; for
narrower boxes every periodic image in range is searched explicitly, so a particle may touch its
own image or the same neighbour through several images (small lattice cells need this).  A sheared
(triclinic) cell is searched over every image in range, ghosts and all
(``dtcrit.packing.periodic_cell.cell_pairs``), whatever its tilt.
The contact point is the middle of the overlap along the centre line,
``x_c = x_i + (R_i - delta/2) n`` (Peng et al. 2020, Eqs (1)-(2) define both arms from this one
point).
"""
from __future__ import annotations

import itertools

import numpy as np
from scipy.spatial import cKDTree

from dtcrit.errors import InputError

from dtcrit.packing.contact_set import index_dtype
from dtcrit.packing.model import Box, Contacts, Packing
from dtcrit.packing.periodic_cell import cell_pairs, own_images, shortest_translation, spacings, wrap
from dtcrit.packing.uniform_values import uniform
from dtcrit.packing.detection.sphere_fields import _filled, _image_of, _joined, _touching


def wrap_positions(positions: np.ndarray, box: Box | None) -> np.ndarray:
    """Positions mapped into ``[lo, hi)`` along the periodic axes of ``box``.

    Parameters
    ----------
    positions : numpy.ndarray
        Centres, shape ``(n, 3)`` [m] (not modified).
    box : Box or None
        The simulation box; ``None`` or non-periodic axes leave the coordinates as they are.

    Returns
    -------
    numpy.ndarray
        Wrapped copy of ``positions``.
    """
    x = np.array(positions, dtype=float, copy=True)
    if box is None:
        return x
    if box.cell is not None:
        return wrap(box, x)
    for a in range(3):
        if box.periodic[a]:
            length = box.lengths[a]
            x[:, a] = box.lo[a] + np.mod(x[:, a] - box.lo[a], length)
            x[x[:, a] >= box.hi[a], a] = box.lo[a]  # mod can round up to exactly L
    return x


DETECT_CHUNK = 1 << 20
"""Candidate pairs one pass of the sphere contact test handles: its temporaries (separations,
normals, arms) are O(chunk), and only the finished contact fields are O(contacts)."""


def _search_frame(x: np.ndarray, cutoff: float, box: Box | None):
    """``(y, boxsize)`` for ``cKDTree``: positions shifted so that periodic axes are a torus of the
    box lengths (``cKDTree`` wants data strictly inside ``[0, L)``) and non-periodic ones a box too
    wide to wrap; ``(x, None)`` without periodic axes.  ``None`` as ``y`` when some periodic axis is
    narrower than twice the cutoff (no unique minimum image).
    """
    if box is None:
        return x, None
    if box.cell is not None:
        return None, None  # a sheared cell: every image in range (cell_pairs)
    periodic = np.array(box.periodic)
    if not periodic.any():
        return x, None
    lengths = box.lengths
    if not np.all(lengths[periodic] > 2.0 * cutoff):
        return None, None
    shift = x.min(axis=0)
    y = x - np.where(periodic, box.lo, shift)
    size = np.where(periodic, lengths, (x.max(axis=0) - shift) + 4.0 * cutoff + 1.0)
    return np.minimum(y, np.nextafter(size, 0)), size


def _sorted_pairs(y: np.ndarray, size, cutoff: float) -> tuple[np.ndarray, np.ndarray]:
    """Pairs ``(i, j)``, ``i < j``, with (minimum-image) distance within ``cutoff``, sorted by
    ``(i, j)``: ``cKDTree.query_pairs`` of one tree of all particles (each pair found once; toroidal
    along periodic axes), sorted as the keys ``i N + j`` (exact in int64 up to 3e9 particles); the
    pairs are given in ``index_dtype(N)`` (int32 when ``6 N < 2^31``).

    Temporaries: the tree and 24 bytes per pair (the pairs and their keys).
    """
    n = len(y)
    pairs = cKDTree(y, boxsize=size).query_pairs(cutoff, output_type="ndarray")
    keys = pairs[:, 0].astype(np.int64)
    keys *= n
    keys += pairs[:, 1]
    del pairs
    keys.sort()
    i, j = np.empty(keys.shape, index_dtype(n)), np.empty(keys.shape, index_dtype(n))
    np.floor_divide(keys, np.int64(n), out=i, casting="same_kind")  # < n: fits the index dtype
    np.remainder(keys, np.int64(n), out=j, casting="same_kind")
    return i, j


AXES = "xyz"


def check_box_holds_particles(packing: Packing) -> None:
    """Refuse a periodic box shorter than the widest particle's diameter.

    Such a particle overlaps its own periodic image (touching it, length = diameter, is kept), which is
    not a packing; the image search of such a box also grows as ``(diameter / length)^3``.

    Parameters
    ----------
    packing : Packing
        Particles (radii) and their box.

    Raises
    ------
    InputError
        With key ``box`` when a periodic length is too short.
    """
    box = packing.box
    if box is None or not any(box.periodic) or packing.n == 0:
        return
    normals = np.eye(3) if box.cell is None else np.linalg.inv(box.cell) * spacings(box)[:, None]
    for a in range(3):
        if not box.periodic[a]:
            continue
        widths = 2.0 * packing.radii if packing.shapes is None else _widths_along(packing, normals[a])
        widest = int(np.argmax(widths))
        diameter = float(widths[widest])
        length = float(box.lengths[a] if box.cell is None else spacings(box)[a])
        if packing.shapes is None and box.cell is not None:
            length = shortest_translation(box)  # a sphere overlaps its image only within the shortest one
        if length < diameter * (1.0 - 1e-12):
            raise InputError("box", f"the periodic length along {AXES[a]} is {length:.6g} m, shorter than the "
                                    f"width {diameter:.6g} m of particle {packing.particle_id(widest)}: it "
                                    "overlaps its own periodic image")


def _widths_along(packing: Packing, e: np.ndarray) -> np.ndarray:
    """Width of each (centrally symmetric) body along a unit direction ``e``: twice its support there."""
    rot = packing.orientations if packing.orientations is not None else np.repeat(np.eye(3)[None], packing.n, 0)
    assert packing.shapes is not None  # only called for packings of shaped bodies
    return np.array([2.0 * abs(_support_point(shape, r, e) @ e) for shape, r in zip(packing.shapes, rot)])


def _narrow_box_pairs(x: np.ndarray, cutoff: float, box: Box):
    """``(i, j, image)`` of a periodic box narrower than twice the cutoff: every image in range is
    searched explicitly, so a particle may touch its own image or a neighbour through several.
    """
    if box.cell is not None:
        return cell_pairs(x, cutoff, box)
    lengths = box.lengths
    periodic = np.array(box.periodic)
    reach = [int(np.ceil(cutoff / lengths[a])) if periodic[a] else 0 for a in range(3)]
    tree = cKDTree(x)
    out_i, out_j, out_s = [], [], []
    for offset in itertools.product(*(range(-r, r + 1) for r in reach)):
        s = np.array(offset, dtype=np.int64)
        other = cKDTree(x + s * lengths)
        sdm = tree.sparse_distance_matrix(other, cutoff, output_type="ndarray")
        i, j = sdm["i"].astype(np.int64), sdm["j"].astype(np.int64)
        positive = offset > (0, 0, 0)
        keep = (i < j) | ((i == j) & positive)  # (i, j, s) and (j, i, -s) are one contact
        out_i.append(i[keep])
        out_j.append(j[keep])
        out_s.append(np.repeat(s[None, :], keep.sum(), axis=0))
    return np.concatenate(out_i), np.concatenate(out_j), np.concatenate(out_s)


def _candidate_pairs(x: np.ndarray, cutoff: float, box: Box | None):
    """Pairs ``(i, j, image)`` with centre distance within ``cutoff``, each physical pair once
    (the search of ``find_sphere_contacts``).
    """
    y, size = _search_frame(x, cutoff, box)
    if y is None:
        assert box is not None  # no search frame only for a periodic box
        return _narrow_box_pairs(x, cutoff, box)
    i, j = _sorted_pairs(y, size, cutoff)
    return i, j, _image_of(x[j] - x[i], box if size is not None else None).astype(np.int64)


def find_sphere_contacts(packing: Packing, tolerance: float = 1e-9, chunk: int = DETECT_CHUNK) -> Contacts:
    """Every touching or overlapping pair of spheres, periodic images included.

    A pair is a contact when ``d <= (R_i + R_j) (1 + tolerance)``; normals point from ``i`` to ``j``, arms
    are at the middle of the overlap, ``(R - delta/2) n`` (Peng et al. 2020, Eqs (1)-(2)).  Without
    periodic axes, or with a unique minimum image, one ``cKDTree.query_pairs`` of all particles
    (toroidal along periodic axes: ``boxsize``) finds each candidate pair once (24 bytes per pair of
    temporaries), and the pairs are tested ``chunk`` at a time, so the test's temporaries stay
    O(chunk); narrower periodic boxes search every image.  Image shifts are stored as int8 when they
    fit.

    Parameters
    ----------
    packing : Packing
        A sphere packing.
    tolerance : float
        Relative gap up to which a pair still counts (dimensionless, finite, ``>= 0``).
    chunk : int
        Candidate pairs tested per batch.

    Returns
    -------
    Contacts
        Sorted by ``(i, j, image)``, with overlaps ``delta`` [m] (zero for touching pairs).

    Raises
    ------
    InputError
        For a packing that is not of spheres, a bad ``tolerance`` or a too-short periodic box.
    """
    if not packing.is_spheres:
        raise InputError("packing", "find_sphere_contacts needs a sphere packing; use find_convex_contacts")
    if not np.isfinite(tolerance) or tolerance < 0:
        raise InputError("tolerance", f"must be a finite number >= 0, got {tolerance}")
    check_box_holds_particles(packing)
    box = packing.box
    x = wrap_positions(packing.positions, box)
    cutoff = 2.0 * packing.radii.max() * (1.0 + tolerance)
    y, size = _search_frame(x, cutoff, box)
    if y is None:
        assert box is not None  # no search frame only for a periodic box
        i, j, image = _narrow_box_pairs(x, cutoff, box)
        order = np.lexsort((image[:, 2], image[:, 1], image[:, 0], j, i))
        return _joined([_touching(packing, x, i[order], j[order], image[order], tolerance, own_images(packing, x))],
                       packing.radii)
    pair_i, pair_j = _sorted_pairs(y, size, cutoff)
    return _filled(packing, x, pair_i, pair_j, box if size is not None else None, tolerance, max(1, int(chunk)))


def _support_point(shape, rotation: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """Global-frame support point (relative to the centre) of a rotated convex shape."""
    local = np.asarray(shape.support(rotation.T @ direction), dtype=float).reshape(3)
    return rotation @ local


def convex_penetration(shape_i, rot_i, shape_j, rot_j, separation, n0=None):
    """Penetration of two convex bodies with centre separation ``x_j - x_i``.

    The overlap along a unit direction ``n`` is ``h(n) = s_i(n) + s_j(-n) - n . separation`` with
    ``s`` the support functions; the penetration depth is its minimum over ``n`` (the minimum
    translation that separates the bodies) and the minimiser is the contact normal.  By Danskin's
    theorem ``grad h = p_i(n) - p_j(-n) - separation`` (the support points), which drives a BFGS
    search over ``v`` with ``n = v / |v|``.

    Parameters
    ----------
    shape_i : object
        Convex shape of body ``i`` (``dtcrit.packing.model`` shape, body frame).
    rot_i : numpy.ndarray
        Rotation matrix body ``i`` -> world, ``(3, 3)``.
    shape_j : object
        Convex shape of body ``j``.
    rot_j : numpy.ndarray
        Rotation matrix body ``j`` -> world.
    separation : numpy.ndarray
        ``x_j - x_i`` [m].
    n0 : numpy.ndarray or None
        Starting direction (default: along ``separation``).

    Returns
    -------
    depth : float
        Penetration depth [m] (negative: a gap).
    normal : numpy.ndarray
        Unit contact normal from ``i`` to ``j``.
    point_i : numpy.ndarray
        Deepest support point of ``i``, relative to its centre [m].
    point_j : numpy.ndarray
        Deepest support point of ``j``, relative to its centre [m].
    """
    from scipy.optimize import minimize

    sep = np.asarray(separation, dtype=float)
    scale = float(np.linalg.norm(sep)) or 1.0

    def value_and_grad(v):
        nv = np.linalg.norm(v)
        n = v / nv
        pi = _support_point(shape_i, rot_i, n)
        pj = _support_point(shape_j, rot_j, -n)
        g = pi - pj - sep
        value = float(n @ g)
        return value / scale, ((g - value * n) / nv) / scale

    start = sep / scale if n0 is None else np.asarray(n0, float)
    best = minimize(value_and_grad, start, jac=True, method="BFGS", options={"gtol": 1e-15, "maxiter": 500})
    n = best.x / np.linalg.norm(best.x)
    pi = _support_point(shape_i, rot_i, n)
    pj = _support_point(shape_j, rot_j, -n)
    return float(n @ (pi - pj - sep)), n, pi, pj


def find_convex_contacts(packing: Packing, tolerance: float = 1e-9) -> Contacts:
    """Contacts of a packing of convex, centrally symmetric shapes with true contact points.

    Candidates come from the bounding spheres (``radii``); each candidate's normal and depth come
    from :func:`convex_penetration`; the contact point is the middle of the two deepest support
    points and both arms point from the centres to it.  Suited to small packings (one
    optimisation per candidate pair).

    Parameters
    ----------
    packing : Packing
        Convex bodies (``shapes``, orientations); a packing without shapes goes to
        ``find_sphere_contacts``.
    tolerance : float
        Relative gap (a fraction of the summed bounding radii) up to which a pair still counts.

    Returns
    -------
    Contacts
        The contacts with normals, arms [m] and depths [m].
    """
    if packing.shapes is None:
        return find_sphere_contacts(packing, tolerance)
    check_box_holds_particles(packing)
    box = packing.box
    x = wrap_positions(packing.positions, box)
    rot = packing.orientations if packing.orientations is not None else np.repeat(np.eye(3)[None], packing.n, 0)
    cutoff = 2.0 * packing.radii.max() * (1.0 + tolerance)
    i, j, image = _candidate_pairs(x, cutoff, box)
    rows = []
    for a, b, s in zip(i, j, image):
        sep = x[b] + (0.0 if box is None else box.shift(s)) - x[a]
        d = np.linalg.norm(sep)
        if d > (packing.radii[a] + packing.radii[b]) * (1.0 + tolerance):
            continue
        depth, n, pa, pb = convex_penetration(packing.shapes[a], rot[a], packing.shapes[b], rot[b], sep)
        scale = packing.radii[a] + packing.radii[b]
        if depth < -tolerance * scale:
            continue
        point = 0.5 * (pa + (sep + pb))  # relative to x_i
        rows.append((a, b, s, n, point, point - sep, max(depth, 0.0)))
    if not rows:
        return Contacts.empty()
    a, b, s, n, ai, aj, dep = zip(*rows)
    a, b, moved = np.array(a, dtype=np.int64), np.array(b, dtype=np.int64), own_images(packing, x)
    s = np.array(s, dtype=np.int64) if moved is None else np.array(s, dtype=np.int64) + moved[b] - moved[a]
    return Contacts(
        i=a, j=b, normal=np.array(n), arm_i=np.array(ai), arm_j=np.array(aj), overlap=np.array(dep), image=s,
        radius_eff=uniform(np.nan, len(rows)),
    )


def find_contacts(packing: Packing, tolerance: float = 1e-9) -> Contacts:
    """Sphere or convex-shape contacts, whichever the packing holds.

    Parameters
    ----------
    packing : Packing
        Spheres (``find_sphere_contacts``) or convex shapes (``find_convex_contacts``).
    tolerance : float
        Relative gap (a fraction of the summed bounding radii) up to which a pair still counts.

    Returns
    -------
    Contacts
        The contacts.
    """
    return find_sphere_contacts(packing, tolerance) if packing.is_spheres else find_convex_contacts(packing, tolerance)
