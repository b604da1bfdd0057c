"""``dtcrit bench [--quick] [--out DIR] [--json]``: error against run time for every route to the
critical step, the extreme-case suite and the stability check by simulation.

Parses, calls ``dtcrit.bench.runner.run_bench`` and ``dtcrit.bench.report.write_report``, prints.
The bench imports SymPy for its reference step, so everything is imported inside ``run``.
"""
from __future__ import annotations

import json

from dtcrit.cli.flags import number

MAX_SCENES = 10_000_000  # ten times the full run: the batch's arrays stay within a few GB


def add_parser(subparsers) -> None:
    """Add the ``dtcrit bench`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = subparsers.add_parser(
        "bench",
        help="error against run time of every route to the critical step; extreme-case suite",
        description="Compute the critical step of a batch of scenes by every route (generated closed form in "
        "NumPy and C, the paper's Cardano route, eigvals + bisection, mpmath eigenvalues), report the error "
        "against a 50-digit reference and the time per scene, run the extreme-case suite and check stability "
        "by simulation.  Writes bench.md, CSV files and work_precision.png into DIR.",
    )
    p.add_argument("--quick", action="store_true", help="small batch and samples (about a minute)")
    p.add_argument("--out", metavar="DIR", default="dtcrit-bench", help="output folder (default: ./dtcrit-bench)")
    p.add_argument("--json", action="store_true", help="print the summary as JSON on standard output")
    p.add_argument("--scenes", type=number(int, maximum=MAX_SCENES, what="number of scenes"), metavar="N",
                   help=f"batch size (default 20000 quick, 1000000 full; at most {MAX_SCENES})")
    p.set_defaults(run=run)


def run(args) -> int:
    """Run ``dtcrit bench``: time every route to the critical step and write the report.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    int
        The exit status (0; bad input raises ``ValueError``, printed as one line with status 2).
    """
    from dataclasses import replace

    from dtcrit.bench.report import json_summary, markdown, write_report
    from dtcrit.bench.runner import FULL_RUN, QUICK, run_bench
    from dtcrit.errors import InputError

    from dtcrit.cli.outputs import check_output_dir

    check_output_dir(args.out)
    config = QUICK if args.quick else FULL_RUN
    if args.scenes is not None:
        if args.scenes < max(config.n_ref, config.n_eig, config.n_mp, 1):
            raise InputError("--scenes", f"must be at least {max(config.n_ref, config.n_eig, config.n_mp)} "
                             f"(the reference and timing samples; got {args.scenes})")
        config = replace(config, n_batch=args.scenes)
    result = run_bench(config)
    paths = write_report(result, args.out)
    if args.json:
        print(json.dumps(json_summary(result), indent=1))
    else:
        text = markdown(result)
        head = text.split("## Max ulp per route")[0]
        print(head.rstrip())
        print()
        print("Wrote " + ", ".join(str(p) for p in paths))
    return 0
