"""``dtcrit audit``: the critical step of a real simulation snapshot, as its engine integrates it.

    dtcrit audit DUMP --pair-style 'gran/hooke/history 1e4 NULL 0 NULL 0.5 0' [--local CONTACTS.local]
    dtcrit audit DUMP --contacts TABLE [--engine liggghts|yade]
    dtcrit audit DUMP --liggghts-input in.file --engine liggghts
    dtcrit audit EXPORT.json --engine yade          (written by dtcrit/engine_scripts/yade_export.py)
    ... [--wall 'fix 2 all wall/gran hertz/history 2e5 NULL 50 NULL 0.5 1 zplane 0 NULL'] (repeatable)
    ... [--dt DT] [--local-damping ALPHA --local-damping-law yade|pfc] [--json] [--plot FILE.png]

The engine's conventions (``dtcrit.packing.conventions.engines``) decide which pairs touch, the contact arms,
the pre-load and the integrator; the dashpots enter the damping matrix contact by contact.
"""
from __future__ import annotations

import json
import sys


def add_parser(subparsers) -> None:
    """Add the ``dtcrit audit`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = subparsers.add_parser(
        "audit", help="critical time step of a simulation snapshot (LAMMPS/LIGGGHTS dump, YADE export)",
        description="The critical step of the packing in a snapshot, with the engine's own contact conventions, "
                    "per-contact stiffness and dashpots: dt_crit, a rigorous lower bound dt_safe, the particles "
                    "the governing mode sits on, and the codes' estimators beside it.")
    p.add_argument("snapshot", help="LAMMPS/LIGGGHTS text dump (ITEM: ATOMS id type x y z radius|diameter "
                                    "[mass]) or a YADE export (JSON, dtcrit-yade-export/1)")
    p.add_argument("--engine", choices=("lammps", "liggghts", "yade"),
                   help="whose conventions to apply (default: yade for a YADE export, liggghts with "
                        "--liggghts-input, else lammps)")
    p.add_argument("--pair-style", metavar="'STYLE ARGS'",
                   help="the input script's pair style, e.g. 'gran/hooke/history 1e4 NULL 0 NULL 0.5 0'")
    p.add_argument("--liggghts-input", metavar="FILE",
                   help="LIGGGHTS input script: 'pair_style gran model hertz|hooke ...' and its 'fix property/global' "
                        "materials per atom type (the dump's type column)")
    p.add_argument("--local", metavar="FILE", help="LAMMPS dump local of the engine's contact list (patom1 patom2)")
    p.add_argument("--contacts", metavar="TABLE", help="contact table with the columns id1 id2 kn ks [cn cs kr ktw cr ctw fn], any order, # comments")
    p.add_argument("--wall", action="append", metavar="'FIX LINE'",
                   help="the input script's 'fix ID group wall/gran STYLE ARGS xplane|yplane|zplane lo hi|zcylinder r' "
                        "line (LAMMPS; repeatable): its wall contacts enter against a fixed body")
    p.add_argument("--density", type=float, help="particle density [kg/m^3] for a dump without a mass column")
    p.add_argument("--snapshot-index", type=int, default=-1, help="snapshot in the dump (default: the last)")
    p.add_argument("--dt", type=float, help="the simulation's own step [s], rated against dt_crit")
    p.add_argument("--local-damping", type=float, metavar="ALPHA",
                   help="local (Cundall) damping coefficient in [0, 1): dt_crit and dt_safe times 1/sqrt(1+ALPHA) "
                        "(default: a YADE export's newton_damping)")
    p.add_argument("--local-damping-law", choices=("yade", "pfc"),
                   help="its law: yade (sign of the power at the on-step velocity estimate) or pfc (sign of F.v at "
                        "the half step); yade for a YADE export")
    p.add_argument("--integrator", help="override the engine's integrator (see dtcrit step's integrators)")
    p.add_argument("--json", action="store_true", help="print the result as JSON (schema dtcrit-audit/1)")
    p.add_argument("--plot", metavar="FILE.png", help="also draw the particles by their share of the governing mode "
                                                      "and the top of the spectrum with dt_crit, dt_safe and the estimators")
    p.set_defaults(run=run_command)


def _dump_flag(exc, path: str) -> str:
    """The flag (or the file) to name for an error in the dump: its reader's key as a flag."""
    if exc.key.startswith(str(path)):
        return exc.key
    return str(path) if exc.key == "file" else f"--{exc.key.replace('_', '-')}"


def flag_of(key: str, args) -> str | None:
    """The flag (or ``SNAPSHOT:key``) to name for a library ``InputError`` key.

    Parameters
    ----------
    key : str
        The ``InputError.key`` the API raised (a parameter name, a file key).
    args : argparse.Namespace
        The parsed flags (which of ``--contacts``, ``--pair-style`` gave the law).

    Returns
    -------
    str or None
        The flag, or None to keep the key as it is.
    """
    if key.startswith("-") or ":" in key:
        return None
    if key in ("stiffness", "damping", "youngs", "kn", "ks"):
        if getattr(args, "liggghts_input", None):
            return "--liggghts-input"
        return "--contacts" if args.contacts else "--pair-style" if args.pair_style else f"{args.snapshot}:contacts"
    if key in ("box", "positions", "mass", "radius"):
        return f"{args.snapshot}:{key}"
    return {"integrator": "--integrator", "density": "--density", "dt": "--dt", "engine": "--engine",
            "snapshot": "SNAPSHOT", "local": "--local", "contact_table": "--contacts",
            "pair_style": "--pair-style", "plot": "--plot", "local_damping": "--local-damping",
            "local_damping_law": "--local-damping-law", "liggghts_input": "--liggghts-input"}.get(key)


def run_command(args) -> int:
    """Run ``dtcrit audit`` with the library's errors as one line each.

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

    return run_naming_flags(_run, args, args.snapshot, flag_of, lambda exc: f"--integrator: {exc}",
                            f"{args.snapshot}: ran out of memory analysing this snapshot")


def _run(args) -> int:
    from dtcrit.errors import InputError
    from dtcrit.packing.audit.run import DumpReadError, audit_snapshot

    args.source_label = None
    if args.plot:
        from dtcrit.figures.audit_plot import check_plot_path, write_audit_plot

        check_plot_path(args.plot)  # before the work: a bad path is one line at once
    try:
        result = audit_snapshot(args.snapshot, dt=args.dt, integrator=args.integrator,
                                local_damping=args.local_damping, local_damping_law=args.local_damping_law,
                                engine=args.engine,
                                pair_style=args.pair_style, local=args.local, contact_table=args.contacts,
                                density=args.density, snapshot_index=args.snapshot_index,
                                liggghts_input=args.liggghts_input, walls=args.wall)
    except DumpReadError as exc:  # the dump reader's key as the flag that set it
        raise InputError(_dump_flag(exc, args.snapshot), exc.reason) from None
    if args.plot:
        write_audit_plot(result, args.plot)
    if args.json:
        json.dump(result.to_json(), sys.stdout, indent=2, sort_keys=True)
        sys.stdout.write("\n")
    else:
        print(result.to_text())
    return 0
