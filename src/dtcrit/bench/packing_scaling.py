"""Scale benchmark of the global analysis (a benchmark, not a test).

``python -m dtcrit.bench.packing_scaling 1e3,1e4,1e5`` (or ``dtcrit packing --scale 1e3,1e4,1e5``) runs
each size in a fresh Python process (so that the peak memory of one size is not inherited by the
next) and prints a table: time for generating the packing, finding contacts, assembling ``K``,
the eigen-solve and the estimates, wall-clock and CPU time, peak resident memory, and, where
``6N`` is small enough, the relative difference of ``omega_max`` from dense ``scipy.linalg.eigh``.
Each size runs by the matrix-free route (``dtcrit.packing.operators.matrix_free``) and, up to ``ASSEMBLED_MAX``
spheres, also by the assembled route in the same run, with the ratios printed; the matrix-free rows
add ``floor x``, the eigen-solve time over a memory-bandwidth floor (one pass over the contact
arrays per operator application at the measured copy bandwidth).  The growth exponent ``b`` of
``time ~ N^b`` is fitted per route over the sizes with ``N >= 10^4``.

Packings: ``"fcc"`` (default) is a periodic FCC lattice compressed by 0.2 % in radius and
jittered by 5e-4 radii so every sphere keeps its 12 contacts but the contact normals are
disordered (coordination 12: the densest sparsity pattern of the study, so the harshest case for
memory); ``"random"`` uses ``dtcrit.packing.generators.random_packing`` (coordination 6).
"""
from __future__ import annotations

import json
import math
import os
import resource
import subprocess
import sys
import time

import numpy as np

DENSE_CHECK_DOFS = 6000


def jittered_fcc(n_target: int, seed: int = 0):
    """An FCC lattice of about ``n_target`` unit spheres, positions jittered by up to 5e-4 (seeded).

    Parameters
    ----------
    n_target : int
        Wanted number of particles (the cube of cells nearest to it is used).
    seed : int
        Seed of the jitter.

    Returns
    -------
    dtcrit.packing.model.Packing
        The packing, radius 1.002 so neighbours overlap.
    """
    from dtcrit.packing.generators.lattices import lattice_positions
    from dtcrit.packing.model import Packing

    cells = max(1, round((n_target / 4.0) ** (1.0 / 3.0)))
    x, box = lattice_positions("fcc", cells, 1.0)
    rng = np.random.default_rng(seed)
    x = x + rng.uniform(-5e-4, 5e-4, x.shape)
    return Packing.spheres(x, 1.002, density=1.0, box=box, label=f"jittered FCC, {cells}^3 cells")


def memory_bandwidth(megabytes: int = 128) -> float:
    """Bytes per second of a large array copy (read + write), best of three: the floor's rate.

    Parameters
    ----------
    megabytes : int
        Size of the array copied.

    Returns
    -------
    float
        Bytes per second.
    """
    a = np.ones(megabytes * (1 << 20) // 8)
    b = np.empty_like(a)
    best = math.inf
    for _ in range(3):
        t = time.perf_counter()
        np.copyto(b, a)
        best = min(best, time.perf_counter() - t)
    return 2.0 * a.nbytes / best


def run_one(n: int, packing_kind: str = "fcc", method: str = "auto", dense_check: bool = True,
            route: str = "assembled", search_floor: bool = True) -> dict:
    """Time every stage for one size in this process; returns a dict of figures.  ``route``:
    ``"assembled"`` (sparse ``K``, the route before the matrix-free operator) or ``"matrix-free"``
    (``dtcrit.packing.operators.matrix_free``; its bandwidth floor is also reported).

    Parameters
    ----------
    n : int
        Number of particles.
    packing_kind : str
        ``"fcc"`` (jittered lattice) or ``"random"``.
    method : str
        Eigen-solver of the largest mode.
    dense_check : bool
        Also compare with a dense eigen-solve where small enough.
    route : str
        ``"assembled"`` or ``"matrix-free"``.
    search_floor : bool
        Time SciPy's pair search alone for the search stage's floor (``stage_floors``).

    Returns
    -------
    dict
        Timings, memory and solver figures of the run.
    """
    from dtcrit.packing.operators.assembly import mass_diagonal, scale_symmetric, stiffness_matrix
    from dtcrit.packing.detection.overlaps import find_sphere_contacts
    from dtcrit.packing.solvers.largest_mode import largest_mode
    from dtcrit.packing.bounds import estimates as est
    from dtcrit.packing.bounds import rayleigh_trials as trials
    from dtcrit.packing.model import LinearLaw, apply_law
    from dtcrit.packing.generators.random_packing import random_packing

    out: dict = {"n_target": n, "packing": packing_kind}
    clock, cpu = time.perf_counter(), time.process_time()
    packing = jittered_fcc(n) if packing_kind == "fcc" else random_packing(n, cn=6.0, seed=1)
    out["t_generate"] = time.perf_counter() - clock
    peaks = {"generate": _peak_mib()}
    t0, c0 = time.perf_counter(), time.process_time()
    contacts = apply_law(find_sphere_contacts(packing), LinearLaw(1.0, 1.0))
    t1 = time.perf_counter()
    peaks["search"] = _peak_mib()
    if route == "matrix-free":  # the operator holds its scale, not M: no mass diagonal held through the solve
        from dtcrit.packing.operators.matrix_free import stiffness_operator

        a = stiffness_operator(packing, contacts)
    else:
        a = scale_symmetric(stiffness_matrix(packing, contacts), mass_diagonal(packing), inplace=True)
    t2 = time.perf_counter()
    peaks["operator"] = _peak_mib()
    def hint():  # all particles co-rotating: built inside the solver, released after its start
        return trials.co_rotation(packing, 0) + trials.co_rotation(packing, 1) + trials.co_rotation(packing, 2)

    top = largest_mode(a, method, hint=hint)
    t3 = time.perf_counter()
    peaks["eigen"] = _peak_mib()
    before = getattr(a, "applications", 0)
    md = mass_diagonal(packing)
    w_c = est.single_contact_frequencies(packing, contacts)
    estimates = (est.gershgorin(a, md), est.block_diagonal(a), est.diagonal_stiffness(a), est.two_particle_amax(packing, contacts),
                 est.two_particle_exact(packing, contacts, w_c), trials.rayleigh(a, packing, contacts, w_c))
    t4 = time.perf_counter()
    peaks["bounds"] = _peak_mib()
    out.update(
        route=route, n=packing.n, dofs=packing.dofs, contacts=contacts.count, nnz=int(getattr(a, "nnz", 0)),
        t_contacts=t1 - t0, t_assembly=t2 - t1, t_eigen=t3 - t2, t_estimates=t4 - t3,
        t_analysis=t4 - t0, cpu_analysis=time.process_time() - c0, cpu_total=time.process_time() - cpu,
        omega2=top.value, method=top.method, matvecs=top.matvecs, residual=top.residual,
        estimates={e.name: e.omega2 for e in estimates}, peak_after_mib=peaks,
        bounds_products=getattr(a, "applications", 0) - before,
    )
    out["peak_rss_mib"] = _peak_mib()
    if route == "matrix-free":  # after the peak is read: the probe's arrays are not the analysis's
        out.update(stage_floors(a, packing, top.matvecs, out["bounds_products"], search_floor))
        floors = out["floor_s_by_stage"]
        out["floor_ratio_by_stage"] = {"search": (t1 - t0) / floors["search"], "eigen": (t3 - t2) / floors["eigen"],
                                       "bounds": (t4 - t3) / floors["bounds"]}
        out["floor_ratio"] = out["floor_ratio_by_stage"]["eigen"]
        out["floor_s"] = floors["eigen"]
        out["memory_floor_ratio"] = out["peak_rss_mib"] * 2.0 ** 20 / out["memory_floor_bytes"]
    if dense_check and packing.dofs <= DENSE_CHECK_DOFS:
        dense = largest_mode(a, "dense")
        out["dense_rel_diff"] = abs(top.value - dense.value) / dense.value
    return out


def _peak_mib() -> float:
    """Peak resident memory of this process so far [MiB] (``ru_maxrss``)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def stage_floors(a, packing, matvecs: int, bounds_products: int, search: bool = True) -> dict:
    """What each stage of the matrix-free analysis cannot go below on this machine.

    * eigen-solve: one pass over the contact arrays a product reads per product, at the measured
      copy bandwidth (``memory_bandwidth``);
    * bounds: the same for their products plus two passes (the particle pass of the diagonal blocks
      and row sums, ``particle_pass``, and the single-contact frequencies);
    * search: SciPy's pair search alone, ``cKDTree(...).query_pairs`` of the same spheres (built and
      queried again here when ``search``; the contact test and the fields are not in it);
    * memory: the contact arrays a product reads plus ``LEAN_NCV + 5`` vectors of ``6N`` (the lean
      ARPACK basis, its three work vectors, its residual and the product's output).

    Parameters
    ----------
    a : dtcrit.packing.operators.matrix_free.ContactOperator
        The operator of the run.
    packing : dtcrit.packing.model.Packing
        The spheres.
    matvecs, bounds_products : int
        Products of the eigen-solve and of the bounds.
    search : bool
        Time the pair search (else its floor is NaN).

    Returns
    -------
    dict
        ``bandwidth_gbs``, ``contact_bytes``, ``floor_s_by_stage`` [s] and ``memory_floor_bytes``.
    """
    from scipy.spatial import cKDTree

    from dtcrit.packing.detection.overlaps import _search_frame, wrap_positions
    from dtcrit.packing.solvers.largest_mode import LEAN_NCV

    rate = memory_bandwidth()
    per_pass = a.memory_bytes() / rate
    floors = {"eigen": matvecs * per_pass, "bounds": (bounds_products + 2) * per_pass, "search": math.nan}
    if search:
        x = wrap_positions(packing.positions, packing.box)
        cutoff = 2.0 * float(packing.radii.max()) * (1.0 + 1e-9)
        y, size = _search_frame(x, cutoff, packing.box)
        if y is not None:
            clock = time.perf_counter()
            cKDTree(y, boxsize=size).query_pairs(cutoff, output_type="ndarray")
            floors["search"] = time.perf_counter() - clock
    return {"bandwidth_gbs": rate / 1e9, "contact_bytes": a.memory_bytes(), "floor_s_by_stage": floors,
            "memory_floor_bytes": a.memory_bytes() + (LEAN_NCV + 5) * 8 * a.shape[0]}


ASSEMBLED_MAX = 200_000
"""Sizes up to which ``run_sizes`` also runs the assembled route, side by side (it needs about
7 GiB at 1e6 spheres)."""


def run_sizes(sizes, packing_kind: str = "fcc", method: str = "auto", stream=sys.stdout,
              routes=("assembled", "matrix-free")) -> list[dict]:
    """Each size and route in a fresh interpreter; prints a table as results arrive, then the
    matrix-free/assembled ratios of each size run both ways and the growth exponents.

    Parameters
    ----------
    sizes : sequence of int
        Numbers of particles.
    packing_kind : str
        ``"fcc"`` or ``"random"``.
    method : str
        Eigen-solver of the largest mode.
    stream : file-like
        Where the table is printed.
    routes : sequence of str
        Routes run for each size.

    Returns
    -------
    list of dict
        The figures of every run.
    """
    rows = []
    header = (f"{'N':>9} {'route':>11} {'DOFs':>9} {'contacts':>9} {'gen s':>7} {'assemble s':>10} {'eigen s':>8} "
              f"{'estim s':>8} {'analysis s':>10} {'cpu s':>7} {'peak MiB':>9} {'solver':>7} {'matvecs':>7} "
              f"{'vs dense':>9} {'floor x':>8}")
    print(header, file=stream, flush=True)
    jobs = [(n, r) for n in sizes for r in routes if r == "matrix-free" or n <= ASSEMBLED_MAX]
    for n, route in jobs:
        cmd = [sys.executable, "-m", "dtcrit.bench.packing_scaling", "--one", str(int(n)), "--packing", packing_kind,
               "--method", method, "--route", route]
        # one BLAS thread: ARPACK's small dense steps gain nothing from threads, and oversubscribed
        # OpenBLAS threads on a busy 2-core machine slow them down by an order of magnitude
        env = dict(os.environ, DTCRIT_PROGRESS="0", OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
        done = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if done.returncode != 0:
            print(f"{int(n):>9} failed: {done.stderr.strip().splitlines()[-1] if done.stderr.strip() else done.returncode}",
                  file=stream, flush=True)
            continue
        r = json.loads(done.stdout.strip().splitlines()[-1])
        rows.append(r)
        dense = f"{r['dense_rel_diff']:.1e}" if "dense_rel_diff" in r else "-"
        floor = f"{r['floor_ratio']:.1f}" if "floor_ratio" in r else "-"
        print(f"{r['n']:>9} {route:>11} {r['dofs']:>9} {r['contacts']:>9} {r['t_generate']:>7.2f} "
              f"{r['t_assembly']:>10.2f} {r['t_eigen']:>8.2f} {r['t_estimates']:>8.2f} {r['t_analysis']:>10.2f} "
              f"{r['cpu_analysis']:>7.1f} {r['peak_rss_mib']:>9.0f} {r['method']:>7} {r['matvecs']:>7} {dense:>9} "
              f"{floor:>8}", file=stream, flush=True)
    for r in rows:
        if "floor_ratio_by_stage" in r:
            print(stage_line(r), file=stream, flush=True)
    for n in sizes:
        pair = {r["route"]: r for r in rows if r["n_target"] == n}
        if len(pair) == 2:
            old, new = pair["assembled"], pair["matrix-free"]
            print(f"N = {new['n']}: matrix-free {old['t_analysis'] / new['t_analysis']:.2f}x faster, "
                  f"{new['peak_rss_mib'] / old['peak_rss_mib']:.2f}x the peak memory, omega^2 relative difference "
                  f"{abs(new['omega2'] - old['omega2']) / old['omega2']:.1e}", file=stream, flush=True)
    for route in routes:
        big = [r for r in rows if r["n"] >= 10_000 and r["route"] == route]
        if len(big) >= 2:
            ns = [r["n"] for r in big]
            b = fit_exponent(ns, [r["t_analysis"] for r in big])
            c = fit_exponent(ns, [r["cpu_analysis"] for r in big])
            print(f"{route}: fitted growth of the analysis time (sizes {min(ns)}..{max(ns)}): wall ~ N^{b:.2f}, "
                  f"CPU ~ N^{c:.2f}", file=stream, flush=True)
    return rows


def stage_line(r: dict) -> str:
    """One line of where a matrix-free run's time and memory went, stage by stage, with each stage's
    time over its floor (``stage_floors``) and the peak memory over the memory floor.

    Parameters
    ----------
    r : dict
        A matrix-free row of ``run_one``.

    Returns
    -------
    str
        The line.
    """
    ratio, peak = r["floor_ratio_by_stage"], r["peak_after_mib"]
    parts = [f"search {r['t_contacts']:.1f} s ({ratio['search']:.1f}x floor, peak {peak['search'] / 1024:.2f} GiB)",
             f"operator {r['t_assembly']:.1f} s (peak {peak['operator'] / 1024:.2f} GiB)",
             f"eigen-solve {r['t_eigen']:.1f} s ({ratio['eigen']:.1f}x floor, {r['matvecs']} products, "
             f"peak {peak['eigen'] / 1024:.2f} GiB)",
             f"bounds {r['t_estimates']:.1f} s ({ratio['bounds']:.1f}x floor, {r['bounds_products']} products, "
             f"peak {peak['bounds'] / 1024:.2f} GiB)"]
    return (f"N = {r['n']} stages: " + "; ".join(parts) + f"; memory {r['memory_floor_ratio']:.2f}x its floor "
            f"({r['memory_floor_bytes'] / 2 ** 30:.2f} GiB)")


def fit_exponent(ns, ts) -> float:
    """Least-squares slope of ``log t`` against ``log N``.

    Parameters
    ----------
    ns : array_like
        Sizes.
    ts : array_like
        Times [s].

    Returns
    -------
    float
        The growth exponent.
    """
    x, y = np.log(np.asarray(ns, float)), np.log(np.asarray(ts, float))
    return float(np.polyfit(x, y, 1)[0])


def parse_sizes(text: str) -> list[int]:
    """The sizes of a comma-separated list such as ``1e3,1e4``, each in [2, 5e7].

    Parameters
    ----------
    text : str
        The list.

    Returns
    -------
    list of int
        The sizes.

    Raises
    ------
    InputError
        When an entry is no number or out of range.
    """
    from dtcrit.errors import InputError

    sizes = []
    for part in str(text).split(","):
        try:
            value = float(part)
        except ValueError:
            raise InputError("scale", f"sizes must be numbers like 1e3,1e4, got {part!r}") from None
        if not math.isfinite(value) or value < 2 or value > 5e7:
            raise InputError("scale", f"each size must lie in [2, 5e7], got {part!r}")
        sizes.append(int(value))
    return sizes


def main(argv=None) -> int:
    """Command line: time the packing analysis at each size (``--one N`` runs a single size in this process).

    Parameters
    ----------
    argv : list of str, optional
        Arguments (``sys.argv[1:]`` when omitted).

    Returns
    -------
    int
        Exit status.
    """
    import argparse

    parser = argparse.ArgumentParser(prog="python -m dtcrit.bench.packing_scaling")
    parser.add_argument("sizes", nargs="?", default="1e3,1e4,1e5")
    parser.add_argument("--one", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--packing", choices=("fcc", "random"), default="fcc")
    parser.add_argument("--method", default="auto")
    parser.add_argument("--route", choices=("assembled", "matrix-free"), default="assembled")
    args = parser.parse_args(argv)
    if args.one:
        print(json.dumps(run_one(args.one, args.packing, args.method, route=args.route)))
        return 0
    run_sizes(parse_sizes(args.sizes), args.packing, args.method)
    return 0


if __name__ == "__main__":
    sys.exit(main())
