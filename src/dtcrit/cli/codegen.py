"""``dtcrit codegen SCENE --lang {c,numpy,fortran}``: emit the per-contact critical step as code.

    dtcrit codegen examples/paper_ellipsoids.toml --lang c > dt_crit.c
    dtcrit codegen examples/damped_spheres.toml --lang numpy --name contact_dt

The emitted function takes the scene's free parameters (masses, principal moments, contact arms,
stiffnesses, damping, omega_max) and leaves out everything the scene does not need; its header
states the equations, the integrator, the derivation hash and the arguments with units.  The
output is deterministic.  Generation uses SymPy and takes a few seconds.
"""
from __future__ import annotations


def add_parser(subparsers) -> None:
    """Add the ``dtcrit codegen`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = subparsers.add_parser(
        "codegen",
        help="emit C, NumPy or Fortran code for the per-contact critical time step of a scene",
        description="Emit a self-contained function computing the critical time step of one contact, "
        "specialised to the scene's structure (Peng et al. 2020; exact integrator boundaries).",
    )
    p.add_argument("scene", metavar="SCENE", help="scene file (TOML; every key is listed on the documentation's Scene keys page)")
    p.add_argument("--lang", required=True, choices=("c", "numpy", "fortran"), help="output language")
    p.add_argument("--name", default="dtcrit_dt_crit", help="function name (default dtcrit_dt_crit)")
    p.add_argument("--out", metavar="FILE", help="write to FILE instead of standard output")
    p.add_argument("--json", action="store_true", help="print the metadata (schema dtcrit-codegen/1: language, integrator, "
                   "arguments, formulas, derivation hashes and the source) as JSON on standard output")
    p.set_defaults(run=run)


def run(args) -> int:
    """Run ``dtcrit codegen``: emit the scene's kernel (``dtcrit.emitted_code``), print it or write it, with ``--json`` its metadata.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    int
        The exit status (0; bad input raises ``ValueError``, printed as one line with status 2).
    """
    import shlex
    import sys

    from dtcrit.scenes.scene import load_scene

    name = _checked_name(args.name)
    if args.out:
        from dtcrit.cli.outputs import check_output_file

        check_output_file(args.out, "--out")
    args.source_label = args.scene
    scene = load_scene(args.scene)
    from dtcrit.codegen.api import emitted_code  # SymPy: only now

    # the header's "Regenerate with" line: the path quoted for a shell (the header's comment text is made
    # safe for the language in dtcrit.codegen.render, whatever the path holds)
    command = f"dtcrit codegen {shlex.quote(args.scene)} --lang {args.lang}" + (f" --name {name}" if name != "dtcrit_dt_crit" else "")
    code = _checked_name(name, lambda: emitted_code(scene, args.lang, name, command=command), args)
    for key, message in scene.warnings:  # only once nothing can fail any more: one line for a refusal
        sys.stderr.write(f"{args.scene}:{key}: {message}\n")
    text = code.source
    if args.out:
        try:
            with open(args.out, "w", encoding="utf-8") as fh:
                fh.write(text)
        except OSError as exc:
            args.source_label = None
            raise ValueError(f"--out: cannot write {args.out}: {exc.strerror or exc}") from None
    if getattr(args, "json", False):
        import json

        sys.stdout.write(json.dumps(code.to_json(), indent=1) + "\n")
    elif not args.out:
        sys.stdout.write(text)
    return 0


def _checked_name(name: str, then=None, args=None):
    """``check_name(name)`` (or ``then()``, which checks it against the kernel's own names), with a
    refusal of the name reported as ``--name: reason`` (a flag, not a key of the scene).
    """
    from dtcrit.codegen.names import check_name
    from dtcrit.errors import InputError

    try:
        return check_name(name) if then is None else then()
    except InputError as exc:
        if exc.key != "name":
            raise
        if args is not None:
            args.source_label = None
        raise InputError("--name", exc.reason) from None
