"""dtcrit: the critical time step of explicit DEM simulations, derived, verified and emitted.

Data flows one way: ``dtcrit.symbolic`` (SymPy derivations) -> ``dtcrit._generated`` (committed,
emitted code) -> the runtime modules -> ``dtcrit.cli``.  Nothing imported from this top-level
namespace imports SymPy.

The public API is loaded lazily so that ``import dtcrit`` stays cheap for the command line.
"""
from __future__ import annotations

import importlib

__version__ = "0.1.0"

# name -> module that defines it (relative to this package)
_API = {
    # shapes
    "Sphere": "bodies",
    "Ellipsoid": "bodies",
    "Superquadric": "bodies",
    "Box": "bodies",
    "ConvexPolyhedron": "bodies",
    "shape_from_spec": "bodies",
    "AssumptionWarning": "bodies",
    # contact kinematics (Peng et al. 2020, Sections 2, 3, 5)
    "a_max": "bodies.contact",
    "a_bound": "bodies.contact",
    "b_max": "bodies.contact",
    "coefficient_matrix": "bodies.contact",
    "b_bound": "bodies.contact",
    # scenes and the `dtcrit step` API
    "load_scene": "scenes.scene",
    "parse_scene": "scenes.scene",
    "critical_step": "scenes.timestep",
    # stability engine (Peng et al. 2020, Section 4; CFL note)
    "critical_dt": "integrators.stability",
    "paper_eq46": "integrators.stability",
    "critical_dt_array": "integrators.stability",
    "INTEGRATORS": "integrators.stability",
    "spectral_radius": "integrators.amplification",
    # impact (CFL note, Feng 2005)
    "exact_impact": "impact",
    "impact_report": "impact",
}

__all__ = sorted(_API)


def __getattr__(name: str):
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module 'dtcrit' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_API))
