"""``dtcrit packing``: global eigenmode analysis of a packing (Otsubo et al. 2017).

    dtcrit packing FILE [--density RHO]                    a LAMMPS / LIGGGHTS dump file
    dtcrit packing BODIES.json                             non-spherical bodies (dtcrit-bodies/1)
    dtcrit packing --lattice fcc --cells 4 [--radius R]    a periodic lattice
    dtcrit packing --random 500 --cn 6 [--sizes lognormal --spread 0.3] [--seed 1]
    dtcrit packing --scale 1e3,1e4,1e5                     the scale benchmark (table)
    mpirun -n P .venv-mpi/bin/dtcrit packing ... --backend slepc   PETSc/SLEPc on P processes

Contact law (required: the step scales with it): ``--kn/--ks`` linear springs (``--ks`` defaults to
``--kn``) or ``--youngs/--poisson`` for Hertz-Mindlin tangent stiffness at each contact's overlap.
A FILE whose first character is ``{`` is a bodies file (``dtcrit.packing.readers.bodies_file``); its own
``contacts`` list, when given, replaces the command-line law.

``--backend slepc`` (``dtcrit.packing.distributed.slepc_backend``) finds ``omega_max`` with PETSc and SLEPc on the
processes of an MPI launcher (one process without a launcher is a one-rank run); it needs petsc4py and
slepc4py (the environment ``.venv-mpi`` of ``python3 dev.py mpi-env``), else one line says what to
install (exit 2).  ``--petsc-indices`` chooses the width of PETSc's indices (auto: Debian's 64-bit-index
build when ``6 N > 2^31 - 1``; ``dtcrit.packing.distributed.petsc_build``).  It reports ``omega_max``,
``dt_crit``, the Gershgorin lower bound and the solver's figures, not the serial report's estimates and
certificate.  Only rank 0 prints.
"""
from __future__ import annotations

import json
import os
import sys
import time

from dtcrit.errors import InputError
from dtcrit.packing.defaults import DEFAULT_DENSITY, DEFAULT_RADIUS


def add_parser(subparsers) -> None:
    """Add the ``dtcrit packing`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = subparsers.add_parser(
        "packing", help="critical time step of a whole packing from its largest eigenfrequency",
        description="Global eigenmode analysis of a DEM packing (Otsubo, O'Sullivan & Shire 2017): "
                    "dt_crit = 2/omega_max beside the cheap estimates.")
    p.add_argument("file", nargs="?", help="LAMMPS/LIGGGHTS text dump (ITEM: ATOMS id type x y z radius [mass]), "
                                           "or a dtcrit-bodies/1 JSON file of non-spherical bodies")
    src = p.add_argument_group("generated packings")
    src.add_argument("--lattice", choices=("sc", "bcc", "fcc", "hcp"), help="periodic lattice")
    src.add_argument("--cells", type=int, default=2, help="lattice cells along each axis (default 2)")
    src.add_argument("--random", type=int, metavar="N", help="random packing of N spheres")
    src.add_argument("--cn", type=float, default=6.0, help="target mean coordination of --random (default 6)")
    src.add_argument("--sizes", choices=("mono", "uniform", "lognormal"), default="mono")
    src.add_argument("--spread", type=float, default=0.0,
                     help="uniform: half-width / radius; lognormal: sigma of ln R (default 0)")
    src.add_argument("--seed", type=int, default=0)
    src.add_argument("--radius", type=float, default=DEFAULT_RADIUS, help="sphere (median) radius [m]")
    mat = p.add_argument_group("material and contacts")
    mat.add_argument("--density", type=float, help=f"particle density [kg/m^3] (generated default {DEFAULT_DENSITY:g}; "
                                                   "required for a dump without a mass column)")
    mat.add_argument("--kn", type=float, help="normal spring stiffness [N/m] (this or --youngs is required)")
    mat.add_argument("--ks", type=float, help="tangential spring stiffness [N/m] (default: equal to kn)")
    mat.add_argument("--youngs", type=float, help="Young's modulus [Pa]: Hertz-Mindlin tangent stiffness instead")
    mat.add_argument("--poisson", type=float, default=0.25, help="Poisson's ratio with --youngs (default 0.25)")
    mat.add_argument("--snapshot", type=int, default=-1, help="snapshot index in the dump (default: last)")
    run = p.add_argument_group("analysis")
    run.add_argument("--integrator", default="velocity-verlet", help="integrator for the damped bound (default velocity-verlet)")
    run.add_argument("--damping-ratio", type=float, default=0.0, help="modal damping ratio of the highest mode")
    run.add_argument("--solver", choices=("auto", "dense", "eigsh", "lobpcg"), default="auto")
    run.add_argument("--route", choices=("auto", "assembled", "matrix-free"), default="auto",
                     help="assembled sparse K, or K applied matrix-free from the contact list (auto: by size)")
    run.add_argument("--certify", choices=("auto", "yes", "no"), default="auto",
                     help="certify that no mode lies above omega_max^2 (1 + 1e-6) by an LDL^T inertia count "
                          "(auto: when it costs at most a few eigen-solves, about 3k DOFs of FCC; yes: up to 1e5 "
                          "DOFs, with a time estimate)")
    run.add_argument("--json", action="store_true", help="print the report as JSON")
    run.add_argument("--write-dump", metavar="PATH", help="also write the analysed sphere packing as a dump file")
    run.add_argument("--scale", metavar="SIZES", help="run the scale benchmark, e.g. 1e3,1e4,1e5")
    run.add_argument("--scale-packing", choices=("fcc", "random"), default="fcc")
    run.add_argument("--backend", choices=("serial", "slepc"), default="serial",
                     help="serial (this process), or slepc: PETSc/SLEPc Krylov-Schur on the processes of "
                          "mpirun -n P .venv-mpi/bin/dtcrit packing ... (python3 dev.py mpi-env builds .venv-mpi)")
    run.add_argument("--partitioned-read", action="store_true", default=None,
                     help="with --backend slepc: each rank reads only its piece of the dump FILE and keeps its "
                          "Morton slab (automatic for a .npz sphere file)")
    run.add_argument("--slepc-matrix", choices=("shell", "assembled"), default=None,
                     help="with --backend slepc: shell (default: matrix-free, the contact kernel on each rank's "
                          "contacts) or assembled (PETSc MPISBAIJ)")
    run.add_argument("--petsc-indices", choices=("auto", "32", "64"), default=None,
                     help="with --backend slepc: the width of PETSc's indices. 32: Debian's python3-petsc4py-real "
                          "build, at most 2^31 - 1 DOFs (357,913,941 particles); 64: its python3-petsc4py-64-real "
                          "and python3-slepc4py-64-real build (python3 dev.py mpi-env installs and records them); "
                          "auto (default): 64 only when 6 N > 2^31 - 1")
    p.set_defaults(run=run_command)


FLAGS = {"cells": "--cells", "n": "--random", "radius": "--radius", "kn": "--kn", "ks": "--ks",
         "youngs": "--youngs", "poisson": "--poisson", "density": "--density", "cn": "--cn", "spread": "--spread",
         "sizes": "--sizes", "seed": "--seed", "integrator": "--integrator", "damping_ratio": "--damping-ratio",
         "damping-ratio": "--damping-ratio", "method": "--solver", "route": "--route", "snapshot": "--snapshot",
         "lattice": "--lattice", "scale": "--scale", "random": "--random", "write_dump": "--write-dump",
         "slepc_matrix": "--slepc-matrix", "petsc_indices": "--petsc-indices"}
"""Library keys (``InputError.key``) and the flags of ``dtcrit packing`` that set them."""


def _source(args) -> str:
    """The flag or FILE that gave the packing."""
    return "--cells" if args.lattice is not None else "--random" if args.random is not None else str(args.file)


def flag_of(key: str, args) -> str | None:
    """The flag (or ``FILE:key``) to name for a library ``InputError`` key.

    Parameters
    ----------
    key : str
        The ``InputError.key`` the API raised (a parameter name, a file key).
    args : argparse.Namespace
        The parsed flags (which flags gave the packing and the law).

    Returns
    -------
    str or None
        The flag, or None to keep the key as it is.
    """
    if key.startswith("-") or ":" in key:
        return None
    if key == "stiffness":
        return "--youngs" if args.youngs is not None else "--kn" if args.kn is not None else f"{args.file}:contacts"
    if key in ("box", "positions", "mass"):
        return f"{args.file}:{key}" if args.file is not None else "--radius"
    return FLAGS.get(key)


def run_command(args) -> int:
    """Run ``dtcrit packing`` with the library's errors as one line each.

    Library keys become the flags that set them; a solver that stops early, or memory that runs out
    after all, is one line too (``dtcrit.cli.library_errors``).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    int
        The exit status.
    """
    from dtcrit.cli.library_errors import run_naming_flags

    return run_naming_flags(_run, args, args.file, flag_of,
                            lambda exc: f"--solver: {exc} (another --solver may converge)",
                            f"{_source(args)}: ran out of memory (the estimate said it fits: another process may "
                            "have taken memory, or the packing is denser than modelled); try a smaller packing, "
                            "--route matrix-free or --certify no")


def _packing_options(args) -> dict:
    """The keyword arguments of ``packing_step`` the flags give."""
    return {"lattice": args.lattice, "cells": args.cells, "random": args.random, "cn": args.cn, "sizes": args.sizes,
            "spread": args.spread, "seed": args.seed, "radius": args.radius, "density": args.density, "kn": args.kn,
            "ks": args.ks, "youngs": args.youngs, "poisson": args.poisson, "snapshot": args.snapshot,
            "integrator": args.integrator, "damping_ratio": args.damping_ratio}


def _run(args) -> int:
    if args.backend == "slepc":
        return _run_slepc(args)
    if args.partitioned_read:
        raise ValueError("partitioned-read: reads a FILE in pieces for --backend slepc only")
    if args.slepc_matrix is not None:
        raise InputError("--slepc-matrix", "only with --backend slepc (the serial backend chooses with --route)")
    if args.petsc_indices is not None:
        raise InputError("--petsc-indices", "only with --backend slepc (the serial backend does not use PETSc)")
    if args.scale:
        from dtcrit.bench.packing_scaling import parse_sizes, run_sizes

        run_sizes(parse_sizes(args.scale), args.scale_packing)
        return 0
    from dtcrit.packing.step import packing_step

    if args.write_dump:
        from dtcrit.cli.outputs import check_output_file

        check_output_file(args.write_dump, "--write-dump")
    step = packing_step(args.file, **_packing_options(args), solver=args.solver, route=args.route,
                        certify=args.certify, write_dump=args.write_dump)
    if args.json:
        json.dump(step.to_json(), sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print(step.to_text())
    return 0


SLEPC_UNUSED = (("--scale", "scale", None), ("--write-dump", "write_dump", None), ("--solver", "solver", "auto"),
                ("--route", "route", "auto"), ("--certify", "certify", "auto"))
LAUNCHER_RANK = ("OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK")
QUIET_EXIT_DELAY = 1.0
"""Seconds a silent rank waits before exiting on bad input: the launcher stops the whole job when a
rank exits with status 2, and rank 0 is then still writing the one line."""


def _run_slepc(args) -> int:
    """``--backend slepc``: every rank builds the packing and its share of the contacts; rank 0 prints.
    Bad input is one line from rank 0 (the same on every rank) or from the lowest rank that met it
    alone (``slepc_backend.agree``); the other ranks exit with status 2 silently.
    """
    try:  # no MPI here: the API reads the input, then chooses the PETSc build (petsc_build) and starts MPI
        return _slepc_report(args)
    except (ValueError, SystemExit) as exc:
        if isinstance(exc, SystemExit) or (_rank() != 0 and not getattr(exc, "report_here", False)):
            time.sleep(QUIET_EXIT_DELAY)
            raise SystemExit(2) from None
        raise


def _rank() -> int:
    """The process's rank: MPI's once petsc4py has started it (``mpi_support.started_rank``), else the
    launcher's environment (``LAUNCHER_RANK``; 0 without one), before MPI starts.
    """
    from dtcrit.packing.distributed.mpi_support import started_rank

    rank = started_rank()
    if rank is not None:
        return rank
    return int(next((os.environ[k] for k in LAUNCHER_RANK if os.environ.get(k, "").isdigit()), "0"))


def _slepc_report(args) -> int:
    from dtcrit.packing.distributed.step import distributed_packing_step

    for flag, key, default in SLEPC_UNUSED:
        if getattr(args, key) != default:
            raise ValueError(f"{flag[2:]}: not used with --backend slepc (it reports omega_max, dt_crit and "
                             "dt_safe; the serial backend has the estimates, routes and certificate)")
    step = distributed_packing_step(args.file, **_packing_options(args), partitioned=args.partitioned_read,
                                    matrix=args.slepc_matrix or "shell", petsc_indices=args.petsc_indices or "auto")
    if step.rank != 0:
        return 0
    if args.json:
        json.dump(step.to_json(), sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print(step.to_text())
    return 0
