"""Shapes from specifications: keyword parameters (:func:`shape_from_spec`) or the shape keys of a
``[[particle]]`` table (:func:`shape_from_table`), the one parser of a shape that scene files
(``dtcrit.scenes.scene``) and bodies files (``dtcrit.packing.readers.bodies_file``) share.

A table's keys (``docs/howto/step.md``, section "The scene format"; every key on the Scene keys
reference page, ``docs/reference/generated/scene-keys``): ``shape`` is one of ``sphere`` (``radius``), ``ellipsoid``
(``semi_axes``, largest first), ``superquadric`` (``semi_axes``, ``exponents``), ``box``
(``half_lengths``), ``polyhedron`` (``vertices``), ``clump`` (``spheres`` ``[[x, y, z, r], ...]``),
with exactly one of ``density`` [kg/m^3] or ``mass`` [kg].  Each problem is one ``InputError``
keyed by the table's ``prefix`` and the key (``particle[2].semi_axes``).
"""
from __future__ import annotations

import warnings
from typing import Any

from dtcrit.bodies.base import _Shape
from dtcrit.bodies.smooth import Ellipsoid, Sphere, Superquadric
from dtcrit.errors import InputError
from dtcrit.inputs.arrays import clump_spheres, vector, vertices
from dtcrit.inputs.keys import check_keys, required
from dtcrit.inputs.text import short, type_name
from dtcrit.inputs.values import choice, number, string

_KINDS = {
    "sphere": (Sphere, ("radius",)),
    "ellipsoid": (Ellipsoid, ("a", "b", "c")),
    "superquadric": (Superquadric, ("a", "b", "c", "eps1", "eps2")),
    "box": ("Box", ("a", "b", "c")),  # dtcrit.bodies.polyhedra, imported when one is built (_shape_class)
    "polyhedron": ("ConvexPolyhedron", ("vertices",)),
}
_OPTIONAL = {"density", "mass"}


def _shape_class(cls: Any) -> Any:
    """A shape class of ``_KINDS``; a polyhedron's or clump's named one is imported here, on first use."""
    if not isinstance(cls, str):
        return cls
    if cls == "Clump":
        from dtcrit.bodies.clump import Clump

        return Clump
    from dtcrit.bodies.polyhedra import Box, ConvexPolyhedron

    return {"Box": Box, "ConvexPolyhedron": ConvexPolyhedron}[cls]

# ----------------------------------------------------------------------------------------------
# The vocabulary of a [[particle]] table
# ----------------------------------------------------------------------------------------------
SHAPE_KEYS: dict[str, tuple[tuple[str, int | None], ...]] = {
    "sphere": (("radius", None),),
    "ellipsoid": (("semi_axes", 3),),
    "superquadric": (("semi_axes", 3), ("exponents", 2)),
    "box": (("half_lengths", 3),),
    "polyhedron": (("vertices", -1),),
    "clump": (("spheres", -2),),
}
"""Shape -> the dimension keys it needs: (key, length; None a scalar, -1 vertices, -2 clump spheres)."""
PARTICLE_COMMON = ("shape", "density", "mass", "youngs_modulus", "poisson_ratio", "name")
"""Keys every ``[[particle]]`` table may hold."""
SPHERE_SIZE_KEYS = ("radius", "radii", "fractions", "lognormal")
"""A sphere's size keys: one radius, or a size distribution (``dtcrit.scenes.sizes``)."""
PARTICLE_ALL = tuple(dict.fromkeys(PARTICLE_COMMON + SPHERE_SIZE_KEYS + tuple(k for v in SHAPE_KEYS.values() for k, _ in v)))
"""Every key a ``[[particle]]`` table may hold for some shape."""
TOP_LEVEL_KEYS = ("integrator", "omega_max", "safety", "pairs", "title", "coordination_max", "overlap_max", "isolated",
                  "local_damping", "local_damping_law")
"""Keys of a scene that belong before its first table (``dtcrit.scenes.model.TOP_KEYS`` without the
tables): found inside a table, the message explains TOML's rule."""

# key names used by the shape constructors -> table key
_SHAPE_ARG_TO_KEY = {
    "sphere": {"radius": "radius"},
    "ellipsoid": {"a": "semi_axes", "b": "semi_axes", "c": "semi_axes"},
    "superquadric": {"a": "semi_axes", "b": "semi_axes", "c": "semi_axes", "eps1": "exponents", "eps2": "exponents"},
    "box": {"a": "half_lengths", "b": "half_lengths", "c": "half_lengths"},
    "polyhedron": {"vertices": "vertices"},
    "clump": {"spheres": "spheres"},
}


def shape_from_spec(kind: str, **params: Any) -> _Shape:
    """Build a shape from a kind name and keyword parameters.

    Parameters
    ----------
    kind : str
        One of ``sphere, ellipsoid, superquadric, box, polyhedron`` (any case).
    **params
        The constructor arguments by name (``radius``; ``a, b, c``; ``eps1, eps2``; ``vertices``)
        plus exactly one of ``density`` [kg/m^3] / ``mass`` [kg] (and ``rtol`` for polyhedra).

    Returns
    -------
    _Shape
        The shape.  Unknown or missing parameters raise ``InputError`` naming them.

    Examples
    --------
    >>> from dtcrit import shape_from_spec
    >>> shape_from_spec("ellipsoid", a=3.0, b=2.0, c=1.0, density=1000.0).kind
    'ellipsoid'
    """
    if not isinstance(kind, str) or kind.lower() not in _KINDS:
        raise InputError("kind", f"must be one of {', '.join(_KINDS)} (got {kind!r})")
    cls, needed = _KINDS[kind.lower()]
    cls = _shape_class(cls)
    allowed = set(needed) | _OPTIONAL | ({"rtol"} if kind.lower() == "polyhedron" else set())
    for key in params:
        if key not in allowed:
            raise InputError(key, f"unknown parameter for a {kind.lower()} (expected {', '.join(sorted(allowed))})")
    for key in needed:
        if key not in params:
            raise InputError(key, f"missing (a {kind.lower()} needs {', '.join(needed)})")
    positional = [params.pop(key) for key in needed]
    return cls(*positional, **params)


def check_table_keys(prefix: str, table: dict, allowed: tuple[str, ...], vocabulary: tuple[str, ...], where: str) -> None:
    """:func:`dtcrit.inputs.keys.check_keys` with a scene's top-level keys (:data:`TOP_LEVEL_KEYS`).

    Parameters
    ----------
    prefix : str
        The table's path with its trailing dot, empty at the top level.
    table : dict
        The table as read.
    allowed : tuple of str
        The keys accepted here.
    vocabulary : tuple of str
        Keys valid elsewhere (then "not used" here rather than unknown).
    where : str
        Where the keys are read, for the message.
    """
    check_keys(prefix, table, allowed, vocabulary, where, TOP_LEVEL_KEYS)


def table_kind(prefix: str, table: Any) -> str:
    """The ``shape`` of a ``[[particle]]`` table, after checking that every key fits that shape.

    Parameters
    ----------
    prefix : str
        The table's path with its trailing dot (``particle[2].``).
    table : Any
        The table as read.

    Returns
    -------
    str
        A key of :data:`SHAPE_KEYS`.
    """
    if not isinstance(table, dict):
        raise InputError(prefix.removesuffix("."), f"must be a table (got {type_name(table)}: {short(table)})")
    kind = choice(f"{prefix}shape", required(prefix, table, "shape", f"one of {', '.join(SHAPE_KEYS)}"),
                  tuple(SHAPE_KEYS), "shape")
    needed = () if kind == "sphere" else SHAPE_KEYS[kind]
    sizes = SPHERE_SIZE_KEYS if kind == "sphere" else ()
    allowed = tuple(dict.fromkeys(("shape",) + sizes + tuple(k for k, _ in needed) + PARTICLE_COMMON[1:]))
    check_table_keys(prefix, table, allowed, PARTICLE_ALL, f"by a {kind}")
    return kind


def table_dimensions(prefix: str, table: dict, kind: str) -> dict[str, Any]:
    """The checked dimension entries of a table whose shape is not a sphere (empty for a sphere,
    whose sizes a scene may give as a distribution: ``dtcrit.scenes.sizes``).

    Parameters
    ----------
    prefix : str
        The table's path with its trailing dot.
    table : dict
        The table as read.
    kind : str
        Its shape (:func:`table_kind`).

    Returns
    -------
    dict
        Key -> value: lengths [m] as floats or lists, vertex and sphere rows as lists.
    """
    needed = () if kind == "sphere" else SHAPE_KEYS[kind]
    dims: dict[str, Any] = {}
    for key, length in needed:
        value = required(prefix, table, key, f"a {kind} needs {', '.join(k for k, _ in needed)}")
        if length is None:
            dims[key] = number(prefix + key, value)
        elif length == -1:
            dims[key] = vertices(prefix + key, value)
        elif length == -2:
            dims[key] = clump_spheres(prefix + key, value)
        else:
            dims[key] = vector(prefix + key, value, length)
    return dims


def density_or_mass(prefix: str, table: dict, *, per_size: bool = False) -> tuple[float | None, float | None]:
    """``(density, mass)`` of a table: exactly one given, the other None.

    Parameters
    ----------
    prefix : str
        The table's path with its trailing dot.
    table : dict
        The table as read.
    per_size : bool
        The table describes several sizes (a sphere size distribution): only a density fits.

    Returns
    -------
    tuple
        ``(density [kg/m^3] or None, mass [kg] or None)``.
    """
    if "density" in table and "mass" in table:
        raise InputError(f"{prefix}mass", "give density or mass, not both")
    if "density" not in table and "mass" not in table:
        raise InputError(f"{prefix}density", "missing: give density [kg/m^3] or mass [kg]")
    if "mass" in table and per_size:
        raise InputError(f"{prefix}mass", "a size distribution needs the density (each size has its own mass)")
    density = number(prefix + "density", table["density"]) if "density" in table else None
    mass = number(prefix + "mass", table["mass"]) if "mass" in table else None
    return density, mass


def build_shape(prefix: str, kind: str, dims: dict, density: float | None, mass: float | None) -> _Shape:
    """The shape of checked table entries; the constructors' errors are keyed by the table's keys.

    A shape that breaks the paper's assumption 3 (Peng et al. 2020, Section 3) is refused, naming
    the issue; other warnings of the shape layer are not the user's concern and are dropped.

    Parameters
    ----------
    prefix : str
        The table's path with its trailing dot.
    kind : str
        The shape (:data:`SHAPE_KEYS`).
    dims : dict
        The dimension entries (:func:`table_dimensions`; a sphere's ``{key: radius}``).
    density, mass : float or None
        Exactly one given (:func:`density_or_mass`).

    Returns
    -------
    _Shape
        The shape.
    """
    args: tuple
    cls: Any  # one of the shape classes, each taking density= and mass=
    if kind == "sphere":
        args, cls = (next(iter(dims.values())),), Sphere
    elif kind == "ellipsoid":
        args, cls = tuple(dims["semi_axes"]), Ellipsoid
    elif kind == "superquadric":
        args, cls = tuple(dims["semi_axes"]) + tuple(dims["exponents"]), Superquadric
    elif kind == "box":
        args, cls = tuple(dims["half_lengths"]), _shape_class("Box")
    elif kind == "clump":
        args, cls = (dims["spheres"],), _shape_class("Clump")
    else:
        args, cls = (dims["vertices"],), _shape_class("ConvexPolyhedron")
    size_key = next(iter(dims))
    try:
        with warnings.catch_warnings(record=True):  # other warnings of the shape layer are dropped
            warnings.simplefilter("always")
            shape = cls(*args, density=density, mass=mass)
    except InputError as exc:
        entry = exc.location.key or exc.key
        key = _SHAPE_ARG_TO_KEY[kind].get(entry, entry)
        reason = exc.reason
        if entry in ("a", "b", "c") and "a >= b >= c" in reason:
            reason += "; list the axes largest first (Peng et al. 2020, Section 3, assumption 3)"
        raise InputError(f"{prefix}{key}", reason) from None
    except (ValueError, ArithmeticError) as exc:  # numerical trouble inside the shape
        raise InputError(f"{prefix}{size_key}", f"cannot build the {kind}: {' '.join(str(exc).split())}") from None
    issues = getattr(shape, "assumption_issues", ())
    if issues:
        raise InputError(f"{prefix}{size_key}", "breaks Peng et al. 2020, Section 3, assumption 3: " + "; ".join(issues))
    return shape


def shape_from_table(prefix: str, table: Any) -> _Shape:
    """The one body a ``[[particle]]`` table describes (module docstring): a sphere of one ``radius``
    (no size distribution) or any other shape, with its ``density`` or ``mass``.

    Parameters
    ----------
    prefix : str
        The table's path with its trailing dot (``FILE: bodies[3].shape.``), naming it in errors.
    table : Any
        The table as read (keys of a scene's ``[[particle]]`` table; the caller refuses the ones it
        does not use, e.g. a size distribution or the elastic constants).

    Returns
    -------
    _Shape
        The shape.
    """
    kind = table_kind(prefix, table)
    dims = table_dimensions(prefix, table, kind)
    if kind == "sphere":
        if "radius" not in table:
            raise InputError(prefix + "radius", "missing: a sphere needs radius, or radii with fractions, or lognormal")
        dims = {"radius": number(prefix + "radius", table["radius"])}
    density, mass = density_or_mass(prefix, table)
    if "name" in table:
        string(prefix + "name", table["name"])
    return build_shape(prefix, kind, dims, density, mass)
