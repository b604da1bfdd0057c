"""Global eigenmode analysis of DEM packings (Otsubo, O'Sullivan & Shire 2017).

The largest eigenfrequency of ``K phi = omega^2 M phi`` over the whole packing gives the critical
step ``dt_crit = 2 / omega_max`` of the central-difference family; the report sets it beside the
cheap estimates (Gershgorin, per-body diagonal and block bounds, the two-particle bound of Peng et
al. 2020, a Rayleigh quotient).

    >>> from dtcrit.packing import lattice, analyse, LinearLaw
    >>> round(analyse(lattice("sc", 2, mass=1.0), LinearLaw(1.0, 1.0)).alpha, 4)
    0.4472

Modules: ``model`` (Packing, Box, the contact laws applied per contact), ``periodic_cell`` (images in a
sheared cell), ``contact_set`` (Contacts), ``normal_arms`` (sphere arms held as lengths),
``uniform_values`` (a per-contact value of one number held once), ``step``
(``packing_step``, the analysis behind ``dtcrit packing``), ``step_input`` (its inputs: a dump, a
bodies file or a generated packing), ``defaults`` (the generated packings' density and radius),
``report`` (``analyse`` and the report), ``report_text`` (its text),
``wall_bodies`` (fixed walls as bodies of infinite mass); and the subpackages
``readers`` (engine files), ``conventions`` (each engine's contact conventions), ``detection``
(contacts from positions), ``operators`` (the contact element, ``K`` assembled or applied),
``solvers`` (largest mode, damped step, certificate, memory), ``bounds`` (cheap estimates and
rigorous lower bounds), ``distributed`` (PETSc/SLEPc under MPI), ``generators`` (lattices, random
packings) and ``audit`` (an engine snapshot's step).
"""
import importlib as _importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the names' types for the checkers; at run time they load on first use (below)
    from dtcrit.packing.operators.assembly import mass_matrix, scale_symmetric, stiffness_matrix
    from dtcrit.packing.detection.overlaps import find_contacts, find_convex_contacts, find_sphere_contacts
    from dtcrit.packing.readers.lammps_dump import read_dump, write_dump
    from dtcrit.packing.solvers.largest_mode import largest_mode
    from dtcrit.packing.generators.lattices import LATTICES, lattice
    from dtcrit.packing.model import Box, Contacts, HertzMindlinLaw, LinearLaw, Packing, apply_law
    from dtcrit.packing.generators.random_packing import random_packing
    from dtcrit.packing.report import PackingReport, analyse
    from dtcrit.packing.report_text import format_report

# Loaded on first use (PEP 562), so that ``dtcrit`` commands that only need a constant of a packing
# module (``dtcrit step`` builds every subcommand's parser) do not import SciPy at start-up.
_HOMES = {
    "mass_matrix": "operators.assembly", "scale_symmetric": "operators.assembly",
    "stiffness_matrix": "operators.assembly", "find_contacts": "detection.overlaps",
    "find_convex_contacts": "detection.overlaps", "find_sphere_contacts": "detection.overlaps",
    "read_dump": "readers.lammps_dump", "write_dump": "readers.lammps_dump",
    "largest_mode": "solvers.largest_mode", "LATTICES": "generators.lattices", "lattice": "generators.lattices",
    "Box": "model", "Contacts": "model", "HertzMindlinLaw": "model", "LinearLaw": "model", "Packing": "model",
    "apply_law": "model", "random_packing": "generators.random_packing", "PackingReport": "report",
    "analyse": "report", "format_report": "report_text",
}


def __getattr__(name: str):
    """The public name ``name``, imported from its home module on first use."""
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(_importlib.import_module(f"{__name__}.{home}"), name)
    globals()[name] = value
    return value


__all__ = [
    "Box", "Contacts", "HertzMindlinLaw", "LATTICES", "LinearLaw", "Packing", "PackingReport", "analyse",
    "apply_law", "find_contacts", "find_convex_contacts", "find_sphere_contacts", "format_report", "largest_mode",
    "lattice", "mass_matrix", "random_packing", "read_dump", "scale_symmetric", "stiffness_matrix", "write_dump",
]
