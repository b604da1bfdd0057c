"""Resolution steps shipped as generated data: ``resolve`` run ahead of time for the standard cases.

For each scheme of ``tables.SCHEMES``, law of ``RESOLUTION_LAWS`` (clipped as the code clips), restitution
of ``tables.RESTITUTIONS`` and tolerance of ``TOLS``, with the default quantities (restitution and peak
overlap), ``resolve`` (the same algorithm ``resolution_step`` runs) gives ``N_res``; the tables store it
and its worst errors rounded to ``DIGITS`` significant digits, and ``lookup`` answers from them.  A case
is tabulated when the sampled error curve of ``tables`` puts ``N_res`` at most ``N_CAP`` (the cost of
``resolve`` grows as ``N_res``: about 0.03 s per step per collision on one core), plus the engine
acceptance cases (``ALWAYS``); the others are computed on request.  Generation runs on ``WORKERS``
processes; the entries are sorted, so the output does not depend on their order of completion.
"""
from __future__ import annotations

import math
from multiprocessing import get_context

import numpy as np

from dtcrit.collisions.laws import scaled_law
from dtcrit.collisions.resolution import Resolution, resolve
from dtcrit.physics.collision_laws import DAMPING_MODELS

TOLS: tuple[float, ...] = (0.01, 0.001)
DEFAULT_QUANTITIES: tuple[str, ...] = ("restitution", "peak_overlap")
DIGITS = 6
N_CAP = 200.0
WORKERS = 2
#: (normal, damping) whose resolution steps are tabulated: the curves' laws, LAMMPS coeff_restitution, elastic
EXTRA_LAWS: tuple[tuple[str, str], ...] = (("hertz", "lammps-coeff-restitution"), ("hertz", "none"), ("hooke", "none"))
#: (scheme, normal, damping, e, tol) tabulated whatever their cost: the engine acceptance cases
ALWAYS: tuple[tuple[str, str, str, float, float], ...] = tuple(
    [("velocity-verlet", "hertz", "lammps-coeff-restitution", e, 0.01) for e in (0.9, 0.5, 0.1)]
    + [("leapfrog", "hertz", "yade-mindlin", e, 0.01) for e in (0.9, 0.5, 0.1)])


def _round(x: float) -> float | None:
    return float(f"{x:.{DIGITS}g}") if math.isfinite(x) else None


def predicted_n(errors: dict, steps, tol: float) -> float:
    """``N_res`` as the sampled curve puts it: the first grid N above the last one over ``tol``.

    Parameters
    ----------
    errors : dict
        quantity -> sampled worst errors over ``steps`` (``None`` where not separated).
    steps : sequence of float
        The curve's grid of N.
    tol : float
        Tolerance.

    Returns
    -------
    float
        The predicted ``N_res`` (``inf`` beyond the grid).
    """
    err = np.max([[np.inf if x is None else x for x in errors[q]] for q in DEFAULT_QUANTITIES], axis=0)
    bad = np.nonzero(err > tol)[0]
    if not bad.size:
        return float(steps[0])
    return float(steps[bad[-1] + 1]) if bad[-1] + 1 < len(steps) else math.inf


def plan(curves: list, steps) -> list[tuple]:
    """The cases to tabulate, sorted: ``(scheme, normal, damping, e, tol)``.

    Parameters
    ----------
    curves : list of dict
        The ``cases`` of the curve tables (scheme, normal, damping, restitution, errors).
    steps : sequence of float
        Their grid of N.

    Returns
    -------
    list of tuple
        The cases.
    """
    out = set(ALWAYS)
    schemes = sorted({c["scheme"] for c in curves})
    for c in curves:
        for tol in TOLS:
            if predicted_n(c["errors"], steps, tol) <= N_CAP:
                out.add((c["scheme"], c["normal"], c["damping"], float(c["restitution"]), tol))
    for scheme in schemes:
        for normal, damping in EXTRA_LAWS:
            ref = "lammps-tsuji" if damping == "lammps-coeff-restitution" else "liggghts"
            for c in curves:
                if (c["scheme"], c["normal"], c["damping"]) != (scheme, normal, ref):
                    continue
                if damping == "none" and c["restitution"] != 1.0:
                    continue
                for tol in TOLS:  # coeff_restitution: priced by tsuji's curve (the same dashpot form)
                    if predicted_n(c["errors"], steps, tol) <= N_CAP:
                        out.add((scheme, normal, damping, float(c["restitution"]), tol))
    return sorted(out)


def entry(case: tuple) -> dict:
    """One tabulated resolution step (``resolve`` with the code's clipping and the default quantities).

    Parameters
    ----------
    case : tuple
        ``(scheme, normal, damping, e, tol)``.

    Returns
    -------
    dict
        The case's keys, ``clip``, ``steps_per_collision`` and ``worst`` rounded to ``DIGITS`` digits.
    """
    scheme, normal, damping, e, tol = case
    law = scaled_law(normal, damping, e)
    res = resolve(scheme, law, tol, DEFAULT_QUANTITIES)
    return {"scheme": scheme, "normal": normal, "damping": damping, "restitution": e, "tol": tol,
            "clip": bool(law.clip), "steps_per_collision": _round(res.steps_per_collision),
            "worst": {k: _round(v) for k, v in sorted(res.worst.items())}}


def build(curves: list, steps, workers: int = WORKERS) -> list[dict]:
    """Every tabulated resolution step, in the sorted order of ``plan``.

    Parameters
    ----------
    curves : list of dict
        The curve tables' cases.
    steps : sequence of float
        Their grid of N.
    workers : int
        Processes (1: in this process).

    Returns
    -------
    list of dict
        The entries.
    """
    cases = plan(curves, steps)
    # the costly cases first, so the two workers finish together
    order = sorted(range(len(cases)), key=lambda i: -predicted_cost(cases[i], curves, steps))
    if workers <= 1:
        done = {i: entry(cases[i]) for i in order}
    else:
        with get_context("spawn").Pool(workers) as pool:
            done = dict(zip(order, pool.map(entry, [cases[i] for i in order], chunksize=1)))
    return [done[i] for i in range(len(cases))]


def predicted_cost(case: tuple, curves: list, steps) -> float:
    """The predicted ``N_res`` of a case (its cost), from the curve of its law or tsuji's.

    Parameters
    ----------
    case : tuple
        ``(scheme, normal, damping, e, tol)``.
    curves : list of dict
        The curve tables' cases.
    steps : sequence of float
        Their grid of N.

    Returns
    -------
    float
        The predicted ``N_res`` (0 when no curve prices it).
    """
    scheme, normal, damping, e, tol = case
    ref = {"lammps-coeff-restitution": "lammps-tsuji", "none": "liggghts"}.get(damping, damping)
    for c in curves:
        if (c["scheme"], c["normal"], c["damping"], c["restitution"]) == (scheme, normal, ref, e):
            n = predicted_n(c["errors"], steps, tol)
            return n if math.isfinite(n) else 1e6
    return 0.0


def find(entries: list, scheme, normal, damping, restitution, tol, quantities, clip) -> Resolution | None:
    """The tabulated resolution step matching the request exactly, or None.

    Parameters
    ----------
    entries : list of dict
        The tabulated entries.
    scheme, normal, damping : str
        The case.
    restitution, tol : float
        Restitution and tolerance.
    quantities : tuple of str
        The quantities (only the default pair is tabulated).
    clip : bool or None
        Clipping (None: the code's default).

    Returns
    -------
    Resolution or None
        The stored resolution, or None when it is not tabulated.
    """
    if tuple(quantities) != DEFAULT_QUANTITIES or damping not in DAMPING_MODELS:
        return None
    want_clip = DAMPING_MODELS[damping].clips if clip is None else bool(clip)
    for c in entries:
        if (c["scheme"], c["normal"], c["damping"], c["clip"]) == (scheme, normal, damping, want_clip) \
                and c["restitution"] == restitution and c["tol"] == tol and c["steps_per_collision"] is not None:
            n = float(c["steps_per_collision"])
            worst = {k: (math.inf if v is None else float(v)) for k, v in c["worst"].items()}
            return Resolution(n, 1.0 / n, float(tol), DEFAULT_QUANTITIES, worst)
    return None


__all__ = ["TOLS", "DEFAULT_QUANTITIES", "DIGITS", "N_CAP", "WORKERS", "EXTRA_LAWS", "ALWAYS", "predicted_n",
           "plan", "entry", "build", "predicted_cost", "find"]
