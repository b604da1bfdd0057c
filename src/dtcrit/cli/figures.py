"""``dtcrit figures``: reproduce the paper's Figures 3-6 and the Appendix A search (PNG + CSV).

Parses the arguments, calls :func:`dtcrit.figures.make_figures` and prints the files written and a
short summary (``--json``: the full summary as JSON on standard output, schema ``dtcrit-figures/1``,
behind the envelope of every dtcrit JSON document; see :mod:`dtcrit.figures.summary`).
"""
from __future__ import annotations

import json
import sys

from dtcrit.errors import InputError

HELP = "reproduce Figs 3-6 and the Appendix A search of Peng et al. 2020 (PNG + CSV)"


def add_parser(subparsers) -> None:
    """Add the ``dtcrit figures`` subcommand and its flags.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The ``dtcrit`` parser's subcommands.
    """
    p = subparsers.add_parser("figures", help=HELP, description=HELP + ".")
    p.add_argument("--out", default="figures", metavar="DIR", help="output folder (default: ./figures)")
    p.add_argument("--fine", action="store_true", help="fine grids for the long sweeps (Fig 6, Appendix A)")
    p.add_argument("--json", action="store_true", help="print the summary as JSON on standard output")
    p.add_argument("--only", default=None, metavar="LIST",
                   help="comma-separated subset of fig3,fig4,fig5,fig6,appendix_a (default: all)")
    p.set_defaults(run=run)


def _short(summary: dict) -> list[str]:
    lines = []
    ar = summary.get("aspect_ratio")
    if ar:
        lines.append(
            f"Fig 6: rotation/translation step ratio {ar['min_ratio']:.4g} .. {ar['max_ratio']:.4g} (finite), "
            f"> 1e4 on {ar['points_over_1e4']} of {ar['points']} grid points "
            f"(fraction {ar['fraction_over_1e4']:.4g}); at a=3, b=2, c=1: {ar['ratio_at_a3_b2_c1']:.4g}"
        )
    ap = summary.get("appendix_a")
    if ap and "max_found" in ap:
        lines.append(
            f"Appendix A: |xdd_c| orthogonal {ap['orthogonal']:.6g}, max found {ap['max_found']:.6g} "
            f"(+{100 * ap['margin']:.3g} %), orthogonal is max: {ap['orthogonal_is_max']}"
        )
        for name, s in ap.get("shapes", {}).items():
            verdict = "holds" if s["eq26_is_upper_bound_lambda"] else "FAILS"
            lines.append(
                f"  {name}: largest eigenvalue {s['max_lambda']:.6g} vs Eq (26) A_max {s['a_max_eq26']:.6g} "
                f"-> Eq (26) {verdict} as an upper bound"
            )
    return lines


def run(args) -> int:
    """Run ``dtcrit figures``: draw the paper's figures into the output folder.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed flags.

    Returns
    -------
    int
        The exit status (0; bad input raises ``ValueError``, printed as one line with status 2).
    """
    from dtcrit.figures import check_figure_names, make_figures

    only = None
    if args.only is not None:
        parts = [s for s in args.only.split(",") if s.strip()]
        if not parts:
            raise InputError("only", "empty list")
        only = check_figure_names(parts)
    from dtcrit.cli.outputs import check_output_dir

    out = check_output_dir(args.out)
    result = make_figures(out, fine=args.fine, only=only, show_progress=not args.json)
    if args.json:
        from dtcrit.figures.summary import document

        sys.stdout.write(json.dumps(document(result.summary), indent=2, allow_nan=False) + "\n")
        return 0
    for f in result.files:
        print(f"wrote {f}")
    for line in _short(result.summary):
        print(line)
    return 0
