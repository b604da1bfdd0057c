"""dtcrit: the critical time step of explicit DEM simulations, derived, verified and emitted.

Data flows one way: ``dtcrit.symbolic`` (SymPy derivations) -> ``dtcrit._generated`` (committed,
emitted code) -> the runtime modules -> ``dtcrit.cli``.  Nothing imported from this top-level
namespace imports SymPy.

The public API (``__all__``) is loaded lazily, by a module ``__getattr__``, so that ``import dtcrit``
stays cheap for the command line; ``dir(dtcrit)`` lists the API only.  The functions behind the
commands return frozen results whose ``to_json()`` is what the command prints with ``--json``:

* the step of a scene: ``load_scene`` / ``parse_scene``, then ``critical_step`` -> ``StepResult``;
* the step of a packing: ``packing_step`` -> ``PackingStep`` (``distributed_packing_step`` on MPI);
* a simulation snapshot: ``read_snapshot`` -> ``Snapshot``, ``audit_snapshot`` -> ``SnapshotAudit``;
* code emission: ``emit_code`` -> source text, ``emitted_code`` -> ``EmittedCode``;
* the paper's printed formulas beside the verified ones: the module ``dtcrit.paper``.

Bad input raises ``InputError`` (a ``ValueError`` whose ``key`` names the parameter), a solver that
stops early ``NotConvergedError`` (with its bracket), a call the API does not support ``MisuseError``
(a ``TypeError``); all three are ``DtcritError``.
"""
import importlib as _importlib

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
    "StepResult": "scenes.timestep",
    # packings, snapshots and code emission (the commands packing, audit, codegen)
    "packing_step": "packing.step",
    "PackingStep": "packing.step",
    "distributed_packing_step": "packing.distributed.step",
    "DistributedStep": "packing.distributed.step",
    "read_snapshot": "packing.audit.run",
    "audit_snapshot": "packing.audit.run",
    "Snapshot": "packing.audit.results",
    "SnapshotAudit": "packing.audit.results",
    "emit_code": "codegen.api",
    "emitted_code": "codegen.api",
    "EmittedCode": "codegen.api",
    # the paper's printed formulas beside the verified ones (a module)
    "paper": "paper",
    # errors
    "DtcritError": "errors",
    "InputError": "errors",
    "MisuseError": "errors",
    "NotConvergedError": "errors",
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

_MODULES = frozenset({"paper"})
"""Names of ``_API`` that are modules, not names defined in one."""

__all__ = sorted(_API)


def __getattr__(name: str):
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module 'dtcrit' has no attribute {name!r}")
    loaded = _importlib.import_module(f".{module}", __name__)
    value = loaded if name in _MODULES else getattr(loaded, name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(_API) | {"__version__"})
