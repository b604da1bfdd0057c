"""Local (Cundall) damping in ``dtcrit audit``: where the coefficient comes from and what it does to the step.

Local damping (YADE ``NewtonIntegrator.damping``, PFC ``damp``) scales each force and torque component
by ``1 -+ alpha`` by the sign of its power.  For a linear network in leapfrog every step above
``2/(omega_max sqrt(1 + alpha))`` grows (both laws), PFC's law is proved stable below it, and YADE's
law has that onset by simulation, with windows of stability above it and none proved below
(:mod:`dtcrit.physics.local_damping`, ``derivations/records/local_damping.md``).  So the audit's
undamped ``dt_crit = 2/omega_max`` and its rigorous ``dt_safe`` are multiplied by ``1/sqrt(1 + alpha)``,
the user's step and the estimators are rated against the damped ``dt_crit``, and the estimators keep
the steps their codes compute.

What is not modelled is refused in one line naming it: local damping with viscous dashpots ``cn``,
``cs`` (the two together are not derived), with an integrator other than leapfrog, and on clumps (YADE
rotates aspherical bodies with its own scheme and damps their torques in the global frame against a
non-diagonal inertia).
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Mapping

from dtcrit.errors import InputError
from dtcrit.physics import local_damping as phys
from dtcrit.physics.estimate import RatedEstimate

if TYPE_CHECKING:
    from dtcrit.packing.audit.snapshot import AuditReport

__all__ = ["MODELLED_INTEGRATORS", "LocalDamping", "apply", "resolve", "text_lines"]

MODELLED_INTEGRATORS = ("leapfrog",)
"""The integrators local damping is modelled for: YADE's NewtonIntegrator and PFC's central difference."""

_LAW_WORDS = {"yade": "YADE's law, sign of the power at the on-step velocity estimate",
              "pfc": "PFC's law, sign of F.v at the half step"}


@dataclass(frozen=True)
class LocalDamping:
    """A local damping coefficient, its law and the input key that set it.

    Parameters
    ----------
    alpha : float
        The coefficient, in (0, 1).
    law : {"yade", "pfc"}
        Whose sign of the power is read (:data:`dtcrit.physics.local_damping.LAWS`).
    key : str
        The input that set it (``local_damping`` for the flag, ``FILE: newton_damping`` for an export),
        named in a refusal.
    """

    alpha: float
    law: str
    key: str

    @property
    def factor(self) -> float:
        """``1/sqrt(1 + alpha)``, the damped critical step over the undamped one."""
        return float(phys.step_factor(self.alpha))

    @property
    def status(self) -> str:
        """``"proved"`` (PFC's law) or ``"onset"`` (YADE's law): what ``dt_crit`` is."""
        return phys.STATUS[self.law]

    def to_json(self) -> dict:
        """The ``local_damping`` object of schema ``dtcrit-audit/1``.

        Returns
        -------
        dict
            ``alpha``, ``law``, ``status``, ``factor`` and ``statement``.
        """
        return {"alpha": self.alpha, "law": self.law, "status": self.status, "factor": self.factor,
                "statement": phys.STATEMENT[self.law]}


def _same(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-12 * max(abs(a), abs(b), 1.0)


def resolve(meta: Mapping[str, Any], source: str, alpha: float | None, law: str | None) -> LocalDamping | None:
    """The local damping of a snapshot: a YADE export's ``newton_damping`` (law ``yade``) and the flags.

    Parameters
    ----------
    meta : Mapping
        The snapshot's extras (``newton_damping`` and ``clumps`` of a YADE export).
    source : str
        The snapshot file, named in errors about its ``newton_damping``.
    alpha : float or None
        ``--local-damping``: must agree with the export's coefficient when it has one.
    law : {"yade", "pfc"} or None
        ``--local-damping-law``: ``yade`` for a YADE export (given otherwise it is refused); required
        with ``alpha`` for any other snapshot.

    Returns
    -------
    LocalDamping or None
        None when there is no local damping (absent or zero).

    Raises
    ------
    InputError
        A coefficient outside [0, 1), an unknown law, a flag that disagrees with the export, a law
        without a coefficient, a coefficient without its law, or local damping on clumps.
    """
    exported = meta.get("newton_damping")
    if alpha is not None:
        alpha = phys.check_alpha(alpha, "local_damping")
    if law is not None:
        law = phys.check_law(law, "local_damping_law")
    key = "local_damping"
    if exported is not None:
        exported = phys.check_alpha(exported, f"{source}: newton_damping")
        if alpha is not None and not _same(alpha, exported):
            raise InputError("local_damping", f"{alpha!r} disagrees with the export's newton_damping {exported!r} "
                                              "(YADE's NewtonIntegrator.damping); give the same value or none")
        if law not in (None, "yade"):
            raise InputError("local_damping_law", f"{law!r}: the export's newton_damping is YADE's law (yade)")
        alpha, law, key = exported, "yade", f"{source}: newton_damping"
    elif "newton_damping" in meta and alpha is not None:
        law = law or "yade"  # a YADE export without a NewtonIntegrator: the flag is YADE's damping
    if alpha is None:
        if law is not None:
            raise InputError("local_damping_law", "give the coefficient with --local-damping ALPHA")
        return None
    if law is None:
        raise InputError("local_damping", "name the law with --local-damping-law yade|pfc (YADE: sign of the power "
                                          "at the on-step velocity estimate; PFC: sign of F.v at the half step)")
    if alpha == 0.0:
        return None
    phys.check_established(alpha, law, key)
    if meta.get("clumps"):
        raise InputError(key, f"local damping {alpha:g} on clumps is not modelled (YADE rotates aspherical bodies "
                              "with its own scheme and damps their torques against a non-diagonal inertia)")
    return LocalDamping(alpha, law, key)


def _bound_kind(kind: str) -> str:
    if kind.startswith("lower bound"):
        return "lower bound on the undamped step 2/omega_max (local damping lowers dt_crit)"
    return kind


def apply(report: AuditReport, local: LocalDamping | None) -> AuditReport:
    """The audit with local damping: ``dt_crit`` and ``dt_safe`` times ``1/sqrt(1 + alpha)`` (module docstring).

    Parameters
    ----------
    report : AuditReport
        The undamped audit (:func:`dtcrit.packing.audit.snapshot.audit`).
    local : LocalDamping or None
        The local damping (:func:`resolve`); None returns ``report`` unchanged.

    Returns
    -------
    AuditReport
        A new report: damped ``dt_crit``, ``dt_safe``, the estimators rated against the damped
        ``dt_crit`` and ``local_damping`` (the JSON object of :meth:`LocalDamping.to_json`).

    Raises
    ------
    InputError
        Keyed by ``local.key``: viscous dashpots as well, or an integrator other than leapfrog.
    """
    if local is None:
        return report
    if report.damped:
        raise InputError(local.key, f"local damping {local.alpha:g} together with the contacts' viscous dashpots "
                                    "(cn, cs) is not modelled")
    if report.integrator not in MODELLED_INTEGRATORS:
        raise InputError(local.key, f"local damping {local.alpha:g} with the integrator {report.integrator} is not "
                                    f"modelled (only {', '.join(MODELLED_INTEGRATORS)}: YADE's NewtonIntegrator, PFC)")
    f = local.factor
    dt_crit = report.dt_crit * f
    rows = [RatedEstimate(replace(r.estimate, kind=_bound_kind(r.estimate.kind)), dt_crit) for r in report.estimators]
    return replace(report, dt_crit=dt_crit, dt_safe=report.dt_safe * f, estimators=rows,
                   method=f"{report.method}, x 1/sqrt(1 + alpha) for local damping", local_damping=local.to_json())


def text_lines(report: AuditReport) -> list[str]:
    """The lines ``dtcrit audit`` prints about local damping (none without it).

    Parameters
    ----------
    report : AuditReport
        The audit.

    Returns
    -------
    list of str
        The coefficient, the law, the undamped step and what ``dt_crit`` is for this law.
    """
    ld = report.local_damping
    if not ld:
        return []
    what = ("proved: every step below it is stable, every step above it grows" if ld["status"] == "proved" else
            "the onset of instability: every step above it grows from the top mode; above it stability "
            "comes in windows, never an interval")
    lines = [f"local damping alpha = {ld['alpha']:g} ({_LAW_WORDS[ld['law']]}): dt_crit = 2/(omega_max sqrt(1 + alpha)) "
             f"= {ld['factor']:.6g} x undamped 2/omega_max = {report.dt_undamped:.6g} s", f"  dt_crit is {what}"]
    return lines
