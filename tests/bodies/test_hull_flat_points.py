"""Nearly coplanar points are refused by ``convex_hull_3d`` on both of its routes: the NumPy faces of
``small_hull`` (at most ``SMALL_POINTS`` points) and Qhull (more); a slab thicker than the tolerance is a
closed hull on both, with the slab's volume.
"""
from __future__ import annotations

import numpy as np
import pytest

from dtcrit.bodies.hull import HULL_RTOL, HullError, convex_hull_3d
from dtcrit.bodies.small_hull import SMALL_POINTS


def _slab(n, thickness, seed=1):
    """``n`` points of the box ``[-1, 1]^2 x [-t/2, t/2]``: its 8 corners and random points on its top and
    bottom faces (so the hull is the box, of volume ``4 t``).
    """
    rng = np.random.default_rng(seed)
    corners = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-thickness / 2, thickness / 2)])
    face = np.column_stack([rng.uniform(-1.0, 1.0, (n - 8, 2)), rng.choice([-thickness / 2, thickness / 2], n - 8)])
    return np.vstack([corners, face])


@pytest.mark.parametrize("n", [30, SMALL_POINTS, SMALL_POINTS + 1, 60, 300])
def test_points_thinner_than_the_tolerance_are_refused_on_both_routes(n):
    """Thickness 1e-11 (relative about 7e-12 < HULL_RTOL): no full-dimensional hull, whichever route."""
    assert 1e-11 / np.sqrt(2.0) < HULL_RTOL
    with pytest.raises(HullError, match="coplanar"):
        convex_hull_3d(_slab(n, 1e-11))


@pytest.mark.parametrize("n", [30, 60, 300])
def test_random_nearly_coplanar_points_are_refused(n):
    """Random points within 1e-11 of the plane z = 0 (the reviewer's case: Qhull gave 2 faces)."""
    rng = np.random.default_rng(1)
    p = rng.uniform(-1.0, 1.0, (n, 3))
    p[:, 2] = rng.uniform(-0.5e-11, 0.5e-11, n)
    with pytest.raises(HullError):
        convex_hull_3d(p)


@pytest.mark.parametrize("n", [30, 60, 300])
def test_a_slab_thicker_than_the_tolerance_is_a_closed_box(n):
    """Thickness 1e-7 (relative about 7e-8 > HULL_RTOL): six faces and the volume 4 t of the box."""
    hull = convex_hull_3d(_slab(n, 1e-7))
    assert len(hull.faces) == 6
    assert hull.volume == pytest.approx(4e-7, rel=1e-6)
