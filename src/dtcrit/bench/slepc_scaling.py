"""Scale measurements of the PETSc/SLEPc back-end beside the serial route (a benchmark, not a test).

    mpirun -n P .venv-mpi/bin/python -m dtcrit.bench.slepc_scaling N [KIND] [shell|assembled] [OPTIONS]
    .venv-mpi/bin/python -m dtcrit.bench.slepc_scaling N [KIND] serial
    .venv-mpi/bin/python -m dtcrit.bench.slepc_scaling compare N [KIND] [noassembled]

(``OPTIONS``: ``nosolve``, ``nostart``, ``tol=X``).  The first form runs one size in fresh processes (a process's peak memory is never given back, so
one size per launch) and rank 0 prints one JSON line: every rank's stage times (generating or
reading the packing, its slab's contacts, the operator -- assembly, or the shell's set-up --, the
solve, and for the shell the bounds) and its peak resident memory after each stage, the resident
memory before any work (interpreter, NumPy, SciPy, PETSc), the matrix's nonzeros, the solver's
restarts and products, PETSc's time per product and the answer (``omega2``, ``dt_crit``, ``dt_safe``
and the bracket).  ``shell`` (the default) is the matrix-free route (``slepc_shell``), ``assembled``
the ``MPISBAIJ`` matrix, each at its own default tolerance unless ``tol=X``; ``nostart`` starts the
shell's Krylov-Schur from SLEPc's random vector instead of the Chebyshev-filtered one.  The second form is the
serial matrix-free route in one process (contact search, LOBPCG from the Chebyshev start, the
Gershgorin and block-diagonal bounds), as ``dtcrit packing --route matrix-free`` runs it.

``compare`` runs them side by side in ONE invocation, each case in its own launch (this
interpreter; ``mpirun`` for the MPI cases): serial, SLEPc assembled at 1 and 2 ranks (its default
relative residual 1e-12, and 1e-6 on one rank: the serial route's), SLEPc shell at 1 and 2 ranks
(and on one rank from a random start);
``noassembled`` leaves the assembled cases out (at 10^6 FCC they take 16 min).  It prints a
Markdown table and the cases' JSON.  The MPI cases run unbound (``mpirun --bind-to none``): every
case has the machine's cores, a rank its share of them (``mpi_support.rank_threads``: both cores for
one rank, one each for two), as the serial route has them all.

Packings: ``fcc`` the jittered FCC lattice of ``dtcrit.bench.packing_scaling`` (coordination 12),
``random`` ``dtcrit.packing.generators.random_packing`` (coordination 6), or a dump file (density
2650 kg/m^3 when it has no mass column).  Linear springs ``k_n = k_s = 1``: the eigenvalue's value
is not the point, the cost is.  ``nosolve`` stops after the operator (the input and contact stages
of a large file without the long solve).
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time

from dtcrit.packing.distributed import mpi_support as mpi
from dtcrit.packing.distributed import slepc_analysis as sa
from dtcrit.packing.distributed import slepc_backend as sb


def _packing(n: int, kind: str):
    """The benchmark packing (module docstring)."""
    if kind == "fcc":
        from dtcrit.bench.packing_scaling import jittered_fcc

        return jittered_fcc(n)
    if kind == "random":
        from dtcrit.packing.generators.random_packing import random_packing

        return random_packing(n, cn=6.0, seed=1)
    from dtcrit.packing.readers.lammps_dump import read_dump

    try:
        return read_dump(kind)
    except ValueError:
        return read_dump(kind, density=2650.0)


def measure(n: int, kind: str = "fcc", solve: bool = True, matrix: str = "shell", tolerance: float | None = None,
            filtered_start: bool = True) -> dict:
    """One size on ``COMM_WORLD`` (collective): the figures of the module docstring.

    Parameters
    ----------
    n : int
        Number of particles.
    kind : str
        Packing kind (``"fcc"``).
    solve : bool
        Also solve for the largest mode.
    matrix : str
        ``"shell"`` or ``"assembled"``.
    tolerance : float or None
        Relative residual of the solve (default: the route's).
    filtered_start : bool
        The shell's Chebyshev-filtered start (``False``: SLEPc's random start).

    Returns
    -------
    dict
        The figures of the run.
    """
    from dtcrit.packing.model import LinearLaw

    _, rank, size = mpi.world()
    base = mpi.peak_mib()
    clock = time.perf_counter()
    packing = _packing(n, kind)
    share = sb.distribute(packing, LinearLaw(1.0, 1.0), t_input=time.perf_counter() - clock)
    del packing
    assert share.contacts is not None  # distribute always detects the contacts of its share
    mine = {"rank": rank, "contacts": share.contacts.count, "local_particles": int(share.glob.size)}
    if not solve:
        clock = time.perf_counter()
        sa.build_operator(share, matrix)[0].destroy()
        share.times["assembly"], share.peaks["assembly"] = time.perf_counter() - clock, mpi.peak_mib()
        keys = sorted(mine) + sorted(f"t_{k}" for k in share.times) + sorted(f"rss_{k}" for k in share.peaks)
        values = {**mine, **{f"t_{k}": v for k, v in share.times.items()}, **{f"rss_{k}": v for k, v in share.peaks.items()}}
        rows = mpi.allgather([values[k] for k in keys] + [base])
        return {"kind": kind, "ranks": size, "n_particles": share.n, "solve": False,
                "per_rank": [dict(zip(keys + ["rss_base"], map(float, row))) for row in rows]}
    r = sa.analyse_share(share, tolerance, matrix, filtered_start=filtered_start)
    mine.update({f"t_{k}": v for k, v in share.times.items()})
    mine.update({f"rss_{k}": v for k, v in share.peaks.items()})
    keys = sorted(mine)
    rows = mpi.allgather([mine[k] for k in keys] + [base])
    ranks = [dict(zip(keys + ["rss_base"], map(float, row))) for row in rows]
    return {"kind": kind, "ranks": size, "n_particles": r.n_particles, "n_contacts": r.n_contacts,
            "matrix_nonzeros": r.matrix_nonzeros, "iterations": r.iterations, "matvecs": r.matvecs,
            "matvec_seconds": r.matvec_seconds, "omega2": r.omega_max ** 2, "relative_residual": r.relative_residual,
            "matrix": r.matrix, "tolerance": r.tolerance, "ncv": r.ncv, "dt_crit": r.dt_crit, "dt_safe": r.dt_safe,
            "dt_bracket": r.dt_bracket, "times": r.times, "per_rank": ranks}


def serial(n: int, kind: str = "fcc") -> dict:
    """The serial matrix-free route in this process (module docstring): stage times, products, peak
    memory and the answer with its bracket.

    Parameters
    ----------
    n : int
        Number of particles.
    kind : str
        Packing kind.

    Returns
    -------
    dict
        The figures, keyed as ``measure``'s where they mean the same.
    """
    from dtcrit.packing.bounds import estimates as est
    from dtcrit.packing.bounds import rayleigh_trials as trials
    from dtcrit.packing.detection.overlaps import find_contacts
    from dtcrit.packing.model import LinearLaw, apply_law
    from dtcrit.packing.operators.assembly import mass_diagonal
    from dtcrit.packing.operators.matrix_free import stiffness_operator
    from dtcrit.packing.solvers.certificate import bracket
    from dtcrit.packing.solvers.largest_mode import largest_mode

    base = mpi.peak_mib()
    clock = time.perf_counter()
    packing = _packing(n, kind)
    times = {"input": time.perf_counter() - clock}
    clock = time.perf_counter()
    contacts = apply_law(find_contacts(packing), LinearLaw(1.0, 1.0))
    times["contacts"] = time.perf_counter() - clock
    clock = time.perf_counter()
    md = mass_diagonal(packing)
    op = stiffness_operator(packing, contacts, mass_diag=md)
    times["assembly"] = time.perf_counter() - clock

    def hint():  # as report.analyse: all particles co-rotating
        return trials.co_rotation(packing, 0) + trials.co_rotation(packing, 1) + trials.co_rotation(packing, 2)

    clock = time.perf_counter()
    top = largest_mode(op, "auto", hint=hint)
    times["solve"] = time.perf_counter() - clock
    clock = time.perf_counter()
    dt_safe = max(e.dt for e in (est.gershgorin(op, md), est.block_diagonal(op)) if e.dt is not None)
    times["bounds"] = time.perf_counter() - clock
    return {"kind": kind, "ranks": 1, "n_particles": packing.n, "n_contacts": contacts.count, "matrix": "serial",
            "solver": top.method, "tolerance": None, "matvecs": top.matvecs, "omega2": top.value,
            "relative_residual": top.residual / top.value, "dt_crit": 2.0 / top.omega, "dt_safe": dt_safe,
            "dt_bracket": bracket(top.value, dt_safe, None).to_dict(), "times": times,
            "per_rank": [{"rank": 0, "rss_base": base, "rss_solve": mpi.peak_mib()}]}


def _launch(cmd: list[str], env: dict) -> dict:
    """One case in its own processes; its JSON line, or the error."""
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("{")]
    if proc.returncode != 0 or not lines:
        return {"error": (proc.stderr or proc.stdout)[-2000:]}
    return json.loads(lines[-1])


CASES = (("serial", 1, "serial", None), ("SLEPc assembled", 1, "assembled", None),
         ("SLEPc assembled", 2, "assembled", None), ("SLEPc assembled, rtol 1e-6", 1, "assembled", 1e-6),
         ("SLEPc shell", 1, "shell", None), ("SLEPc shell", 2, "shell", None),
         ("SLEPc shell, random start", 1, "shell nostart", None))
"""The cases of ``compare``: (name, ranks, route and options, tolerance or ``None`` for the route's default)."""


def compare(n: int, kind: str = "fcc", assembled: bool = True, stream=sys.stdout) -> list[dict]:
    """Every case of ``CASES`` side by side (module docstring), each in fresh processes; a Markdown table
    on ``stream`` as the cases finish.

    Parameters
    ----------
    n : int
        Number of particles.
    kind : str
        Packing kind.
    assembled : bool
        Include the assembled cases.
    stream : file
        Where the table goes.

    Returns
    -------
    list of dict
        Each case's figures (``name`` added).
    """
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    env.setdefault("OMPI_MCA_mpi_yield_when_idle", "1")  # a waiting rank yields its core (a shared machine)
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    me = [sys.executable, "-m", "dtcrit.bench.slepc_scaling", str(n), kind]
    print("| route | ranks | rtol | total s | solve s | products | peak MiB per rank | omega^2 [1/s^2] | "
          "dt bracket [s] | relative residual |", file=stream)
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- | ---: |", file=stream, flush=True)
    out = []
    for name, ranks, route, tol in CASES:
        if route == "assembled" and not assembled:
            continue
        extra = route.split() + ([f"tol={tol:g}"] if tol else [])
        # unbound ranks: each takes its share of the cores (mpi_support.rank_threads), as the serial route
        # takes them all (Open MPI would bind one or two ranks to a core each)
        cmd = me + extra if route == "serial" else [shutil.which("mpirun") or "mpirun", "--oversubscribe", "--bind-to",
                                                          "none", "-n", str(ranks), *me, *extra]
        doc = dict(_launch(cmd, env), name=name)
        out.append(doc)
        if "error" in doc:
            print(f"| {name} | {ranks} | | failed: {doc['error'].splitlines()[-1] if doc['error'] else ''} |",
                  file=stream, flush=True)
            continue
        t = doc["times"]
        peak = max(max(v for k, v in r.items() if k.startswith("rss_")) for r in doc["per_rank"])
        b = doc["dt_bracket"]
        print(f"| {name} | {ranks} | {doc['tolerance'] or '1e-6 (LOBPCG)'} | "
              f"{sum(v for k, v in t.items() if k != 'input'):.3g} | {t['solve']:.3g} | {doc['matvecs']} | {peak:.0f} | "
              f"{doc['omega2']:.12g} | [{b['lower']:.6g}, {b['upper']:.10g}] | {doc['relative_residual']:.2g} |",
              file=stream, flush=True)
    return out


def main(argv: list[str]) -> int:
    """Command line (module docstring); rank 0 prints the figures as JSON (``compare``: the table, then
    one JSON line per case).

    Parameters
    ----------
    argv : list of str
        Arguments.

    Returns
    -------
    int
        Exit status, 0.
    """
    if argv and argv[0] == "compare":
        docs = compare(int(float(argv[1])), argv[2] if len(argv) > 2 else "fcc", "noassembled" not in argv[3:])
        for doc in docs:
            print(json.dumps(doc))
        return 0
    n = int(float(argv[0]))
    kind = argv[1] if len(argv) > 1 else "fcc"
    if "serial" in argv[2:]:
        print(json.dumps(serial(n, kind)))
        return 0
    tol = next((float(a[4:]) for a in argv[2:] if a.startswith("tol=")), None)
    matrix = "assembled" if "assembled" in argv[2:] else "shell"
    doc = measure(n, kind, solve="nosolve" not in argv[2:], matrix=matrix, tolerance=tol,
                  filtered_start="nostart" not in argv[2:])
    _, rank, _ = mpi.world()
    if rank == 0:
        print(json.dumps(doc))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
