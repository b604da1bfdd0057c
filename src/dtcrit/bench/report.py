"""Write the bench's report: Markdown table, CSV files and the work-precision plot.

``write_report(result, out_dir)`` writes

* ``bench.md``  -- the route table (error in ulps and relative, time per scene, failures), the
  section-4 ratios, the per-integrator breakdown, the extreme-case suite (outcome per case and
  route), the paper's forms, the simulation check, and the machine and package versions at the foot;
* ``routes.csv`` (one row per route and integrator), ``suite.csv``, ``paper_forms.csv``,
  ``simulation.csv``;
* ``work_precision.png`` -- log-log, error (max ulps) against seconds per scene, one marker per
  route, left panel well-conditioned scenes, right panel near-critical/extreme scenes (the batch's,
  plus the suite's worst finite error as a hollow marker).

``jsonable(result)`` turns non-finite floats into strings so that ``json.dumps`` emits strict JSON.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

from dtcrit.bench.startup import markdown as startup_markdown

ULP_FLOOR = 0.1  # errors below this are drawn at this height on the log axis
ULP_CEIL = 1e17  # relative error ~1 or worse (all digits lost) is drawn at this height


def jsonable(obj):
    """``obj`` with non-finite floats spelled ``"inf"``, ``"-inf"``, ``"nan"`` and tuples as lists (strict JSON).

    Parameters
    ----------
    obj : object
        A float, dict, list, tuple or other JSON value.

    Returns
    -------
    object
        The converted value.
    """
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else ("inf" if obj > 0 else "-inf" if obj < 0 else "nan")
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    return obj


def _f(x, fmt="{:.3g}") -> str:
    if x is None:
        return "-"
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    return fmt.format(x)


BENCH_UNITS = {"seconds_per_scene": "s", "floor_seconds": "s", "copy_seconds": "s", "generated_seconds": "s",
               "fused_seconds": "s", "c_seconds": "s", "best_seconds": "s", "median_seconds": "s",
               "growth_below": "1 (amplitude ratio)", "growth_above": "1 (amplitude ratio)", "ulp": "units in the last place",
               "k": "N/m", "c": "N s/m", "A": "1/kg"}


def json_summary(result: dict) -> dict:
    """The ``--json`` document: routes, suite, the two ratios, plus the simulation check.

    Parameters
    ----------
    result : dict
        The result of ``run_bench``.

    Returns
    -------
    dict
        The JSON document.
    """
    routes = [{"name": r["name"], "family": r["family"], "max_ulp": r["max_ulp"], "median_ulp": r["median_ulp"],
               "max_rel": r["max_rel"], "median_rel": r["median_rel"], "seconds_per_scene": r["seconds_per_scene"],
               "failures": r["failures"], "n_accuracy": r["n_accuracy"], "n_timed": r["n_timed"],
               "by_integrator": {n: {k: e[k] for k in ("max_ulp", "median_ulp", "seconds_per_scene", "failures")}
                                 for n, e in r["by_integrator"].items()}}
              for r in result["routes"]]
    suite = [{k: e[k] for k in ("case", "route", "integrator", "outcome", "ulp", "digits_lost", "note")}
             for e in result["suite"] + result["paper_forms"]]
    from dtcrit.json_meta import envelope

    return jsonable({
        **envelope("dtcrit-bench/1", BENCH_UNITS),
        "routes": routes,
        "suite": suite,
        "speedup_vs_eig": result["speedup_vs_eig"],
        "kernel_vs_floor": result["kernel_vs_floor"],
        "ratios": result["ratios"],
        "simulation": [{k: s[k] for k in ("case", "integrator", "outcome", "growth_below", "growth_above", "n_steps", "note")}
                       for s in result["simulation"]],
        "startup": result.get("startup"),
        "config": result["config"],
        "machine": result["machine"],
    })


# --- Markdown --------------------------------------------------------------------------------

def _route_table(result) -> list[str]:
    lines = ["| route | family | max ulp | median ulp | max rel | median rel | s / scene | scenes timed | failures |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in result["routes"]:
        lines.append(f"| {r['name']} | {r['family']} | {_f(r['max_ulp'])} | {_f(r['median_ulp'])} | {_f(r['max_rel'])} | "
                     f"{_f(r['median_rel'])} | {_f(r['seconds_per_scene'])} | {r['n_timed']} | {r['failures']} |")
    return lines


def _integrator_table(result) -> list[str]:
    names = list(result["config"]["integrators"])
    lines = ["| route | " + " | ".join(names) + " |", "|---|" + "---:|" * len(names)]
    for r in result["routes"]:
        cells = []
        for n in names:
            e = r["by_integrator"].get(n)
            cells.append("n/a" if e is None else f"{_f(e['max_ulp'])}" + (f" ({e['failures']} fail)" if e["failures"] else ""))
        lines.append(f"| {r['name']} | " + " | ".join(cells) + " |")
    return lines


def _suite_tables(result) -> list[str]:
    out = []
    routes = []
    for e in result["suite"]:
        if e["route"] not in routes:
            routes.append(e["route"])
    cases = [c["name"] for c in result["suite_cases"]]
    by = {(e["case"], e["route"], e["integrator"]): e for e in result["suite"]}
    names = list(result["config"]["integrators"])

    def cell(e):
        if e is None:
            return ""
        o = e["outcome"]
        if o == "ok":
            return "ok"
        if o == "digits_lost":
            return f"-{e['digits_lost']:g}d"
        return "REF" if o == "refused" else "FAIL"

    out.append("Cells: `ok` within 4 ulp; `-Nd` N decimal digits lost; `REF` refused (InputError); `FAIL` NaN, inf, "
               "exception, 0 for a stable contact, or a value where none is stable (notes below).  Empty: not run.")
    for name in names:
        out += ["", f"**{name}**", "", "| case | " + " | ".join(routes) + " |", "|---|" + "---|" * len(routes)]
        for case in cases:
            out.append(f"| {case} | " + " | ".join(cell(by.get((case, r, name))) for r in routes) + " |")
    notes = [e for e in result["suite"] if e["outcome"] in ("failed", "refused") or
             (e["held_to_4_ulp"] and e["outcome"] == "digits_lost")]
    if notes:
        out += ["", "Failures, refusals, and dtcrit routes beyond 4 ulp:", "",
                "| case | integrator | route | outcome | ulp | note |", "|---|---|---|---|---:|---|"]
        for e in notes:
            out.append(f"| {e['case']} | {e['integrator']} | {e['route']} | {e['outcome']} | {_f(e['ulp'])} | "
                       f"{e['note'].replace('|', '/')} |")
    return out


def _paper_table(result) -> list[str]:
    forms = []
    for e in result["paper_forms"]:
        if e["route"] not in forms:
            forms.append(e["route"])
    by = {(e["case"], e["route"]): e for e in result["paper_forms"]}
    lines = ["Float64 evaluation of each printed form against the same form at 50 digits (`ok`, `-Nd` digits lost, "
             "`FAIL`, `undef` = no real value), and in brackets the form's value over the verified velocity-Verlet "
             "bound (the form as a *bound*).", "",
             "| case | " + " | ".join(forms) + " |", "|---|" + "---|" * len(forms)]
    for c in result["suite_cases"]:
        cells = []
        for f in forms:
            e = by.get((c["name"], f))
            if e is None:
                cells.append("")
                continue
            o = e["outcome"]
            tag = {"ok": "ok", "failed": "FAIL", "undefined": "undef", "refused": "REF"}.get(o)
            if tag is None:
                tag = f"-{e['digits_lost']:g}d"
            ratio = e["ratio_to_velocity_verlet_bound"]
            text = "" if ratio is None else (f" [{ratio:.3g}]" if isinstance(ratio, float) else f" [{ratio}]")
            cells.append(tag + text)
        lines.append(f"| {c['name']} | " + " | ".join(cells) + " |")
    return lines


def _simulation_table(result) -> list[str]:
    lines = ["| case | integrator | outcome | tau* | zeta | steps | growth at 0.99 tau* | growth at 1.01 tau* | note |",
             "|---|---|---|---:|---:|---:|---:|---:|---|"]
    for s in result["simulation"]:
        lines.append(f"| {s['case']} | {s['integrator']} | {s['outcome']} | {_f(s['tau_crit'], '{:.6g}')} | {_f(s['zeta'])} | "
                     f"{s['n_steps']} | {_f(s['growth_below'])} | {_f(s['growth_above'])} | {s['note']} |")
    return lines


def markdown(result: dict) -> str:
    """The bench report in Markdown: the routes' accuracy and speed, the ratios, the simulation check.

    Parameters
    ----------
    result : dict
        The result of ``run_bench``.

    Returns
    -------
    str
        The report.
    """
    cfg = result["config"]
    rat = result["ratios"]
    counts: dict[str, int] = {}
    for s in result["simulation"]:
        counts[s["outcome"]] = counts.get(s["outcome"], 0) + 1
    held = [e for e in result["suite"] if e["held_to_4_ulp"]]
    held_bad = [e for e in held if e["outcome"] not in ("ok", "refused")]
    lines = [
        f"# dtcrit bench ({'quick' if cfg['quick'] else 'full'})",
        "",
        f"Batch: {result['batch']['n']} scenes ({result['batch']['n_extreme']} near-critical/extreme), seed {result['batch']['seed']}; "
        f"errors on the first {cfg['n_ref']} scenes per integrator (mpmath routes: first {cfg['n_mp']}) against the "
        "50-digit reference; vectorised closed forms timed on the whole batch (best of "
        f"{cfg['repeats']}), per-scene and bisection routes on the first {cfg['n_eig']}, mpmath routes on the first {cfg['n_mp']}.",
        "",
        "## Routes",
        "",
        *_route_table(result),
        "",
        "## Section 4 ratios (measured in this run)",
        "",
        f"- `speedup_vs_eig` = {_f(result['speedup_vs_eig'])}: eigvals + bisection time per scene over the generated "
        "closed form's (`critical_dt_array`), the smallest over the integrators.",
        f"- `kernel_vs_floor` = {_f(result['kernel_vs_floor'])}: best dtcrit NumPy kernel (fused form) over the trivial "
        "kernel 2/sqrt(k A) on the same arrays, the largest over the six integrators with radical closed forms; "
        f"generated kernel: {_f(rat['kernel_vs_floor_generated'])}; paper-eq40 (cubic): {_f(rat['kernel_vs_floor_cubic'])}.",
        "",
        f"- `kernel_vs_memory_floor` = {_f(rat.get('kernel_vs_memory_floor'))}: the same kernels over the memory floor, one "
        "NumPy pass reading k and A and writing one array (`np.multiply(k, A, out=...)`); a NumPy square root alone "
        "costs several such passes, so no kernel with a square root comes close to it.",
        f"- `speedup_vs_eig_c` = {_f(rat.get('speedup_vs_eig_c'))}: eigvals + bisection over the emitted careful C step "
        "(`closed-form-c`), the smallest over the integrators.",
        "",
        "| integrator | floor [s] | memory floor [s] | generated [s] | generated / floor | fused [s] | fused / floor | "
        "speedup vs eigvals (NumPy) | (C) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for n, e in rat["kernel_vs_floor_by_integrator"].items():
        lines.append(f"| {n} | {_f(e['floor_seconds'])} | {_f(e.get('memory_floor_seconds'))} | {_f(e['generated_seconds'])} | "
                     f"{_f(e['generated_ratio'])} | {_f(e.get('fused_seconds'))} | {_f(e.get('fused_ratio'))} | "
                     f"{_f(rat['speedup_vs_eig_by_integrator'].get(n))} | "
                     f"{_f(rat.get('speedup_vs_eig_c_by_integrator', {}).get(n))} |")
    lines += ["", "## Max ulp per route and integrator (reference sample)", "", *_integrator_table(result), "",
              "## Extreme-case suite", "",
              f"dtcrit's own closed-form routes: {len(held) - len(held_bad)} of {len(held)} (case, integrator, route) "
              f"results within 4 ulp or refused; {len(held_bad)} not.", "", *_suite_tables(result), "",
              "### Cases", "", "| case | group | k | c | A | zeta | description |", "|---|---|---:|---:|---:|---:|---|"]
    for c in result["suite_cases"]:
        lines.append(f"| {c['name']} | {c['group']} | {c['k']:.6g} | {c['c']:.6g} | {c['A']:.6g} | {_f(c['zeta'])} | {c['description']} |")
    lines += ["", "## The paper's forms on the suite", "", *_paper_table(result), "",
              "## Stability by simulation (section 3)", "",
              "Outcome counts: " + ", ".join(f"{k}: {v}" for k, v in sorted(counts.items())), "",
              *_simulation_table(result), "", "## Start-up of `dtcrit step`", "",
              *(startup_markdown(result["startup"]) if result.get("startup") else
                ["Not measured: the example scenes (`examples/`) are not beside this installation."]),
              "", "## Machine", ""]
    for k, v in result["machine"].items():
        lines.append(f"- {k}: {v}")
    lines.append(f"- wall time of this run: {result['wall_seconds']:.1f} s")
    return "\n".join(lines) + "\n"


# --- CSV -------------------------------------------------------------------------------------

def _write_csv(path: Path, header: list[str], rows: list[list]) -> None:
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for r in rows:
            w.writerow(["" if v is None else v for v in r])


def write_csvs(result: dict, out: Path) -> list[Path]:
    """Write the per-route, per-integrator and per-case tables as CSV into ``out``.

    Parameters
    ----------
    result : dict
        The result of ``run_bench``.
    out : pathlib.Path
        Folder to write into.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    keys = ["n_accuracy", "max_ulp", "median_ulp", "max_rel", "median_rel", "max_ulp_well_conditioned",
            "max_ulp_extreme", "seconds_per_scene", "n_timed", "failures"]
    rows = [[r["name"], r["family"], n] + [e[k] for k in keys] for r in result["routes"] for n, e in r["by_integrator"].items()]
    paths = [out / "routes.csv", out / "suite.csv", out / "paper_forms.csv", out / "simulation.csv"]
    _write_csv(paths[0], ["route", "family", "integrator"] + keys, rows)
    skeys = ["case", "group", "route", "integrator", "outcome", "ulp", "digits_lost", "value", "reference", "note"]
    _write_csv(paths[1], skeys, [[e[k] for k in skeys] for e in result["suite"]])
    pkeys = ["case", "group", "route", "outcome", "ulp", "digits_lost", "value", "reference", "ratio_to_velocity_verlet_bound", "note"]
    _write_csv(paths[2], pkeys, [[e[k] for k in pkeys] for e in result["paper_forms"]])
    mkeys = ["case", "integrator", "outcome", "tau_crit", "zeta", "rho_above_minus_1", "n_steps", "growth_below", "growth_above", "note"]
    _write_csv(paths[3], mkeys, [[s[k] for k in mkeys] for s in result["simulation"]])
    return paths


# --- plot ------------------------------------------------------------------------------------

def _clip(u: float) -> float:
    return min(max(u, ULP_FLOOR), ULP_CEIL)


def plot(result: dict, path: Path) -> Path:
    """Draw the work-precision figure: seconds per scene against the largest ulp error, per route.

    Parameters
    ----------
    result : dict
        The result of ``run_bench``.
    path : pathlib.Path
        File to write (PNG).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharey=True)
    markers = "osD^v<>ph*X"
    suite_worst: dict = {}
    for e in result["suite"]:
        if e["ulp"] is not None and math.isfinite(e["ulp"]):
            suite_worst[e["route"]] = max(suite_worst.get(e["route"], 0.0), e["ulp"])
    for i, r in enumerate(result["routes"]):
        t = r["seconds_per_scene"]
        m, color = markers[i % len(markers)], plt.cm.tab10(i % 10)
        for ax, key in ((axes[0], "max_ulp_well_conditioned"), (axes[1], "max_ulp_extreme")):
            y = r.get(key)
            if y is None:
                continue
            ax.loglog([t], [_clip(y)], m, ms=9, color=color, label=r["name"], linestyle="none")
            med = r.get(key.replace("max", "median"))
            if med is not None:
                ax.plot([t, t], [_clip(med), _clip(y)], "-", color=color, lw=1)
        if r["name"] in suite_worst:
            axes[1].loglog([t], [_clip(suite_worst[r["name"]])], m, ms=13, mfc="none", color=color)
    for ax, title in ((axes[0], "well-conditioned scenes"), (axes[1], "near-critical / extreme scenes (hollow: suite worst)")):
        ax.axhline(4.0, color="grey", lw=0.8, ls="--")
        ax.set_ylim(ULP_FLOOR / 2, ULP_CEIL * 5)
        ax.set_xlabel("seconds per scene")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("error [ulp]: max (marker), line down to the median")
    axes[0].legend(fontsize=7, loc="upper left")
    fig.suptitle(f"dtcrit bench ({'quick' if result['config']['quick'] else 'full'}): work-precision, dashed line = 4 ulp; "
                 f"errors below {ULP_FLOOR} drawn at {ULP_FLOOR}, above {ULP_CEIL:.0e} (all digits lost) at {ULP_CEIL:.0e}",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def write_report(result: dict, out_dir) -> list[Path]:
    """Write ``bench.md``, the CSV tables and ``work_precision.png`` into ``out_dir``.

    Parameters
    ----------
    result : dict
        The result of ``run_bench``.
    out_dir : str or pathlib.Path
        Folder to write into (created if needed).

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    md = out / "bench.md"
    md.write_text(markdown(result))
    paths = [md] + write_csvs(result, out)
    paths.append(plot(result, out / "work_precision.png"))
    return paths
