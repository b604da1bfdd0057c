"""``dtcrit figures``: the paper's numerics reproduced and checked (Peng et al. 2020, Section 6 and Appendix A).

One module per figure, each with a ``figN_data`` function (NumPy arrays from the library API) and
a ``write_figN(out, fine=...)`` that writes a PNG and the CSV of its data:

* :mod:`.fig3_damping` -- Fig. 3, dt*sqrt(k/m) against beta for two spheres (Eqs. (58)-(60) and
  each integrator's verified bound);
* :mod:`.fig4_stiffness`, :mod:`.fig5_density` -- Figs. 4 and 5, the a=3, b=2, c=1 m ellipsoids
  (shared scene in :mod:`.ellipsoid_pair`);
* :mod:`.fig6_aspect_ratio` -- Fig. 6, translation- and rotation-dominant steps over aspect ratios;
* :mod:`.appendix_a` (+ :mod:`.appendix_a_search`, :mod:`.appendix_a_contacts`, :mod:`.appendix_a_plots`) --
  the Appendix A search over admissible contacts.

:mod:`.audit_plot` draws ``dtcrit audit --plot`` (not a paper figure; data from
:mod:`dtcrit.packing.audit.plot_data`).
:mod:`.collide_plot` draws ``dtcrit collide --plot`` (the error against steps per collision).
:mod:`.plan_added_mass` draws a density-scaling plan: added mass per particle against its size.

:func:`make_figures` runs them; :mod:`.summary` builds the JSON summary of ``--json``.
Matplotlib is needed only to draw (``pip install dtcrit[figures]``).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from dtcrit.errors import InputError

__all__ = ["FIGURES", "FiguresRun", "make_figures", "check_figure_names"]

FIGURES: tuple[str, ...] = ("fig3", "fig4", "fig5", "fig6", "appendix_a")


@dataclass
class FiguresRun:
    """What ``make_figures`` wrote.

    Parameters
    ----------
    files : list of pathlib.Path
        The PNG and CSV files written, in order.
    summary : dict
        The figures' JSON-ready summary (``dtcrit.figures.summary.summary``).
    """

    files: list[Path] = field(default_factory=list)
    summary: dict = field(default_factory=dict)


def check_figure_names(names) -> tuple[str, ...]:
    """Validate a list of figure names (``InputError`` naming the first unknown one).

    Parameters
    ----------
    names : iterable of str
        Figure names as typed (aliases such as ``a`` or ``appendix`` accepted).

    Returns
    -------
    tuple of str
        The canonical names, in the order given.
    """
    out = []
    for name in names:
        key = str(name).strip().lower().replace("-", "_")
        if key in ("a", "appendix", "appendixa"):
            key = "appendix_a"
        if key not in FIGURES:
            raise InputError("only", f"unknown figure {name!r}; choose from {', '.join(FIGURES)}")
        if key not in out:
            out.append(key)
    return tuple(out)


def make_figures(out, *, fine: bool = False, only=None, show_progress: bool = True) -> FiguresRun:
    """Write the PNG + CSV of every figure in ``only`` (default: all) into ``out``; return files and summary.

    Parameters
    ----------
    out : str or pathlib.Path
        Folder to write into (created if needed).
    fine : bool
        Use the fine grids (slower) instead of the coarse ones.
    only : iterable of str, optional
        Figure names to make; all when omitted.
    show_progress : bool
        Show progress bars for the long searches.

    Returns
    -------
    FiguresRun
        The files written and the summary.
    """
    from dtcrit.figures import summary as _summary
    from dtcrit.figures.fig3_damping import write_fig3
    from dtcrit.figures.fig4_stiffness import write_fig4
    from dtcrit.figures.fig5_density import write_fig5
    from dtcrit.figures.fig6_aspect_ratio import write_fig6

    names = FIGURES if only is None else check_figure_names(only)
    out = Path(out)
    run = FiguresRun()
    if "fig3" in names:
        run.files += write_fig3(out, fine=fine)
    if "fig4" in names:
        run.files += write_fig4(out, fine=fine)
    if "fig5" in names:
        run.files += write_fig5(out, fine=fine)
    if "fig6" in names:
        run.files += write_fig6(out, fine=fine, show_progress=show_progress)
    study = None
    if "appendix_a" in names:
        from dtcrit.figures.appendix_a import appendix_a_study
        from dtcrit.figures.appendix_a_plots import write_appendix_a

        study = appendix_a_study(fine=fine, show_progress=show_progress)
        run.files += write_appendix_a(out, study)
    run.summary = _summary.summary(names, fine=fine, appendix=study)
    return run
