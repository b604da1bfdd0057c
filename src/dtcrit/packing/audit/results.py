"""The results of ``dtcrit audit``'s API: a snapshot as read (:class:`Snapshot`), its audit
(:class:`SnapshotAudit`, frozen; ``to_json()`` is the document ``dtcrit audit --json`` prints, schema
``dtcrit-audit/1``) and the error of a dump file (:class:`DumpReadError`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping

from dtcrit.errors import InputError

if TYPE_CHECKING:
    from dtcrit.packing.audit.mode_character import ModeCharacter
    from dtcrit.packing.audit.snapshot import AuditReport
    from dtcrit.packing.conventions.engines import EngineConvention
    from dtcrit.packing.model import Contacts, Packing
    from dtcrit.physics.estimate import RatedEstimate

__all__ = ["DumpReadError", "Snapshot", "SnapshotAudit"]


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
    governing_mode : ModeCharacter or None
        Which springs hold the governing mode's energy (``dtcrit.packing.audit.mode_character``).
    snapshot : Snapshot or None
        The snapshot audited (its packing and contacts; for ``dtcrit.packing.audit.plot_data``).
    local_damping : Mapping or None
        Local damping applied to the steps (:mod:`dtcrit.packing.audit.local_damping`), None without it.

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
    governing_mode: ModeCharacter | None = None
    snapshot: Snapshot | None = field(default=None, repr=False, compare=False)
    local_damping: Mapping[str, Any] | None = None

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

        values = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "snapshot"}
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
