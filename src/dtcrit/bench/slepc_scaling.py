"""Scale measurements of the PETSc/SLEPc back-end (a benchmark, not a test).

    mpirun -n P .venv-mpi/bin/python -m dtcrit.bench.slepc_scaling N [fcc|random|FILE.dump] [nosolve]

runs one size in fresh processes (a process's peak memory is never given back, so one size per
launch) and rank 0 prints one JSON line: every rank's stage times (generating or reading the
packing, its slab's contacts, assembly, solve) and its peak resident memory after each stage, the
resident memory before any work (interpreter, NumPy, SciPy, PETSc), the matrix's nonzeros, the
solver's restarts and products and PETSc's time per product.  Packings: ``fcc`` the jittered FCC
lattice of ``dtcrit.bench.packing_scaling`` (coordination 12), ``random`` ``dtcrit.packing.generators.random_packing``
(coordination 6), or a dump file (density 2650 kg/m^3 when it has no mass column).  Linear springs
``k_n = k_s = 1``: the eigenvalue's value is not the point, the cost is.  ``nosolve`` stops after the
assembly (the input and contact stages of a large file without the long solve).
"""
from __future__ import annotations

import json
import sys
import time

from dtcrit.packing.distributed import mpi_support as mpi
from dtcrit.packing.distributed import slepc_backend as sb


def measure(n: int, kind: str = "fcc", solve: bool = True) -> dict:
    """One size on ``COMM_WORLD`` (collective): the figures of the module docstring.

    Parameters
    ----------
    n : int
        Number of particles.
    kind : str
        Packing kind (``"fcc"``).
    solve : bool
        Also solve for the largest mode.

    Returns
    -------
    dict
        The figures of the run.
    """
    from dtcrit.packing.model import LinearLaw

    _, rank, size = mpi.world()
    base = mpi.peak_mib()
    clock = time.perf_counter()
    if kind == "fcc":
        from dtcrit.bench.packing_scaling import jittered_fcc

        packing = jittered_fcc(n)
    elif kind == "random":
        from dtcrit.packing.generators.random_packing import random_packing

        packing = random_packing(n, cn=6.0, seed=1)
    else:
        from dtcrit.packing.readers.lammps_dump import read_dump

        try:
            packing = read_dump(kind)
        except ValueError:
            packing = read_dump(kind, density=2650.0)
    share = sb.distribute(packing, LinearLaw(1.0, 1.0), t_input=time.perf_counter() - clock)
    del packing
    assert share.contacts is not None  # distribute always detects the contacts of its share
    mine = {"rank": rank, "contacts": share.contacts.count, "local_particles": int(share.glob.size)}
    if not solve:
        clock = time.perf_counter()
        sb.assemble(share).destroy()
        share.times["assembly"], share.peaks["assembly"] = time.perf_counter() - clock, mpi.peak_mib()
        keys = sorted(mine) + sorted(f"t_{k}" for k in share.times) + sorted(f"rss_{k}" for k in share.peaks)
        values = {**mine, **{f"t_{k}": v for k, v in share.times.items()}, **{f"rss_{k}": v for k, v in share.peaks.items()}}
        rows = mpi.allgather([values[k] for k in keys] + [base])
        return {"kind": kind, "ranks": size, "n_particles": share.n, "solve": False,
                "per_rank": [dict(zip(keys + ["rss_base"], map(float, row))) for row in rows]}
    r = sb.analyse_share(share)
    mine.update({f"t_{k}": v for k, v in share.times.items()})
    mine.update({f"rss_{k}": v for k, v in share.peaks.items()})
    keys = sorted(mine)
    rows = mpi.allgather([mine[k] for k in keys] + [base])
    ranks = [dict(zip(keys + ["rss_base"], map(float, row))) for row in rows]
    return {"kind": kind, "ranks": size, "n_particles": r.n_particles, "n_contacts": r.n_contacts,
            "matrix_nonzeros": r.matrix_nonzeros, "iterations": r.iterations, "matvecs": r.matvecs,
            "matvec_seconds": r.matvec_seconds, "omega2": r.omega_max ** 2, "relative_residual": r.relative_residual,
            "per_rank": ranks}


def main(argv: list[str]) -> int:
    """Command line under MPI: ``N [KIND] [nosolve]``; rank 0 prints the figures as JSON.

    Parameters
    ----------
    argv : list of str
        Arguments.

    Returns
    -------
    int
        Exit status, 0.
    """
    n = int(float(argv[0]))
    doc = measure(n, argv[1] if len(argv) > 1 else "fcc", solve="nosolve" not in argv[2:])
    _, rank, _ = mpi.world()
    if rank == 0:
        print(json.dumps(doc))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
