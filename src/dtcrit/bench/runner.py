"""``dtcrit bench``: error against run time for every route, the extreme-case suite, and the
stability check by simulation.

``run_bench(config)`` returns a plain dictionary (JSON-ready apart from ``float('inf')``, which
``dtcrit.bench.report.jsonable`` turns into the string "inf"):

* ``routes``: one entry per route -- ``name``, ``family``, ``max_ulp``, ``median_ulp``,
  ``max_rel``, ``median_rel`` (on the reference sample, all integrators the route covers),
  ``seconds_per_scene`` (mean over integrators, on the route's timing set), ``failures``
  (NaN, inf, exception, or a positive step where none is stable), and ``by_integrator``;
* ``suite``: one entry per extreme case, integrator and route: ``outcome`` (``ok`` within 4 ulp,
  ``digits_lost`` with how many, ``refused`` = InputError with its reason, ``failed``) and ``ulp``;
* ``paper_forms``: the printed forms on the suite (float64 vs the same form at 50 digits);
* ``simulation``: section 3 rows (``dtcrit.bench.simulation_check``);
* ``speedup_vs_eig`` and ``kernel_vs_floor`` (section 4), with their per-integrator values;
* ``startup``: wall time of ``dtcrit step`` on each example scene, fresh interpreter, against a
  bare ``import numpy`` (``dtcrit.bench.startup``), or ``None`` without the source tree's
  ``examples/``.

Errors are measured against ``dtcrit.bench.reference`` (>= 50 digits, exact float inputs) on a
reference sample of the batch; the reference step is never timed.  Times are best-of-``repeats``
wall-clock on the route's timing set: the full batch for the vectorised closed forms, the first
``n_eig`` scenes for the per-scene and bisection routes, the first ``n_mp`` for mpmath.
"""
from __future__ import annotations

import math
import platform
import statistics
import sys
import time
from typing import Any
from dataclasses import asdict

import mpmath as mp
import numpy as np

from dtcrit.bench import reference as ref
from dtcrit.bench.config import FULL_RUN as FULL_RUN  # the command line imports both from here
from dtcrit.bench.config import QUICK, BenchConfig
from dtcrit.bench.paper_forms import PAPER_FORMS
from dtcrit.bench.ratios import ratios as _ratios
from dtcrit.bench.routes import EIG_SAMPLE, FULL, MP_SAMPLE, ROUTES
from dtcrit.bench.suite import SUITE, random_batch
from dtcrit.errors import InputError
from tqdm import tqdm

ULP_OK = 4.0
FLOAT_DIGITS = 15.95  # log10(2^53)




# --- outcome of one value against its reference -------------------------------------------------

def classify(got: float | None, reference, error: BaseException | None = None) -> dict:
    """{'outcome', 'ulp', 'digits_lost', 'note'} for one route value (see the module docstring).

    Parameters
    ----------
    got : float or None
        The route's value (None when it raised).
    reference : mpmath.mpf
        The exact step.
    error : BaseException, optional
        What the route raised.

    Returns
    -------
    dict
        The outcome and its error measures.
    """
    if isinstance(error, InputError):
        return {"outcome": "refused", "ulp": None, "digits_lost": None, "note": str(error)}
    if error is not None:
        return {"outcome": "failed", "ulp": None, "digits_lost": None, "note": f"{type(error).__name__}: {error}"}
    beyond = ref.beyond_float64(reference)
    if got is None or math.isnan(got):
        return {"outcome": "failed", "ulp": None, "digits_lost": None, "note": "NaN"}
    if beyond:
        what = "inf" if math.isinf(got) else f"{got!r}"
        return {"outcome": "failed", "ulp": None, "digits_lost": None,
                "note": f"returns {what} for a step beyond float64 ({mp.nstr(reference, 3)} s): should refuse"}
    if math.isinf(got):
        return {"outcome": "failed", "ulp": None, "digits_lost": None, "note": "inf"}
    if reference > 0 and got == 0.0:
        below = reference < ref.SUBNORMAL_ULP / 2
        return {"outcome": "failed", "ulp": None, "digits_lost": None,
                "note": "returns 0.0 ('no stable step') for a stable contact"
                + (f" whose step {mp.nstr(reference, 3)} s is below float64's range: should refuse" if below else "")}
    if reference == 0 and got != 0.0:
        return {"outcome": "failed", "ulp": None, "digits_lost": None,
                "note": f"returns {got:.3g} where no step is stable"}
    u = ref.ulp_error(got, reference)
    if u <= ULP_OK:
        return {"outcome": "ok", "ulp": u, "digits_lost": 0.0, "note": ""}
    with mp.workdps(30):
        rel = float(abs(mp.mpf(got) - reference) / abs(reference))
    digits = FLOAT_DIGITS if rel >= 1 else min(FLOAT_DIGITS, round(math.log10(u), 1))
    return {"outcome": "digits_lost", "ulp": u, "digits_lost": digits, "note": f"relative error {rel:.2g}"}


def _is_failure(c: dict) -> bool:
    return c["outcome"] in ("failed", "refused")


# --- timing ----------------------------------------------------------------------------------

def _time(fn, repeats: int) -> tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _stats(values: list[float]) -> tuple[float | None, float | None]:
    vals = [v for v in values if v is not None and math.isfinite(v)]
    if not vals:
        return None, None
    return max(vals), statistics.median(vals)


# --- machine ---------------------------------------------------------------------------------

def machine_info() -> dict:
    """The machine and library versions the bench ran on (for the report).

    Returns
    -------
    dict
        Platform, CPU, Python and library versions.
    """
    import numpy
    import scipy
    import sympy

    info = {
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "machine": platform.machine(),
        "cpu": platform.processor() or "",
        "cpus": __import__("os").cpu_count(),
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "sympy": sympy.__version__,
        "mpmath": mp.__version__,
    }
    try:
        import matplotlib

        info["matplotlib"] = matplotlib.__version__
    except ImportError:  # pragma: no cover
        info["matplotlib"] = "not installed"
    try:
        with open("/proc/cpuinfo") as fh:  # Linux: the CPU model name
            for line in fh:
                if line.startswith("model name"):
                    info["cpu"] = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    from dtcrit.bench.c_kernel import compiler

    cc = compiler()
    if cc:
        import subprocess

        first = subprocess.run([cc, "--version"], capture_output=True, text=True).stdout.splitlines()
        info["cc"] = first[0] if first else "cc"
    else:
        info["cc"] = "none"
    return info


# --- the batch: errors against run time -------------------------------------------------------

def _evaluate(route, name, k, c, A):
    try:
        with np.errstate(all="ignore"):
            return np.asarray(route.evaluate(name, k, c, A), dtype=float), None
    except Exception as exc:  # a route that fails outright is reported, not raised
        return None, exc


def _batch_part(config: BenchConfig, batch, refs, routes) -> tuple[list[dict], dict]:
    n_ref = min(config.n_ref, len(batch))
    per_route: list[dict] = []
    sizes = {FULL: len(batch), EIG_SAMPLE: min(config.n_eig, len(batch)), MP_SAMPLE: min(config.n_mp, len(batch))}
    timing_raw: dict = {}
    jobs = [(r, n) for r in routes for n in config.integrators if r.applies_to(n)
            and not (r.family == "mpmath" and config.mp_integrators is not None and n not in config.mp_integrators)]
    rows: dict[str, dict] = {}
    for route, name in tqdm(jobs, desc="bench: routes", disable=None):
        size = sizes[route.tier]
        sub = batch.take(slice(0, size))
        repeats = config.repeats if route.tier == FULL else 1
        t, (values, error) = _time(lambda: _evaluate(route, name, sub.k, sub.c, sub.A), repeats)
        n_acc = min(n_ref, size)
        row = rows.setdefault(route.name, {"name": route.name, "family": route.family, "summary": route.summary,
                                           "tier": route.tier, "held_to_4_ulp": route.held_to_4_ulp,
                                           "by_integrator": {}})
        entry: dict[str, Any] = {"n_timed": size, "seconds": t, "seconds_per_scene": t / size, "n_accuracy": n_acc}
        ulps, rels, extreme, failures = [], [], [], 0
        notes: list[str] = []
        for i in range(n_acc):
            r = refs[name][i]
            c = classify(None if values is None else float(values[i]), r, error)
            if _is_failure(c):
                failures += 1
                if len(notes) < 3:
                    notes.append(c["note"])
                continue
            ulps.append(c["ulp"])
            with mp.workdps(30):
                rels.append(float(abs(mp.mpf(float(values[i])) - r) / r) if r != 0 else 0.0)
            extreme.append(bool(batch.extreme[i]))
        entry["failures"] = failures
        entry["failure_notes"] = notes
        entry["max_ulp"], entry["median_ulp"] = _stats(ulps)
        entry["max_rel"], entry["median_rel"] = _stats(rels)
        wc = [u for u, e in zip(ulps, extreme) if not e]
        ex = [u for u, e in zip(ulps, extreme) if e]
        entry["max_ulp_well_conditioned"], entry["median_ulp_well_conditioned"] = _stats(wc)
        entry["max_ulp_extreme"], entry["median_ulp_extreme"] = _stats(ex)
        entry["_ulps"] = ulps
        entry["_rels"] = rels
        entry["_extreme"] = extreme
        row["by_integrator"][name] = entry
        timing_raw[(route.name, name)] = t / size
    for row in rows.values():
        entries = list(row["by_integrator"].values())
        allu = [u for e in entries for u in e.pop("_ulps")]
        allr = [u for e in entries for u in e.pop("_rels")]
        allx = [x for e in entries for x in e.pop("_extreme")]
        # keep the split for the plot
        row["max_ulp"], row["median_ulp"] = _stats(allu)
        row["max_rel"], row["median_rel"] = _stats(allr)
        row["max_ulp_well_conditioned"], _ = _stats([u for u, x in zip(allu, allx) if not x])
        row["max_ulp_extreme"], _ = _stats([u for u, x in zip(allu, allx) if x])
        row["median_ulp_well_conditioned"] = _stats([u for u, x in zip(allu, allx) if not x])[1]
        row["median_ulp_extreme"] = _stats([u for u, x in zip(allu, allx) if x])[1]
        row["failures"] = sum(e["failures"] for e in entries)
        row["seconds_per_scene"] = statistics.fmean(e["seconds_per_scene"] for e in entries)
        row["n_timed"] = entries[0]["n_timed"]
        row["n_accuracy"] = sum(e["n_accuracy"] for e in entries)
        per_route.append(row)
    return per_route, timing_raw


# --- the suite -------------------------------------------------------------------------------

def _suite_part(config: BenchConfig, routes) -> tuple[list[dict], list[dict], dict, dict]:
    entries: list[dict] = []
    paper: list[dict] = []
    tau_ref: dict = {}
    zeta_ref: dict = {}
    mp_cases = set(config.mp_suite_cases) if config.mp_suite_cases is not None else None
    mp_ints = set(config.mp_integrators) if config.mp_integrators is not None else None
    all_refs: list[dict] = []
    for case in tqdm(SUITE, desc="bench: suite references", disable=None):
        zeta_ref[case.name] = ref.zeta_exact(case.k, case.c, case.A)
        refs = {}
        for name in config.integrators:
            r = ref.dt_reference(name, case.k, case.c, case.A)
            refs[name] = r
            with mp.workdps(60):
                tau_ref[(case.name, name)] = r * mp.sqrt(mp.mpf(case.k) * mp.mpf(case.A))
        all_refs.append(refs)
    # routes: the whole suite at once per (route, integrator); case by case when that raises
    k = np.array([c.k for c in SUITE])
    c_ = np.array([c.c for c in SUITE])
    A = np.array([c.A for c in SUITE])
    jobs = [(r, n) for r in routes for n in config.integrators if r.applies_to(n)]
    for route, name in tqdm(jobs, desc="bench: suite routes", disable=None):
        chosen = [i for i, case in enumerate(SUITE)
                  if not (route.family == "mpmath" and ((mp_cases is not None and case.name not in mp_cases)
                                                         or (mp_ints is not None and name not in mp_ints)))]
        if not chosen:
            continue
        values, error = _evaluate(route, name, k[chosen], c_[chosen], A[chosen])
        results: dict[int, tuple[float | None, Any]] = {}
        if error is None:
            results = {i: (float(v), None) for i, v in zip(chosen, values)}
        else:
            for i in chosen:
                v, e = _evaluate(route, name, k[i:i + 1], c_[i:i + 1], A[i:i + 1])
                results[i] = (None if v is None else float(v[0]), e)
        for i in chosen:
            case, r = SUITE[i], all_refs[i][name]
            got, e = results[i]
            entries.append({"case": case.name, "group": case.group, "route": route.name, "integrator": name,
                            "family": route.family, "held_to_4_ulp": route.held_to_4_ulp,
                            "value": got, "reference": float(r),
                            "step_representable": not ref.beyond_float64(r) and not (0 < r < ref.SUBNORMAL_ULP / 2),
                            **classify(got, r, e)})
    order = {(r.name, n, case.name): j for j, (r, n, case) in
             enumerate((r, n, case) for case in SUITE for r in routes for n in config.integrators)}
    entries.sort(key=lambda e: order[(e["route"], e["integrator"], e["case"])])
    for case, refs in zip(SUITE, all_refs):
        bound_vv = refs.get("velocity-verlet")
        for form_name, key, fn, needs_m in PAPER_FORMS:
            if needs_m and case.m is None:
                continue
            r = ref.paper_form_reference(key, case.k, case.c, case.A, case.m)
            try:
                with np.errstate(all="ignore"):
                    got = float(np.asarray(fn(np.array([case.k]), np.array([case.c]), np.array([case.A]),
                                              None if case.m is None else np.array([case.m])))[0])
                err = None
            except Exception as exc:  # pragma: no cover - reported
                got, err = None, exc
            if mp.isnan(r):
                c = {"outcome": "undefined", "ulp": None, "digits_lost": None,
                     "note": "the printed form has no real value here (beyond its asymptote)"
                     + ("" if got is None or math.isnan(got) else f"; float64 gives {got:.6g}")}
            else:
                c = classify(got, r, err)
            ratio = None
            if bound_vv is not None and bound_vv > 0 and not mp.isnan(r):
                with mp.workdps(30):
                    q = r / bound_vv
                    ratio = float(q) if mp.mpf(10) ** -300 < q < mp.mpf(10) ** 300 else mp.nstr(q, 3)
            paper.append({"case": case.name, "group": case.group, "route": form_name, "integrator": None,
                          "value": got, "reference": None if mp.isnan(r) else float(r),
                          "ratio_to_velocity_verlet_bound": ratio, **c})
    return entries, paper, tau_ref, zeta_ref


def run_bench(config: BenchConfig = QUICK, route_names: tuple[str, ...] | None = None) -> dict:
    """Run the whole bench (see the module docstring); ``route_names`` restricts the routes.

    Parameters
    ----------
    config : BenchConfig
        Sizes and repeats.
    route_names : tuple of str, optional
        Routes to run (all when omitted).

    Returns
    -------
    dict
        The routes, suite, ratios, simulation check and machine information.
    """
    routes = [r for r in ROUTES if route_names is None or r.name in route_names]
    started = time.perf_counter()
    stages = {}
    batch = random_batch(config.n_batch, config.seed)
    n_ref = min(config.n_ref, len(batch))
    refs = {}
    for name in tqdm(config.integrators, desc="bench: references", disable=None):
        refs[name] = [ref.dt_reference(name, batch.k[i], batch.c[i], batch.A[i]) for i in range(n_ref)]
    stages["references"] = time.perf_counter() - started
    t = time.perf_counter()
    per_route, timing_raw = _batch_part(config, batch, refs, routes)
    stages["routes"] = time.perf_counter() - t
    t = time.perf_counter()
    ratios = _ratios(config, batch, timing_raw)
    stages["ratios"] = time.perf_counter() - t
    t = time.perf_counter()
    suite, paper, tau_ref, zeta_ref = _suite_part(config, routes)
    stages["suite"] = time.perf_counter() - t
    from dtcrit.bench.simulation_check import check

    t = time.perf_counter()
    sim = check(SUITE, config.integrators, tau_ref, zeta_ref, config.sim_budget)
    stages["simulation"] = time.perf_counter() - t
    from dtcrit.bench import startup as startup_bench

    t = time.perf_counter()
    scenes = startup_bench.example_scenes()
    startup = startup_bench.measure(scenes, config.startup_repeats) if scenes else None
    stages["startup"] = time.perf_counter() - t
    return {
        "config": asdict(config),
        "machine": machine_info(),
        "routes": per_route,
        "suite": suite,
        "paper_forms": paper,
        "simulation": [asdict(r) for r in sim],
        "startup": startup,
        "speedup_vs_eig": ratios["speedup_vs_eig"],
        "kernel_vs_floor": ratios["kernel_vs_floor"],
        "ratios": ratios,
        "suite_cases": [{"name": c.name, "group": c.group, "description": c.description, "k": c.k, "c": c.c,
                         "A": c.A, "m": c.m, "zeta": float(zeta_ref[c.name]) if mp.isfinite(zeta_ref[c.name])
                         and abs(zeta_ref[c.name]) < mp.mpf(2) ** 1023 else math.inf} for c in SUITE],
        "batch": {"n": len(batch), "n_extreme": int(batch.extreme.sum()), "seed": config.seed},
        "stage_seconds": stages,
        "wall_seconds": time.perf_counter() - started,
    }
