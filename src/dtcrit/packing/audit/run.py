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
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping

from dtcrit.errors import InputError, MisuseError

if TYPE_CHECKING:
    from dtcrit.packing.audit.snapshot import AuditReport
    from dtcrit.packing.conventions.engines import EngineConvention
    from dtcrit.packing.model import Contacts, Packing
    from dtcrit.physics.estimate import RatedEstimate

__all__ = ["DumpReadError", "Snapshot", "SnapshotAudit", "audit_snapshot", "read_snapshot"]


class DumpReadError(InputError):
    """Bad input in the dump file of a snapshot.

    Parameters
    ----------
    key : str or None
        The reader's key: ``snapshot_index``, ``density``, ``file``, or one that starts with the file's
        path (``PATH:LINE``).
    reason : str
        What is wrong.
    source : str or os.PathLike or None
        The dump file the value came from.
    line : int or None
        The 1-based line in ``source``.
    """


@dataclass(frozen=True)
class Snapshot:
    """A snapshot's packing and contacts with every term its engine applies.

    Parameters
    ----------
    source : str
        The snapshot file as given.
    packing : Packing
        The particles, by the engine's ids.
    contacts : Contacts
        The contacts with their springs, dashpots and pre-load.
    convention : EngineConvention
        The engine's conventions (contact detection, arms, pre-load, integrator).
    law : str
        The contact law in words.
    meta : Mapping
        What the file adds: ``dt`` (a YADE export's step [s]), ``material`` (Young's modulus [Pa],
        Poisson's ratio) of a pair style that has one; with walls ``fixed_bodies`` (how many of the
        packing's last bodies are walls, ``dtcrit.packing.wall_bodies``) and ``notes``.

    Examples
    --------
    >>> from dtcrit import read_snapshot
    >>> s = read_snapshot("examples/packings/random_lognormal_60.dump",
    ...                   pair_style="gran/hertz/history 1e9 NULL 0 NULL 0.5 0")
    >>> sorted(s.meta), s.contacts.count > 0
    (['material'], True)
    """

    source: str
    packing: Packing = field(repr=False)
    contacts: Contacts = field(repr=False)
    convention: EngineConvention
    law: str
    meta: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))


@dataclass(frozen=True)
class SnapshotAudit:
    """The critical step of a snapshot as its engine integrates it, and the codes' estimators beside it.

    Parameters
    ----------
    source, engine, engine_source, integrator, law : str
        The snapshot, the engine, where its conventions come from, the integrator and the contact law.
    n_particles, n_contacts : int
        Particles and contacts.
    coordination_mean : float
        Mean coordination number.
    damped, preload : bool
        Whether dashpots enter the damping matrix, and pre-loaded contacts the stiffness.
    dt_crit : float
        The exact critical step of the packing for the integrator [s].
    dt_safe : float
        A rigorous lower bound on it [s].
    dt_undamped : float
        ``2 / omega_max`` without the dashpots [s].
    method : str
        How ``dt_crit`` was found.
    limiting : tuple of int
        Ids of the particles the governing mode sits on (empty when it is spread out).
    limiting_share : float
        The share of the governing mode's energy the most energetic particles hold.
    dt_user : float or None
        The simulation's own step [s], rated against ``dt_crit``.
    estimators : tuple of RatedEstimate
        The codes' estimators, each rated against ``dt_crit`` (:class:`dtcrit.physics.estimate.RatedEstimate`).
    notes : tuple of str
        Notes printed with the result.
    participation : float
        Participation ratio of the governing mode's particle energies.

    Examples
    --------
    >>> from dtcrit import audit_snapshot
    >>> a = audit_snapshot("examples/packings/random_lognormal_60.dump",
    ...                    pair_style="gran/hooke/history 1e5 NULL 0 NULL 0.5 0")
    >>> a.to_json()["schema"], a.dt_user is None
    ('dtcrit-audit/1', True)
    """

    source: str
    engine: str
    engine_source: str
    integrator: str
    law: str
    n_particles: int
    n_contacts: int
    coordination_mean: float
    damped: bool
    preload: bool
    dt_crit: float
    dt_safe: float
    dt_undamped: float
    method: str
    limiting: tuple[int, ...]
    limiting_share: float
    dt_user: float | None
    estimators: tuple[RatedEstimate, ...] = ()
    notes: tuple[str, ...] = ()
    participation: float = math.nan

    @property
    def ratio(self) -> float | None:
        """``dt_user / dt_crit`` (None without ``dt_user``)."""
        return None if self.dt_user is None else self.dt_user / self.dt_crit

    @classmethod
    def from_report(cls, report: AuditReport) -> SnapshotAudit:
        """The frozen form of a :class:`dtcrit.packing.audit.snapshot.AuditReport`.

        Parameters
        ----------
        report : AuditReport
            The report of :func:`dtcrit.packing.audit.snapshot.audit`.

        Returns
        -------
        SnapshotAudit
            The same numbers, frozen.
        """
        values = {f.name: getattr(report, f.name) for f in fields(report)}
        values.update(limiting=tuple(report.limiting), notes=tuple(report.notes),
                      estimators=tuple(report.estimators))
        return cls(**values)

    def report(self) -> AuditReport:
        """The mutable :class:`dtcrit.packing.audit.snapshot.AuditReport` of the same numbers.

        Returns
        -------
        AuditReport
            A new report.
        """
        from dtcrit.packing.audit.snapshot import AuditReport

        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values.update(limiting=list(self.limiting), notes=list(self.notes),
                      estimators=list(self.estimators))
        return AuditReport(**values)

    def to_json(self) -> dict:
        """The JSON document ``dtcrit audit --json`` prints (schema ``dtcrit-audit/1``).

        Returns
        -------
        dict
            The envelope and the audit; non-finite numbers are ``None``.
        """
        from dtcrit.packing.audit.output import audit_json

        return audit_json(self.report())

    def to_text(self) -> str:
        """The text ``dtcrit audit`` prints.

        Returns
        -------
        str
            The audit without a final newline.
        """
        from dtcrit.packing.audit.output import format_audit

        return format_audit(self.report())


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
    with open(path, "rb") as fh:
        head = fh.read(64).lstrip(b"\xef\xbb\xbf \t\r\n")
    return head.startswith(b"{")


def _table_contacts(packing: Packing, convention: EngineConvention, path) -> tuple[Contacts, str]:
    """The contacts of a per-contact table (``id1 id2 kn ks [cn cs kr ktw fn]``) and the law's words."""
    from dtcrit.packing.conventions.engines import overlaps_of_pairs, with_arms
    from dtcrit.packing.readers.contact_tables import read_contact_table

    table = read_contact_table(path, packing)
    contacts = with_arms(packing, overlaps_of_pairs(packing, table.i, table.j), convention.arm)
    v = table.values
    contacts = contacts.with_stiffness(v["kn"], v["ks"], v.get("kr"), v.get("ktw"))
    contacts = contacts.with_damping(v.get("cn", 0.0), v.get("cs", 0.0))
    contacts = contacts.with_normal_force(v.get("fn", v["kn"] * contacts.overlap))
    return contacts, f"per-contact table {Path(path).name}" + ("" if "fn" in v else " (pre-load kn x overlap)")


def read_snapshot(path: str | os.PathLike, *, engine: str | None = None, pair_style: str | None = None,
                  local: str | os.PathLike | None = None, contact_table: str | os.PathLike | None = None,
                  density: float | None = None, snapshot_index: int = -1, walls=None) -> Snapshot:
    """Read a snapshot with its engine's conventions: the packing and its contacts with every term.

    Parameters
    ----------
    path : str or os.PathLike
        A LAMMPS/LIGGGHTS text dump (``ITEM: ATOMS id type x y z radius|diameter [mass]``) or a YADE
        export (JSON, ``dtcrit-yade-export/1``, written by ``dtcrit/engine_scripts/yade_export.py``).
    engine : {'lammps', 'liggghts', 'yade'}, optional
        Whose conventions to apply (default: yade for a YADE export, else lammps).
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
    from dtcrit.packing.conventions.pair_styles import apply_terms, parse_pair_style
    from dtcrit.packing.readers.contact_tables import read_local_dump
    from dtcrit.packing.readers.yade_export import check_schema, read_yade_audit

    _check_files(path, local, contact_table)
    source = str(path)
    yade_file = _is_yade_export(path)
    if yade_file:
        check_schema(path)  # a JSON file of another format is not "a YADE export"
    convention = engine_convention(engine or ("yade" if yade_file else "lammps"))
    if yade_file != (convention.name == "yade"):
        raise InputError("engine", f"{source} is {'a YADE export' if yade_file else 'a dump'}, "
                                   f"which does not go with --engine {convention.name}")
    if yade_file:
        if pair_style or local or contact_table or walls:
            raise InputError("engine", "a YADE export carries its own contacts; --pair-style, --local, --contacts "
                                       "and --wall do not apply")
        packing, contacts, meta = read_yade_audit(path)  # YADE's kinematics (clumps too) applied on reading
        return Snapshot(source, packing, contacts, convention, "YADE's per-contact kn, ks (export)",
                        MappingProxyType(dict(meta)))
    style = parse_pair_style(pair_style) if pair_style else None
    if contact_table and (style or local):
        raise InputError("contact_table", "a contact table already gives each contact's stiffness; "
                                          "do not combine it with --pair-style or --local")
    if not contact_table and style is None:
        raise InputError("pair_style", "give the contact law (the input script's pair style) or a --contacts table")
    packing = _read_dump(path, density, snapshot_index)
    if contact_table:
        contacts, law = _table_contacts(packing, convention, contact_table)
        return _with_walls(Snapshot(source, packing, contacts, convention, law), walls)
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
                   integrator: str | None = None, **read: Any) -> SnapshotAudit:
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
    **read
        The keyword arguments of :func:`read_snapshot` (``engine``, ``pair_style``, ``local``,
        ``contact_table``, ``density``, ``snapshot_index``, ``walls``) for a file.

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
    from dtcrit.packing.audit import snapshot as analysis

    if isinstance(snapshot, Snapshot):
        if read:
            raise MisuseError(f"audit_snapshot: {', '.join(sorted(read))} apply to a file, not to a Snapshot already read")
        given = snapshot
    else:
        _check_files(snapshot, read.get("local"), read.get("contact_table"))
        if dt is not None and not (math.isfinite(dt) and dt > 0):
            raise InputError("dt", f"must be a positive finite number, got {dt}")
        given = read_snapshot(snapshot, **read)
    report = analysis.audit(given.packing, given.contacts, given.convention, law=given.law, source=given.source,
                            integrator=integrator, dt_user=dt if dt is not None else given.meta.get("dt"),
                            material=given.meta.get("material"))
    if given.meta.get("fixed_bodies"):  # walls are bodies of the model, not particles of the report
        from dtcrit.packing.wall_bodies import count_particles_only

        count_particles_only(report, given.packing, given.contacts, given.packing.n - given.meta["fixed_bodies"])
    report.notes.extend(given.meta.get("notes", ()))
    return SnapshotAudit.from_report(report)
