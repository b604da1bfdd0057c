"""The benchmarks page, written from ``dtcrit bench --json`` and the scale benchmark's output.

``dtcrit bench --quick`` takes minutes on a small shared machine, too long for every build, so its
output is committed: ``python3 dev.py docs-bench`` runs it (and the scale benchmark at small sizes)
into ``docs/benchmarks/data`` (``bench.json``, ``work_precision.png``, ``scale.txt`` and
``provenance.json``: when, the command, the CPU from ``/proc/cpuinfo``).  With
``DTCRIT_DOCS_BENCH=1`` the build runs the bench itself instead.  The page says which it shows and
describes both the machine that measured and the machine that built the site (read from
``/proc/cpuinfo`` at build time).
"""
from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
DATA = DOCS / "benchmarks" / "data"
BENCH_ARGS = ["bench", "--quick", "--json"]
SCALE_ARGS = ["packing", "--scale", "1e3,1e4"]


def cpu_description() -> dict:
    """The CPU model, logical cores and memory of the machine running this, from ``/proc/cpuinfo`` and ``/proc/meminfo``.

    Returns
    -------
    dict
        ``cpu_model``, ``logical_cores``, ``memory_gib`` (None where not readable), ``platform``.
    """
    info = {"cpu_model": platform.processor() or None, "logical_cores": os.cpu_count(), "memory_gib": None,
            "platform": platform.platform()}
    try:
        text = Path("/proc/cpuinfo").read_text()
        models = [line.split(":", 1)[1].strip() for line in text.splitlines() if line.startswith("model name")]
        if models:
            info["cpu_model"] = models[0]
            info["logical_cores"] = len(models)
        mem = [line for line in Path("/proc/meminfo").read_text().splitlines() if line.startswith("MemTotal")]
        if mem:
            info["memory_gib"] = round(int(mem[0].split()[1]) / 2**20, 1)
    except OSError:
        pass
    return info


def _dtcrit(args: list[str], cwd: Path) -> str:
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), os.environ.get("PYTHONPATH")]))
    done = subprocess.run([sys.executable, "-m", "dtcrit", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=3600)
    if done.returncode != 0:
        raise RuntimeError(f"dtcrit {' '.join(args)} failed:\n{done.stdout}{done.stderr}")
    return done.stdout


def run_benchmarks(out: Path = DATA) -> Path:
    """Run the bench and the small scale benchmark; write their output and provenance into ``out``.

    Parameters
    ----------
    out : pathlib.Path
        Folder to write (``docs/benchmarks/data`` for the committed run).

    Returns
    -------
    pathlib.Path
        ``out``.
    """
    out.mkdir(parents=True, exist_ok=True)
    scratch = out / "_bench"
    start = time.time()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    document = json.loads(_dtcrit([*BENCH_ARGS, "--out", str(scratch)], ROOT))
    (out / "bench.json").write_text(json.dumps(document, separators=(",", ":")) + "\n")
    (scratch / "work_precision.png").replace(out / "work_precision.png")
    for leftover in scratch.iterdir():
        leftover.unlink()
    scratch.rmdir()
    (out / "scale.txt").write_text(_dtcrit(SCALE_ARGS, ROOT))
    provenance = {"commands": ["dtcrit " + " ".join(BENCH_ARGS), "dtcrit " + " ".join(SCALE_ARGS)],
                  "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime(start)),
                  "seconds": round(time.time() - start), "load_average_at_start": load,
                  "machine": cpu_description()}
    (out / "provenance.json").write_text(json.dumps(provenance, indent=1) + "\n")
    return out


def _g(x, fmt: str = "{:.3g}") -> str:
    return "–" if x is None else fmt.format(x)


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    return ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header),
            *("| " + " | ".join(row) + " |" for row in rows), ""]


def _machine_lines(machine: dict) -> list[str]:
    memory = f", {machine['memory_gib']} GiB of memory" if machine.get("memory_gib") else ""
    return [f"{machine.get('cpu_model') or 'unknown CPU'}, {machine.get('logical_cores')} logical cores{memory} "
            f"({machine.get('platform', '')})"]


def bench_sections(bench: dict) -> list[str]:
    """The page's tables from a ``dtcrit-bench/1`` document.

    Parameters
    ----------
    bench : dict
        The document ``dtcrit bench --json`` prints.

    Returns
    -------
    list of str
        Markdown lines.
    """
    lines = ["## Accuracy and speed of every route", "",
             "Errors against 50-digit references, in units in the last place (ulp); time per scene "
             "in a batch.  Wall-clock times: compare them within this run, not across machines.", ""]
    lines += _table(["route", "family", "max ulp", "median ulp", "s per scene", "failures"],
                    [[f"`{r['name']}`", r["family"], _g(r["max_ulp"]), _g(r["median_ulp"]),
                      _g(r["seconds_per_scene"]), str(r["failures"])] for r in bench["routes"]])
    ratios = bench["ratios"]
    lines += ["## Closed forms against an eigen-solve, kernels against a floor", "",
              f"The closed forms (NumPy, per scene of a batch) are at least {_g(bench['speedup_vs_eig'])} times "
              f"faster than an eigenvalue solve with bisection (the smallest factor over the integrators); the "
              f"integrators with a fused NumPy kernel run within {_g(bench['kernel_vs_floor'])} times an "
              f"arithmetic floor (the largest factor among them; the last column: every integrator's best "
              f"kernel over the floor).", ""]
    lines += _table(["integrator", "closed form / eigvals + bisection", "with the C kernel", "kernel / floor"],
                    [[f"`{name}`", _g(speed), _g(ratios.get("speedup_vs_eig_c_by_integrator", {}).get(name)),
                      _g(ratios.get("kernel_vs_floor_by_integrator", {}).get(name, {}).get("best_ratio"))]
                     for name, speed in ratios.get("speedup_vs_eig_by_integrator", {}).items()])
    outcomes = Counter((e["route"], e["outcome"]) for e in bench["suite"])
    routes = sorted({route for route, _ in outcomes})
    kinds = sorted({kind for _, kind in outcomes})
    lines += ["## The extreme-case suite", "", "Outcomes per route over the suite's cases and integrators.", ""]
    lines += _table(["route", *kinds], [[f"`{r}`", *(str(outcomes.get((r, k), 0)) for k in kinds)] for r in routes])
    sims = Counter(s["outcome"] for s in bench["simulation"])
    lines += ["## Stepping just below and above each step", "",
              "Each case is time-stepped at 0.99 and 1.01 of its critical step: "
              + ", ".join(f"{n} {outcome}" for outcome, n in sorted(sims.items())) + ".", ""]
    startup = bench.get("startup") or {}
    if startup.get("scenes"):
        lines += ["## Start-up of `dtcrit step`", "",
                  f"Best of {startup.get('repeats')} runs, against a bare `import numpy` "
                  f"({_g(startup.get('numpy_import_best_seconds'))} s).", ""]
        lines += _table(["scene", "best s", "x import numpy", "heavy modules loaded"],
                        [[f"`{s['scene']}`", _g(s["best_seconds"]), _g(s["best_over_numpy_import"]),
                          ", ".join(s["heavy_modules"]) or "none"] for s in startup["scenes"]])
    return lines


def page_text(bench: dict, scale: str | None, provenance: dict | None, live: bool) -> str:
    """The benchmarks page fragment.

    Parameters
    ----------
    bench : dict
        The bench's JSON document.
    scale : str or None
        The scale benchmark's printed table.
    provenance : dict or None
        Where a committed run came from (``run_benchmarks``).
    live : bool
        True when the build ran the bench itself.

    Returns
    -------
    str
        MyST Markdown (included by ``benchmarks/index.md``).
    """
    if live:
        origin = ["These figures were measured while this site was built (`DTCRIT_DOCS_BENCH=1`)."]
    else:
        when = provenance.get("date_utc") if provenance else "an unrecorded date"
        origin = [f"These figures come from the committed run in `docs/benchmarks/data` "
                  f"(`python3 dev.py docs-bench`, {when} UTC), not from this build: the bench takes minutes.  "
                  f"`DTCRIT_DOCS_BENCH=1 python3 dev.py docs` measures them during the build instead."]
    measured = (provenance or {}).get("machine") or {
        "cpu_model": bench["machine"].get("cpu"), "logical_cores": bench["machine"].get("cpus"),
        "platform": bench["machine"].get("platform")}
    m = bench["machine"]
    load = (provenance or {}).get("load_average_at_start")
    busy = f" (load average {load:.1f} when the run started)" if load is not None else ""
    lines = [*origin, "", "**Measured on:** " + _machine_lines(measured)[0] + busy + f"; Python {m.get('python')}, "
             f"NumPy {m.get('numpy')}, SciPy {m.get('scipy')}, compiler {m.get('cc')}.", "",
             "**This site was built on:** " + _machine_lines(cpu_description())[0] + ".", "",
             f"Settings: `dtcrit bench --quick` (batch {bench['config'].get('n_batch')}, "
             f"seed {bench['config'].get('seed')}).", ""]
    lines += bench_sections(bench)
    if scale:
        lines += ["## Packings at scale", "", "`dtcrit packing --scale 1e3,1e4` (jittered FCC, both routes, each "
                  "size in a fresh process):", "", "```text", scale.rstrip(), "```", ""]
    return "\n".join(lines)


def build_benchmarks(docs: Path = DOCS) -> Path:
    """Write ``benchmarks/_generated/bench.md`` from the committed run, or from a run now.

    Parameters
    ----------
    docs : pathlib.Path
        The documentation folder.

    Returns
    -------
    pathlib.Path
        The written page fragment.
    """
    out = docs / "benchmarks" / "_generated"
    out.mkdir(parents=True, exist_ok=True)
    live = os.environ.get("DTCRIT_DOCS_BENCH") == "1"
    data = run_benchmarks(out / "run") if live else docs / "benchmarks" / "data"
    page = out / "bench.md"
    if not (data / "bench.json").is_file():
        page.write_text("No benchmark run is committed: `python3 dev.py docs-bench` makes one "
                        "(or build with `DTCRIT_DOCS_BENCH=1`).\n")
        return page
    bench = json.loads((data / "bench.json").read_text())
    scale = (data / "scale.txt").read_text() if (data / "scale.txt").is_file() else None
    provenance = json.loads((data / "provenance.json").read_text()) if (data / "provenance.json").is_file() else None
    text = page_text(bench, scale, provenance, live)
    if not page.is_file() or page.read_text() != text:
        page.write_text(text)
    return page
