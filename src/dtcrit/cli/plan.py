"""``dtcrit plan``: the least intrusive way to a larger step, and what the simulation costs before and after.

    dtcrit plan DUMP --pair-style 'gran/hooke/history 1e5 NULL 0 NULL 0.5 0' --target-dt 2e-5
    dtcrit plan EXPORT.json --target-dt DT          (a YADE export, as dtcrit audit reads it)
    ... [--max-factor 100] [--duration T] [--strain-rate RATE] [--gravity G] [--velocity V]
    ... [--write-dump SCALED.dump] [--json] [--plot FILE.png]

The snapshot flags are ``dtcrit audit``'s own (``dtcrit.cli.audit``); the plan is
:func:`dtcrit.plan.report.plan_snapshot`.
"""
from __future__ import annotations

import argparse
import json
import sys

from dtcrit.cli.flags import number

SNAPSHOT_FLAGS = ("snapshot", "engine", "pair_style", "liggghts_input", "local", "contacts", "wall", "density",
                  "snapshot_index", "local_damping", "local_damping_law", "integrator")
"""The ``dtcrit audit`` flags ``dtcrit plan`` takes over (the same definitions, not copies)."""


def _audit_actions() -> list:
    """The actions of ``dtcrit audit``'s parser that read a snapshot (``SNAPSHOT_FLAGS``)."""
    from dtcrit.cli import audit

    holder = argparse.ArgumentParser(add_help=False)
    audit.add_parser(holder.add_subparsers())
    sub = next(a for a in holder._actions if isinstance(a, argparse._SubParsersAction))
    return [a for a in sub.choices["audit"]._actions if a.dest in SNAPSHOT_FLAGS]


def add_parser(subparsers) -> None:
    """Add the ``dtcrit plan`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = subparsers.add_parser(
        "plan", help="density scaling or stiffness reduction to reach a target step, proved stable, and the cost",
        description="The binding step of a snapshot and the least added mass (per-body density scaling, confirmed "
                    "stable at the target by the exact eigen-solve of the scaled packing) or the stiffness factor "
                    "that reaches --target-dt; YADE's densityScaling rule and a uniform factor beside it; the "
                    "inertial number, contact durations and the cost before and after.")
    for action in _audit_actions():
        p._add_action(action)
    p.add_argument("--target-dt", type=number(float, what="number of seconds"), required=True, metavar="DT",
                   help="the step to reach [s]")
    p.add_argument("--max-factor", type=number(float), default=100.0, metavar="F",
                   help="largest mass factor of any body (default 100)")
    p.add_argument("--duration", type=number(float, what="number of seconds"), metavar="T",
                   help="simulated time [s]: steps and particle-steps before and after")
    p.add_argument("--strain-rate", type=number(float), metavar="RATE",
                   help="shear strain rate [1/s]: the inertial number before and after")
    p.add_argument("--gravity", type=number(float, positive=False), metavar="G",
                   help="gravitational acceleration [m/s^2] of the simulation: warns what scaling does to it")
    p.add_argument("--velocity", type=number(float, positive=False), metavar="V",
                   help="impact speed [m/s] in the simulation: warns what scaling does to impacts")
    p.add_argument("--write-dump", metavar="FILE", help="write the snapshot with the planned masses as a LAMMPS dump "
                                                         "(id type x y z radius mass) that dtcrit audit reads")
    p.add_argument("--json", action="store_true", help="print the plan as JSON (schema dtcrit-plan/1)")
    p.add_argument("--plot", metavar="FILE.png", help="also draw the added mass of each particle (and its factor) "
                                                      "against its radius, beside YADE's rule and the uniform factor")
    p.set_defaults(run=run_command)


def flag_of(key: str, args) -> str | None:
    """The flag (or ``SNAPSHOT:key``) to name for a library ``InputError`` key.

    Parameters
    ----------
    key : str
        The ``InputError.key`` the API raised.
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    str or None
        The flag, or None to keep the key as it is.
    """
    from dtcrit.cli import audit

    own = {"target_dt": "--target-dt", "max_factor": "--max-factor", "duration": "--duration",
           "strain_rate": "--strain-rate", "gravity": "--gravity", "velocity": "--velocity",
           "write_dump": "--write-dump", "plot": "--plot"}
    return own.get(key) or audit.flag_of(key, args)


def run_command(args) -> int:
    """Run ``dtcrit plan`` with the library's errors as one line each.

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
                            f"{args.snapshot}: ran out of memory planning this snapshot")


def _run(args) -> int:
    from dtcrit.cli.audit import _dump_flag
    from dtcrit.errors import InputError
    from dtcrit.packing.audit.run import DumpReadError
    from dtcrit.plan.density import read_input
    from dtcrit.plan.report import plan_snapshot

    args.source_label = None
    if args.plot:
        from dtcrit.figures.audit_plot import check_plot_path

        check_plot_path(args.plot)  # before the work: a bad path is one line at once
    try:
        given = read_input(args.snapshot, dict(engine=args.engine, pair_style=args.pair_style, local=args.local,
                                               contact_table=args.contacts, density=args.density,
                                               snapshot_index=args.snapshot_index, liggghts_input=args.liggghts_input,
                                               walls=args.wall))
    except DumpReadError as exc:
        raise InputError(_dump_flag(exc, args.snapshot), exc.reason) from None
    if args.write_dump:
        from dtcrit.plan.dump import check_dump_target

        check_dump_target(given, args.write_dump, per_type_law=bool(args.liggghts_input))
    plan = plan_snapshot(given, args.target_dt, max_factor=args.max_factor, duration=args.duration,
                         strain_rate=args.strain_rate, gravity=args.gravity, velocity=args.velocity,
                         integrator=args.integrator, local_damping=args.local_damping,
                         local_damping_law=args.local_damping_law)
    if args.write_dump:
        from dtcrit.plan.dump import write_scaled_dump

        write_scaled_dump(args.write_dump, given.packing, plan.density.factors, plan.density.free)
    if args.plot:
        from dtcrit.figures.plan_added_mass import write_added_mass_figure

        write_added_mass_figure(plan.density, plan.snapshot.packing.radii, args.plot)
    if args.json:
        json.dump(plan.to_json(), sys.stdout, indent=2, sort_keys=True)
        sys.stdout.write("\n")
    else:
        print(plan.to_text())
    return 0
