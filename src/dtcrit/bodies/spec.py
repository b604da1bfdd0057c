"""Build a shape from a kind name and keyword parameters (scene files).
"""
from __future__ import annotations

from typing import Any

from dtcrit.bodies.base import _Shape
from dtcrit.bodies.polyhedra import Box, ConvexPolyhedron
from dtcrit.bodies.smooth import Ellipsoid, Sphere, Superquadric
from dtcrit.errors import InputError

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
