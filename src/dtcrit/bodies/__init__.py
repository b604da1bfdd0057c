"""Particle bodies: shapes and their mass properties, arm suprema, contact search and the contact
coefficient matrix of Peng, Burns & Hanley (2020), Sections 2-3 and 5.

Shapes (one module per family): :mod:`~dtcrit.bodies.smooth` (sphere, ellipsoid, superquadric),
:mod:`~dtcrit.bodies.polyhedra` (box, convex polyhedron), :mod:`~dtcrit.bodies.clump` (multi-sphere clumps); every shape is immutable and exposes
``kind``, ``mass``, ``volume``, ``density``, ``inertia`` (principal moments ``(I_xx, I_yy, I_zz)``
about the centre, local frame), ``half_lengths``, ``max_arm``, ``equivalent_radius``, ``vertices``,
``surface_points(n)``, ``support(direction)``, ``satisfies_paper_assumptions`` and
``assumption_issues``.  NumPy only at import, and :mod:`~dtcrit.bodies.polyhedra` and
:mod:`~dtcrit.bodies.clump` only on first use of ``Box``, ``ConvexPolyhedron`` or ``Clump`` (module
``__getattr__``); a polyhedron of up to 40 corners finds its hull in
NumPy (:mod:`~dtcrit.bodies.small_hull`), a larger one imports ``scipy.spatial`` (Qhull) on first use
(:mod:`~dtcrit.bodies.hull`).
"""
from dtcrit.bodies.checks import ORDER_RTOL, SUPERQUADRIC_EPS_MAX, SUPERQUADRIC_EPS_MIN, SYMMETRY_RTOL, AssumptionWarning
from dtcrit.bodies.smooth import Ellipsoid, Sphere, Superquadric
from dtcrit.bodies.spec import shape_from_spec
from dtcrit.bodies.superquadric_surface import superquadric_max_arm

__all__ = [
    "AssumptionWarning",
    "Sphere",
    "Ellipsoid",
    "Superquadric",
    "Box",
    "ConvexPolyhedron",
    "Clump",
    "shape_from_spec",
    "superquadric_max_arm",
    "SUPERQUADRIC_EPS_MIN",
    "SUPERQUADRIC_EPS_MAX",
    "SYMMETRY_RTOL",
    "ORDER_RTOL",
]

_POLYHEDRA = ("Box", "ConvexPolyhedron")


def __getattr__(name: str):
    """``Box`` and ``ConvexPolyhedron`` from :mod:`~dtcrit.bodies.polyhedra`, and ``Clump`` from
    :mod:`~dtcrit.bodies.clump`, imported on first use: a scene without polyhedra starts without their
    hull and frame modules (about 5 ms), one without clumps without the clump's mass properties.
    """
    if name == "Clump":
        from dtcrit.bodies.clump import Clump

        return Clump
    if name in _POLYHEDRA:
        from dtcrit.bodies.polyhedra import Box, ConvexPolyhedron

        return {"Box": Box, "ConvexPolyhedron": ConvexPolyhedron}[name]
    raise AttributeError(f"module 'dtcrit.bodies' has no attribute {name!r}")
