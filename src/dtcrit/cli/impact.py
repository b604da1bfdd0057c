"""``dtcrit impact``: stability of the time-stepped one-dimensional impact (CFL note; Feng 2005).

    dtcrit impact --integrator leapfrog --zeta 0.05                 sweep omega*dt over (0, 2.2]
    dtcrit impact --integrator velocity-verlet --zeta 0 --omega-dt 1.2 --json
    dtcrit impact --integrator leapfrog --zeta 0.1 --sweep --out figs/

For each omega*dt the exit/entry speed ratio is computed over equally spaced entry phases (where
within a step the contact begins) and compared with the exact impact.  A sweep also summarises the
damping ratios 0, 0.05 and 0.2 and studies the undamped Hertz contact against the linearised bound.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from dtcrit.cli.flags import flag_errors, number

# the library's keys of the flags' values (its range checks name them so): reported as the flags
FLAGS = {"integrator": "--integrator", "zeta": "--zeta", "omega-dt": "--omega-dt", "step": "--step",
         "phases": "--phases", "energy_threshold": "--energy-threshold"}


def add_parser(subparsers) -> None:
    """Add the ``dtcrit impact`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    from dtcrit.integrators.schemes import NAMES

    p = subparsers.add_parser(
        "impact",
        help="exit/entry speed of a time-stepped one-dimensional impact (CFL note, Feng 2005)",
        description="Time-step the one-dimensional spring-dashpot impact m d'' = -c d' - k d (d >= 0) with an "
        "integrator, sweeping omega*dt and the entry phase, and compare v_exit/v_entry with the exact impact.",
    )
    p.add_argument("--integrator", required=True, metavar="NAME", help=f"one of {', '.join(NAMES)}")
    p.add_argument("--zeta", type=number(positive=False, what="damping ratio"), default=0.0, help="damping ratio c/(2 sqrt(k m)) (default 0)")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--omega-dt", type=number(), metavar="X", help="evaluate this omega*dt only")
    mode.add_argument("--sweep", action="store_true", help="sweep omega*dt over (0, 2.2] (the default)")
    p.add_argument("--step", type=number(), default=0.005, help="grid spacing of the sweep (default 0.005)")
    p.add_argument("--phases", type=number(int), default=128, help="entry phases per omega*dt (default 128)")
    p.add_argument("--energy-threshold", type=number(), default=0.01,
                   help="Hertz study: tolerated energy error abs(v_e^2/v_0^2 - 1) (default 0.01)")
    p.add_argument("--no-hertz", action="store_true", help="skip the Hertz study of a sweep")
    p.add_argument("--out", metavar="DIR", help="write the JSON report and PNG figures into DIR")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.set_defaults(run=run)


def _fmt(x) -> str:
    return "-" if x is None else f"{x:.6g}"


def _ranges(rs) -> str:
    if not rs:
        return "none"
    return ", ".join(f"[{a:.4g}, {b:.4g}]" for a, b in rs)


def _text(rep: dict) -> str:
    ex = rep["exact"]
    lines = [
        f"integrator {rep['integrator']}, zeta = {rep['zeta']:g}; linear stability bound omega*dt = {rep['critical_omega_dt']:.6g}",
        f"exact impact (geometric separation): duration = {_fmt(ex['duration'])}/omega, v_exit/v_entry = {_fmt(ex['exit_ratio'])}"
        + ("" if ex["separates"] else " (never separates: overlap only tends to 0)"),
        f"exact impact (force-based release):  duration = {_fmt(ex['force_based']['duration'])}/omega, "
        f"v_exit/v_entry = {_fmt(ex['force_based']['exit_ratio'])}",
        f"time-stepped impact over {rep['phases']} entry phases (simulation: geometric separation)",
        f"{'omega*dt':>10} {'min':>10} {'mean':>10} {'max':>10} {'on_step':>10} {'separated':>9}",
    ]
    rows = rep["numerical"]
    if len(rows) > 24:  # a sweep: every 0.1
        keep = [r for r in rows if abs(r["omega_dt"] * 10 - round(r["omega_dt"] * 10)) < 1e-9]
        rows = keep or rows[:: max(1, len(rows) // 22)]
    for r in rows:
        lines.append(
            f"{r['omega_dt']:10.4g} {_fmt(r['min']):>10} {_fmt(r['mean']):>10} {_fmt(r['max']):>10} "
            f"{_fmt(r['on_step']):>10} {r['separated']:9.3g}"
        )
    ec = rep["energy_created"]
    lines.append(f"max ratio > exact on omega*dt in {_ranges(ec['above_exact'])}")
    lines.append(f"max ratio > 1     on omega*dt in {_ranges(ec['above_one'])}")
    cf = rep.get("undamped_closed_form")
    if cf:
        lines.append(f"undamped closed form: {cf['formula']}")
        lines.append(f"  max relative difference from the simulation: {_fmt(cf['max_relative_difference_from_simulation'])}")
        for p in cf.get("unit_ratio_steps", [])[:6]:
            lines.append(f"  N = {p['N']}: omega*dt = {p['omega_dt']:.6g}, max |ratio - 1| = {p['max_abs_ratio_minus_one']:.2g}")
    for s in rep.get("by_zeta", []):
        lines.append(
            f"zeta = {s['zeta']:g}: exact {s['exact_exit_ratio']:.6g}, bound {s['critical_omega_dt']:.6g}; "
            f"ratio > 1 on {_ranges(s['energy_created']['above_one'])}"
        )
    hz = rep.get("hertz")
    if hz:
        lines.append(f"Hertz (undamped): {hz['verdict']}")
    return "\n".join(lines)


def run(args) -> int:
    """Run ``dtcrit impact``: the exact and time-stepped impact of one contact (``dtcrit.impact_report``), printed or written.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    int
        The exit status (0; bad input raises ``ValueError``, printed as one line with status 2).
    """
    import dtcrit.impact as imp

    from dtcrit.cli.outputs import check_output_dir

    if args.out:
        check_output_dir(args.out)
    omega_dt = args.omega_dt
    with flag_errors(FLAGS):
        if omega_dt is not None:
            imp.check_omega_dt(omega_dt, "omega-dt")
        rep = imp.impact_report(
            args.integrator,
            args.zeta,
            omega_dt=omega_dt,
            n_phases=args.phases,
            hertz=False if args.no_hertz else None,
            energy_threshold=args.energy_threshold,
            step=args.step,
        )
    data = imp.to_json(rep)
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        stem = f"impact_{rep['integrator']}_zeta{rep['zeta']:g}"
        (out / f"{stem}.json").write_text(json.dumps(data, indent=2) + "\n")
        if omega_dt is None:
            imp.plot_sweep(rep, out / f"{stem}_ratio.png")
            if "hertz" in rep:
                imp.plot_hertz(rep["hertz"], out / f"impact_{rep['integrator']}_hertz.png")
        else:
            imp.plot_phase_curve(rep, out / f"{stem}_omegadt{omega_dt:g}_phases.png")
    if args.json:
        sys.stdout.write(json.dumps(data, indent=2) + "\n")
    else:
        sys.stdout.write(_text(rep) + "\n")
    return 0
