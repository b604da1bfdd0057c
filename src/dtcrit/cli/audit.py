"""``dtcrit audit``: the critical step of a real simulation snapshot, as its engine integrates it.

    dtcrit audit DUMP --pair-style 'gran/hooke/history 1e4 NULL 0 NULL 0.5 0' [--local CONTACTS.local]
    dtcrit audit DUMP --contacts TABLE [--engine liggghts]
    dtcrit audit EXPORT.json --engine yade          (written by dtcrit/engine_scripts/yade_export.py)
    ... [--dt DT] [--json]

The engine's conventions (``dtcrit.packing.conventions.engines``) decide which pairs touch, the contact arms,
the pre-load and the integrator; the dashpots enter the damping matrix contact by contact.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path


def add_parser(subparsers) -> None:
    p = subparsers.add_parser(
        "audit", help="critical time step of a simulation snapshot (LAMMPS/LIGGGHTS dump, YADE export)",
        description="The critical step of the packing in a snapshot, with the engine's own contact conventions, "
                    "per-contact stiffness and dashpots: dt_crit, a rigorous lower bound dt_safe, the particles "
                    "the governing mode sits on, and the codes' estimators beside it.")
    p.add_argument("snapshot", help="LAMMPS/LIGGGHTS text dump (ITEM: ATOMS id type x y z radius|diameter "
                                    "[mass]) or a YADE export (JSON, dtcrit-yade-export/1)")
    p.add_argument("--engine", choices=("lammps", "liggghts", "yade"),
                   help="whose conventions to apply (default: yade for a YADE export, else lammps)")
    p.add_argument("--pair-style", metavar="'STYLE ARGS'",
                   help="the input script's pair style, e.g. 'gran/hooke/history 1e4 NULL 0 NULL 0.5 0'")
    p.add_argument("--local", metavar="FILE", help="LAMMPS dump local of the engine's contact list (patom1 patom2)")
    p.add_argument("--contacts", metavar="TABLE", help="contact table with the columns id1 id2 kn ks [cn cs kr ktw fn]")
    p.add_argument("--density", type=float, help="particle density [kg/m^3] for a dump without a mass column")
    p.add_argument("--snapshot-index", type=int, default=-1, help="snapshot in the dump (default: the last)")
    p.add_argument("--dt", type=float, help="the simulation's own step [s], rated against dt_crit")
    p.add_argument("--integrator", help="override the engine's integrator (see dtcrit step's integrators)")
    p.add_argument("--json", action="store_true", help="print the result as JSON (schema dtcrit-audit/1)")
    p.set_defaults(run=run_command)


def _check_file(flag: str, path: str | None) -> None:
    if path is not None and not Path(path).is_file():
        raise ValueError(f"{flag}: {path} is not a readable file")


def _read_dump(path: str, density, index):
    from dtcrit.errors import InputError
    from dtcrit.packing.readers.lammps_dump import read_dump

    try:
        return read_dump(path, density=density, snapshot=index)
    except InputError as exc:
        if exc.key.startswith(str(path)):
            raise
        flag = "--snapshot-index" if exc.key == "snapshot" else f"--{exc.key.replace('_', '-')}"
        raise InputError(f"{path}" if exc.key == "file" else flag, exc.reason) from None


def _is_yade_export(path: str) -> bool:
    with open(path, "rb") as fh:
        head = fh.read(64).lstrip(b"\xef\xbb\xbf \t\r\n")
    return head.startswith(b"{")


def _build(args):
    """``(packing, contacts, convention, law text, metadata)`` from the arguments."""
    from dtcrit.packing.readers.contact_tables import read_contact_table, read_local_dump
    from dtcrit.packing.conventions.engines import engine_convention, engine_sphere_contacts, overlaps_of_pairs, with_arms
    from dtcrit.packing.conventions.pair_styles import apply_terms, parse_pair_style
    from dtcrit.packing.readers.yade_export import check_schema, read_yade_audit

    yade_file = _is_yade_export(args.snapshot)
    if yade_file:
        check_schema(args.snapshot)  # a JSON file of another format is not "a YADE export"
    convention = engine_convention(args.engine or ("yade" if yade_file else "lammps"))
    if yade_file != (convention.name == "yade"):
        raise ValueError(f"--engine: {args.snapshot} is {'a YADE export' if yade_file else 'a dump'}, "
                         f"which does not go with --engine {convention.name}")
    if yade_file:
        if args.pair_style or args.local or args.contacts:
            raise ValueError("--engine: a YADE export carries its own contacts; --pair-style, --local and --contacts "
                             "do not apply")
        packing, contacts, meta = read_yade_audit(args.snapshot)  # YADE's kinematics (clumps too) applied on reading
        return packing, contacts, convention, "YADE's per-contact kn, ks (export)", meta
    style = parse_pair_style(args.pair_style) if args.pair_style else None
    if args.contacts and (style or args.local):
        raise ValueError("--contacts: a contact table already gives each contact's stiffness; "
                         "do not combine it with --pair-style or --local")
    if not args.contacts and style is None:
        raise ValueError("--pair-style: give the contact law (the input script's pair style) or a --contacts table")
    packing = _read_dump(args.snapshot, args.density, args.snapshot_index)
    if args.contacts:
        table = read_contact_table(args.contacts, packing)
        contacts = with_arms(packing, overlaps_of_pairs(packing, table.i, table.j), convention.arm)
        v = table.values
        contacts = contacts.with_stiffness(v["kn"], v["ks"], v.get("kr"), v.get("ktw"))
        contacts = contacts.with_damping(v.get("cn", 0.0), v.get("cs", 0.0))
        force = v.get("fn", v["kn"] * contacts.overlap)
        contacts = contacts.with_normal_force(force)
        law = f"per-contact table {Path(args.contacts).name}" + ("" if "fn" in v else " (pre-load kn x overlap)")
        return packing, contacts, convention, law, {}
    if args.local:
        i, j = read_local_dump(args.local, packing)
        contacts = overlaps_of_pairs(packing, i, j)
        contacts = contacts.subset(contacts.overlap > 0)
    else:
        contacts = engine_sphere_contacts(packing, convention)
    contacts = with_arms(packing, contacts, style.arm)  # the pair style's own kinematics
    return packing, apply_terms(contacts, style.terms(packing, contacts), preload=convention.preload), \
        convention, style.describe(), {"material": style.material()}


def flag_of(key: str, args) -> str | None:
    """The flag (or ``SNAPSHOT:key``) to name for a library ``InputError`` key; None to keep the key."""
    if key.startswith("-") or ":" in key:
        return None
    if key in ("stiffness", "damping", "youngs", "kn", "ks"):
        return "--contacts" if args.contacts else "--pair-style" if args.pair_style else f"{args.snapshot}:contacts"
    if key in ("box", "positions", "mass", "radius"):
        return f"{args.snapshot}:{key}"
    return {"integrator": "--integrator", "density": "--density", "dt": "--dt", "engine": "--engine"}.get(key)


def run_command(args) -> int:
    """``dtcrit audit``: library keys become the flags that set them; a solver that stops early, or
    memory that runs out, is one line too (``dtcrit.cli.library_errors``).
    """
    from dtcrit.cli.library_errors import run_naming_flags

    return run_naming_flags(_run, args, args.snapshot, flag_of, lambda exc: f"--integrator: {exc}",
                            f"{args.snapshot}: ran out of memory analysing this snapshot")


def _run(args) -> int:
    from dtcrit.packing.audit.snapshot import audit
    from dtcrit.packing.audit.output import audit_json, format_audit

    import math

    for flag, path in (("SNAPSHOT", args.snapshot), ("--local", args.local), ("--contacts", args.contacts)):
        _check_file(flag, path)
    if args.dt is not None and not (math.isfinite(args.dt) and args.dt > 0):
        raise ValueError(f"--dt: must be a positive finite number, got {args.dt}")
    args.source_label = None
    packing, contacts, convention, law, meta = _build(args)
    report = audit(packing, contacts, convention, law=law, source=args.snapshot, integrator=args.integrator,
                   dt_user=args.dt if args.dt is not None else meta.get("dt"), material=meta.get("material"))
    if args.json:
        json.dump(audit_json(report), sys.stdout, indent=2, sort_keys=True)
        sys.stdout.write("\n")
    else:
        print(format_audit(report))
    return 0
