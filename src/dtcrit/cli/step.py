"""``dtcrit step SCENE [--json]``: the verified critical time step of a scene file.

    dtcrit step examples/paper_ellipsoids.toml
    dtcrit step examples/glass_spheres_hertz.toml --json

Prints the critical step, what governs it (translation- or rotation-dominant, which pair and
direction), the formula with its equation numbers, and the estimates DEM codes use side by side,
each flagged UNSAFE when it exceeds the verified step.  ``--json`` prints the documented, stable
JSON form (schema ``dtcrit-step/1``, on the documentation's JSON reference pages).  A bad scene gives one line ``SCENE:key: reason`` and exit status 2.

This module and everything it imports stay free of SymPy (start-up time).
"""
from __future__ import annotations

import sys


def add_parser(subparsers) -> None:
    """Add the ``dtcrit step`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = subparsers.add_parser(
        "step",
        help="critical time step of a scene file (TOML)",
        description="Verified critical time step of the contacts described by a scene file (Peng et al. 2020; "
        "exact integrator boundaries), with the estimates DEM codes use side by side.",
    )
    p.add_argument("scene", metavar="SCENE", help="scene file (TOML; every key is listed on the documentation's Scene keys page)")
    p.add_argument("--json", action="store_true", help="print the result as JSON (schema dtcrit-step/1)")
    p.set_defaults(run=run)


def _s(x) -> str:
    return "n/a" if x is None else f"{x:.6g}"


def ratio_text(r: float, digits: int = 4) -> str:
    """A ratio with enough digits that one other than exactly 1 never reads as 1.

    ``digits`` significant digits, or as many more as it takes (up to 17, round-trip): 1.0024 x
    dt_crit UNSAFE printed as '1' would mislead.

    Parameters
    ----------
    r : float
        The ratio.
    digits : int
        Significant digits at least.

    Returns
    -------
    str
        The ratio's text.
    """
    for d in range(digits, 18):
        text = f"{r:.{d}g}"
        if r == 1.0 or float(text) != 1.0:
            return text
    return repr(r)


def _contact_line(sc, convention: str | None) -> str:
    c = sc.contact
    damping = c.damping + ("" if c.damping in ("none", "coefficients") else f" (damping convention {convention})")
    if c.model == "linear":
        return f"  contact: linear, kn = {c.kn:g} N/m, ks = {c.ks:g} N/m, damping: {damping}"
    if c.model == "yade":
        return f"  contact: YADE linear law kn = 2 E1 R1 E2 R2/(E1 R1 + E2 R2), ks = {c.ks_ratio:g} kn, damping: {damping}"
    if c.model == "bond":
        b = c.bond
        return (f"  contact: bond ({b.source}): kn = {c.kn:g} N/m, ks = {c.ks:g} N/m, kr = {b.kr:g} N m/rad, "
                f"ktw = {b.ktw:g} N m/rad, damping: {damping}")
    return (f"  contact: hertz at impact speed {c.velocity:g} m/s (tangent stiffness at the largest overlap), "
            f"damping: {damping}")


def _pair_line(p) -> str:
    c = p.contact
    sizes = "" if c.radius_i is None else f" (R = {c.radius_i:g}" + ("" if c.radius_j is None else f", {c.radius_j:g}") + ")"
    zeta = "" if c.zeta_n is None else f", zeta_n = {c.zeta_n:.4g}" + ("" if c.zeta_s is None else f", zeta_s = {c.zeta_s:.4g}")
    shear = "free" if p.shear.dt == float("inf") else f"{p.shear.dt:.6g} s"
    rot = "".join(f", dt_{d.direction} = {d.dt:.6g} s" for d in p.rotational)
    return (f"  pair {p.label}{sizes}: {p.method}, A_n = {p.normal.A:.6g}, A_s = {p.shear.A:.6g} 1/kg, "
            f"dt_normal = {p.normal.dt:.6g} s, dt_shear = {shear}{rot}{zeta}")


def _order_text(integrator: str) -> str:
    """', user-written, order of accuracy p (q undamped)' for a user scheme; '' for a built-in."""
    from dtcrit.scenes.step_json import order_of_accuracy_json

    order = order_of_accuracy_json(integrator)
    if order is None:
        return ""
    return (f" (user-written; consistent with x'' = f(x, v), order of accuracy {order['damped']} damped, "
            f"{order['undamped']} undamped; its step is confirmed by stepping its rules at 0.99x and 1.01x)")


def _isolated_line(result) -> str:
    """The isolated-contact step, named as such, beside the headline (or why the headline is that step)."""
    if result.basis == "isolated":
        why = ("isolated = true in the scene" if result.scene.isolated else result.basis_note +
               "; the headline is the isolated-contact step")
        return f"  isolated contact: the headline is the two-particle step ({why}); a packing needs less (below)"
    if not (result.dt_isolated > 0 and result.dt_crit > 0):
        return f"  isolated contact: dt = {result.dt_isolated:.6g} s (two particles alone; set isolated = true to headline it)"
    return (f"  isolated contact: dt = {result.dt_isolated:.6g} s (two particles alone, {ratio_text(result.dt_isolated / result.dt_crit)} "
            "x dt_crit; not safe in a packing; set isolated = true to headline it)")


def format_text(result) -> str:
    """The text ``dtcrit step`` prints for a scene's critical step.

    Parameters
    ----------
    result : StepResult
        The result of ``dtcrit.critical_step``.

    Returns
    -------
    str
        The scene, the headline step and what governs it (Peng et al. 2020, Eqs. (26), (29)-(30),
        (54), (56)), the pairs, the rotation bound and the codes' estimates rated against it.
    """
    sc = result.scene
    lines = [f"scene: {sc.source}" + (f" ({sc.title})" if sc.title else "")]
    for p in sc.particles:
        lines.append(f"  particle {p.number}: {p.describe()}")
    lines.append(_contact_line(sc, result.pairs[0].contact.convention))
    for w in sc.walls:
        lines.append(f"  wall {w.number} ({w.name}): {w.springs_text()}, damping: {w.damping}, "
                     f"touched by particle {', '.join(map(str, w.particles))}")
    lines.append(f"  integrator: {sc.integrator}" + _order_text(sc.integrator)
                 + (f", omega_max = {sc.omega_max:g} rad/s" if sc.omega_max is not None else ""))
    lines.append("")
    lines.append(f"critical time step  dt_crit = {result.dt_crit:.6g} s   (holds for {result.holds_for})")
    lines.append(_isolated_line(result))
    if result.coordination is not None:
        lines.append(f"  largest coordination: {result.coordination.how} (set coordination_max if yours is lower)")
    if sc.safety != 1.0:
        lines.append(f"with safety {sc.safety:g}:      dt = {result.dt_recommended:.6g} s")
    lines.append(f"governed by {result.bound}")
    lines.append(f"  formula: {result.formula}")
    lines.append("  (Peng et al. 2020, Eqs. (26), (29)-(30); the exact stability boundary of the integrator)")
    t = result.translation
    a_max = "n/a (wall)" if t.A_max is None else f"{t.A_max:.6g} 1/kg"
    lines.append(f"translation: A_max (Eq. (26) as printed) = {a_max}, A_bound (verified) = {t.A_bound:.6g} 1/kg, "
                 f"dt = {t.dt_translation:.6g} s ({t.label}, {t.governing_direction.direction} mode, {t.method})")
    if result.dense is None:
        factors = ", ".join(f"z = {z}: x {ratio_text(f, 3)}" if f is not None else f"z = {z}: n/a" for z, f in result.dense_factors.items())
        lines.append(f"dense packings: any packing with at most z contacts per particle is proven stable at ({factors}) "
                     "of the isolated-contact step by the block bound")
    for p in result.pairs:
        lines.append(_pair_line(p))
    if sc.omega_max is None:
        lines.append("rotation: omega_max not given, the rotation-dominant bound (Eqs. (54), (56)) is not evaluated")
    elif result.rotation is None and max(result.B_max.values()) == 0:
        lines.append("rotation: B_max = 0 for every pair (Eq. (54)): no rotation-dominant limit")
    elif result.rotation is None:
        lines.append(f"rotation: B_max = {max(result.B_max.values()):.6g}, but 2/(omega_max (B_i + B_j)) lies beyond the "
                     "float64 range: no rotation-dominant limit")
    else:
        r = result.rotation
        lines.append(f"rotation: B_max = {max(result.B_max.values()):.6g}, dt = 2/(omega_max (B_i + B_j)) = {r.dt_rotation:.6g} s "
                     f"(pair {r.label}; Eqs. (54), (56))")
    lines.append("")
    lines.append("estimates DEM codes use, against dt_crit (" + ("isolated contact" if result.basis == "isolated" else
                 "the packing step") + "; UNSAFE: larger than it):")
    width = max(len(e.estimate.name) for e in result.estimates)
    missing: dict[str, list[str]] = {}
    for e in result.estimates:
        if e.estimate.dt is None:
            missing.setdefault(e.estimate.detail, []).append(e.estimate.name)
            continue
        ratio = e.estimate.dt / result.dt_crit if result.dt_crit > 0 else float("inf")
        flag = "UNSAFE" if e.unsafe else "ok"
        lines.append(f"  {e.estimate.name:<{width}}  {e.estimate.dt:12.6g} s  {ratio_text(ratio):>8} x dt_crit  {flag:<6}  "
                     f"{e.estimate.label}")
    for note, keys in missing.items():
        lines.append(f"  not applicable: {', '.join(keys)} ({note})")
    return "\n".join(lines)


def run(args) -> int:
    """Run ``dtcrit step``: load the scene, find its critical step (``dtcrit.critical_step``) and print the text or JSON.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    int
        The exit status (0; bad input raises ``ValueError``, printed as one line with status 2).
    """
    from dtcrit.scenes.scene import load_scene
    from dtcrit.scenes.timestep import critical_step

    args.source_label = args.scene
    scene = load_scene(args.scene)
    result = critical_step(scene)  # may still refuse the scene: then its one line is the only one on stderr
    for key, message in scene.warnings:
        sys.stderr.write(f"{args.scene}:{key}: {message}\n")
    if args.json:
        import json

        print(json.dumps(result.to_json(), indent=2, allow_nan=False))
    else:
        print(format_text(result))
        speed = scene.collision_v_max if scene.collision_v_max is not None else getattr(scene.contact, "velocity", None)
        if speed is not None:  # impacts: their resolution is another step
            print(f"impacts at {speed:g} m/s: `dtcrit collide SCENE` gives the step that resolves them")
    return 0
