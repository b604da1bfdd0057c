"""Local (Cundall) damping in a scene: the top-level keys ``local_damping`` and ``local_damping_law``.

``local_damping = ALPHA`` (in [0, 1)) with ``local_damping_law = "yade"`` (YADE's
``NewtonIntegrator.damping``, sign of the power at the on-step velocity estimate) or ``"pfc"`` (PFC's
``damp``, sign of ``F.v`` at the half step) multiplies the scene's undamped step by
``1/sqrt(1 + alpha)`` (:mod:`dtcrit.physics.local_damping`, ``derivations/records/local_damping.md``:
every step above ``2/(omega_max sqrt(1 + alpha))`` grows; below it PFC's law is proved stable, YADE's
only observed).  The scene's step is a bound on ``2/omega_max`` of the contacts and packings it
describes, so the damped bound is that bound times the factor.

Refused in one line (key ``local_damping``), as not modelled: an integrator other than leapfrog, any
dashpot (``cn``, ``cs``, ``cr``, ``ctw`` of a contact or wall), and ``omega_max`` (the rotation bound of
Peng et al. 2020 is not a vibration the factor applies to).
"""
from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

from dtcrit.errors import InputError
from dtcrit.physics import local_damping as phys
from dtcrit.physics.estimate import RatedEstimate

if TYPE_CHECKING:
    from dtcrit.scenes.model import PairContact, Scene

__all__ = ["KEYS", "MODELLED_INTEGRATORS", "apply", "check", "parse"]

KEYS = {
    "local_damping": "local (Cundall) damping coefficient in [0, 1): the step times 1/sqrt(1 + alpha)",
    "local_damping_law": "its law: \"yade\" (sign of the power at the on-step velocity estimate) or \"pfc\" "
                         "(sign of F.v at the half step)",
}
"""The scene keys of local damping and what they mean."""

MODELLED_INTEGRATORS = ("leapfrog",)
"""The integrators local damping is modelled for (YADE's NewtonIntegrator, PFC)."""


def parse(doc: dict[str, Any]) -> tuple[float, str] | None:
    """``(alpha, law)`` from a scene's top level, or None without local damping (absent or zero).

    Parameters
    ----------
    doc : dict
        The scene's top-level table.

    Returns
    -------
    tuple or None
        The coefficient and the law.

    Raises
    ------
    InputError
        A coefficient outside [0, 1) or not a number, an unknown law, a law without a coefficient or a
        coefficient without its law.
    """
    alpha, law = doc.get("local_damping"), doc.get("local_damping_law")
    if alpha is None:
        if law is not None:
            raise InputError("local_damping_law", "give the coefficient as local_damping = ALPHA")
        return None
    if isinstance(alpha, bool):
        raise InputError("local_damping", f"must be a number in [0, 1), got {alpha!r}")
    value = phys.check_alpha(alpha, "local_damping")
    if law is None:
        raise InputError("local_damping", "name the law as local_damping_law = \"yade\" or \"pfc\"")
    law = phys.check_law(law, "local_damping_law")
    phys.check_established(value, law, "local_damping")
    return None if value == 0.0 else (value, law)


def _damped(c: PairContact) -> bool:
    return any(v > 0 for v in (c.cn, c.cs, c.cr, c.ctw))


def check(scene: Scene, contacts) -> None:
    """Refuse local damping where it is not modelled (module docstring).

    Parameters
    ----------
    scene : Scene
        The scene (``local_damping``, ``integrator``, ``omega_max``).
    contacts : iterable of (str, PairContact)
        Every resolved contact with where it is (``pair 1-1``, ``wall[2]``).

    Raises
    ------
    InputError
        Keyed ``local_damping``, naming what is not modelled with it.
    """
    if scene.local_damping is None:
        return
    alpha = scene.local_damping[0]
    if scene.integrator not in MODELLED_INTEGRATORS:
        raise InputError("local_damping", f"local damping {alpha:g} with the integrator {scene.integrator} is not "
                                          f"modelled (only {', '.join(MODELLED_INTEGRATORS)}: YADE's NewtonIntegrator, PFC)")
    if scene.omega_max is not None:
        raise InputError("local_damping", f"local damping {alpha:g} with omega_max (the rotation-dominant bound) "
                                          "is not modelled")
    for where, c in contacts:
        if _damped(c):
            raise InputError("local_damping", f"local damping {alpha:g} together with the dashpots of {where} "
                                              "(cn, cs, cr, ctw) is not modelled")


def apply(result: Any) -> Any:
    """The step with the scene's local damping: ``dt_crit`` times ``1/sqrt(1 + alpha)``.

    Parameters
    ----------
    result : dtcrit.scenes.timestep.StepResult
        The undamped step of the scene.

    Returns
    -------
    dtcrit.scenes.timestep.StepResult
        ``result`` unchanged without local damping; else the damped ``dt_crit``, its bound in words and
        the estimates rated against it (each keeps the step its code computes).
    """
    local = result.scene.local_damping
    if local is None:
        return result
    alpha, law = local
    factor = float(phys.step_factor(alpha))
    dt = result.dt_crit * factor
    what = ("proved: below it every step is stable" if phys.STATUS[law] == "proved" else
            "the onset of instability (YADE's law: above it stability comes in windows, never an interval)")
    bound = (f"{result.bound}; x 1/sqrt(1 + alpha) = {factor:.6g} for local damping alpha = {alpha:g} (law {law}"
             f"): {what}")
    estimates = tuple(RatedEstimate(r.estimate, dt) for r in result.estimates)
    dense = result.dense  # the packing step and the isolated-contact step are damped alike
    if dense is not None and dense.dt is not None:
        dense = replace(dense, dt=dense.dt * factor)
    return replace(result, dt_crit=dt, bound=bound, estimates=estimates, dense=dense,
                   dt_isolated=result.dt_isolated * factor)
