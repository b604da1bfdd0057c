"""Text and JSON (schema ``dtcrit-audit/1``, ``src/dtcrit/schemas/dtcrit-audit-1.json``) of an audit."""
from __future__ import annotations

import math

from dtcrit.json_meta import envelope
from dtcrit.physics.estimate import RatedEstimate
from dtcrit.physics.json_numbers import finite_or_none as _finite

from dtcrit.packing.audit.mode_character import describe
from dtcrit.packing.audit.local_damping import text_lines as local_damping_lines
from dtcrit.packing.audit.snapshot import AuditReport

JSON_SCHEMA = "dtcrit-audit/1"
UNITS = {"dt_crit": "s", "dt_safe": "s", "dt_undamped": "s", "dt_user": "s", "estimators.*.dt": "s"}


def audit_json(r: AuditReport) -> dict:
    """The audit as a JSON document (schema ``dtcrit-audit/1``; non-finite numbers as null).

    Parameters
    ----------
    r : AuditReport
        The audit.

    Returns
    -------
    dict
        The document.
    """
    out = envelope(JSON_SCHEMA, UNITS)
    out.update({
        "snapshot": r.source, "engine": r.engine, "engine_conventions": r.engine_source, "integrator": r.integrator,
        "law": r.law, "n_particles": r.n_particles, "n_contacts": r.n_contacts,
        "coordination_mean": r.coordination_mean, "damped": r.damped, "preload": r.preload,
        "dt_crit": _finite(r.dt_crit), "dt_safe": _finite(r.dt_safe), "dt_undamped": _finite(r.dt_undamped),
        "method": r.method, "limiting": {"ids": r.limiting, "energy_share": r.limiting_share,
                                           "participation_ratio": _finite(r.participation)},
        "governing_mode": None if r.governing_mode is None else r.governing_mode.to_json(),
        "dt_user": _finite(r.dt_user), "dt_user_ratio": _finite(r.ratio),
        "stable": None if r.ratio is None else bool(r.ratio < 1.0),
        "estimators": {e.estimate.name: _estimate_json(e) for e in r.estimators},
        "notes": list(r.notes),
        "local_damping": None if r.local_damping is None else dict(r.local_damping),
    })
    return out


def _estimate_json(rated: RatedEstimate) -> dict:
    """Schema ``dtcrit-audit/1``'s form of a rated estimate: the common shape without ``name`` and ``label``."""
    common = rated.to_json()
    return {"dt": _finite(common["dt"]), "ratio": _finite(common["ratio"]), "safe": common["safe"],
            "kind": common["kind"], "detail": common["detail"]}


def len_top(r: AuditReport) -> int:
    """How many particles the ``limiting`` share counts: ``LIMITING_COUNT`` or all of them.

    Parameters
    ----------
    r : AuditReport
        The audit.

    Returns
    -------
    int
        The count.
    """
    from dtcrit.packing.audit.snapshot import LIMITING_COUNT

    return min(LIMITING_COUNT, r.n_particles)


def _ratio(x: float) -> str:
    """Enough digits that a ratio other than 1 never prints as 1."""
    text = f"{x:.4g}"
    if float(text) == 1.0 and x != 1.0:
        text = f"{x:.10g}"
    return text


def _safe_words(r: AuditReport) -> str:
    """What ``dt_safe`` is: a rigorous lower bound, except under YADE's local damping law, where it bounds
    the onset of instability and stability below the onset is shown by simulation only.
    """
    if r.local_damping and r.local_damping.get("status") == "onset":
        return "rigorous lower bound on the onset; stability below it is shown by simulation only"
    return "rigorous lower bound"


def format_audit(r: AuditReport) -> str:
    """The audit as text.

    Parameters
    ----------
    r : AuditReport
        The audit.

    Returns
    -------
    str
        The lines ``dtcrit audit`` prints.
    """
    lines = [
        f"snapshot: {r.source}",
        f"engine: {r.engine} ({r.engine_source}); integrator {r.integrator}",
        f"contact law: {r.law}",
        f"particles {r.n_particles}, contacts {r.n_contacts}, mean coordination {r.coordination_mean:.4g}"
        + (", dashpots in the damping matrix" if r.damped else ", no dashpots"),
        "",
        f"dt_crit = {r.dt_crit:.7g} s   ({r.method})",
        f"dt_safe = {r.dt_safe:.7g} s   ({_safe_words(r)}; dt_safe/dt_crit = {_ratio(r.dt_safe / r.dt_crit)})",
    ]
    if r.damped:
        lines.append(f"undamped 2/omega_max = {r.dt_undamped:.7g} s")
    lines += local_damping_lines(r)
    if r.limiting:
        lines.append(f"limiting particles (ids): {' '.join(str(i) for i in r.limiting)}  "
                     f"({100 * r.limiting_share:.3g} % of the governing mode's energy)")
    elif math.isfinite(r.participation):
        lines.append(f"governing mode: spread out, participation ratio {r.participation:.3g} (about "
                     f"{r.participating:.3g} of {r.n_particles} particles share its energy; the {len_top(r)} with the "
                     f"most hold {100 * r.limiting_share:.3g} %): no few particles limit the step")
    lines.append(describe(r.governing_mode) if r.governing_mode is not None else
                 "governing mode: not resolved (this integrator's route gives no mode vector)")
    if r.dt_user is not None:
        ratio = r.dt_user / r.dt_crit  # AuditReport.ratio
        verdict = "stable" if ratio < 1.0 else "UNSTABLE"
        lines.append(f"your dt = {r.dt_user:.6g} s = {_ratio(ratio)} x dt_crit: {verdict}")
    lines += [""] + r.notes + [""] if r.notes else [""]
    lines.append(f"{'estimator':<26}{'dt [s]':>13}{'dt/dt_crit':>13}  {'safe':<5}what it is (what it bounds); detail")
    for rated in r.estimators:
        e, times = rated.estimate, rated.ratio
        if e.dt is None or times is None:  # an estimate that does not apply (the detail says why)
            lines.append(f"{e.name:<26}{'n/a':>13}{'':>13}  {'-':<5}{e.kind}; {e.detail}")
            continue
        lines.append(f"{e.name:<26}{e.dt:>13.6g}{_ratio(times):>13}  {'yes' if rated.safe else 'NO':<5}"
                     f"{e.kind}; {e.detail}")
    return "\n".join(lines)
