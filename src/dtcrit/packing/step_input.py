"""Read or generate the packing of ``packing_step`` and resolve its contact law.

A LAMMPS/LIGGGHTS dump, a ``dtcrit-bodies/1`` file, a periodic lattice or a random packing; linear
springs (``kn``, ``ks``) or the Hertz-Mindlin tangent stiffness (``youngs``, ``poisson``), unless a
bodies file lists each contact's.  A generated packing whose analysis would not fit in memory, or
whose generation would take too long, is refused before any work.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from dtcrit.errors import InputError
from dtcrit.packing.defaults import DEFAULT_DENSITY, DEFAULT_RADIUS

if TYPE_CHECKING:
    from dtcrit.packing.model import Contacts, Packing

__all__ = ["DEFAULT_DENSITY", "DEFAULT_RADIUS", "PackingInput", "RANDOM_SECONDS_LIMIT", "packing_input"]

RANDOM_SECONDS_LIMIT = 1800.0
"""A random packing whose generation is estimated to take longer than this [s] is refused up front
(``random_packing.generation_seconds``); below it a progress bar shows the relaxation on a terminal."""


@dataclass(frozen=True)
class PackingInput:
    """A packing with its contacts and contact law, as :func:`packing_input` resolves them.

    Parameters
    ----------
    packing : Packing
        The particles (positions, masses, inertia, shapes, periodic box).
    contacts : Contacts or None
        The contacts a bodies file lists (None: found from the overlaps).
    law : LinearLaw or HertzMindlinLaw or None
        The contact law (None when the bodies file gives each contact's ``kn`` and ``ks``).
    """

    packing: Packing
    contacts: Contacts | None
    law: Any


def _law(kn: float | None, ks: float | None, youngs: float | None, poisson: float):
    from dtcrit.packing.model import HertzMindlinLaw, LinearLaw

    if youngs is not None:
        if kn is not None or ks is not None:
            raise InputError("kn", "give either --kn/--ks or --youngs/--poisson, not both")
        return HertzMindlinLaw(youngs, poisson)
    if kn is None:
        raise InputError("kn", "give the contact stiffness (--kn [--ks] for linear springs, or --youngs [--poisson] "
                               "for Hertz-Mindlin): the step scales with it")
    return LinearLaw(kn, kn if ks is None else ks)


def _bodies(source, generated: bool, density: float | None, write_dump):
    """The ``dtcrit-bodies/1`` file ``source`` names, or None when it is not one (then it is a dump)."""
    from dtcrit.packing.readers.bodies_file import is_bodies_file, read_bodies_file

    if source is None or generated or not is_bodies_file(source):
        return None
    for key, value in (("density", density), ("write_dump", write_dump)):
        if value is not None:
            raise InputError(key, "not used with a bodies file (each body's shape gives its density or mass; a dump "
                                  "holds spheres only)")
    return read_bodies_file(source)


def _certificate_cost(certify: str, n: int, coordination: float) -> dict:
    """``check_fits``'s extra memory for ``certify="yes"`` (``certificate.factor_bytes``)."""
    from dtcrit.packing.solvers.certificate import SPARSE_DOFS, factor_bytes

    if certify != "yes" or 6 * n > SPARSE_DOFS:
        return {}
    return {"extra": factor_bytes(6 * n, coordination), "what": "the certificate's factorisation"}


def _check_generation_time(n: int) -> None:
    from dtcrit.packing.generators.random_packing import SECONDS_PER_SPHERE_STEP, generation_seconds

    seconds = generation_seconds(n)
    if seconds > RANDOM_SECONDS_LIMIT:
        raise InputError("random", f"{n:,} spheres take about {seconds / 60:.0f} min to generate (FIRE relaxation, "
                                   f"250 steps at a measured {SECONDS_PER_SPHERE_STEP * 1e6:.2g} us per sphere and "
                                   f"step), more than the {RANDOM_SECONDS_LIMIT / 60:.0f} min allowed; generate it "
                                   "once elsewhere and give it as a dump FILE, or use a --lattice")


def _packing(o: dict, check_memory: bool):
    """The packing of a dump, a lattice or a random packing (``o``: :func:`packing_input`'s arguments)."""
    from dtcrit.packing.generators.lattices import lattice
    from dtcrit.packing.generators.random_packing import random_packing
    from dtcrit.packing.readers.lammps_dump import read_dump

    chosen = [name for name, v in (("FILE", o["source"]), ("--lattice", o["lattice"]), ("--random", o["random"]))
              if v is not None]
    if len(chosen) != 1:
        raise InputError("packing", "give exactly one of FILE, --lattice or --random"
                                    + (f" (got {', '.join(chosen)})" if chosen else ""))
    if o["source"] is not None:
        return read_dump(o["source"], density=o["density"], snapshot=o["snapshot"])
    if o["snapshot"] != -1:
        raise InputError("snapshot", f"picks a snapshot of a dump FILE; {chosen[0]} has none")
    from dtcrit.packing.generators.lattices import _BASIS, COORDINATION
    from dtcrit.packing.solvers.memory import check_fits

    density = DEFAULT_DENSITY if o["density"] is None else o["density"]
    cells, n, cn = o["cells"], o["random"], o["cn"]
    if o["lattice"] is not None:
        if check_memory and isinstance(cells, int) and cells > 0:
            count = len(_BASIS[o["lattice"]][0]) * cells**3
            z = COORDINATION[o["lattice"]]
            check_fits(count, z, o["route"], key="cells", **_certificate_cost(o["certify"], count, z))
        return lattice(o["lattice"], cells, radius=o["radius"], density=density)
    if check_memory and isinstance(n, int) and n > 1 and 0 <= cn <= 14:
        check_fits(n, cn, o["route"], key="random", **_certificate_cost(o["certify"], n, cn))
        _check_generation_time(n)
    return random_packing(n, cn=cn, sizes=o["sizes"], radius=o["radius"], spread=o["spread"], density=density,
                          seed=o["seed"])


def packing_input(source: str | os.PathLike | None = None, *, lattice: str | None = None, cells: int = 2,
                  random: int | None = None, cn: float = 6.0, sizes: str = "mono", spread: float = 0.0,
                  seed: int = 0, radius: float = DEFAULT_RADIUS, density: float | None = None,
                  kn: float | None = None, ks: float | None = None, youngs: float | None = None,
                  poisson: float = 0.25, snapshot: int = -1, route: str = "auto", certify: str = "auto",
                  write_dump: str | os.PathLike | None = None,
                  check_memory: bool = True) -> PackingInput:
    """Read or generate a packing and resolve its contact law (the parameters of :func:`packing_step`).

    Parameters
    ----------
    source, lattice, cells, random, cn, sizes, spread, seed, radius, density, kn, ks, youngs, poisson, snapshot
        As in :func:`dtcrit.packing.step.packing_step`.
    route, certify : str
        As in :func:`dtcrit.packing.step.packing_step`: they size the memory check of a generated packing.
    write_dump : str or os.PathLike, optional
        Refused with a bodies file (a dump holds spheres only); not written here.
    check_memory : bool
        Refuse up front a generated packing whose analysis would not fit in memory (or whose generation
        would take longer than ``RANDOM_SECONDS_LIMIT``).

    Returns
    -------
    PackingInput
        The packing, the contacts a bodies file lists (else None) and the contact law (None when the
        bodies file gives each contact's stiffness).
    """
    generated = lattice is not None or random is not None
    bodies = _bodies(source, generated, density, write_dump)
    if bodies is not None and bodies.stiffness_given:
        if kn is not None or ks is not None or youngs is not None:
            raise InputError("kn", f"{source} lists each contact's kn and ks; drop --kn/--ks/--youngs")
        return PackingInput(bodies.packing, bodies.contacts, None)
    law = _law(kn, ks, youngs, poisson)
    if bodies is not None:
        return PackingInput(bodies.packing, bodies.contacts, law)
    options = {"source": source, "lattice": lattice, "cells": cells, "random": random, "cn": cn, "sizes": sizes,
               "spread": spread, "seed": seed, "radius": radius, "density": density, "snapshot": snapshot,
               "route": route, "certify": certify}
    return PackingInput(_packing(options, check_memory), None, law)
