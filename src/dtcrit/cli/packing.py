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
install (exit 2).  It reports ``omega_max``, ``dt_crit``, the Gershgorin lower bound and the solver's
figures, not the serial report's estimates and certificate.  Only rank 0 prints.
"""
from __future__ import annotations

import json
import math
import os
import sys
import time

DEFAULT_DENSITY = 2650.0  # kg/m^3 (quartz), for generated packings
DEFAULT_RADIUS = 1.0e-3  # m


def add_parser(subparsers) -> None:
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
    p.set_defaults(run=run_command)


def _law(args):
    from dtcrit.packing.model import HertzMindlinLaw, LinearLaw

    if args.youngs is not None:
        if args.kn is not None or args.ks is not None:
            raise ValueError("--kn: give either --kn/--ks or --youngs/--poisson, not both")
        return HertzMindlinLaw(args.youngs, args.poisson)
    if args.kn is None:
        raise ValueError("--kn: give the contact stiffness (--kn [--ks] for linear springs, or --youngs [--poisson] "
                         "for Hertz-Mindlin): the step scales with it")
    return LinearLaw(args.kn, args.kn if args.ks is None else args.ks)


def _bodies(args):
    """The ``dtcrit-bodies/1`` file FILE names, or None when FILE is not one (then it is a dump)."""
    from dtcrit.packing.readers.bodies_file import is_bodies_file, read_bodies_file

    if args.file is None or args.lattice is not None or args.random is not None or not is_bodies_file(args.file):
        return None
    for flag, value in (("--density", args.density), ("--write-dump", args.write_dump)):
        if value is not None:
            raise ValueError(f"{flag}: not used with a bodies file (each body's shape gives its density or mass; "
                             "a dump holds spheres only)")
    return read_bodies_file(args.file)


def _bodies_and_law(args):
    """The bodies file (or None) and the contact law (None when the file lists each contact's)."""
    bodies = _bodies(args)
    if bodies is not None and bodies.stiffness_given:
        if args.kn is not None or args.ks is not None or args.youngs is not None:
            raise ValueError(f"--kn: {args.file} lists each contact's kn and ks; drop --kn/--ks/--youngs")
        return bodies, None
    return bodies, _law(args)


def _packing(args, check_memory: bool = True):
    from dtcrit.packing.readers.lammps_dump import read_dump
    from dtcrit.packing.generators.lattices import lattice
    from dtcrit.packing.generators.random_packing import random_packing

    chosen = [name for name, v in (("FILE", args.file), ("--lattice", args.lattice), ("--random", args.random))
              if v is not None]
    if len(chosen) != 1:
        raise ValueError("packing: give exactly one of FILE, --lattice or --random"
                         + (f" (got {', '.join(chosen)})" if chosen else ""))
    if args.file is not None:
        return read_dump(args.file, density=args.density, snapshot=args.snapshot)
    if args.snapshot != -1:
        raise ValueError(f"--snapshot: picks a snapshot of a dump FILE; {chosen[0]} has none")
    from dtcrit.packing.generators.lattices import COORDINATION, _BASIS
    from dtcrit.packing.solvers.memory import check_fits

    density = DEFAULT_DENSITY if args.density is None else args.density
    if args.lattice is not None:
        if check_memory and isinstance(args.cells, int) and args.cells > 0:
            n = len(_BASIS[args.lattice][0]) * args.cells**3
            check_fits(n, COORDINATION[args.lattice], args.route, key="--cells", **_certificate_cost(args, n,
                                                                                                  COORDINATION[args.lattice]))
        return lattice(args.lattice, args.cells, radius=args.radius, density=density)
    if check_memory and isinstance(args.random, int) and args.random > 1 and 0 <= args.cn <= 14:
        check_fits(args.random, args.cn, args.route, key="--random", **_certificate_cost(args, args.random, args.cn))
        _check_generation_time(args.random)
    return random_packing(args.random, cn=args.cn, sizes=args.sizes, radius=args.radius, spread=args.spread,
                          density=density, seed=args.seed)


def _certificate_cost(args, n: int, coordination: float) -> dict:
    """``check_fits``'s extra memory for ``--certify yes`` (``certificate.factor_bytes``)."""
    from dtcrit.packing.solvers.certificate import SPARSE_DOFS, factor_bytes

    if args.certify != "yes" or 6 * n > SPARSE_DOFS:
        return {}
    return {"extra": factor_bytes(6 * n, coordination), "what": "the certificate's factorisation"}


RANDOM_SECONDS_LIMIT = 1800.0
"""``--random`` refuses up front a packing whose generation is estimated to take longer than this [s]
(``random_packing.generation_seconds``); below it a progress bar shows the relaxation on a terminal."""


def _check_generation_time(n: int) -> None:
    from dtcrit.packing.generators.random_packing import SECONDS_PER_SPHERE_STEP, generation_seconds

    seconds = generation_seconds(n)
    if seconds > RANDOM_SECONDS_LIMIT:
        raise ValueError(f"--random: {n:,} spheres take about {seconds / 60:.0f} min to generate (FIRE relaxation, "
                         f"250 steps at a measured {SECONDS_PER_SPHERE_STEP * 1e6:.2g} us per sphere and step), more "
                         f"than the {RANDOM_SECONDS_LIMIT / 60:.0f} min allowed; generate it once elsewhere and give "
                         "it as a dump FILE, or use a --lattice")


FLAGS = {"cells": "--cells", "n": "--random", "radius": "--radius", "kn": "--kn", "ks": "--ks",
         "youngs": "--youngs", "poisson": "--poisson", "density": "--density", "cn": "--cn", "spread": "--spread",
         "sizes": "--sizes", "seed": "--seed", "integrator": "--integrator", "damping_ratio": "--damping-ratio",
         "damping-ratio": "--damping-ratio", "method": "--solver", "route": "--route", "snapshot": "--snapshot",
         "lattice": "--lattice", "scale": "--scale"}
"""Library keys (``InputError.key``) and the flags of ``dtcrit packing`` that set them."""


def _source(args) -> str:
    """The flag or FILE that gave the packing."""
    return "--cells" if args.lattice is not None else "--random" if args.random is not None else str(args.file)


def flag_of(key: str, args) -> str | None:
    """The flag (or ``FILE:key``) to name for a library ``InputError`` key; None to keep the key."""
    if key.startswith("-") or ":" in key:
        return None
    if key == "stiffness":
        return "--youngs" if args.youngs is not None else "--kn" if args.kn is not None else f"{args.file}:contacts"
    if key in ("box", "positions", "mass"):
        return f"{args.file}:{key}" if args.file is not None else "--radius"
    return FLAGS.get(key)


def run_command(args) -> int:
    """``dtcrit packing``: library keys become the flags that set them; a solver that stops early, or
    memory that runs out after all, is one line too (``dtcrit.cli.library_errors``).
    """
    from dtcrit.cli.library_errors import run_naming_flags

    return run_naming_flags(_run, args, args.file, flag_of,
                            lambda exc: f"--solver: {exc} (another --solver may converge)",
                            f"{_source(args)}: ran out of memory (the estimate said it fits: another process may "
                            "have taken memory, or the packing is denser than modelled); try a smaller packing, "
                            "--route matrix-free or --certify no")


def _run(args) -> int:
    if args.backend == "slepc":
        return _run_slepc(args)
    if args.scale:
        from dtcrit.bench.packing_scaling import parse_sizes, run_sizes

        run_sizes(parse_sizes(args.scale), args.scale_packing)
        return 0
    from dtcrit.packing.readers.lammps_dump import write_dump
    from dtcrit.packing.report import analyse, format_report

    if not math.isfinite(args.damping_ratio) or args.damping_ratio < 0:
        raise ValueError(f"--damping-ratio: must be a finite number >= 0, got {args.damping_ratio}")
    if args.write_dump:
        from dtcrit.cli.outputs import check_output_file

        check_output_file(args.write_dump, "--write-dump")
    bodies, law = _bodies_and_law(args)
    packing = _packing(args) if bodies is None else bodies.packing
    contacts = None if bodies is None else bodies.contacts
    certify = {"auto": "auto", "yes": True, "no": False}[args.certify]
    report = analyse(packing, law, contacts, integrator=args.integrator, damping_ratio=args.damping_ratio, method=args.solver,
                     route=args.route, certify_step=certify)
    if report.n_contacts == 0:
        raise ValueError("packing: no two particles touch: no contact limits the step (nothing to analyse)")
    if not report.omega_max > 0:
        why = (" (Hertz stiffness 2 E* sqrt(R* delta) vanishes at zero overlap: the spheres only touch)"
               if "hertz" in report.law.lower() else "")
        raise ValueError(f"packing: every contact has zero stiffness{why}: no vibrating mode, no critical step")
    if args.write_dump:
        write_dump(args.write_dump, packing)
    if args.json:
        from dtcrit.json_meta import envelope
        from dtcrit.packing.report import JSON_SCHEMA, UNITS

        doc = envelope(JSON_SCHEMA, UNITS)
        doc.update(report.to_dict())
        json.dump(doc, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print(format_report(report))
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
    rank = int(next((os.environ[k] for k in LAUNCHER_RANK if os.environ.get(k, "").isdigit()), "0"))
    try:
        from dtcrit.packing.distributed import slepc_backend as sb
        from dtcrit.packing.distributed.mpi_support import world

        _, rank, _ = world()
        return _slepc_report(args, sb, rank)
    except (ValueError, SystemExit) as exc:
        if isinstance(exc, SystemExit) or (rank != 0 and not getattr(exc, "report_here", False)):
            time.sleep(QUIET_EXIT_DELAY)
            raise SystemExit(2) from None
        raise


def _slepc_report(args, sb, rank: int) -> int:
    from dtcrit.packing.solvers.integrator_step import integrator_dt

    for flag, key, default in SLEPC_UNUSED:
        if getattr(args, key) != default:
            raise ValueError(f"{flag[2:]}: not used with --backend slepc (it reports omega_max, dt_crit and "
                             "dt_safe; the serial backend has the estimates, routes and certificate)")
    integrator_dt(1.0, args.integrator, args.damping_ratio)  # bad names and ratios fail before the work
    clock = time.perf_counter()
    bodies, law = _bodies_and_law(args)
    packing = _packing(args, check_memory=False) if bodies is None else bodies.packing
    contacts = None if bodies is None else bodies.contacts
    share = sb.distribute(packing, law, contacts, t_input=time.perf_counter() - clock)
    del packing, contacts, bodies  # the O(N) input is not needed by the matrix and the solve
    result = sb.analyse_share(share)
    del share
    if result.n_contacts == 0:
        raise ValueError("packing: no two particles touch: no contact limits the step (nothing to analyse)")
    if not result.omega_max > 0:
        raise ValueError("packing: every contact has zero stiffness: no vibrating mode, no critical step")
    dt_int, formula = integrator_dt(result.omega_max, args.integrator, args.damping_ratio)
    if rank != 0:
        return 0
    if args.json:
        from dtcrit.json_meta import envelope

        doc = envelope(sb.JSON_SCHEMA, sb.UNITS)
        doc.update(result.to_dict(), integrator=args.integrator, damping_ratio=float(args.damping_ratio),
                   dt_integrator=dt_int, integrator_formula=formula)
        json.dump(doc, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print(sb.format_result(result))
        print(f"{args.integrator}, modal damping ratio {args.damping_ratio:g}: dt = {dt_int:.6g} s"
              + ("  (no step is stable)" if dt_int == 0 else ""))
    return 0
