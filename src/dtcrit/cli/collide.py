"""``dtcrit collide SCENE``: the step that resolves each collision of a scene (``dtcrit.scenes.collide``).

dtcrit collide examples/glass_spheres_hertz.toml
dtcrit collide examples/glass_spheres_hertz.toml --tol 0.001 --json
dtcrit collide examples/spheres_on_a_floor.toml --v-max 2 --plot collide.png
dtcrit collide SCENE --angle 60      (oblique impacts: tangential restitution and rebound spin)
"""
from __future__ import annotations

import argparse
import json
import math
import sys

from dtcrit.cli.flags import number


def _tol(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.0 < value < 1.0:
        raise argparse.ArgumentTypeError(f"must be a number in (0, 1) (got {text!r})")
    return value


def add_parser(subparsers) -> None:
    """Add the ``dtcrit collide`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = subparsers.add_parser("collide", help="the step that resolves each collision of a scene",
                              description="Per contact of a scene: the contact time, the peak overlap, the linear "
                              "stability step there, the step that resolves the impact within --tol, which binds, "
                              "and the codes' rules rated against it.")
    p.add_argument("scene", metavar="SCENE", help="scene file (TOML) with a hertz, linear or yade contact law")
    p.add_argument("--tol", type=_tol, default=0.01, help="relative tolerance on restitution and peak overlap, in (0, 1) (default 0.01)")
    p.add_argument("--engine", "--integrator", dest="engine", metavar="NAME", help="engine or integrator (default: the scene's)")
    p.add_argument("--v-max", type=number(what="speed"), metavar="V", help="largest impact speed [m/s] (default: [contact] velocity)")
    p.add_argument("--angle", type=float, metavar="DEG", help="angle of the impact from the normal [deg], in [0, 90): "
                   "also resolve the tangential restitution and rebound spin of two equal spheres (default: the "
                   "scene's [collision] angle_deg or tangential_ratio)")
    p.add_argument("--plot", metavar="FILE.png", help="draw the error against steps per collision")
    p.add_argument("--json", action="store_true", help="print the report as JSON (schema dtcrit-collide/1)")
    p.set_defaults(run=run)


def format_text(rep: dict) -> str:
    """The report as text.

    Parameters
    ----------
    rep : dict
        From ``collide_report``.

    Returns
    -------
    str
        One block per contact.
    """
    lines = [f"collisions resolved by {rep['integrator']} within {rep['tol']:g} (restitution, peak overlap) at v_max = {rep['v_max']:g} m/s"]
    for e in rep["pairs"]:
        cont = "" if abs(e["restitution_continuum"] - e["restitution"]) < 5e-5 else f" (continuum impact: {e['restitution_continuum']:.4g})"
        if e["damping"] in ("lammps-viscoelastic", "lammps-mass-velocity"):
            cont = " (of the continuum impact at v_max, from damping_coefficient)"
        lines += [f"pair {e['pair']}: {e['normal']} law, damping {e['damping']}, e = {e['restitution']:.4g}{cont}",
                  f"  t_c = {e['t_c']:.6g} s, peak overlap = {e['peak_overlap']:.6g} m",
                  f"  dt_stability = {e['dt_stability']:.6g} s, " + (f"dt_resolution = {e['dt_resolution']:.6g} s "
                  f"(N_res = {e['steps_resolution']:.4g})" if e["dt_resolution"] else "no step resolves it")
                  + f"; binding: {e['binding']}",
                  f"  dt = {e['dt']:.6g} s = t_c/{e['steps_per_collision']:.4g}; there the integrator {e['energy_verdict']}"]
        if "oblique" in e:
            lines += _oblique_lines(e["oblique"])
        for r in e["rules"]:
            tail = "not applicable" if r["dt"] is None else f"{r['dt']:.4g} s = {r['ratio']:.3g} x dt  {r['verdict']}"
            lines.append(f"    {r['label']:<48} {tail}")
    lines.append(f"step for every collision: {rep['dt']:.6g} s")
    return "\n".join(lines)


def _oblique_lines(o: dict) -> list[str]:
    err = o["errors_at_dt"]
    return [f"  oblique at {o['angle_deg']:.4g} deg (v_t/v_n = {o['tangential_ratio']:.4g}, friction {o['friction']:g}, "
            f"{o['regime']}): t_c = {o['t_c']:.6g} s, tangential restitution {o['reference']['tangential_restitution']:.4g}, "
            f"spin {o['reference']['spin']:.4g} v_t/R",
            f"    dt_oblique = {o['dt_resolution']:.6g} s (N_res = {o['steps_resolution']:.4g}); at dt: tangential "
            f"restitution error {err['tangential_restitution']:.3g}, spin error {err['spin']:.3g} v_t/R"
            + ("; binding" if o["binding"] else "")]


def run(args) -> int:
    """Run ``dtcrit collide``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    int
        0; bad input raises ``InputError``, printed as one line with status 2.
    """
    from dtcrit.errors import InputError
    from dtcrit.scenes.collide import collide_report
    from dtcrit.json_meta import envelope
    from dtcrit.scenes.scene import load_scene

    if args.plot:
        from dtcrit.figures.audit_plot import check_plot_path

        check_plot_path(args.plot)
    args.source_label = args.scene
    scene = load_scene(args.scene)
    try:
        rep = collide_report(scene, tol=args.tol, engine=args.engine, v_max=args.v_max, angle_deg=args.angle)
    except InputError as exc:  # a value a flag set is named by its flag, not by the scene file
        flag = {"tol": "--tol", "engine": "--engine" if args.engine else None,
                "integrator": "--engine" if args.engine else None,
                "v_max": "--v-max" if args.v_max is not None else None,
                "angle": "--angle"}.get(exc.key or "")
        if flag is None:
            raise
        args.source_label = None
        raise InputError(flag, exc.reason) from None
    if args.plot:
        from dtcrit.figures.collide_plot import write_collide_plot

        write_collide_plot(rep, args.plot)
    if args.json:
        doc = envelope("dtcrit-collide/1", {"t_c": "s", "dt": "s", "peak_overlap": "m", "v_max": "m/s", "m_eff": "kg",
                                            "angle_deg": "deg", "v_normal": "m/s", "v_tangential": "m/s"})
        doc.update(rep)
        print(json.dumps(doc, indent=2, allow_nan=False))
    else:
        print(format_text(rep))
    sys.stdout.flush()
    return 0
