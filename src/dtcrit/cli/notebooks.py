"""``dtcrit notebooks --out DIR``: execute the teaching notebooks and write them with outputs."""
from __future__ import annotations

import time
from pathlib import Path

from dtcrit.cli.flags import number

MAX_TIMEOUT = 86400  # a day per cell


def add_parser(sub):
    """Add the ``dtcrit notebooks`` subcommand and its flags.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = sub.add_parser("notebooks", help="execute the teaching notebooks into .ipynb files with outputs")
    p.add_argument("--out", default="out/notebooks", help="folder for the executed notebooks (default: out/notebooks)")
    p.add_argument("--only", nargs="*", default=None, help="stems of the notebooks to run (default: all)")
    p.add_argument("--timeout", type=number(int, maximum=MAX_TIMEOUT, what="number of seconds"), default=300,
                   help=f"seconds per cell, a whole number from 1 to {MAX_TIMEOUT} (default 300)")
    p.set_defaults(run=run)


def run(args) -> int:
    """Run ``dtcrit notebooks``: execute the teaching notebooks into .ipynb files with outputs.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    int
        The exit status (0; bad input raises ``ValueError``, printed as one line with status 2).
    """
    from dtcrit.notebooks import render, sources

    from dtcrit.cli.outputs import check_output_dir

    check_output_dir(args.out)
    todo = [s for s in sources() if not args.only or s.stem in args.only]
    if not todo:
        raise ValueError("notebooks: no notebook sources matched")
    for src in todo:
        start = time.perf_counter()
        render(src, Path(args.out), timeout=args.timeout)
        print(f"{src.stem}: executed in {time.perf_counter() - start:.1f} s -> {Path(args.out) / (src.stem + '.ipynb')}")
    return 0
