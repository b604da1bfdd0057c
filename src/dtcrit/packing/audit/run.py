"""Read a simulation snapshot with its engine's conventions and audit its critical step: the API behind
``dtcrit audit``.

``read_snapshot`` turns a LAMMPS/LIGGGHTS dump (with the input script's pair style, a ``dump local``
of the engine's contact list, or a table of per-contact terms) or a YADE export into a packing and
its contacts, each carrying the terms the engine applies (``dtcrit.packing.conventions.engines``,
``dtcrit.packing.conventions.pair_styles``).  ``audit_snapshot`` runs the analysis of
``dtcrit.packing.audit.snapshot`` on it and returns a frozen :class:`SnapshotAudit`, whose
``to_json()`` is the document ``dtcrit audit --json`` prints (schema ``dtcrit-audit/1``).

Bad input raises :class:`dtcrit.errors.InputError` whose ``key`` names the parameter (``snapshot``,
``engine``, ``pair_style``, ``local``, ``contact_table``, ``dt``); an error in the dump itself is a
:class:`DumpReadError` carrying the reader's key (``snapshot_index`` for the snapshot's index).
"""
from __future__ import annotations

import math
import os
from dataclasses import replace
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from dtcrit.errors import InputError, MisuseError

from dtcrit.packing.audit.results import DumpReadError, Snapshot, SnapshotAudit

if TYPE_CHECKING:
    from dtcrit.packing.conventions.engines import EngineConvention
    from dtcrit.packing.model import Contacts, Packing

__all__ = ["DumpReadError", "Snapshot", "SnapshotAudit", "audit_snapshot", "read_snapshot"]


def _check_files(path, local, contact_table) -> None:
    for key, value in (("snapshot", path), ("local", local), ("contact_table", contact_table)):
        if value is not None and not Path(value).is_file():
            raise InputError(key, f"{value} is not a readable file")


def _read_dump(path, density: float | None, index: int):
    from dtcrit.packing.readers.lammps_dump import read_dump

    try:
        return read_dump(path, density=density, snapshot=index)
    except InputError as exc:
        raise DumpReadError("snapshot_index" if exc.key == "snapshot" else exc.key, exc.reason) from None


def _is_yade_export(path) -> bool:
    try:
        with open(path, "rb") as fh:
            head = fh.read(64).lstrip(b"\xef\xbb\xbf \t\r\n")
    except OSError as exc:  # a special file (/proc/self/mem) that is a file but cannot be read
        raise InputError("snapshot", f"{path} cannot be read: {exc.strerror or exc}") from None
    return head.startswith(b"{")


def _table_contacts(packing: Packing, convention: EngineConvention, path) -> tuple[Contacts, str]:
    """The contacts of a per-contact table (``id1 id2 kn ks [cn cs kr ktw cr ctw fn]``), with the engine's
    kinematics, and the law's words.
    """
    from dtcrit.packing.readers.contact_tables import read_contact_table, table_contacts

    table = read_contact_table(path, packing)
    contacts = table_contacts(packing, table, convention.arm)
    return contacts, f"per-contact table {Path(path).name}" + ("" if "fn" in table.values else " (pre-load kn x overlap)")


def read_snapshot(path: str | os.PathLike, *, engine: str | None = None, pair_style: str | None = None,
                  local: str | os.PathLike | None = None, contact_table: str | os.PathLike | None = None,
                  density: float | None = None, snapshot_index: int = -1,
                  liggghts_input: str | os.PathLike | None = None, walls=None) -> Snapshot:
    """Read a snapshot with its engine's conventions: the packing and its contacts with every term.

    Parameters
    ----------
    path : str or os.PathLike
        A LAMMPS/LIGGGHTS text dump (``ITEM: ATOMS id type x y z radius|diameter [mass]``) or a YADE
        export (JSON, ``dtcrit-yade-export/1``, written by ``dtcrit/engine_scripts/yade_export.py``).
    engine : {'lammps', 'liggghts', 'yade'}, optional
        Whose conventions to apply (default: yade for a YADE export, liggghts with ``liggghts_input``, else lammps).
    pair_style : str, optional
        The input script's pair style, e.g. ``'gran/hooke/history 1e4 NULL 0 NULL 0.5 0'``.
    local : str or os.PathLike, optional
        A LAMMPS ``dump local`` of the engine's contact list (``patom1 patom2``).
    contact_table : str or os.PathLike, optional
        A contact table with the columns ``id1 id2 kn ks [cn cs kr ktw fn]``.
    density : float, optional
        Particle density [kg/m^3] for a dump without a mass column.
    snapshot_index : int
        The snapshot in the dump (-1: the last).
    liggghts_input : str or os.PathLike, optional
        A LIGGGHTS input: the law per atom type (``dtcrit.packing.conventions.liggghts_input``).
    walls : sequence of str, optional
        The input script's ``fix ... wall/gran`` lines (LAMMPS;
        ``dtcrit.packing.conventions.lammps_walls``): each wall's contacts enter against a fixed body.

    Returns
    -------
    Snapshot
        The packing, its contacts, the engine's conventions, the law in words and the file's extras.

    Raises
    ------
    InputError
        A missing file, a law given twice or not at all, an engine that does not fit the file.
    DumpReadError
        Bad content in the dump.

    Examples
    --------
    >>> from dtcrit import read_snapshot
    >>> s = read_snapshot("examples/packings/random_lognormal_60.dump",
    ...                   pair_style="gran/hooke/history 1e5 NULL 0 NULL 0.5 0")
    >>> s.convention.name, s.packing.n
    ('lammps', 60)
    """
    from dtcrit.packing.conventions.engines import engine_convention, engine_sphere_contacts, overlaps_of_pairs
    from dtcrit.packing.conventions.engines import with_arms
    from dtcrit.packing.conventions.liggghts_law import read_liggghts_law
    from dtcrit.packing.conventions.pair_styles import apply_terms, parse_pair_style
    from dtcrit.packing.readers.contact_tables import read_local_dump
    from dtcrit.packing.readers.yade_export import check_schema, read_yade_audit

    _check_files(path, local, contact_table)
    source = str(path)
    yade_file = _is_yade_export(path)
    if yade_file:
        check_schema(path)  # a JSON file of another format is not "a YADE export"
    convention = engine_convention(engine or ("yade" if yade_file else "liggghts" if liggghts_input else "lammps"))
    if yade_file != (convention.name == "yade") and not (contact_table and not yade_file):
        raise InputError("engine", f"{source} is {'a YADE export' if yade_file else 'a dump'}, "
                                   f"which does not go with --engine {convention.name}"
                                   + ("" if yade_file else " without a --contacts table"))
    if yade_file:
        if pair_style or local or contact_table or liggghts_input or walls:
            raise InputError("engine", "a YADE export carries its own contacts; --pair-style, --local, --contacts, "
                                       "--liggghts-input and --wall do not apply")
        packing, contacts, meta = read_yade_audit(path)  # YADE's kinematics (clumps too) applied on reading
        return Snapshot(source, packing, contacts, convention, "YADE's per-contact kn, ks (export)",
                        MappingProxyType(dict(meta)))
    if liggghts_input and (pair_style or contact_table):
        raise InputError("liggghts_input", "a LIGGGHTS input gives the contact law: do not combine it with "
                                           "--pair-style or --contacts")
    if convention.name == "yade" and (pair_style or local or liggghts_input):
        raise InputError("engine", "with --engine yade a dump goes with a --contacts table (YADE's per-contact terms); "
                                   "--pair-style, --local and --liggghts-input do not apply")
    style = parse_pair_style(pair_style) if pair_style else None
    if contact_table and (style or local):
        raise InputError("contact_table", "a contact table already gives each contact's stiffness; "
                                          "do not combine it with --pair-style or --local")
    if not contact_table and style is None and not liggghts_input:
        raise InputError("pair_style", "give the contact law (the input script's pair style) or a --contacts table")
    packing = _read_dump(path, density, snapshot_index)
    if contact_table:
        contacts, law = _table_contacts(packing, convention, contact_table)
        return _with_walls(Snapshot(source, packing, contacts, convention, law), walls)
    if liggghts_input:
        style = read_liggghts_law(liggghts_input, path, snapshot_index, packing)
    assert style is not None
    if local:
        i, j = read_local_dump(local, packing)
        contacts = overlaps_of_pairs(packing, i, j)
        contacts = contacts.subset(contacts.overlap > 0)
    else:
        contacts = engine_sphere_contacts(packing, convention)
    contacts = with_arms(packing, contacts, style.arm)  # the pair style's own kinematics
    contacts = apply_terms(contacts, style.terms(packing, contacts), preload=convention.preload)
    return _with_walls(Snapshot(source, packing, contacts, convention, style.describe(),
                                MappingProxyType({"material": style.material()})), walls)


def _with_walls(snapshot: Snapshot, walls) -> Snapshot:
    """The snapshot with its ``fix wall/gran`` walls' contacts (``dtcrit.packing.conventions.lammps_walls``)."""
    if not walls:
        return snapshot
    from dtcrit.packing.conventions.lammps_walls import add_walls, parse_wall

    if snapshot.convention.name != "lammps":
        raise InputError("--wall", f"reads LAMMPS fix wall/gran lines, not {snapshot.convention.name}'s walls")
    parsed = [parse_wall(text) for text in ([walls] if isinstance(walls, str) else walls)]
    packing, contacts, notes = add_walls(snapshot.packing, snapshot.contacts, parsed,
                                         preload=snapshot.convention.preload)
    meta = {**snapshot.meta, "notes": (*snapshot.meta.get("notes", ()), *notes),
            "fixed_bodies": packing.n - snapshot.packing.n}
    return replace(snapshot, packing=packing, contacts=contacts, meta=MappingProxyType(meta))


def audit_snapshot(snapshot: str | os.PathLike | Snapshot, *, dt: float | None = None,
                   integrator: str | None = None, local_damping: float | None = None,
                   local_damping_law: str | None = None, **read: Any) -> SnapshotAudit:
    """The critical step of a simulation snapshot as its engine integrates it.

    ``dt_crit`` is the exact critical step of the whole packing for the engine's integrator (with
    dashpots the root of ``lambda_max(2h C~ + h^2 K~) = 4``, else ``2/omega_max``), ``dt_safe`` a
    rigorous lower bound, beside the codes' own estimators (``dtcrit.packing.audit.snapshot``).

    Parameters
    ----------
    snapshot : str or os.PathLike or Snapshot
        The snapshot file (read with :func:`read_snapshot` and ``read``) or a snapshot already read.
    dt : float, optional
        The simulation's own step [s], rated against ``dt_crit`` (default: a YADE export's own).
    integrator : str, optional
        Override the engine's integrator (a name of ``dtcrit.INTEGRATORS``).
    local_damping, local_damping_law : float and {'yade', 'pfc'}, optional
        Local (Cundall) damping in [0, 1) and its law (default: a YADE export's ``newton_damping``, law
        ``yade``): the steps times ``1/sqrt(1 + alpha)`` (:mod:`dtcrit.packing.audit.local_damping`).
    **read
        The keyword arguments of :func:`read_snapshot` (``engine``, ``pair_style``, ``local``,
        ``contact_table``, ``density``, ``snapshot_index``, ``liggghts_input``, ``walls``) for a file.

    Returns
    -------
    SnapshotAudit
        ``dt_crit``, ``dt_safe``, the limiting particles, the estimators.

    Raises
    ------
    InputError
        Bad input (``key`` names the parameter).
    DumpReadError
        Bad content in the dump.

    Examples
    --------
    >>> from dtcrit import audit_snapshot
    >>> a = audit_snapshot("examples/packings/random_lognormal_60.dump",
    ...                    pair_style="gran/hooke/history 1e5 NULL 0 NULL 0.5 0", dt=1e-6)
    >>> a.engine, a.dt_safe <= a.dt_crit, a.ratio < 1
    ('lammps', True, True)
    """
    from dtcrit.packing.audit import local_damping as damping
    from dtcrit.packing.audit import snapshot as analysis
    from dtcrit.packing.bounds.yade_stepper_export import from_snapshot

    if isinstance(snapshot, Snapshot):
        if read:
            raise MisuseError(f"audit_snapshot: {', '.join(sorted(read))} apply to a file, not to a Snapshot already read")
        given = snapshot
    else:
        _check_files(snapshot, read.get("local"), read.get("contact_table"))
        if dt is not None and not (math.isfinite(dt) and dt > 0):
            raise InputError("dt", f"must be a positive finite number, got {dt}")
        given = read_snapshot(snapshot, **read)
    local = damping.resolve(given.meta, given.source, local_damping, local_damping_law)
    report = analysis.audit(given.packing, given.contacts, given.convention, law=given.law, source=given.source,
                            integrator=integrator, dt_user=dt if dt is not None else given.meta.get("dt"),
                            material=given.meta.get("material"), yade_stepper=from_snapshot(given))
    if given.meta.get("fixed_bodies"):  # walls are bodies of the model, not particles of the report
        from dtcrit.packing.wall_bodies import count_particles_only

        count_particles_only(report, given.packing, given.contacts, given.packing.n - given.meta["fixed_bodies"])
    report.notes.extend(given.meta.get("notes", ()))
    if given.meta.get("cell_strain_rate"):  # a YADE cell in homothetic motion: refused unless negligible
        from dtcrit.packing.readers.yade_terms import check_cell_motion

        check_cell_motion(given.meta["cell_strain_rate"], report.dt_crit)
    return replace(SnapshotAudit.from_report(damping.apply(report, local)), snapshot=given)
