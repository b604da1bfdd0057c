"""The contacts of a density-scaled packing, re-derived from the scaled masses by the engine's own law.

The engines recompute every mass-dependent term from the current masses at every step, so a scaled
mass changes the contact too, not only the inertia:

* LAMMPS ``pair_style gran/*`` (``pair_gran_hooke_history.cpp``): ``c_n = m_eff gamma_n`` -- the
  dashpot grows as ``m_eff``;
* LAMMPS ``pair_style granular`` (``pair_granular.cpp``, ``granular_model.cpp``): ``damping
  mass_velocity`` and ``viscoelastic`` as ``m_eff``, ``tsuji`` as ``sqrt(m_eff)``, ``velocity`` not at all;
* ``fix wall/gran`` as the pair style with ``meff = m`` (``fix_wall_gran.cpp``);
* LIGGGHTS ``hertz``/``hooke`` (``normal_model_hertz.h``, ``normal_model_hooke.h``): ``c ~ sqrt(m_eff k)``,
  and ``hooke``'s ``k`` itself grows as ``m_eff^(1/5)`` through ``characteristicVelocity``.

Rather than a table of exponents, :func:`rebuilder` applies the same convention code the audit uses
(``law.terms(packing, contacts)``, ``dtcrit.packing.conventions``; ``add_walls`` for the walls) to the
packing with the scaled masses, so the planned step is what ``dtcrit audit`` computes for a dump
with those masses.  A YADE export (FrictPhys/CohFrictPhys have no dashpot; YADE's ``densityScaling``
keeps ``state.mass``, from which a ViscElPhys dashpot is set once at contact creation) and a
``--contacts`` table (fixed numbers, given again with the scaled dump) keep their terms: no rebuild.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import Any, Callable

import numpy as np

from dtcrit.errors import InputError
from dtcrit.packing.model import Contacts, Packing

__all__ = ["LAW_KEY", "LawInputs", "law_of", "rebuilder", "with_law_inputs"]

LAW_KEY = "plan_law_inputs"
"""The key of a snapshot's ``meta`` under which :func:`with_law_inputs` keeps how its law was given."""
GRAN_PREFIX = "LAMMPS pair_style "
GRANULAR_PREFIX = "LAMMPS pair_style granular, pair_coeff * * "


@dataclass(frozen=True)
class LawInputs:
    """How a snapshot's contact law was given to ``read_snapshot`` (its keyword arguments).

    Parameters
    ----------
    pair_style : str or None
        ``--pair-style``.
    liggghts_input : str or None
        ``--liggghts-input``.
    walls : tuple of str
        ``--wall`` lines.
    snapshot_index : int
        The snapshot read from the dump (for LIGGGHTS's atom types).
    """

    pair_style: str | None = None
    liggghts_input: str | None = None
    walls: tuple = ()
    snapshot_index: int = -1


def with_law_inputs(snapshot, read: dict):
    """The snapshot with ``read``'s law inputs kept in its ``meta`` (``LAW_KEY``).

    Parameters
    ----------
    snapshot : dtcrit.packing.audit.results.Snapshot
        The snapshot read with ``read_snapshot(path, **read)``.
    read : dict
        Those keyword arguments.

    Returns
    -------
    Snapshot
        A copy with ``meta[LAW_KEY]`` a :class:`LawInputs`.
    """
    walls = read.get("walls") or ()
    inputs = LawInputs(read.get("pair_style"), None if read.get("liggghts_input") is None else str(read["liggghts_input"]),
                       (walls,) if isinstance(walls, str) else tuple(walls), int(read.get("snapshot_index", -1)))
    return replace(snapshot, meta=MappingProxyType({**snapshot.meta, LAW_KEY: inputs}))


def _law_from_text(snapshot) -> Any:
    """The pair style whose description is the snapshot's ``law`` (checked by describing it again), else None."""
    from dtcrit.packing.conventions.pair_styles import parse_pair_style

    law = snapshot.law
    for prefix, head in ((GRANULAR_PREFIX, "granular "), (GRAN_PREFIX, "")):
        if law.startswith(prefix):
            try:
                style = parse_pair_style(head + law[len(prefix):])
            except InputError:
                return None
            return style if style.describe() == law else None
    return None


def law_of(snapshot) -> tuple[Any, tuple]:
    """``(law, parsed walls)`` of a dump snapshot read with a pair style or a LIGGGHTS input.

    Parameters
    ----------
    snapshot : dtcrit.packing.audit.results.Snapshot
        The snapshot (with ``meta[LAW_KEY]`` from :func:`with_law_inputs`, else its ``law`` text parsed back).

    Returns
    -------
    tuple
        ``(GranPairStyle | GranularStyle | LiggghtsLaw, tuple of LammpsWall)``.

    Raises
    ------
    InputError
        A law that cannot be recovered (a LIGGGHTS input or walls of a Snapshot read elsewhere).
    """
    from dtcrit.packing.conventions.lammps_walls import parse_wall
    from dtcrit.packing.conventions.liggghts_law import read_liggghts_law
    from dtcrit.packing.conventions.pair_styles import parse_pair_style

    inputs = snapshot.meta.get(LAW_KEY)
    n_fixed = int(snapshot.meta.get("fixed_bodies", 0))
    if inputs is None:
        law = _law_from_text(snapshot)
        if law is None or n_fixed:
            raise InputError("snapshot", "the planned masses change this law's mass-dependent terms (dashpots m_eff "
                                         "gamma, LIGGGHTS's stiffness), which are re-derived from how the law was "
                                         "given: plan the file (plan_density_scaling(path, **read)) rather than a "
                                         "Snapshot already read")
        return law, ()
    walls = tuple(parse_wall(text) for text in inputs.walls)
    if inputs.pair_style:
        return parse_pair_style(inputs.pair_style), walls
    particles = _particles(snapshot.packing, n_fixed)
    return read_liggghts_law(inputs.liggghts_input, snapshot.source, inputs.snapshot_index, particles), walls


def _particles(packing: Packing, n_fixed: int) -> Packing:
    """The packing without its last ``n_fixed`` bodies (the walls ``add_walls`` appended)."""
    if not n_fixed:
        return packing
    n = packing.n - n_fixed
    half = None if packing.half_lengths is None else packing.half_lengths[:n]
    return replace(packing, positions=packing.positions[:n], masses=packing.masses[:n], inertia=packing.inertia[:n],
                   radii=packing.radii[:n], half_lengths=half, ids=None if packing.ids is None else packing.ids[:n],
                   orientations=None if packing.orientations is None else packing.orientations[:n])


def rebuilder(snapshot) -> Callable[[np.ndarray], tuple[Packing, Contacts]] | None:
    """The packing and contacts under per-body mass factors, re-derived by the engine's law (module docstring).

    Parameters
    ----------
    snapshot : dtcrit.packing.audit.results.Snapshot
        The snapshot (a dump with a pair style or a LIGGGHTS input, optionally walls; a YADE export or
        a contact table gives None).

    Returns
    -------
    callable or None
        ``factors -> (packing, contacts)``: the bodies with mass and principal moments times ``factors``
        and their contacts with every term the law gives at those masses; None when the terms are fixed
        numbers (they do not change with the masses).

    Raises
    ------
    InputError
        A Snapshot read elsewhere whose law cannot be re-derived (a LIGGGHTS input or walls).
    """
    from dtcrit.packing.conventions.lammps_walls import add_walls
    from dtcrit.packing.conventions.pair_styles import apply_terms

    if snapshot.convention.name == "yade" or snapshot.law.startswith("per-contact table") or \
            snapshot.law.startswith("YADE"):
        return None
    law, walls = law_of(snapshot)
    n_fixed = int(snapshot.meta.get("fixed_bodies", 0))
    base = _particles(snapshot.packing, n_fixed)
    n = base.n
    inner = snapshot.contacts.subset((snapshot.contacts.i < n) & (snapshot.contacts.j < n))
    preload = snapshot.convention.preload

    def build(factors) -> tuple[Packing, Contacts]:
        f = np.asarray(factors, float).reshape(-1)[:n]
        packing = replace(base, masses=base.masses * f, inertia=base.inertia * f[:, None])
        contacts = apply_terms(inner, law.terms(packing, inner), preload=preload)
        if walls:
            packing, contacts, _ = add_walls(packing, contacts, list(walls), preload=preload)
        return packing, contacts

    return build
